"""The jobs file under faults (service/runtime/jobstore.py; issue 35, points 3 and 4): a full
file (its disk, or its own cap: the same SQLite error) is a StorageFault naming it, never a
masked "cannot rollback"; the fault is logged once per change; an answer over the cap per
answer fails its job saying so; a client past its cap is refused at submission with the cap
named; a file that is not a database, or a place where none can be made, is found at start."""

from __future__ import annotations

import logging
import sqlite3

import pytest

from service.runtime.jobstore import JobStore, OverQuota
from service.store import StorageFault

PAGE_CAP = 64 * 4096  # a jobs file of 64 pages


def _fill(store: JobStore, owner: str = "filler") -> list[str]:
    """Submit 16 KiB jobs until the file is full; their ids."""
    ids = []
    with pytest.raises(StorageFault) as full:
        for _ in range(1000):
            ids.append(store.submit("cor_solve", {"padding": "x" * 16384}, owner))
    assert full.value.kind == "full" and "full" in full.value.reason
    return ids


def _warnings(caplog) -> list[str]:
    return [r.getMessage() for r in caplog.records if r.levelno >= logging.WARNING and "jobs file" in r.getMessage()]


def test_a_full_file_is_said_once_and_every_change_recovers(tmp_path, caplog):
    """Submissions are a transaction (the client's cap is checked in it): on a full file
    SQLite rolls it back itself, and the fault is the full file, not the "cannot rollback -
    no transaction is active" that a second rollback raised."""
    store = JobStore(tmp_path / "jobs.sqlite3", max_bytes=PAGE_CAP, max_client_bytes=1 << 40)
    ids = _fill(store)
    for _ in range(3):  # every later attempt fails the same way, and is not logged again
        with pytest.raises(StorageFault) as again:
            store.submit("cor_solve", {"padding": "x" * 16384}, "filler")
        assert again.value.kind == "full" and "rollback" not in again.value.reason
    assert store.health.state()["state"] == "full"
    assert len([m for m in _warnings(caplog) if "cannot be used" in m]) == 1
    with sqlite3.connect(tmp_path / "jobs.sqlite3") as operator:  # space returns: an operator deletes some jobs
        operator.execute(f"DELETE FROM jobs WHERE id IN ({','.join('?' * 4)})", ids[:4])
    store.submit("cor_solve", {"padding": "x" * 16384}, "filler")
    assert store.health.state()["state"] == "ok"
    assert any("usable again" in m for m in _warnings(caplog))


def test_an_answer_over_the_cap_fails_its_job_saying_so(tmp_path):
    store = JobStore(tmp_path / "jobs.sqlite3", max_answer_bytes=1024)
    job = store.submit("cor_solve", {"a": 1}, "me")
    store.claim("r")
    store.finish("r", job, "succeeded", 60.0, 200, "application/json", b"[" + b"0," * 2000 + b"0]", "")
    row = store.get(job)
    assert row["state"] == "failed" and row["result"] is None and row["status"] is None
    assert "PESHKIN_JOB_MAX_ANSWER_BYTES" in row["message"] and "4003 bytes" in row["message"]


def test_a_client_past_its_cap_is_refused_at_submission_with_the_cap_named(tmp_path):
    store = JobStore(tmp_path / "jobs.sqlite3", max_client_bytes=40_000)
    first = store.submit("cor_solve", {"padding": "x" * 15_000}, "alice")
    store.submit("cor_solve", {"padding": "x" * 15_000}, "alice")
    with pytest.raises(OverQuota) as quota:
        store.submit("cor_solve", {"padding": "x" * 15_000}, "alice")
    assert "40000 bytes" in str(quota.value) and "PESHKIN_JOB_MAX_CLIENT_BYTES" in str(quota.value)
    store.submit("cor_solve", {"padding": "x" * 15_000}, "bob")  # per client
    store.cancel(first, 60.0)
    assert store.remove(first)  # an ended job forgotten: its bytes no longer count
    store.submit("cor_solve", {"padding": "x" * 15_000}, "alice")


def test_a_file_that_is_not_a_database_or_cannot_be_made_is_found_at_start(tmp_path):
    garbage = tmp_path / "jobs.sqlite3"
    garbage.write_bytes(bytes(range(256)) * 64)
    with pytest.raises(StorageFault) as broken:
        JobStore(garbage).check()
    assert broken.value.kind == "broken"
    with pytest.raises(StorageFault) as nowhere:
        JobStore("/proc/peshkin-nowhere/jobs.sqlite3").check()  # a directory nobody can make
    assert nowhere.value.kind in ("read_only", "unavailable")
    JobStore(tmp_path / "fresh.sqlite3").check()
