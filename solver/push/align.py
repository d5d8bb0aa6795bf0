"""Fence alignment (book 3.4, 4.3): how far must a fence push a polygonal part until an
edge lies flush? One problem in, one result out.

:func:`align` finds the chain of stages of the alignment
(:func:`models.push.fence_geometry.fence_alignment`: the book's fence frame, each stage a
turn about one hull vertex until the next hull edge is flush), then per stage

* the closed forms: (3.41) and the r_min push for mu_c = 0
  (:func:`models.push.fence_geometry.frictionless_push_bounds`), the composite of 4.3 with
  its pieces and transitions for mu_c > 0 (:func:`models.push.gross_motion.fence_push_bound`);
* the exact bounds over the exact COR sketch of the circumscribing disk
  (:func:`models.push.gross_bounds.fence_bounds_exact`): the longest and shortest push and
  how far the fence slips past the contact vertex, with quadrature error estimates (for
  mu_c = 0 the pushes are the closed forms, which are exact, and only the slip is
  integrated, over the frictionless locus);

and sums them over the stages. Before any work it refuses a problem whose exact bounds the
cost model predicts to exceed the budget (:func:`solver.push.bounds.refuse_over_budget`);
the budget is checked before every stage and every sketch, and running out raises
:class:`solver.core.errors.TimeLimitReached` whose ``partial`` holds the stages done.
Lengths are in the footprint's unit; angles in radians.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

from models.core.footprint import Footprint
from models.push import fence_geometry as fg
from models.push import gross_bounds as gb
from models.push import gross_motion as gm
from models.push.quasistatic import QuasiStaticAssessment, ShapeMoments
from solver.core.budget import UNLIMITED, Budget
from solver.push.bounds import (
    SKETCH_COST,
    Bound,
    BoundPiece,
    GrossMethod,
    QuasiStaticQuery,
    SketchCost,
    refuse_over_budget,
)
from solver.sketch.sweep import sticking_spans

PIECE_EQUATIONS = {
    "frictionless": "(3.41)",
    "sticking": "(4.8)",
    "slipping_down": "(4.6) corrected, tip of {COR}_(alpha+nu)",
    "slipping_up": "(4.6) corrected, tip of {COR}_(alpha-nu)",
}
"""The closed form of each regime of the composite bound of 4.3."""

LONGEST_EQUATION_FRICTIONLESS = "(3.41)"
LONGEST_EQUATION_FRICTION = "4.3 composite: (4.8) sticking + (4.6) corrected slipping"
SHORTEST_EQUATION_FRICTIONLESS = "r_min push ((3.31); not in the book)"


@dataclass(frozen=True)
class AlignProblem(GrossMethod):
    """A fence with direction ``fence_angle`` advancing along ``push_direction`` meets
    ``footprint`` turned by ``orientation`` about its CM (radians, world), with fence-part
    friction ``mu_c``. ``method``: one of :data:`solver.push.bounds.GROSS_METHODS`; ``n_nodes`` /
    ``n_points``: Gauss nodes and locus points of the exact bounds; ``cost``: their cost
    model; ``quasi_static``: optionally, whether the fence's speed is quasi-static (6.8)."""

    footprint: Footprint
    orientation: float
    fence_angle: float
    push_direction: float
    mu_c: float = 0.0
    method: str = "both"
    n_nodes: int = 8
    n_points: int = 256
    quasi_static: QuasiStaticQuery | None = None
    cost: SketchCost = SKETCH_COST

    def __post_init__(self) -> None:
        self.check_method()


@dataclass(frozen=True)
class Slip:
    """How far the fence face slips past the part's contact vertex while it turns (the
    book has no closed form): ``most_positive`` / ``most_negative`` along ``direction``
    (the world unit vector of the fence face's alpha_hat), their quadrature error
    estimates, and the exact bounds' time."""

    most_positive: float
    most_negative: float
    quadrature_error_positive: float
    quadrature_error_negative: float
    direction: tuple[float, float]
    exact_time_s: float


@dataclass(frozen=True)
class AlignStage:
    """One stage: its geometry (:class:`models.push.fence_geometry.FenceStage`), the
    longest and shortest push and the slip (None unless the exact bounds were asked for)."""

    stage: fg.FenceStage
    longest: Bound
    shortest: Bound
    slip: Slip | None


