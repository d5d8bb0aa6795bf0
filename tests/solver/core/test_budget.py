"""The one time budget (solver/core/budget.py): deadlines, what remains, child budgets and
the checkpoint, on a ticking clock (one second per reading), so nothing here depends on the
machine's speed."""

from __future__ import annotations

import math

import pytest

from solver.core.budget import UNLIMITED, Budget
from solver.core.errors import SolverError, TimeLimitReached
from tests.budgets import TickingClock, checks_budget


def test_unlimited_budget_never_expires_and_never_reads_a_clock():
    clock = TickingClock()
    for b in (Budget.of(None, clock=clock), Budget.of(math.inf, clock=clock), UNLIMITED):
        assert not b.limited and not b.expired()
        assert b.remaining() == math.inf and b.remaining_or_none() is None
        b.checkpoint("anything")  # does not raise
    assert clock.readings == 2  # only the two creations read it


def test_a_budget_of_n_checks_expires_at_the_next():
    b = checks_budget(3)
    assert [b.expired() for _ in range(4)] == [False, False, False, True]


def test_remaining_and_elapsed_on_the_clock():
    clock = TickingClock()
    b = Budget.of(10.0, clock=clock)  # made at t = 1, deadline 11
    assert b.limit_s == 10.0 and b.deadline == 11.0
    assert b.remaining() == 9.0  # read at t = 2
    assert b.elapsed() == 2.0  # t = 3
    assert b.remaining_or_none() == 7.0  # t = 4


@pytest.mark.parametrize("limit", [0.0, -1.0, math.nan])
def test_zero_negative_or_nan_limits_are_expired(limit):
    b = Budget.of(limit, clock=TickingClock())
    assert b.limited and b.expired() and b.remaining() == 0.0


def test_child_budgets_never_outlast_their_parent():
    clock = TickingClock()
    parent = Budget.of(100.0, clock=clock)  # t = 1, deadline 101
    small = parent.child(limit_s=5.0)  # t = 2: deadline 7
    assert small.deadline == 7.0
    big = parent.child(limit_s=1000.0)  # capped at the parent's deadline
    assert big.deadline == parent.deadline
    half = parent.child(fraction=0.5)  # t = 4: 97 left -> 4 + 48.5
    assert half.deadline == pytest.approx(52.5)
    free = UNLIMITED.child(limit_s=3.0)
    assert free.limited and free.limit_s == pytest.approx(3.0, abs=1e-3)
    assert UNLIMITED.child(fraction=0.5).deadline is None


def test_checkpoint_raises_with_where_and_the_partial_result():
    b = checks_budget(1)
    b.checkpoint("step one")  # first reading: in time
    with pytest.raises(TimeLimitReached) as err:
        b.checkpoint("step two", partial={"done": 1})
    exc = err.value
    assert isinstance(exc, SolverError)
    assert exc.where == "step two" and exc.partial == {"done": 1} and exc.limit_s == 1.0
    assert "before step two" in str(exc) and "time limit 1 s" in str(exc)


def _run_steps(budget: Budget, readings_per_step: int, use_steps: bool) -> tuple[int, float]:
    """A loop of like steps (each reads the clock ``readings_per_step`` times, as a ray's
    queries do); how many ran and by how much the last ended past the deadline."""
    steps, done = budget.steps(), 0
    while (steps.another() if use_steps else not budget.expired()):
        for _ in range(readings_per_step):
            budget.clock()
        done += 1
    return done, budget.clock() - budget.deadline


def test_a_loop_of_steps_starts_none_it_cannot_finish():
    """Steps (solver/core/budget.py): a step is not started when the time left is less than
    the longest step so far, so the loop ends by its deadline; checking only `expired`
    overruns it by most of a step (issue 35: a certified ray started just before the
    deadline got its worker killed under load)."""
    done, past = _run_steps(checks_budget(100), 10, use_steps=True)
    assert past <= 0.0 and done >= 6  # ends by its deadline: 7 steps of 13 readings in 100
    naive_done, naive_past = _run_steps(checks_budget(100), 10, use_steps=False)
    assert naive_past >= 10 and naive_done > done  # the last step began just before the deadline


def test_steps_never_start_after_the_deadline_and_count_what_ran():
    budget = checks_budget(3)
    steps = budget.steps()
    assert steps.another()
    while steps.another():
        pass
    assert budget.expired() or not budget.affords(steps.longest)
    assert steps.done >= 1
