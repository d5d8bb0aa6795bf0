"""A point pushing a disk aside (book 4.4): how long is the encounter, how far does the
disk turn? One problem in, one result out.

:func:`disk_encounter` takes the collision parameter beta_initial (given, or from the
offset of the pusher's line from grazing, (4.24)), then the closed forms: the greatest
length (4.16), the frictionless length, the greatest rotation (4.18, re-derived as
pi/2 - beta_initial) and where sketch i begins (4.17); and the exact greatest and least
length and rotation over the exact COR sketch at every node
(:func:`models.push.gross_bounds.encounter_bounds_exact`). Refusal before work and the
budget's checkpoints as in :mod:`solver.push.align`; running out raises
:class:`solver.core.errors.TimeLimitReached` whose ``partial`` is the result with the
closed forms only (``complete`` False).
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass

from models.core.errors import InvalidInput
from models.push import fence_geometry as fg
from models.push import gross_bounds as gb
from models.push import gross_motion as gm
from models.push.quasistatic import QuasiStaticAssessment, ShapeMoments
from solver.core.budget import UNLIMITED, Budget
from solver.push.bounds import (
    ENCOUNTER_SKETCH_COST,
    Bound,
    GrossMethod,
    QuasiStaticQuery,
    SketchCost,
    refuse_over_budget,
)
from solver.sketch.sweep import sticking_spans

LENGTH_MAX_EQUATION = "(4.16)"
ROTATION_MAX_EQUATION = "(4.18), re-derived: pi/2 - beta_initial"


@dataclass(frozen=True)
class DiskEncounterProblem(GrossMethod):
    """A disk of radius ``disk_radius`` met by a point pusher at collision parameter
    ``beta_initial`` (rad) or with its line ``offset`` inside the grazing line (exactly one),
    pusher-disk friction ``mu_c`` > 0. ``method``, ``n_nodes``, ``n_points``, ``cost``,
    ``quasi_static`` as in :class:`solver.push.align.AlignProblem`."""

    disk_radius: float
    mu_c: float
    beta_initial: float | None = None
    offset: float | None = None
    method: str = "both"
    n_nodes: int = 16
    n_points: int = 256
    quasi_static: QuasiStaticQuery | None = None
    cost: SketchCost = ENCOUNTER_SKETCH_COST

    def __post_init__(self) -> None:
        if (self.beta_initial is None) == (self.offset is None):
            raise InvalidInput("beta_initial", "give exactly one of beta_initial or offset")
        self.check_method()


@dataclass(frozen=True)
class DiskEncounterResult:
    """The encounter: ``beta_initial`` and ``offset`` (one given, the other derived,
    ``beta_source`` says which), the four bounds (exact and, for the greatest, the book's
    closed forms), the frictionless length, sketch i's onset (4.17) and whether it holds
    from the start, the quasi-static verdict (None unless asked for), the predicted and the
    spent time. ``complete`` False: the exact bounds were cut short (the partial result of a
    :class:`TimeLimitReached`)."""

    problem: DiskEncounterProblem
    beta_initial: float
    offset: float
    beta_source: str
    length_max: Bound
    length_min: Bound
    rotation_max: Bound
    rotation_min: Bound
    length_frictionless: float
    sketch_i_onset: float
    sketch_i_at_start: bool
    quasi_static: QuasiStaticAssessment | None
    predicted_time_s: float
    solve_time_s: float
    complete: bool = True

    @property
    def status(self) -> str:
        return "done" if self.complete else "time_limited"

    @property
    def message(self) -> str:
        greatest = self.length_max.exact if self.length_max.exact is not None else self.length_max.closed_form
        text = f"beta = {self.beta_initial:.6g} rad: the encounter lasts at most {greatest:.6g}"
        return text if self.complete else text + " (closed forms only: the exact bounds were cut short)"


def _bound(bounds: dict[str, gb.SketchBound] | None, key: str, book: float | None, equation: str | None) -> Bound:
    ex = None if bounds is None else bounds[key]
    return Bound(
        exact=None if ex is None else ex.value,
        quadrature_error=None if ex is None else ex.quadrature_error,
        closed_form=book,
        equation=equation if book is not None else None,
    )


def disk_encounter(problem: DiskEncounterProblem, budget: Budget = UNLIMITED) -> DiskEncounterResult:
    """The disk encounter of ``problem`` within ``budget`` (module docstring). Raises
    ``InvalidInput`` ("time_limit_s") before any work when the exact bounds are predicted to
    exceed the budget's limit."""
    t0 = time.perf_counter()
    a, mu = problem.disk_radius, problem.mu_c
    if problem.offset is not None:
        beta = fg.encounter_beta_from_offset(a, problem.offset)
        offset, source = problem.offset, "offset"
    else:
        beta = problem.beta_initial
        offset = 2.0 * a * math.sin(0.25 * math.pi - 0.5 * beta) ** 2  # a (1 - sin beta), no cancellation
        source = "beta_initial"
    predicted = problem.cost.bounds_s(1 if problem.exact else 0, problem.n_nodes, problem.n_points)
    refuse_over_budget(predicted, budget)
    book_length = gm.encounter_length_max(beta, a) if problem.closed else None
    book_rotation = gm.rotation_max(beta) if problem.closed else None
    closed_only = DiskEncounterResult(
        problem=problem, beta_initial=beta, offset=offset, beta_source=source,
        length_max=_bound(None, "length_max", book_length, LENGTH_MAX_EQUATION),
        length_min=_bound(None, "length_min", None, None),
        rotation_max=_bound(None, "rotation_max", book_rotation, ROTATION_MAX_EQUATION),
        rotation_min=_bound(None, "rotation_min", None, None),
        length_frictionless=gm.encounter_length_frictionless(beta, a),
        sketch_i_onset=gm.sketch_i_onset(mu), sketch_i_at_start=bool(gm.sketch_i(beta, mu)),
        quasi_static=None, predicted_time_s=predicted, solve_time_s=0.0, complete=False,
    )
    bounds = None
    if problem.exact:
        def checkpoint(where: str) -> None:
            budget.checkpoint(where, dataclasses.replace(closed_only, solve_time_s=time.perf_counter() - t0))

        bounds = gb.encounter_bounds_exact(a, beta, mu, n_nodes=problem.n_nodes, n_points=problem.n_points,
                                           checkpoint=checkpoint, spans=sticking_spans)
    qs = None if problem.quasi_static is None else problem.quasi_static.assess(ShapeMoments.disk(a))
    return dataclasses.replace(
        closed_only,
        length_max=_bound(bounds, "length_max", book_length, LENGTH_MAX_EQUATION),
        length_min=_bound(bounds, "length_min", None, None),
        rotation_max=_bound(bounds, "rotation_max", book_rotation, ROTATION_MAX_EQUATION),
        rotation_min=_bound(bounds, "rotation_min", None, None),
        quasi_static=qs, solve_time_s=time.perf_counter() - t0, complete=True,
    )
