"""Budgets for tests of time-limited computations that do not depend on the machine's
speed: a clock that advances one second per reading, so a budget of n seconds on it
expires after exactly n readings (every ``expired``/``remaining`` check is one), on any
machine and under any load."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from solver.core.budget import Budget


class TickingClock:
    """A clock that advances ``step`` seconds per reading (1, 2, 3, ... by default)."""

    def __init__(self, step: float = 1.0) -> None:
        self.step = step
        self.now = 0.0
        self.readings = 0

    def __call__(self) -> float:
        self.readings += 1
        self.now += self.step
        return self.now


def checks_budget(n_checks: int) -> Budget:
    """A budget that allows ``n_checks`` clock readings after its creation and has expired
    at the next one (a work limit, not a time limit)."""
    return Budget.of(float(n_checks), clock=TickingClock())


class ChecksBudgets:
    """Stands in for :class:`solver.core.budget.Budget` where a route makes its own budget
    (``monkeypatch.setattr(routes, "Budget", ChecksBudgets(n))``): ``of(limit_s)`` gives a
    budget of the request's limit on a clock that allows ``n_checks`` readings after the
    budget's creation and has expired at the next (each reading spends
    limit_s / (n_checks + 1/2))."""

    def __init__(self, n_checks: int) -> None:
        self.n_checks = n_checks

    def of(self, limit_s: float | None) -> Budget:
        if limit_s is None or not limit_s > 0.0:
            return Budget.of(limit_s)
        return Budget.of(limit_s, clock=TickingClock(step=limit_s / (self.n_checks + 0.5)))


class NoLimitBudgets:
    """Stands in for :class:`solver.core.budget.Budget` where a route makes its own budget
    and the test is about the answer, not the time limit: every budget is unlimited, so
    the answer does not depend on how busy the machine is."""

    @staticmethod
    def of(limit_s: float | None) -> Budget:
        return Budget.of(None)



def deadline_budgets(budgets: ChecksBudgets | type[NoLimitBudgets]) -> Callable[[Any], Budget]:
    """A stand-in for :meth:`service.runtime.deadline.Deadline.budget`, where a route's job
    makes its solver budget (``monkeypatch.setattr(Deadline, "budget",
    deadline_budgets(ChecksBudgets(n)))``): the budget ``budgets`` makes of the request's
    time limit. Jobs run in the test process (tests/conftest.py), so the patch reaches them."""

    def budget(deadline: Any) -> Budget:
        return budgets.of(deadline.limit_s)

    return budget