@dataclass(frozen=True)
class AlignResult:
    """The alignment (:class:`models.push.fence_geometry.FenceAlignment`), its stages and
    their totals (``longest``, ``shortest``, ``slip``: sums over the stages, None where a
    stage lacks the value), the quasi-static verdict (None unless asked for), the cost
    model's prediction and the time taken."""

    problem: AlignProblem
    alignment: fg.FenceAlignment
    stages: tuple[AlignStage, ...]
    longest: Bound
    shortest: Bound
    slip: Slip | None
    quasi_static: QuasiStaticAssessment | None
    predicted_time_s: float
    solve_time_s: float

    @property
    def status(self) -> str:
        return "aligned" if self.stages else "no_turn"

    @property
    def complete(self) -> bool:
        return True

    @property
    def message(self) -> str:
        al = self.alignment
        if not self.stages:
            return "an edge is already flush: the part does not turn (zero push)"
        bits = [f"{label} {value:.6g}" for label, value in
                (("closed form", self.longest.closed_form), ("exact", self.longest.exact)) if value is not None]
        return (f"the part turns {al.total_rotation:.6g} rad in {len(self.stages)} stage(s)"
                + (f"; longest push: {', '.join(bits)}" if bits else ""))


def slip_direction(alignment: fg.FenceAlignment, push_direction: float) -> tuple[float, float]:
    """alpha_hat of the fence frame in the world: (cos alpha, sin alpha) in the frame (push
    along +x), reflected back (y -> -y) when the problem was mirrored, turned by the push
    direction."""
    y = -math.sin(alignment.alpha) if alignment.mirrored else math.sin(alignment.alpha)
    cp, sp = math.cos(push_direction), math.sin(push_direction)
    x0 = math.cos(alignment.alpha)
    return (cp * x0 - sp * y, sp * x0 + cp * y)


def _stage(problem: AlignProblem, al: fg.FenceAlignment, st: fg.FenceStage, number: int,
           direction: tuple[float, float], checkpoint) -> AlignStage:
    """The closed forms and exact bounds of one stage (module docstring)."""
    a, c, alpha, bi, bf, mu = al.disk_radius, st.contact_distance, al.alpha, st.beta_initial, st.beta_final, problem.mu_c
    frictionless = fg.frictionless_push_bounds(a, c, alpha, bi, bf) if mu == 0.0 else None
    long_cf = short_cf = pieces = transitions = None
    if problem.closed:
        if frictionless is not None:
            long_cf, short_cf = frictionless
            pieces = (BoundPiece(bi, bf, "frictionless", long_cf, PIECE_EQUATIONS["frictionless"]),)
            transitions = ()
        else:
            bound = gm.fence_push_bound(a, c, alpha, bi, bf, mu)
            long_cf = bound.total
            pieces = tuple(BoundPiece(p.beta_start, p.beta_end, p.regime, p.push, PIECE_EQUATIONS[p.regime])
                           for p in bound.pieces)
            transitions = tuple(float(t) for t in bound.transitions)
    long_ex = short_ex = long_err = short_err = long_t = short_t = None
    long_src = short_src = slip = None
    if problem.exact:
        if st.rotation == 0.0:
            long_ex = short_ex = long_err = short_err = 0.0
            slip = Slip(0.0, 0.0, 0.0, 0.0, direction, 0.0)
        else:
            checkpoint(f"the exact bounds of stage {number}")
            # mu_c = 0: the push bounds are the closed forms (3.41) and r_min; the slip needs
            # the frictionless locus (cheap). mu_c > 0: one exact sketch per node serves all four.
            which = gb.FENCE_BOUNDS[2:] if frictionless is not None else gb.FENCE_BOUNDS
            bounds = gb.fence_bounds_exact(a, c, alpha, bi, bf, mu, n_nodes=problem.n_nodes, n_points=problem.n_points,
                                           which=which, checkpoint=checkpoint, spans=sticking_spans)
            if frictionless is not None:
                long_ex, short_ex = frictionless
                long_err = short_err = 0.0
            else:
                lb, sb = bounds["push_max"], bounds["push_min"]
                long_ex, long_err, long_t = lb.value, lb.quadrature_error, lb.solve_time_s
                short_ex, short_err, short_t = sb.value, sb.quadrature_error, sb.solve_time_s
                long_src, short_src = tuple(sorted(set(lb.sources))), tuple(sorted(set(sb.sources)))
            hi, lo = bounds["slip_max"], bounds["slip_min"]
            slip = Slip(hi.value, lo.value, hi.quadrature_error, lo.quadrature_error, direction, lo.solve_time_s)
    long_eq = LONGEST_EQUATION_FRICTIONLESS if mu == 0.0 else LONGEST_EQUATION_FRICTION
    short_eq = SHORTEST_EQUATION_FRICTIONLESS if mu == 0.0 else None
    longest = Bound(long_ex, long_err, long_cf, long_eq if problem.closed else None, pieces, transitions,
                    long_src, long_t)
    shortest = Bound(short_ex, short_err, short_cf, short_eq if problem.closed else None, None, None,
                     short_src, short_t)
    return AlignStage(st, longest, shortest, slip)


