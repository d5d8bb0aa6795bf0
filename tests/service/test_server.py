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


def test_a_web_process_listens_only_when_its_app_is_ready():
    """Issue 35, point 9: gunicorn's socket of a web process listened from its fork on, so
    connections queued and hung while it imported the app and started its workers. After
    listen_when_ready the socket is bound but refuses connections, until asyncio listens on
    it (what uvicorn does once the app's startup is done)."""
    import errno
    import socket
    from types import SimpleNamespace

    from service.server import listen_when_ready

    gunicorns = socket.socket()
    gunicorns.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEPORT, 1)
    gunicorns.bind(("127.0.0.1", 0))
    gunicorns.listen(16)
    port = gunicorns.getsockname()[1]
    worker = SimpleNamespace(sockets=[gunicorns])
    listen_when_ready(None, worker)
    (bound,) = worker.sockets
    try:
        assert bound.getsockname()[1] == port and gunicorns.fileno() == -1
        with socket.socket() as client:
            assert client.connect_ex(("127.0.0.1", port)) == errno.ECONNREFUSED  # refused, not queued
        bound.listen(16)
        with socket.socket() as client:
            assert client.connect_ex(("127.0.0.1", port)) == 0
    finally:
        bound.close()


def test_a_second_server_does_not_take_the_first_ones_control_socket(tmp_path):
    """Issue 35, point 9: given the first server's PESHKIN_CONTROL_SOCKET, a second took it
    over and deleted it on exit. It now refuses to start; a path left by a gone server is
    taken."""
    import socket

    import pytest

    from service.server import ControlSocketInUse, ensure_control_socket_free

    path = str(tmp_path / "ctl.sock")
    ensure_control_socket_free(path)  # nothing there
    first = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    first.bind(path)
    first.listen(1)
    try:
        with pytest.raises(ControlSocketInUse, match="in use by another server"):
            ensure_control_socket_free(path)
    finally:
        first.close()
    ensure_control_socket_free(path)  # stale: the first is gone


def test_the_supervisor_drops_its_listening_line_without_an_address():
    import logging

    from service.server import NoEmptyListening

    f = NoEmptyListening()
    make = logging.LogRecord
    assert not f.filter(make("gunicorn.error", logging.INFO, "", 0, "Listening at: %s (%s)", ("", 4115), None))
    assert f.filter(make("gunicorn.error", logging.INFO, "", 0, "Listening at: %s (%s)", ("http://x:1", 4115), None))
    assert f.filter(make("gunicorn.error", logging.INFO, "", 0, "Booting worker with pid: %s", (4116,), None))
