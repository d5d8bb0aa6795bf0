"""Independent solver tasks in parallel on Ray (issue 27): a local Ray started by the
process that first needs it, or an existing Ray cluster (``address``); or, without Ray (no
workers asked for, or an image built without Ray), one task after the other in this
process. Ray schedules the tasks; nothing here does.

A task is ``fn(item, ends_at)``: a top-level function (Ray pickles it by reference) of one
item and the wall-clock time (``time.time()``, seconds) at which the whole map's deadline
falls, or None without a limit. The wall clock, not this process's monotonic one, because a
task may run on another machine. Tasks not finished by the deadline are cancelled and their
results are None: a map never reports as done a task that did not finish.
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import tempfile
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from solver.core.budget import Budget

LOCAL_OBJECT_STORE_BYTES = 256 * 1024 * 1024
"""Shared memory of a local Ray's object store (Ray's default takes 30 % of the RAM from
/dev/shm, which a container rarely has): results larger than this spill to disk."""

TASK_RETURN_MARGIN = 0.05
"""The share of the time left that a task leaves for its answer to come back: it stops that
much before the map's deadline."""

_lock = threading.Lock()
_connected: tuple[str | None, int] | None = None
_local_dirs: list[str] = []  # a local Ray's session files, removed when it stops


@dataclass(frozen=True)
class RayPool:
    """Where a map runs: ``workers`` = 0, in this process one task after the other; else on
    Ray, at ``address`` (an existing cluster, e.g. "10.0.0.5:6379") or, with ``address``
    None, on a local Ray of ``workers`` CPUs started on first use and kept for the
    process's life."""

    workers: int = 0
    address: str | None = None

    @property
    def on_ray(self) -> bool:
        return self.workers > 0 or self.address is not None


@dataclass(frozen=True)
class ParallelRun:
    """The results of a map, in the items' order (None: not finished by the deadline), where
    it ran ("ray" or "in_process"), the CPUs and nodes it had, and the time it took."""

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
    import ray  # imported on first use: a process that never maps does not load it

    global _connected
    key = (pool.address, pool.workers)
    with _lock:
        if ray.is_initialized() and _connected == key:
            return ray
        if ray.is_initialized():
            _shutdown(ray)
        os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")
        if pool.address is not None:
            ray.init(address=pool.address, log_to_driver=False)
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
    if not pool.on_ray or importlib.util.find_spec("ray") is None:  # an image built without Ray
        results = []
        for item in items:
            results.append(None if budget.expired() else fn(item, ends_at))
        return ParallelRun(tuple(results), "in_process", 1, 1, time.perf_counter() - t0)
    ray = _ray(pool)
    task = ray.remote(num_cpus=1, max_retries=0)(_call)
    # a task stops a little before the map does, so that what it reached gets back in time
    task_ends = None if ends_at is None else ends_at - TASK_RETURN_MARGIN * max(ends_at - time.time(), 0.0)
    refs = [task.remote(fn, item, task_ends) for item in items]
    index = {ref: i for i, ref in enumerate(refs)}
    out: list[Any] = [None] * len(refs)
    pending = list(refs)
    broken = False
    try:
        while pending:
            wait_s = None if ends_at is None else max(ends_at - time.time(), 0.0)
            done, pending = ray.wait(pending, num_returns=1, timeout=wait_s)
            if not done:
                break
            out[index[done[0]]] = ray.get(done[0])  # a task's error is raised here, for the caller
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
    return ParallelRun(tuple(out), "ray", int(ray.cluster_resources().get("CPU", 0)), len(nodes),
                       time.perf_counter() - t0)
