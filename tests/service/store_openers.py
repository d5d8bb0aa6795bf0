"""A child process of tests/service/test_store.py, kept in a module of its own so that a
spawned child imports only the store, not the test module and the solver stack."""

from __future__ import annotations

from service.store import SqliteStore


def open_and_put(paths: list[str], barrier, faults) -> None:
    """For each path: wait for the other children, open the store there, write one row, and
    report a fault the store recorded (``faults``: a multiprocessing queue)."""
    for path in paths:
        barrier.wait()
        s = SqliteStore(path)
        s.put("ns", "k", {"i": 1})
        if s.health.fault is not None:
            faults.put(f"{s.health.fault.kind}: {s.health.fault.reason}")
