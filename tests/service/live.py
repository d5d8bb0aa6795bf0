"""A live server for tests: ``python -m service`` (gunicorn supervising uvicorn, solver
workers) in a subprocess on a free loopback port."""

from __future__ import annotations

import math
import os
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import httpx

from service.settings import Settings

REPO = Path(__file__).resolve().parents[2]
PENTAGON = {"vertices": [[0, 0], [3, 0], [3.5, 1.5], [1.5, 2.5], [-0.5, 1.2]], "center_of_mass": [1.4, 1.0]}
DESIGN = {"part": PENTAGON, "angles": {"min": math.radians(20), "max": math.radians(70), "step": math.radians(10)},
          "mu_c": 0.25, "alternate": False, "max_depth": 10, "validation_parts": 4, "time_limit_s": 20}
"""A feeder design of a few seconds (the pentagon, 12 candidate fences, 4 validating parts):
the expensive request of the floods (tests/service/runtime/test_flood_live.py, make load)."""

STARTUP_TIMEOUT_S = 120.0
"""How long the server may take to start (its workers import the solver stack)."""
LISTEN = "0A"
"""TCP_LISTEN, as /proc/net/tcp writes a socket's state."""


def listening_sockets(port: int) -> int:
    """How many sockets listen on loopback ``port`` (each web process has its own, with
    SO_REUSEPORT, once its app is ready: service/server.py)."""
    count = 0
    with open("/proc/net/tcp") as table:
        next(table)
        for line in table:
            local, _, state = line.split()[1:4]
            count += state == LISTEN and int(local.rsplit(":", 1)[1], 16) == port
    return count


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def server_command() -> list[str]:
    """The command that runs the service (what scripts/serve.sh and the Dockerfile run)."""
    return [sys.executable, "-m", "service"]


@contextmanager
def live_server(**settings: str) -> Iterator[str]:
    """The base URL of a running server; ``settings`` are PESHKIN_* variables (without the
    prefix, lower case), e.g. ``solver_workers="1"``. Stopped (SIGTERM) at the end."""
    with live_server_process(**settings) as (url, _):
        yield url


@contextmanager
def live_server_process(**settings: str) -> Iterator[tuple[str, subprocess.Popen]]:
    """:func:`live_server`, with the server's process (to stop it in a test)."""
    port = free_port()
    env = {k: v for k, v in os.environ.items() if not k.startswith("PESHKIN_")}
    env.update({"PESHKIN_HOST": "127.0.0.1", "PESHKIN_PORT": str(port), "PESHKIN_LOG_LEVEL": "warning",
                "PESHKIN_STORE_PATH": "",  # no result store unless asked: each run computes what it checks
                "PESHKIN_JOBS_PATH": "",  # and a jobs file of its own, unless asked
                "PESHKIN_RAY_WORKERS": "0"})  # catalogues in process: Ray's own tests are tests/solver/core
    env.update({f"PESHKIN_{k.upper()}": v for k, v in settings.items()})
    proc = subprocess.Popen(server_command(), cwd=REPO, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    url = f"http://127.0.0.1:{port}"
    web = int(settings.get("web_workers", Settings.web_workers))
    try:
        deadline = time.monotonic() + STARTUP_TIMEOUT_S
        while True:  # ready, and every web process listening (one answers /readyz before the others listen)
            if proc.poll() is not None:
                raise RuntimeError(f"the server exited: {proc.stderr.read().decode(errors='replace')[-2000:]}")
            try:
                if httpx.get(f"{url}/readyz", timeout=1.0).status_code == 200 and listening_sockets(port) >= web:
                    break
            except httpx.HTTPError:
                pass
            if time.monotonic() > deadline:
                raise RuntimeError("the server did not become ready")
            time.sleep(0.2)
        yield url, proc
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
