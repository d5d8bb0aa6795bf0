"""The jobs under storage faults, in-process (issue 35, points 3 and 4): a full jobs file is
a 507 naming it and readiness says so, everything resumes when space returns and nothing
accepted is lost (a queued job runs, an end that could not be written is written later); a
jobs file that is not a database turns the jobs off at start, said by readiness and a 503
from every /v1/jobs route, while the rest of the service serves."""

from __future__ import annotations

import sqlite3

from service.app import create_app
from service.runtime import jobstore
from service.settings import Settings
from service.store import StorageFault
from tests.service.api.jobs.test_jobs_api import ENCOUNTER, TestClient, finished

CAP = 64 * 4096
PADDED = {"operation": "push_disk_encounter", "body": {**ENCOUNTER, "padding": "x" * 16384}}
"""An invalid job body: refused 422 before it is stored. The filler is stored directly."""


def client_of(path, **settings):
    return TestClient(create_app(Settings(solver_workers=0, store_path="", jobs_path=str(path), **settings)),
                      raise_server_exceptions=False)


def _fill(path) -> int:
    """Jobs of another client straight into the file until it reaches the cap (large ones,
    then small ones into what room is left); how many."""
    store = jobstore.JobStore(path, max_bytes=CAP)
    n = 0
    for size in (16384, 1024, 16):
        try:
            for _ in range(2000):
                store.submit("push_disk_encounter", {"padding": "y" * size}, "filler")
                n += 1
            raise AssertionError("the file never filled")
        except StorageFault:
            pass
    return n


def test_a_full_jobs_file_is_a_507_and_everything_resumes_when_space_returns(tmp_path):
    path = tmp_path / "jobs.sqlite3"
    with client_of(path, jobs_max_bytes=CAP, job_workers=0) as c:  # nothing runs: the jobs stay queued
        first = c.post("/v1/jobs", json={"operation": "push_disk_encounter", "body": ENCOUNTER})
        assert first.status_code == 202
        _fill(path)
        full = c.post("/v1/jobs", json={"operation": "push_disk_encounter", "body": ENCOUNTER})
        assert full.status_code == 507, full.text
        assert full.json()["detail"][0]["type"] == "storage_full" and str(path) in full.json()["detail"][0]["msg"]
        ready = c.get("/readyz").json()
        assert ready["status"] == "degraded" and ready["storage"][0]["state"] == "full"
        assert c.post("/v1/cor/locus", json={"disk_radius": 1, "contact_point": [0.2, 0.3],
                                             "edge_angle": 1.5708}).status_code == 200
        with sqlite3.connect(path) as operator:  # space returns
            operator.execute("DELETE FROM jobs WHERE owner = 'filler'")
        assert c.post("/v1/jobs", json={"operation": "push_disk_encounter", "body": ENCOUNTER}).status_code == 202
        assert c.get("/readyz").json()["status"] == "ready"
    with client_of(path, jobs_max_bytes=CAP) as c:  # a server that runs jobs: the accepted ones run
        done = finished(c, first.json()["id"])
        assert done["state"] == "succeeded" and done["result"]["offset"] > 0


def test_an_end_that_cannot_be_written_is_written_when_the_file_works_again(tmp_path, monkeypatch):
    finish = jobstore.JobStore.finish
    failures = []

    def full_twice(self, *args):
        if len(failures) < 2:
            failures.append(args[1])
            raise StorageFault(self.path, "full", "database or disk is full")
        return finish(self, *args)

    monkeypatch.setattr(jobstore.JobStore, "finish", full_twice)
    with client_of(tmp_path / "jobs.sqlite3") as c:
        job = c.post("/v1/jobs", json={"operation": "push_disk_encounter", "body": ENCOUNTER}).json()["id"]
        done = finished(c, job)
    assert failures == [job, job]
    assert done["state"] == "succeeded" and done["result"]["offset"] > 0


def test_a_jobs_file_that_is_not_a_database_turns_the_jobs_off_and_says_so(tmp_path, caplog):
    path = tmp_path / "jobs.sqlite3"
    path.write_bytes(bytes(range(256)) * 64)
    with client_of(path) as c:
        ready = c.get("/readyz")
        assert ready.status_code == 200 and ready.json()["status"] == "degraded"
        assert ready.json()["storage"][0]["state"] == "off" and "broken" in ready.json()["storage"][0]["reason"]
        for r in (c.post("/v1/jobs", json={"operation": "push_disk_encounter", "body": ENCOUNTER}),
                  c.get("/v1/jobs"), c.get("/v1/jobs/abc"), c.delete("/v1/jobs/abc")):
            assert r.status_code == 503 and r.json()["detail"][0]["type"] == "jobs_unavailable", r.text
            assert str(path) in r.json()["detail"][0]["msg"]
        assert c.post("/v1/push/disk-encounter", json=ENCOUNTER).status_code == 200
        assert c.get("/metrics").status_code == 200
    said = [r for r in caplog.records if "jobs are off" in r.getMessage()]
    assert len(said) == 1 and not [r for r in caplog.records if r.exc_info]


def test_an_ended_job_is_forgotten_by_delete_and_a_client_past_its_cap_is_refused(tmp_path):
    with client_of(tmp_path / "jobs.sqlite3", job_max_client_bytes=300) as c:
        job = c.post("/v1/jobs", json={"operation": "push_disk_encounter", "body": ENCOUNTER}).json()["id"]
        finished(c, job)
        kept = c.get(f"/v1/jobs/{job}").json()
        assert kept["result"]["offset"] > 0  # the answer, spliced in as stored
        refused = c.post("/v1/jobs", json={"operation": "push_disk_encounter", "body": ENCOUNTER})
        assert refused.status_code == 507 and refused.json()["detail"][0]["type"] == "storage_quota"
        assert "300 bytes" in refused.json()["detail"][0]["msg"]
        gone = c.delete(f"/v1/jobs/{job}")
        assert gone.status_code == 200 and gone.json()["state"] == "succeeded"
        assert c.get(f"/v1/jobs/{job}").status_code == 404
        assert c.post("/v1/jobs", json={"operation": "push_disk_encounter", "body": ENCOUNTER}).status_code == 202
