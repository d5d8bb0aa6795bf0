"""Run slots of expensive work, shared by every web process of one server.

A server has as many slots as the CPUs its processes may use (:func:`usable_cpus`); a job
runs in a solver worker only while it holds one, whichever web process took its request,
so N concurrent expensive requests keep min(N, slots) workers busy however the kernel
spread their connections. Slot i is an exclusive ``flock`` on file i of a directory the
web processes share: the kernel releases it when its holder dies, so a web process that
crashes cannot leak a slot (a counter in shared memory would). Each web process also
publishes its queue there (its running jobs' predicted ends, the work waiting, the run
times it measured), so that each admits by the whole server's backlog.

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

SERVER_PID_ENV = "PESHKIN_RUNTIME_SERVER_PID"
"""The environment variable naming the supervisor's process id (set by it): what lives for
the server's life, its one Ray, watches it."""

METRICS_DIR_ENV = "PROMETHEUS_MULTIPROC_DIR"
"""prometheus-client's variable naming the directory of a multi-process server's samples
(service.runtime.metrics), made in the slot directory by the supervisor."""


def usable_cpus() -> int:
    """The CPUs this process may really use: the smallest of the machine's count, its CPU
    affinity and a container's cgroup CPU quota (``loky.cpu_count``, which reads cgroup v1
    and v2), at least one. ``os.cpu_count()`` counts the host's CPUs whatever the limits."""
    return max(1, int(loky.cpu_count()))


def make_slot_directory() -> str:
    """A new directory for the slots of one server (the caller removes it)."""
    return tempfile.mkdtemp(prefix="peshkin-slots-")


def job_places_of(count: int) -> int:
    """Slots that jobs may hold at once on a server of ``count`` slots: all but one, so that
    a job never takes the last slot from interactive requests; on a server of one slot, that
    slot (a job there makes requests wait, with its predicted end as their Retry-After)."""
    return max(count - 1, 1)


