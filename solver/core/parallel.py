"""Independent solver tasks in parallel on Ray (issue 27): an existing Ray cluster
(``address``), the one local Ray of a server (``server_dir``: its head, started by the
first process that needs it, :mod:`solver.core.ray_head`), or a local Ray of this process;
or, without Ray (no workers asked for, or an image built without Ray), one task after the
other in this process. At most ``parallel`` tasks run at once (the solver slots the caller
holds); Ray schedules them.

A task is ``fn(item, ends_at)``: a top-level function (Ray pickles it by reference) of one
item and the wall-clock time (``time.time()``, seconds) at which the whole map's deadline
falls, or None without a limit. The wall clock, not this process's monotonic one, because a
task may run on another machine. Tasks not finished by the deadline are cancelled and their
results are None: a map never reports as done a task that did not finish.
"""

from __future__ import annotations

import contextlib
import importlib.util
import logging
import os
import shutil
import signal
import tempfile
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from typing import Any

from solver.core.budget import Budget
from solver.core.ray_head import server_ray

LOCAL_OBJECT_STORE_BYTES = 256 * 1024 * 1024
"""Shared memory of a local Ray's object store (Ray's default takes 30 % of the RAM from
/dev/shm, which a container rarely has): results larger than this spill to disk."""

TASK_RETURN_MARGIN = 0.05
"""The share of the time left that a task leaves for its answer to come back: it stops that
much before the map's deadline."""

_lock = threading.Lock()
_connected: tuple[str | None, int] | None = None
_local_dirs: list[str] = []  # a local Ray's session files, removed when it stops


CONNECT_S = 3.0
"""What connecting a process to Ray may take (a local start: 2-4 s): a map with less time
left than this in a process not connected yet runs in process, so that its first tasks
finish within the deadline instead of none."""


@dataclass(frozen=True)
class RayPool:
    """Where a map runs: ``workers`` = 0, in this process one task after the other; else on
    Ray, at ``address`` (an existing cluster, e.g. "10.0.0.5:6379") or, with ``address``
    None, on a local Ray of ``workers`` CPUs: the server's one, whose head lives in
    ``server_dir`` (:mod:`solver.core.ray_head`; it ends with process ``server_pid``), or,
    without it, one of this process started on first use and kept for its life.
    ``parallel`` > 0: at most that many tasks at once."""

    workers: int = 0
    address: str | None = None
    parallel: int = 0
    server_dir: str | None = None
    server_pid: int | None = None

    @property
    def on_ray(self) -> bool:
        return self.workers > 0 or self.address is not None


@dataclass(frozen=True)
class ParallelRun:
    """The results of a map, in the items' order (None: not finished by the deadline), where
    it ran ("ray" or "in_process"), the CPUs it had (the cluster's, at most its ``parallel``)
    and the nodes, and the time it took."""

    results: tuple[Any, ...]
    backend: str
    cpus: int
    nodes: int
    solve_time_s: float

    @property
    def finished(self) -> int:
        return sum(r is not None for r in self.results)

    @property
    def complete(self) -> bool:
        return self.finished == len(self.results)

    @property
    def status(self) -> str:
        """"complete" (every task finished) or "time_limit"."""
        return "complete" if self.complete else "time_limit"

    @property
    def message(self) -> str:
        return f"{self.finished} of {len(self.results)} tasks finished ({self.backend}, {self.cpus} CPUs)"


def _ray(pool: RayPool) -> Any:
    """Ray, initialised for ``pool`` in this process (re-initialised if another pool was)."""
    global _connected
    key = _key(pool)
    with _lock:
        head = None
        if pool.address is None and pool.server_dir is not None and _connected != key:
            head = server_ray(pool.server_dir, pool.workers, pool.server_pid)
            # before Ray is imported (it reads its authentication mode once): this process
            # drives the server's Ray only; and no crash handler of Ray's own, which writes
            # lines that are not the service's log when the server stops its workers
            os.environ.update(head.environment())
            os.environ.setdefault("RAY_DISABLE_FAILURE_SIGNAL_HANDLER", "1")
        import ray  # imported on first use: a process that never maps does not load it

        if ray.is_initialized() and _connected == key:
            return ray
        if ray.is_initialized():
            _shutdown(ray)
        os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")
        with _own_sigterm():
            if pool.address is not None or head is not None:
                address = pool.address if head is None else head.address
                ray.init(address=address, log_to_driver=False, logging_level=logging.WARNING)
            else:
                temp = tempfile.mkdtemp(prefix="pk-ray-", dir="/tmp")  # short: Ray's socket paths must fit 107 bytes
                _local_dirs.append(temp)
                try:
                    ray.init(address="local", num_cpus=pool.workers, include_dashboard=False, log_to_driver=False,
                             object_store_memory=LOCAL_OBJECT_STORE_BYTES, _temp_dir=temp)
                except Exception:
                    _shutdown(ray)  # what a failed start left: its processes and its folder
                    raise
        _connected = key
        return ray


