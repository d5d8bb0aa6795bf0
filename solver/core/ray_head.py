"""One local Ray for a whole server (issue 35): the first solver worker that needs Ray starts
this head process, and every worker of every web process of the server connects to it,
instead of each starting a Ray of its own sized to the whole machine.

The head is ``python -m solver.core.ray_head --cpus N --dir D [--watch PID]``: a process of
its own session (a worker that is ended does not take Ray with it) that starts a local Ray
of ``N`` CPUs, writes its address to ``D/ray-head.json`` and lives until it is stopped
(SIGTERM, :func:`stop_server_ray`), until ``D`` is removed, or until process ``PID`` (the
server's supervisor) is gone; it checks every second. Its own output goes to
``D/ray-head.log``, never into the server's log. :func:`server_ray` finds the head or
starts it, under a file lock so that one head is started however many workers ask at once.
"""

from __future__ import annotations

import argparse
import contextlib
import fcntl
import json
import logging
import os
import secrets
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass
from pathlib import Path

HEAD_FILE = "ray-head.json"
LOCK_FILE = "ray-head.lock"
LOG_FILE = "ray-head.log"
OBJECT_STORE_BYTES = 256 * 1024 * 1024
"""Shared memory of the object store (Ray's default takes 30 % of the RAM from /dev/shm)."""
START_TIMEOUT_S = 90.0
"""How long a worker waits for the head it started to write its address."""
WATCH_S = 1.0
"""How often the head checks that its server is still there."""


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _read_head(directory: Path) -> dict[str, object] | None:
    """The running head's address and process id, or None (none written, or it is gone)."""
    try:
        head = json.loads((directory / HEAD_FILE).read_text())
    except (OSError, ValueError):
        return None
    pid = head.get("pid")
    return head if isinstance(pid, int) and _alive(pid) and isinstance(head.get("address"), str) else None


@dataclass(frozen=True)
class HeadAddress:
    """How a driver reaches the server's Ray: its GCS ``address`` and the authentication
    ``token`` (Ray's token authentication, on: the GCS listens on the host's address)."""

    address: str
    token: str

    def environment(self) -> dict[str, str]:
        """What a driver's environment must hold before ``ray.init(address=...)``."""
        return {"RAY_AUTH_MODE": "token", "RAY_AUTH_TOKEN": self.token}


def _address(head: dict[str, object]) -> HeadAddress:
    return HeadAddress(str(head["address"]), str(head.get("token", "")))


def server_ray(directory: str, cpus: int, watch_pid: int | None = None,
               timeout_s: float = START_TIMEOUT_S) -> HeadAddress:
    """How to reach the server's Ray whose head lives in ``directory``: the running one, or
    one of ``cpus`` CPUs started now that ends with process ``watch_pid`` (waiting at most
    ``timeout_s`` for it)."""
    where = Path(directory)
    with open(where / LOCK_FILE, "a+") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        head = _read_head(where)
        if head is not None:
            return _address(head)
        with contextlib.suppress(OSError):
            (where / HEAD_FILE).unlink()
        with open(where / LOG_FILE, "ab") as log:
            watch = [] if watch_pid is None else ["--watch", str(watch_pid)]
            proc = subprocess.Popen([sys.executable, "-m", "solver.core.ray_head", "--cpus", str(cpus), "--dir",
                                     str(where), *watch], stdin=subprocess.DEVNULL, stdout=log, stderr=log,
                                    start_new_session=True)
        ends = time.monotonic() + timeout_s
        while time.monotonic() < ends:
            head = _read_head(where)
            if head is not None:
                return _address(head)
            if proc.poll() is not None:
                raise RuntimeError(f"the server's Ray head exited with {proc.returncode} (see {where / LOG_FILE})")
            time.sleep(0.05)
        proc.terminate()
        raise RuntimeError(f"the server's Ray head did not start within {timeout_s:g} s (see {where / LOG_FILE})")


def stop_server_ray(directory: str, timeout_s: float = 20.0) -> None:
    """Stop the head of ``directory`` (if one runs) and wait for it to end."""
    head = _read_head(Path(directory))
    if head is None:
        return
    pid = int(head["pid"])  # type: ignore[call-overload]
    with contextlib.suppress(ProcessLookupError):
        os.kill(pid, signal.SIGTERM)
    ends = time.monotonic() + timeout_s
    while _alive(pid) and time.monotonic() < ends:
        time.sleep(0.05)


def _server_gone(directory: Path, watch_pid: int | None) -> bool:
    return not directory.is_dir() or (watch_pid is not None and not _alive(watch_pid))


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--cpus", type=int, required=True)
    parser.add_argument("--dir", required=True)
    parser.add_argument("--watch", type=int, default=None)
    args = parser.parse_args(argv)
    directory = Path(args.dir)
    stop = threading.Event()
    for sig in (signal.SIGTERM, signal.SIGINT):
        signal.signal(sig, lambda *_: stop.set())
    os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")
    token = secrets.token_hex(32)  # Ray's token authentication, with a token every driver reads from the head file
    os.environ.update({"RAY_AUTH_MODE": "token", "RAY_AUTH_TOKEN": token})
    import ray

    temp = tempfile.mkdtemp(prefix="pk-ray-", dir="/tmp")  # short: Ray's socket paths must fit 107 bytes
    try:
        ray.init(address="local", num_cpus=args.cpus, include_dashboard=False, log_to_driver=False,
                 object_store_memory=OBJECT_STORE_BYTES, logging_level=logging.WARNING, _temp_dir=temp)
        address = ray.get_runtime_context().gcs_address
        part = directory / f"{HEAD_FILE}.tmp"
        with open(os.open(part, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600), "w") as f:
            json.dump({"address": address, "pid": os.getpid(), "cpus": args.cpus, "token": token}, f)
        os.replace(part, directory / HEAD_FILE)
        while not stop.wait(WATCH_S):
            if _server_gone(directory, args.watch):
                break
    finally:
        with contextlib.suppress(Exception):
            ray.shutdown()
        shutil.rmtree(temp, ignore_errors=True)
        with contextlib.suppress(OSError):
            (directory / HEAD_FILE).unlink()


if __name__ == "__main__":
    main()
