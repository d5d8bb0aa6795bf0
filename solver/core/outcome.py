"""What every solver result says about itself.

Each public result of the solver layer implements :class:`Outcome`: a ``status`` word
(its meaning is the result's own, e.g. "optimal", "inside", "found"), whether the answer
is ``complete`` (False when a time limit, a cap or an undecided step left part of the
asked work undone), the seconds it took (``solve_time_s``) and a one-line ``message``
saying what was done. ``tests/solver/core/test_outcome.py`` checks every result type of
the public entry points (:mod:`solver`) against it.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable


@runtime_checkable
class Outcome(Protocol):
    """Status, completeness, time and message of a solver result."""

    @property
    def status(self) -> str: ...

    @property
    def complete(self) -> bool: ...

    @property
    def solve_time_s(self) -> float: ...

    @property
    def message(self) -> str: ...


OUTCOME_FIELDS = ("status", "complete", "solve_time_s", "message")
"""The attribute names of :class:`Outcome` (for checks of dataclasses by name)."""
