"""The optimisation layer's errors.

* :class:`SolverError`: a back end failed; the base of the others (and a
  :class:`models.core.errors.ModelError`).
* :class:`NotConverged`: a back end stopped without an answer it could vouch for (an
  iteration cap, a numerical failure, an unusable status).
* :class:`Infeasible`: the problem has no solution (e.g. no pressure distribution gives
  the asked motion), proven by the back end.
* :class:`TimeLimitReached`: the budget ran out; carries where it stopped and what was
  completed (``partial``), so the caller can answer with it.
* :class:`BackendNotFound`: an unknown method or back end was asked for (an input error
  on the named field).
"""

from __future__ import annotations

from collections.abc import Sequence

from models.core.errors import InvalidInput, ModelError


class SolverError(ModelError):
    """An optimisation back end failed or returned an unusable status."""


class NotConverged(SolverError):
    """A back end ended without an answer it could vouch for."""


class Infeasible(SolverError):
    """The problem has no solution (proven by the back end)."""


class TimeLimitReached(SolverError):
    """The time budget ran out before ``where``; ``partial`` is what was completed (a
    result object of the computation, or None when nothing was)."""

    def __init__(self, where: str, limit_s: float | None, elapsed_s: float, partial: object | None = None) -> None:
        limit = "no limit" if limit_s is None else f"time limit {limit_s:g} s"
        super().__init__(f"{limit} reached after {elapsed_s:.3g} s, before {where}")
        self.where = where
        self.limit_s = limit_s
        self.elapsed_s = elapsed_s
        self.partial = partial


class BackendNotFound(InvalidInput, SolverError):
    """No back end called ``name`` for the field ``field``; ``available`` lists them.

    InvalidInput comes first in its method resolution order, so that a handler chosen by
    the exception's MRO (Starlette's) treats it as the input error on ``field``."""

    def __init__(self, field: str, name: object, available: Sequence[str]) -> None:
        InvalidInput.__init__(self, field, f"unknown {field} {name!r}: use one of {', '.join(map(repr, available))}")
        self.available = tuple(available)
