"""The request's deadline (service/runtime/deadline.py): it starts at arrival and the
solver's budget ends a reserve before it."""

from __future__ import annotations

import time

import pytest

from service.runtime.deadline import DEFAULT_RESERVE, Deadline, ReservePolicy

pytestmark = pytest.mark.wall_clock  # the deadline itself: its real clock (tests/service/conftest.py)


def test_the_reserve_is_a_bounded_fraction_of_the_limit():
    p = ReservePolicy(fraction=0.1, min_s=0.05, max_s=2.0)
    assert p.reserve(0.1) == 0.05 and p.reserve(1.0) == pytest.approx(0.1) and p.reserve(100.0) == 2.0


def test_the_solver_budget_ends_the_reserve_before_the_deadline_and_keeps_the_request_limit():
    now = time.monotonic()
    d = Deadline.starting(now - 0.4, 1.0)  # arrived 0.4 s ago with a 1 s limit
    assert d.at == pytest.approx(now + 0.6) and d.reserve_s == DEFAULT_RESERVE.reserve(1.0)
    b = d.budget()
    assert b.limit_s == 1.0 and b.deadline == pytest.approx(d.at - d.reserve_s)
    assert b.elapsed() >= 0.4  # queueing counts
    assert 0.0 < d.solver_s() <= 0.6 - d.reserve_s


def test_a_passed_deadline_leaves_nothing():
    d = Deadline.starting(time.monotonic() - 5.0, 1.0)
    assert d.remaining() == 0.0 and d.solver_s() == 0.0 and d.budget().expired()


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), -1.0])
def test_a_meaningless_limit_is_an_expired_deadline(bad):
    assert Deadline.starting(time.monotonic(), bad).limit_s == 0.0
