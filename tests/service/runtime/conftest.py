"""An app whose expensive jobs run in solver worker processes, with test routes that run
the jobs of tests/service/runtime/jobs_for_tests.py."""

from __future__ import annotations

import time
import warnings

import pytest
from fastapi import FastAPI, Request
from fastapi.responses import Response

from service.app import create_app
from service.runtime.jobs import runner
from service.settings import Settings
from tests.service.runtime import jobs_for_tests

with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient

GRACE_S = 0.25


def pool_app(**settings) -> FastAPI:
    """The service with solver workers (and the test routes ``POST /test/{name}``)."""
    app = create_app(Settings(**{"solver_workers": 2, "deadline_grace_s": GRACE_S, **settings}))

    @app.post("/test/{name}")
    async def run_test_job(name: str, request: Request, seconds: float = 0.0, limit: float | None = None,
                           cheap: bool = False) -> Response:
        job = getattr(jobs_for_tests, f"{name}_job")
        args = (seconds,) if name == "sleep" else ()
        run = runner(request)
        start = run.cheap_job if cheap else run.expensive_job
        return await start(request, job, *args, time_limit_s=limit)

    return app


@pytest.fixture(scope="module")
def pooled():
    """A client of the service with two solver workers."""
    with TestClient(pool_app(), raise_server_exceptions=False) as c:
        yield c


def hold_a_slot(c, ex, seconds: float, limit: float = 10.0):
    """Start a sleep job of ``seconds`` on executor ``ex`` and return its future once it
    holds a slot (the expensive gate shows it in use)."""
    held = ex.submit(c.post, "/test/sleep", params={"seconds": seconds, "limit": limit})
    deadline = time.monotonic() + 5.0
    while c.get("/readyz").json()["gates"][1]["in_use"] < 1 and time.monotonic() < deadline:
        time.sleep(0.01)
    return held