def _total(values: list[float | None], computed: bool) -> float | None:
    """Sum of a value over the stages; None when some stage lacks it (or, with no stages,
    when the method did not compute it: then nothing turns and it is 0)."""
    if not values:
        return 0.0 if computed else None
    if any(v is None for v in values):
        return None
    return float(sum(values))


def _total_bound(stages: tuple[AlignStage, ...], which: str, computed_exact: bool, computed_closed: bool) -> Bound:
    bounds = [getattr(s, which) for s in stages]
    return Bound(
        exact=_total([b.exact for b in bounds], computed_exact),
        quadrature_error=_total([b.quadrature_error for b in bounds], computed_exact),
        closed_form=_total([b.closed_form for b in bounds], computed_closed),
        equation=bounds[0].equation if bounds else None,
    )


def _total_slip(stages: tuple[AlignStage, ...], direction: tuple[float, float] | None) -> Slip | None:
    if direction is None or any(s.slip is None for s in stages):
        return None
    slips = [s.slip for s in stages]
    return Slip(
        most_positive=float(sum(s.most_positive for s in slips)),
        most_negative=float(sum(s.most_negative for s in slips)),
        quadrature_error_positive=float(sum(s.quadrature_error_positive for s in slips)),
        quadrature_error_negative=float(sum(s.quadrature_error_negative for s in slips)),
        direction=direction,
        exact_time_s=sum(s.exact_time_s or 0.0 for s in slips),
    )


def align(problem: AlignProblem, budget: Budget = UNLIMITED) -> AlignResult:
    """The fence alignment of ``problem`` within ``budget`` (module docstring).

    Raises ``InvalidInput`` ("time_limit_s") before any work when the exact bounds are
    predicted to exceed the budget's limit, and :class:`TimeLimitReached` (``partial``:
    the tuple of :class:`AlignStage` done) when the budget runs out on the way."""
    t0 = time.perf_counter()
    al = fg.fence_alignment(problem.footprint, problem.orientation, problem.fence_angle, problem.push_direction)
    fg.require_friction_frame(al, problem.mu_c)
    n_exact = sum(1 for s in al.stages if s.rotation > 0.0)
    # one set of exact sketches per turning stage serves all four bounds (push and slip)
    n_bounds = n_exact if (problem.exact and problem.mu_c > 0.0) else 0
    predicted = problem.cost.bounds_s(n_bounds, problem.n_nodes, problem.n_points)
    refuse_over_budget(predicted, budget)
    direction = slip_direction(al, problem.push_direction)
    done: list[AlignStage] = []

    def checkpoint(where: str) -> None:
        budget.checkpoint(where, tuple(done))

    for k, st in enumerate(al.stages):
        done.append(_stage(problem, al, st, k + 1, direction, checkpoint))
    stages = tuple(done)
    longest = _total_bound(stages, "longest", problem.exact, problem.closed)
    shortest = _total_bound(stages, "shortest", problem.exact, problem.closed and problem.mu_c == 0.0)
    qs = None if problem.quasi_static is None else problem.quasi_static.assess(ShapeMoments.polygon(problem.footprint))
    return AlignResult(
        problem=problem, alignment=al, stages=stages, longest=longest, shortest=shortest,
        slip=_total_slip(stages, direction if problem.exact else None), quasi_static=qs,
        predicted_time_s=predicted, solve_time_s=time.perf_counter() - t0,
    )


def below_line_of_motion(alignment: fg.FenceAlignment) -> bool:
    """Whether some stage's contact starts at or below the line of motion through the CM
    (beta_initial <= 0, module docstring of :mod:`models.push.fence_geometry`)."""
    return any(s.beta_initial <= 0.0 for s in alignment.stages)