@contextlib.contextmanager
def _own_sigterm() -> Iterator[None]:
    """Keep this process's SIGTERM handler across ``ray.init``, which installs its own on the
    main thread (``sys.exit``): a Python handler runs only when the main thread runs Python,
    so a worker idle in a blocking call, with Ray's threads beside it, could ignore SIGTERM
    (a pool of two Ray drivers hung in ``Pool.terminate``). The default handler ends the
    process whichever thread the signal reaches."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.getsignal(signal.SIGTERM)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous if previous is not None else signal.SIG_DFL)


def _key(pool: RayPool) -> tuple[str | None, int]:
    return (pool.address or pool.server_dir, pool.workers)


def connected(pool: RayPool) -> bool:
    """Whether this process is connected to ``pool``'s Ray already."""
    with _lock:
        return _connected == _key(pool)


def release_ray() -> None:
    """Leave Ray in this process (a local Ray is stopped); the next map starts it again."""
    global _connected
    with _lock:
        if _connected is not None:
            import ray

            _shutdown(ray)
            _connected = None


def _shutdown(ray: Any) -> None:
    ray.shutdown()
    while _local_dirs:
        shutil.rmtree(_local_dirs.pop(), ignore_errors=True)


def _call(fn: Callable[[Any, float | None], Any], item: Any, ends_at: float | None) -> Any:
    return fn(item, ends_at)


def parallel_map(fn: Callable[[Any, float | None], Any], items: Sequence[Any], pool: RayPool,
                 budget: Budget) -> ParallelRun:
    """``fn(item, ends_at)`` for every item (module docstring), within ``budget``."""
    t0 = time.perf_counter()
    remaining = budget.remaining_or_none()
    ends_at = None if remaining is None else time.time() + remaining
    late = remaining is not None and remaining < CONNECT_S and not connected(pool)
    if not pool.on_ray or late or importlib.util.find_spec("ray") is None:  # an image built without Ray
        results = []
        steps = budget.steps()
        for item in items:
            results.append(fn(item, ends_at) if steps.another() else None)
        return ParallelRun(tuple(results), "in_process", 1, 1, time.perf_counter() - t0)
    ray = _ray(pool)
    task = ray.remote(num_cpus=1, max_retries=0)(_call)
    # a task stops a little before the map does, so that what it reached gets back in time
    task_ends = None if ends_at is None else ends_at - TASK_RETURN_MARGIN * max(ends_at - time.time(), 0.0)
    at_once = pool.parallel if pool.parallel > 0 else len(items)
    out: list[Any] = [None] * len(items)
    index: dict[Any, int] = {}
    pending: list[Any] = []
    broken = False
    started = 0
    try:
        while (started < len(items) or pending) and (ends_at is None or time.time() < ends_at):
            while started < len(items) and len(pending) < at_once:  # at most `parallel` tasks at once
                ref = task.remote(fn, items[started], task_ends)
                index[ref] = started
                pending.append(ref)
                started += 1
            pending = _collect(ray, pending, index, out, ends_at)
    except ray.exceptions.RaySystemError:
        broken = True
        raise
    finally:
        if broken:
            release_ray()  # the local Ray (or the connection) is gone: the next map starts again
        else:
            for ref in pending:  # past the deadline, or after a task's error: nothing is left running
                ray.cancel(ref, force=True)
    nodes = [n for n in ray.nodes() if n.get("Alive")]
    cpus = int(ray.cluster_resources().get("CPU", 0))
    had = min(cpus, pool.parallel) if pool.parallel > 0 else cpus
    return ParallelRun(tuple(out), "ray", had, len(nodes), time.perf_counter() - t0)


def _collect(ray: Any, pending: list[Any], index: dict[Any, int], out: list[Any], ends_at: float | None) -> list[Any]:
    """Wait for one of ``pending`` (until ``ends_at``) and put its result in ``out``; the
    tasks still pending. A task's error is raised here, for the caller."""
    wait_s = None if ends_at is None else max(ends_at - time.time(), 0.0)
    done, rest = ray.wait(pending, num_returns=1, timeout=wait_s)
    for ref in done:
        out[index[ref]] = ray.get(ref)
    return list(rest)
