"""POST /v1/jobs, GET and DELETE /v1/jobs/{id} in-process (the solver in the web process's
threads): a job's body checked at once, its answer the operation's, jobs listed, cancelled
while queued, and with API keys on each key sees only its own jobs. The live behaviour
(solver workers, restarts, cancelling a running job) is in
tests/service/runtime/test_deferred_live.py."""

from __future__ import annotations

import time
import warnings

from starlette.exceptions import StarletteDeprecationWarning

from service.api.jobs.schemas import DEFERRABLE_OPERATIONS
from service.app import create_app
from service.settings import Settings

with warnings.catch_warnings():
    warnings.simplefilter("ignore", StarletteDeprecationWarning)
    from fastapi.testclient import TestClient

ENCOUNTER = {"disk_radius": 1.0, "beta_initial": 0.7853981633974483, "mu_c": 0.5}
KEY_A, KEY_B = "a" * 20, "b" * 20


def client_of(tmp_path, **settings):
    return TestClient(create_app(Settings(solver_workers=0, store_path="", jobs_path=str(tmp_path / "jobs.sqlite3"),
                                          **settings)), raise_server_exceptions=False)


def finished(c, job_id, headers=None):
    for _ in range(400):
        j = c.get(f"/v1/jobs/{job_id}", headers=headers).json()
        if j["state"] not in ("queued", "running"):
            return j
        time.sleep(0.05)
    raise AssertionError(j)


def test_the_operations_a_job_runs_are_the_routes_deferrable_ones(tmp_path):
    with client_of(tmp_path) as c:
        assert set(c.app.state.deferred.operations) == set(DEFERRABLE_OPERATIONS)
        schema = c.app.openapi()["components"]["schemas"]["JobRequest"]["properties"]["operation"]
        assert set(schema["enum"]) == set(DEFERRABLE_OPERATIONS)


def test_a_job_is_checked_at_once_and_answers_its_operation(tmp_path):
    with client_of(tmp_path) as c:
        bad = c.post("/v1/jobs", json={"operation": "push_disk_encounter", "body": {**ENCOUNTER, "mu_c": -1}})
        assert bad.status_code == 422 and bad.json()["detail"][0]["loc"] == ["body", "body", "mu_c"]
        unknown = c.post("/v1/jobs", json={"operation": "mpp_particle", "body": {}})
        assert unknown.status_code == 422 and unknown.json()["detail"][0]["loc"] == ["body", "operation"]
        r = c.post("/v1/jobs", json={"operation": "push_disk_encounter", "body": ENCOUNTER})
        assert r.status_code == 202 and r.json()["state"] in ("queued", "running")
        assert r.headers["location"] == r.json()["location"] == f"/v1/jobs/{r.json()['id']}"
        done = finished(c, r.json()["id"])
        direct = c.post("/v1/push/disk-encounter", json=ENCOUNTER).json()
        assert done["state"] == "succeeded" and done["status_code"] == 200
        assert done["result"]["message"] == direct["message"] and done["result"]["offset"] == direct["offset"]
        listed = c.get("/v1/jobs").json()["jobs"]
        assert [j["id"] for j in listed] == [r.json()["id"]] and listed[0]["result"] is None
        assert c.get(f"/v1/jobs/{'0' * 32}").status_code == 404


def test_a_queued_job_is_cancelled_at_once(tmp_path):
    with client_of(tmp_path) as c:
        run = c.app.state.deferred
        run.concurrency = 0  # nothing is started: the job stays queued
        job_id = c.post("/v1/jobs", json={"operation": "push_disk_encounter", "body": ENCOUNTER}).json()["id"]
        assert c.get(f"/v1/jobs/{job_id}").json()["progress"]["stage"] == "queued"
        gone = c.delete(f"/v1/jobs/{job_id}").json()
        assert gone["state"] == "cancelled" and gone["result"] is None and gone["finished_at"] and gone["expires_at"]
        run.concurrency = 1
        time.sleep(0.5)
        assert c.get(f"/v1/jobs/{job_id}").json()["state"] == "cancelled"  # never run


def test_with_keys_on_a_client_sees_only_its_own_jobs(tmp_path):
    with client_of(tmp_path, api_keys=(KEY_A, KEY_B)) as c:
        a, b = {"X-API-Key": KEY_A}, {"X-API-Key": KEY_B}
        job_id = c.post("/v1/jobs", json={"operation": "push_disk_encounter", "body": ENCOUNTER}, headers=a).json()["id"]
        assert finished(c, job_id, a)["state"] == "succeeded"
        assert c.get(f"/v1/jobs/{job_id}", headers=b).status_code == 404
        assert c.delete(f"/v1/jobs/{job_id}", headers=b).status_code == 404
        assert c.get("/v1/jobs", headers=b).json()["jobs"] == []
        assert [j["id"] for j in c.get("/v1/jobs", headers=a).json()["jobs"]] == [job_id]
        assert c.get(f"/v1/jobs/{job_id}").status_code == 401


def test_a_job_without_a_time_limit_gets_the_jobs_cap_and_a_client_at_most_100_queued(tmp_path):
    """A request's default time limit is a request's: a job that gives none runs up to the
    jobs' cap (PESHKIN_JOB_MAX_TIME_S); one that gives one keeps it."""
    with client_of(tmp_path) as c:
        run = c.app.state.deferred
        spec = run.operations["push_disk_encounter"]
        assert spec.limit(spec.model.model_validate(ENCOUNTER)) is None
        assert spec.limit(spec.model.model_validate({**ENCOUNTER, "time_limit_s": 7})) == 7.0
        run.concurrency = 0
        codes = [c.post("/v1/jobs", json={"operation": "push_disk_encounter", "body": ENCOUNTER}).status_code
                 for _ in range(101)]
        assert codes[:100] == [202] * 100 and codes[100] == 429


def test_a_part_bound_map_job_without_a_time_limit_gets_the_jobs_cap_too(tmp_path):
    """The map's request default for the part's own bound (FEEDER_PART_DEFAULT_TIME_LIMIT_S)
    is a request's too: a job that gives no time_limit_s runs up to the jobs' cap."""
    with client_of(tmp_path) as c:
        spec = c.app.state.deferred.operations["feeder_map"]
        body = {"part": {"vertices": [[0, 0], [3, 0], [3.5, 1.5], [1.5, 2.5], [-0.5, 1.2]],
                         "center_of_mass": [1.4, 1.0]}, "fences": [{"angle": 0.7, "mu_c": 0.25}], "bound": "part"}
        assert spec.limit(spec.model.model_validate(body)) is None
        assert spec.limit(spec.model.model_validate({**body, "time_limit_s": 40})) == 40.0
