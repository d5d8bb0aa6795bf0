"""Every route's job gives the same answer in a solver worker as in the web process: the
curl examples of docs/api.md sent to the service with workers and to the one without
(tests/conftest.py), compared field by field but for the timings. The spiral examples
are left out here: a cold r* table takes tens of seconds in a fresh worker (their jobs
are the same mechanism; tests/service/runtime/test_jobs.py covers the runtime)."""

from __future__ import annotations

import json

import pytest

from service.app import app as in_process_app
from tests.service.docs_examples import EXAMPLES, split
from tests.service.runtime.conftest import TestClient

pytestmark = pytest.mark.slow

CASES = [(u, b) for u, b in EXAMPLES if not u.startswith(("/v1/spiral/", "/v1/jobs"))]  # a job is no route's job
TIMING_KEYS = ("time", "_ms", "elapsed")


def _without_timings(value):
    if isinstance(value, dict):
        return {k: _without_timings(v) for k, v in value.items() if not any(t in k for t in TIMING_KEYS)}
    if isinstance(value, list):
        return [_without_timings(v) for v in value]
    return value


@pytest.fixture(scope="module")
def in_process():
    with TestClient(in_process_app, raise_server_exceptions=False) as c:
        yield c


@pytest.mark.parametrize("url, body", CASES, ids=[f"{i}:{u}" for i, (u, _) in enumerate(CASES)])
def test_a_worker_answers_as_the_web_process(pooled, in_process, url, body):
    path, params = split(url)
    request = json.loads(body)
    if "time_limit_s" in request or path in ("/v1/push/align", "/v1/push/disk-encounter", "/v1/cor/sketch"):
        request["time_limit_s"] = 30.0
    here = in_process.post(path, json=request, params=params)
    there = pooled.post(path, json=request, params=params)
    assert here.status_code == there.status_code == 200, (here.text[:300], there.text[:300])
    assert here.headers["content-type"] == there.headers["content-type"]
    if here.headers["content-type"].startswith("application/json"):
        assert _without_timings(there.json()) == _without_timings(here.json())
    else:
        assert there.content == here.content
