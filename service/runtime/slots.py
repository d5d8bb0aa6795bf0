"""Run slots of expensive work, shared by every web process of one server.

A server has as many slots as the CPUs its processes may use (:func:`usable_cpus`); a job
runs in a solver worker only while it holds one, whichever web process took its request,
so N concurrent expensive requests keep min(N, slots) workers busy however the kernel
spread their connections. Each web process also publishes its queue there (the work
waiting and the run times it measured), so that each admits by the whole server's backlog. Slot i is an exclusive ``flock`` on file i of a directory the
web processes share: the kernel releases it when its holder dies, so a web process that
crashes cannot leak a slot (a counter in shared memory would).

The supervisor (:mod:`service.server`) makes the directory and hands it to its web
processes in :data:`SLOT_DIR_ENV`; a web process run alone (``uvicorn service.app:app``, the
tests) makes one of its own.
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
import shutil
import tempfile
import threading
from typing import Any

import loky

SLOT_DIR_ENV = "PESHKIN_RUNTIME_SLOT_DIR"
"""The environment variable naming the slot directory of the server (set by the supervisor)."""


def usable_cpus() -> int:
    """The CPUs this process may really use: the smallest of the machine's count, its CPU
    affinity and a container's cgroup CPU quota (``loky.cpu_count``, which reads cgroup v1
    and v2), at least one. ``os.cpu_count()`` counts the host's CPUs whatever the limits."""
    return max(1, int(loky.cpu_count()))


def make_slot_directory() -> str:
    """A new directory for the slots of one server (the caller removes it)."""
    return tempfile.mkdtemp(prefix="peshkin-slots-")


class Slots:
    """``count`` slots in ``directory`` (made, and removed by :meth:`close`, when None).
    Safe to use from several threads of one process."""

    def __init__(self, count: int, directory: str | None = None) -> None:
        if count < 1:
            raise ValueError(f"a server needs at least one slot, got {count}")
        self.count = count
        self._owned = directory is None
        self.directory = make_slot_directory() if directory is None else directory
        os.makedirs(self.directory, exist_ok=True)
        self._lock = threading.Lock()
        self._fds = [os.open(os.path.join(self.directory, f"slot-{i}"), os.O_RDWR | os.O_CREAT, 0o600)
                     for i in range(count)]
        self._held: set[int] = set()
        self._queue_file = f"queue-{os.getpid()}-{id(self):x}.json"

    @classmethod
    def of_server(cls, count: int) -> Slots:
        """The server's slots (the supervisor's directory), or this process's own."""
        return cls(count, os.environ.get(SLOT_DIR_ENV) or None)

    def try_take(self) -> int | None:
        """A free slot, now held by this process (None: all are held)."""
        with self._lock:
            for i, fd in enumerate(self._fds):
                if i not in self._held and _lock(fd):
                    self._held.add(i)
                    return i
            return None

    def give_back(self, slot: int) -> None:
        with self._lock:
            if slot not in self._held:
                raise RuntimeError(f"slot {slot} given back but not held")
            self._held.discard(slot)
            fcntl.flock(self._fds[slot], fcntl.LOCK_UN)

    def held_here(self) -> int:
        with self._lock:
            return len(self._held)

    def held_elsewhere(self) -> int:
        """Slots held by the other web processes now (each is probed; a snapshot)."""
        with self._lock:
            busy = 0
            for i, fd in enumerate(self._fds):
                if i in self._held:
                    continue
                if _lock(fd):
                    fcntl.flock(fd, fcntl.LOCK_UN)
                else:
                    busy += 1
            return busy

    def publish(self, state: dict[str, Any]) -> None:
        """Tell the other web processes this one's queue (``state``: JSON), in a file of
        its own, replaced whole (a reader never sees half of it). Advisory: nothing is
        published once the slots are closed, or when the directory is gone (the server
        stopping)."""
        if not self._fds:
            return
        path = os.path.join(self.directory, self._queue_file)
        temporary = f"{path}.tmp"
        with contextlib.suppress(OSError):
            with open(temporary, "w") as f:
                json.dump(state, f)
            os.replace(temporary, path)

    def peers(self) -> list[dict[str, Any]]:
        """What the other live web processes published (a process that died is forgotten
        and its file removed)."""
        found: list[dict[str, Any]] = []
        try:
            names = os.listdir(self.directory)
        except OSError:
            return found
        for name in names:
            parts = name.split("-")
            if name == self._queue_file or not (name.endswith(".json") and len(parts) == 3 and parts[1].isdigit()):
                continue
            pid = int(parts[1])
            path = os.path.join(self.directory, name)
            if not _alive(pid):
                with contextlib.suppress(OSError):
                    os.remove(path)
                continue
            with contextlib.suppress(OSError, ValueError):
                with open(path) as f:
                    found.append(json.load(f))
        return found

    def close(self) -> None:
        with contextlib.suppress(OSError):
            os.remove(os.path.join(self.directory, self._queue_file))
        with self._lock:
            for fd in self._fds:
                os.close(fd)  # releases what this process held
            self._fds = []
            self._held.clear()
        if self._owned:
            shutil.rmtree(self.directory, ignore_errors=True)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _lock(fd: int) -> bool:
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return False
    return True
