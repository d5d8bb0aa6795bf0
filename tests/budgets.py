"""Budgets for tests of time-limited computations that do not depend on the machine's
speed: a clock that advances one second per reading, so a budget of n seconds on it
expires after exactly n readings (every ``expired``/``remaining`` check is one), on any
machine and under any load."""

from __future__ import annotations

from solver.core.budget import Budget


class TickingClock:
    """A clock that reads 1, 2, 3, ... (seconds)."""

    def __init__(self) -> None:
        self.now = 0.0
        self.readings = 0

    def __call__(self) -> float:
        self.readings += 1
        self.now += 1.0
        return self.now


def checks_budget(n_checks: int) -> Budget:
    """A budget that allows ``n_checks`` clock readings after its creation and has expired
    at the next one (a work limit, not a time limit)."""
    return Budget.of(float(n_checks), clock=TickingClock())
