"""Jobs in solver workers (service/runtime/jobs.py, pool.py): they run in another process,
their errors are answered as in the web process, a worker that crashes or overruns is
replaced and the service goes on, a deadline is kept (the time limit covers everything:
a runaway is stopped and answered 504 at the deadline plus the grace), and a full gate
refuses at once with Retry-After."""

from __future__ import annotations

import os
import time
from concurrent.futures import ThreadPoolExecutor

import pytest

from tests.service.runtime.conftest import GRACE_S, TestClient, hold_a_slot, pool_app
from tests.timing import stretched

pytestmark = pytest.mark.slow

SLACK_S = 0.5
"""What an answer at the deadline may take beyond the grace (event loop, test client)."""


def test_a_job_runs_in_a_worker_and_a_cheap_one_in_the_web_process(pooled):
    r = pooled.post("/test/pid", params={"limit": 2.0})
    assert r.status_code == 200
    got = r.json()
    assert got["pid"] != os.getpid() and got["limit_s"] == 2.0 and 0.0 < got["solver_s"] < 2.0
    assert pooled.post("/test/pid", params={"cheap": True}).json()["pid"] == os.getpid()


def test_errors_in_a_worker_are_answered_as_in_the_web_process(pooled):
    r = pooled.post("/test/invalid")
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["body", "disk_radius"]
    r = pooled.post("/test/limit", params={"limit": 3.0})
    assert r.status_code == 504 and r.json()["reached"] == "the second stage"
    r = pooled.post("/test/bug")
    assert r.status_code == 500 and r.json()["detail"][0]["type"] == "internal_error"
    assert pooled.post("/test/pid").status_code == 200


def test_a_worker_that_crashes_is_replaced_and_the_service_goes_on(pooled):
    r = pooled.post("/test/crash")
    assert r.status_code == 500 and "ended abnormally" in r.json()["detail"][0]["msg"]
    pids = {pooled.post("/test/pid").json()["pid"] for _ in range(6)}
    assert pids and all(p != os.getpid() for p in pids)


def test_a_runaway_is_stopped_at_the_deadline_and_its_worker_replaced(pooled):
    t0 = time.monotonic()
    r = pooled.post("/test/sleep", params={"seconds": 30.0, "limit": 1.0})
    took = time.monotonic() - t0
    assert r.status_code == 504 and r.json()["detail"][0]["type"] == "time_limit"
    assert 1.0 <= took < 1.0 + stretched(GRACE_S + SLACK_S)
    # both workers are free again: two sleeps of 0.3 s run side by side
    with ThreadPoolExecutor(2) as ex:
        t0 = time.monotonic()
        answers = list(ex.map(lambda _: pooled.post("/test/sleep", params={"seconds": 0.3, "limit": 5.0}), range(2)))
    assert [a.status_code for a in answers] == [200, 200]
    assert len({a.json()["pid"] for a in answers}) == 2


def test_a_well_behaved_job_stops_at_its_budget_with_what_it_did(pooled):
    r = pooled.post("/test/budgeted", params={"limit": 0.5})
    assert r.status_code == 504
    body = r.json()
    assert body["reached"].startswith("step ") and body["time_limit_s"] == 0.5
    assert body["elapsed_s"] < 0.5  # the solver stopped the reserve before the deadline


def test_a_worker_killed_from_outside_is_a_503_with_retry_after_not_a_bug(pooled):
    r = pooled.post("/test/killed")
    assert r.status_code == 503 and r.headers["retry-after"] == "1"
    detail = r.json()["detail"][0]
    assert detail["type"] == "worker_lost" and "SIGKILL" in detail["msg"] and "bug" not in detail["msg"]
    assert pooled.post("/test/pid").status_code == 200


def test_a_request_that_cannot_start_in_time_is_refused_at_once_with_the_predicted_wait():
    """One slot: while a 1.5 s job runs, a request whose limit leaves no time after the
    predicted wait is refused at once (Retry-After from the prediction, not the setting);
    one with time to spare waits and is served."""
    with TestClient(pool_app(solver_workers=1, solver_queue=4, solver_queue_wait_s=30.0),
                    raise_server_exceptions=False) as c:
        with ThreadPoolExecutor(2) as ex:
            first = hold_a_slot(c, ex, 1.5)
            t0 = time.monotonic()
            r = c.post("/test/pid", params={"limit": 2.0})  # the sleep's cost is unknown: half its limit, 5 s
            assert time.monotonic() - t0 < 1.0
            assert r.status_code == 503 and int(r.headers["retry-after"]) >= 4
            assert "too late for the 1 s it needs" in r.json()["detail"][0]["msg"]
            waited = c.post("/test/pid", params={"limit": 20.0})
            assert waited.status_code == 200 and first.result().status_code == 200
        gate = c.get("/readyz").json()["gates"][1]
        assert gate["refused"] == 1 and gate["in_use"] == 0
