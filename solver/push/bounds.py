"""What the gross-motion workflows share (book 4.2-4.4): the record of a bound, the cost
model of exact bounds with the refusal before work, and the quasi-static check (6.8).

An exact bound (:mod:`models.push.gross_bounds`) builds one COR sketch per Gauss node at
n_nodes and at max(2, n_nodes // 2) nodes (the error estimate). :class:`SketchCost`
predicts its time; :func:`refuse_over_budget` refuses, before any work, a request whose
prediction exceeds its budget (an input error at ``time_limit_s``); the workflows then
stop at their budget's checkpoint between sketches (:class:`solver.core.errors.TimeLimitReached`).
"""

from __future__ import annotations

from dataclasses import dataclass

from models.core.errors import InvalidInput
from models.push.quasistatic import QuasiStaticAssessment, ShapeMoments, assess
from solver.core.budget import Budget
from solver.core.errors import BackendNotFound

GROSS_METHODS = ("both", "closed_form", "exact")
"""``closed_form``: the book's closed forms only; ``exact``: the exact bounds only; ``both``."""


class GrossMethod:
    """What a gross-motion problem's ``method`` (one of :data:`GROSS_METHODS`) asks for."""

    method: str

    def check_method(self) -> None:
        if self.method not in GROSS_METHODS:
            raise BackendNotFound("method", self.method, GROSS_METHODS)

    @property
    def closed(self) -> bool:
        """The book's closed forms are asked for."""
        return self.method != "exact"

    @property
    def exact(self) -> bool:
        """The exact bounds are asked for."""
        return self.method != "closed_form"


@dataclass(frozen=True)
class SketchCost:
    """Predicted seconds of one exact COR sketch: ``fixed_s + per_point_s * n_points``.

    Measured on one core (2026-11-27, after issue 26 solved the sticking sweep's loci
    together): 0.031 s at 8 points, 0.046 s at 256, 0.071 s at 1024 and 0.16 s at 4096
    (sketch points and sticking sweep alike); whole requests 0.036 s a sketch at 256 points
    and 0.054 s at 1024 (docs/api.md). The default is about 1.5 times those numbers. A
    slower or busier machine may take longer: the workflows also stop at their budget's
    checkpoints."""

    fixed_s: float = 0.05
    per_point_s: float = 4e-5

    def sketch_s(self, n_points: int) -> float:
        """Seconds of one sketch of ``n_points`` boundary points."""
        return self.fixed_s + self.per_point_s * n_points

    def bounds_s(self, n_bounds: int, n_nodes: int, n_points: int) -> float:
        """Seconds of ``n_bounds`` exact bounds: each builds n_nodes + max(2, n_nodes // 2)
        sketches."""
        return n_bounds * (n_nodes + max(2, n_nodes // 2)) * self.sketch_s(n_points)


SKETCH_COST = SketchCost()
"""The cost model of fence alignment (one core). Measured against it (2026-11-27, quiet
2-core machine, docs/api.md): the square of the API guide at 8 nodes, 256 points, 0.43 s
against 0.72 s predicted; at 16 nodes, 1024 points, 1.30 s against 2.18 s; an L shape at
16 nodes 1.01 s against 1.44 s."""

ENCOUNTER_SKETCH_COST = SketchCost(fixed_s=0.06, per_point_s=6e-5)
"""The cost model of the disk encounter, whose sketches cost more (measured 0.050 s each at
256 points and 0.062 s at 512 in whole requests; this is about 1.5 times that): beta 45
degrees, 16 nodes, 256 points took 1.19 s against 1.81 s predicted."""


def refuse_over_budget(predicted_s: float, budget: Budget) -> None:
    """Refuse, before any work, exact bounds predicted to take longer than the budget's
    time limit: ``InvalidInput("time_limit_s", ...)``."""
    if budget.limit_s is not None and predicted_s > budget.limit_s:
        raise InvalidInput(
            "time_limit_s",
            f"the exact bounds are predicted to take {predicted_s:.3g} s, more than time_limit_s = "
            f"{budget.limit_s:g} s: lower n_nodes or n_points, use method closed_form, or raise time_limit_s",
        )


@dataclass(frozen=True)
class BoundPiece:
    """One stretch of a composite closed form: beta from ``beta_start`` to ``beta_end``
    needs at most ``push`` (regime ``regime``, by ``equation``)."""

    beta_start: float
    beta_end: float
    regime: str
    push: float
    equation: str


@dataclass(frozen=True)
class Bound:
    """One bound of a gross motion (a push length, an encounter length, a rotation).

    ``exact``: integrated over the exact COR sketch (:mod:`models.push.gross_bounds`),
    with its ``quadrature_error`` estimate; ``closed_form``: the book's, by ``equation``.
    None where the method did not compute it. ``pieces`` / ``transitions``: the pieces of
    a composite closed form (4.3); ``exact_sources``: the loci the exact extremes came
    from; ``exact_time_s``: the exact bound's time."""

    exact: float | None
    quadrature_error: float | None
    closed_form: float | None
    equation: str | None
    pieces: tuple[BoundPiece, ...] | None = None
    transitions: tuple[float, ...] | None = None
    exact_sources: tuple[str, ...] | None = None
    exact_time_s: float | None = None

    @property
    def difference(self) -> float | None:
        """exact - closed_form, None when either is missing."""
        return None if self.exact is None or self.closed_form is None else self.exact - self.closed_form


@dataclass(frozen=True)
class QuasiStaticQuery:
    """Is a push at ``speed`` (length/s) on a table with friction ``mu_s`` and gravity ``g``
    (length/s^2) quasi-static (6.8)? Checked with the book's permissible errors."""

    speed: float
    mu_s: float
    g: float

    def assess(self, part: ShapeMoments) -> QuasiStaticAssessment:
        """The verdict of 6.8 for ``part`` (:func:`models.push.quasistatic.assess`)."""
        return assess(self.speed, self.mu_s, self.g, part)
