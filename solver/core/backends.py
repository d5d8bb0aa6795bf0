"""Time spent in each numerical back end by the job running on this thread: a ledger the
service reads after a job to publish solver time by back end (its ``/metrics``). Pure
bookkeeping, no I/O; a thread without an open ledger records nothing.

    open_ledger()
    ... with in_backend("clarabel"): solution = solver.solve() ...
    spent = close_ledger()   # {"clarabel": 0.41, ...} seconds

The back ends named: ``clarabel`` (conic solves, directly or through cvxpy), ``casadi``
(IPOPT through CasADi), ``ortools`` (min cost flow, CP-SAT). Everything else a job does
(numpy, Python) is the remainder of its time.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager

BACKENDS = ("clarabel", "casadi", "ortools")
"""The back ends timed."""

_local = threading.local()


def open_ledger() -> None:
    """Start recording this thread's back-end time (from zero)."""
    _local.seconds = {}


def close_ledger() -> dict[str, float]:
    """Stop recording; the seconds spent per back end since :func:`open_ledger`."""
    spent: dict[str, float] = getattr(_local, "seconds", None) or {}
    _local.seconds = None
    return spent


@contextmanager
def in_backend(name: str) -> Iterator[None]:
    """Count the time of the block against back end ``name`` (one of :data:`BACKENDS`)."""
    t0 = time.perf_counter()
    try:
        yield
    finally:
        seconds = getattr(_local, "seconds", None)
        if seconds is not None:
            seconds[name] = seconds.get(name, 0.0) + (time.perf_counter() - t0)
