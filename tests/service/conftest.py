"""Fixtures of the service tests: an in-process client of the ASGI app, and no wall-clock
deadline for the computations it runs (issue 35: on a busy machine a test's default time
limit of 10 s ran out, and it failed for no fault)."""

from __future__ import annotations

import warnings

import pytest
from starlette.exceptions import StarletteDeprecationWarning

with warnings.catch_warnings():
    # starlette's TestClient warns that it prefers httpx2; httpx is what is pinned.
    warnings.simplefilter("ignore", StarletteDeprecationWarning)
    from fastapi.testclient import TestClient

from service.app import app
from service.runtime.deadline import Deadline
from tests.budgets import NoLimitBudgets, deadline_budgets


@pytest.fixture(scope="module")
def client():
    with TestClient(app, raise_server_exceptions=False) as c:
        yield c


@pytest.fixture(autouse=True)
def no_wall_clock_deadlines(request, monkeypatch):
    """A request's solver budget in the test process never runs out (a deadline no machine
    can reach), unless the test is marked ``wall_clock``: it is about the time limit itself,
    with a limit that has passed already or a budget that ticks per reading
    (tests/budgets.py). Live servers (tests/service/live.py) keep their real deadlines."""
    if request.node.get_closest_marker("wall_clock") is None:
        monkeypatch.setattr(Deadline, "budget", deadline_budgets(NoLimitBudgets))

