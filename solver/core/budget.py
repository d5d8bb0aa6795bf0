"""One time budget, passed down: the deadline of a request on the monotonic clock.

A :class:`Budget` is made once, where a time limit enters (a route, a test, a library
call), and handed to every solver below; nothing else in the solver layer reads the clock
to decide when to stop. It knows its deadline, what remains, and makes child budgets
(a part of the remaining time for a sub-step, never more than the parent has).

``checkpoint(where)`` is the one way to stop: it raises
:class:`solver.core.errors.TimeLimitReached` naming the place reached. Pure computations
in :mod:`models` take such a checkpoint as a plain callable, so they never see a clock.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

from solver.core.errors import TimeLimitReached

Clock = Callable[[], float]
"""A monotonic clock in seconds (``time.perf_counter``; tests pass a clock that ticks once
per reading, so that a budget expires after a fixed number of checks on any machine)."""


@dataclass(frozen=True)
class Budget:
    """A deadline on ``clock`` (seconds, None for no limit) and the time limit it was made
    from (``limit_s``, seconds, None for no limit)."""

    started: float
    deadline: float | None
    limit_s: float | None
    clock: Clock = field(default=time.perf_counter, compare=False, repr=False)

    @classmethod
    def of(cls, limit_s: float | None, clock: Clock = time.perf_counter) -> Budget:
        """A budget of ``limit_s`` seconds from now (None or +inf: unlimited). A negative
        or NaN limit is an already expired budget."""
        now = clock()
        if limit_s is None:
            return cls(now, None, None, clock)
        limit = float(limit_s)
        if math.isnan(limit):
            limit = 0.0
        if math.isinf(limit) and limit > 0.0:
            return cls(now, None, None, clock)
        limit = max(limit, 0.0)
        return cls(now, now + limit, limit, clock)

    @classmethod
    def unlimited(cls) -> Budget:
        return cls.of(None)

    @property
    def limited(self) -> bool:
        return self.deadline is not None

    def elapsed(self) -> float:
        """Seconds since the budget was made."""
        return self.clock() - self.started

    def remaining(self) -> float:
        """Seconds left (math.inf without a limit; 0 once expired)."""
        if self.deadline is None:
            return math.inf
        return max(self.deadline - self.clock(), 0.0)

    def remaining_or_none(self) -> float | None:
        """Seconds left, or None without a limit (for back ends that take an optional limit)."""
        return None if self.deadline is None else self.remaining()

    def expired(self) -> bool:
        return self.deadline is not None and self.clock() > self.deadline

    def child(self, limit_s: float | None = None, fraction: float | None = None) -> Budget:
        """A budget for a sub-step: at most ``limit_s`` seconds and at most ``fraction`` of
        what remains, never past this budget's deadline."""
        now = self.clock()
        ends = [] if self.deadline is None else [self.deadline]
        if limit_s is not None:
            ends.append(now + max(float(limit_s), 0.0))
        if fraction is not None and self.deadline is not None:
            ends.append(now + max(float(fraction), 0.0) * max(self.deadline - now, 0.0))
        deadline = min(ends) if ends else None
        return Budget(now, deadline, None if deadline is None else deadline - now, self.clock)

    def affords(self, seconds: float) -> bool:
        """Whether ``seconds`` of work started now would end by the deadline."""
        return self.deadline is None or self.clock() + seconds <= self.deadline

    def steps(self) -> Steps:
        """A timer of like steps of a loop on this budget (:class:`Steps`)."""
        return Steps(self)

    def checkpoint(self, where: str, partial: object | None = None) -> None:
        """Raise :class:`TimeLimitReached` (``where``: what was about to start; ``partial``:
        what was completed) once the deadline has passed."""
        if self.expired():
            raise TimeLimitReached(where, self.limit_s, self.elapsed(), partial)


UNLIMITED = Budget(0.0, None, None)
"""A budget without a deadline (its ``elapsed`` is meaningless)."""


@dataclass
class Steps:
    """The steps of a loop of like work on a budget (rays of a locus, parts of a catalogue):
    :meth:`another` is asked before each step and says whether to start it. A step is not
    started once the budget has expired, nor when the time left is less than the longest
    step so far, which would overrun the deadline by most of a step (the longest step is
    measured as the loop runs, so on a loaded machine the loop stops earlier)."""

    budget: Budget
    longest: float = 0.0
    done: int = 0
    _last: float | None = None

    def another(self) -> bool:
        now = self.budget.clock()
        if self._last is not None:
            self.longest = max(self.longest, now - self._last)
            self.done += 1
        self._last = now
        return not self.budget.expired() and self.budget.affords(self.longest)