class Slots:
    """``count`` slots in ``directory`` (made by :meth:`open`, and removed by :meth:`close`,
    when None), and ``job_places`` places for jobs (default :func:`job_places_of`): a job
    holds a place besides each slot it holds, so jobs never hold more than that many slots.
    Nothing is made before :meth:`open` (importing the app makes no directory). Safe to use
    from several threads of one process.

    Each holder also keeps, while it lives, an ``flock`` on a file ``alive-<id>`` of its own
    and publishes its queue in ``queue-<id>.json``: a reader that can lock another holder's
    ``alive`` file knows that holder is gone (the kernel released its lock), whatever
    became of its process id."""

    def __init__(self, count: int, directory: str | None = None, job_places: int | None = None) -> None:
        if count < 1:
            raise ValueError(f"a server needs at least one slot, got {count}")
        self.count = count
        self.job_places = job_places_of(count) if job_places is None else job_places
        self.directory = directory
        self._owned = directory is None
        self._lock = threading.Lock()
        self._fds: list[int] = []
        self._place_fds: list[int] = []
        self._held: set[int] = set()
        self._places_held: set[int] = set()
        self._id = f"{os.getpid()}-{id(self):x}"
        self._alive: int | None = None

    @classmethod
    def of_server(cls, count: int, job_places: int | None = None) -> Slots:
        """The server's slots (the supervisor's directory), or this process's own."""
        return cls(count, os.environ.get(SLOT_DIR_ENV) or None, job_places)

    def open(self) -> Slots:
        """Open the slots (making the directory when it is this holder's own)."""
        with self._lock:
            if self._fds:
                return self
            if self.directory is None:
                self.directory = make_slot_directory()
            os.makedirs(self.directory, exist_ok=True)
            self._fds = [os.open(self._path(f"slot-{i}"), os.O_RDWR | os.O_CREAT, 0o600) for i in range(self.count)]
            self._place_fds = [os.open(self._path(f"job-{i}"), os.O_RDWR | os.O_CREAT, 0o600)
                               for i in range(self.job_places)]
            self._alive = os.open(self._path(f"alive-{self._id}"), os.O_RDWR | os.O_CREAT, 0o600)
            fcntl.flock(self._alive, fcntl.LOCK_EX)
            return self

    def _path(self, name: str) -> str:
        assert self.directory is not None
        return os.path.join(self.directory, name)

    def try_take(self) -> int | None:
        """A free slot, now held by this process (None: all are held)."""
        return self._take(self._fds, self._held)

    def _take(self, fds: list[int], held: set[int]) -> int | None:
        with self._lock:
            for i, fd in enumerate(fds):
                if i not in held and _lock(fd):
                    held.add(i)
                    return i
            return None

    def _give_back(self, fds: list[int], held: set[int], i: int, what: str) -> None:
        with self._lock:
            if i not in held:
                raise RuntimeError(f"{what} {i} given back but not held")
            held.discard(i)
            fcntl.flock(fds[i], fcntl.LOCK_UN)

    def free(self) -> int:
        """Slots free now, by any holder (probed without blocking; advisory)."""
        with self._lock:
            free = 0
            for i, fd in enumerate(self._fds):
                if i not in self._held and _lock(fd):
                    fcntl.flock(fd, fcntl.LOCK_UN)
                    free += 1
            return free

    def give_back(self, slot: int) -> None:
        self._give_back(self._fds, self._held, slot, "slot")

    def try_take_place(self) -> int | None:
        """A free place for a job, now held by this process (None: jobs hold them all)."""
        return self._take(self._place_fds, self._places_held)

    def give_back_place(self, place: int) -> None:
        self._give_back(self._place_fds, self._places_held, place, "job place")

    def publish(self, state: dict[str, Any]) -> None:
        """Tell the other holders this one's queue (``state``: JSON), in a file of its own,
        replaced whole (a reader never sees half of it). Advisory: nothing is published
        before :meth:`open` or after :meth:`close`, or when the directory is gone (the
        server stopping)."""
        if not self._fds:
            return
        path = self._path(f"queue-{self._id}.json")
        with contextlib.suppress(OSError):
            with open(f"{path}.tmp", "w") as f:
                json.dump(state, f)
            os.replace(f"{path}.tmp", path)

    def peers(self) -> list[dict[str, Any]]:
        """What the other live holders published; a holder found gone is forgotten and its
        files removed."""
        found: list[dict[str, Any]] = []
        if not self._fds:
            return found
        try:
            names = os.listdir(self.directory)
        except OSError:
            return found
        for name in names:
            if not name.startswith("alive-") or name == f"alive-{self._id}":
                continue
            other = name[len("alive-"):]
            if not _still_held(self._path(name)):
                for gone in (name, f"queue-{other}.json"):
                    with contextlib.suppress(OSError):
                        os.remove(self._path(gone))
                continue
            with contextlib.suppress(OSError, ValueError):
                with open(self._path(f"queue-{other}.json")) as f:
                    found.append(json.load(f))
        return found

    def close(self) -> None:
        with self._lock:
            if self._fds:
                for name in (f"queue-{self._id}.json", f"alive-{self._id}"):
                    with contextlib.suppress(OSError):
                        os.remove(self._path(name))
            for fd in [*self._fds, *self._place_fds, *([] if self._alive is None else [self._alive])]:
                os.close(fd)  # releases what this holder held
            self._fds, self._place_fds, self._alive = [], [], None
            self._held.clear()
            self._places_held.clear()
        if self._owned and self.directory is not None:
            shutil.rmtree(self.directory, ignore_errors=True)


def _still_held(path: str) -> bool:
    """Whether another holder keeps its lock on ``path`` (probed without blocking)."""
    try:
        fd = os.open(path, os.O_RDWR)
    except OSError:
        return False
    try:
        if _lock(fd):
            fcntl.flock(fd, fcntl.LOCK_UN)
            return False
        return True
    finally:
        os.close(fd)


def _lock(fd: int) -> bool:
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return False
    return True
