"""The solver worker processes: Pebble's process pool (a maintained library that does what
the standard library's pools cannot: cancel a *running* task by ending its worker, end a
task at a timeout, and replace a worker that died, e.g. in a segfault of a native solver).

Workers are forked from a forkserver that has imported the solver stack once (so a
replacement starts in tens of milliseconds, not the seconds the imports take), and each
worker is one thread: its compiled CasADi solvers, cvxpy problems and matplotlib state are
its own, never shared between threads. The numerical libraries are told to use one thread
each (the parallelism is the number of workers).
"""

from __future__ import annotations

import multiprocessing
import os
import threading
from collections.abc import Callable, Iterable, Sequence
from typing import Any

from pebble import ProcessFuture, ProcessPool

ONE_THREAD_ENV = {
    "OMP_NUM_THREADS": "1",
    "OPENBLAS_NUM_THREADS": "1",
    "MKL_NUM_THREADS": "1",
    "VECLIB_MAXIMUM_THREADS": "1",
    "NUMEXPR_NUM_THREADS": "1",
}
"""The environment of the workers: one thread per numerical library."""

RUNS_JOBS = "service.runtime.jobs"
"""What a worker runs: imported by the forkserver besides the caller's modules."""


class SolverPool:
    """``workers`` solver processes, started on first use. ``max_tasks`` > 0 replaces a
    worker after that many tasks (a bound on slow leaks in native code); 0 keeps it.
    ``preload``: the modules whose functions the workers will run (the routes, which import
    the solver stack), imported once by the forkserver."""

    def __init__(self, workers: int, max_tasks: int = 0, preload: Sequence[str] = ()) -> None:
        if workers < 1:
            raise ValueError(f"a solver pool needs at least one worker, got {workers}")
        self.workers = workers
        self.max_tasks = max_tasks
        self.preload = (*preload, RUNS_JOBS)
        self._lock = threading.Lock()
        self._pool: ProcessPool | None = None

    def _started(self) -> ProcessPool:
        with self._lock:
            if self._pool is None or not self._pool.active:
                for key, value in ONE_THREAD_ENV.items():
                    os.environ.setdefault(key, value)
                ctx = multiprocessing.get_context("forkserver")
                ctx.set_forkserver_preload(list(self.preload))
                self._pool = ProcessPool(max_workers=self.workers, max_tasks=self.max_tasks, context=ctx)
            return self._pool

    def schedule(self, function: Callable[..., Any], args: Iterable[Any], timeout: float | None) -> ProcessFuture:
        """Run ``function(*args)`` in a worker; past ``timeout`` seconds of running, the
        worker is ended and the future fails with ``TimeoutError``. Cancelling the future
        of a running task ends its worker too."""
        return self._started().schedule(function, args=tuple(args), timeout=timeout)

    def warm_up(self, timeout_s: float) -> None:
        """Start the workers now and wait until one has answered (the forkserver's imports
        take seconds: a request must not pay them out of its deadline)."""
        self.schedule(os.getpid, (), timeout=None).result(timeout=timeout_s)

    def close(self, timeout_s: float | None = None) -> None:
        """Stop the workers (running tasks are ended)."""
        with self._lock:
            pool, self._pool = self._pool, None
        if pool is not None:
            pool.stop()
            pool.join(timeout=timeout_s)
