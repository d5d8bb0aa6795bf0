"""The supervisor's configuration (service/server.py): gunicorn's control socket is this
instance's own or none (issue 25: two instances shared gunicorn's default path in the
user's home, and in the image every start logged a Permission denied ERROR for it)."""

from __future__ import annotations

import re
from pathlib import Path

from service.server import Server
from service.settings import Settings

ROOT = Path(__file__).resolve().parents[2]


def test_the_control_socket_is_off_unless_a_path_of_its_own_is_given(tmp_path):
    off = Server(Settings()).cfg
    assert off.control_socket_disable is True
    path = str(tmp_path / "peshkin.ctl")
    own = Server(Settings.from_env({"PESHKIN_CONTROL_SOCKET": path})).cfg
    assert own.control_socket_disable is False and own.control_socket == path
    assert Settings.from_env({"PESHKIN_CONTROL_SOCKET": ""}).control_socket == ""


def test_every_documented_run_line_gives_the_engine_longer_than_the_graceful_shutdown():
    """Issue 25: ``docker stop`` / ``podman stop`` wait 10 s before SIGKILL, the service lets
    requests finish for ``graceful_timeout_s`` (and allows each ``max_time_limit_s``): every
    run line of the README and the Makefile sets a stop timeout longer than both."""
    s = Settings()
    lines = [line for f in ("README.md", "Makefile") for line in (ROOT / f).read_text().splitlines()
             if re.search(r"(docker|podman|PODMAN\)) run\b", line)]
    assert len(lines) >= 3
    for line in lines:
        found = re.search(r"--stop-timeout (\d+)", line)
        assert found, f"no --stop-timeout in: {line}"
        assert int(found.group(1)) > max(s.graceful_timeout_s, s.max_time_limit_s), line
