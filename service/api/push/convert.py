"""Schema <-> domain conversion of the push endpoints (no mechanics here).

``POST /v1/push/quasistatic``: the request becomes a
:class:`models.gross.quasistatic.PartGeometry` (disk or polygon footprint) and a g (given, or
9.81 m/s^2 in the named length unit); :func:`models.gross.quasistatic.assess` computes; the answer
goes back as plain finite floats. Domain ``InvalidInput`` errors name the request's own
fields (speed, mu_s, g, disk_radius, angular_error, translational_error); the polygon's
are located at ``footprint``.

``POST /v1/push/align``: footprint -> :func:`models.gross.fence_geometry.fence_alignment` (the
book's fence frame, stages) -> per stage the closed forms of :mod:`models.gross.gross_motion`
(:func:`models.gross.fence_geometry.frictionless_push_bounds` for mu_c = 0) and the exact bounds
of :mod:`models.gross.gross_bounds`, summed over the stages. ``POST /v1/push/disk-encounter``:
beta (given, or from the offset by (4.24)) -> (4.16), (4.18), (4.17) and
:func:`models.gross.gross_bounds.encounter_bounds_exact`. Both refuse, before any work, a request
whose exact bounds the cost model of :mod:`service.limits` predicts to exceed
``time_limit_s``, and stop (422 on ``time_limit_s``, saying where they got to) when the
time runs out between two sketches of the exact bounds; both add the verdict
of 6.8 when given a speed.
"""

from __future__ import annotations

import math
import time

import numpy as np

from models.gross import fence_geometry as fg
from models.gross import gross_bounds as gb
from models.gross import gross_motion as gm
from models.gross import quasistatic as qs
from models.footprint import Footprint
from service.convert import _f, _v
from service.convert_mpp import exactly_one, footprint_of, located
from service.errors import FieldError
from service.limits import GROSS_MIN_LENGTH, GROSS_SKETCH_COST_PER_POINT_S, GROSS_SKETCH_COST_S, MAX_TIME_LIMIT_S
from service.schemas_push import (
    BoundOut,
    ErrorSpeedOut,
    FenceBoundOut,
    FenceEdgeOut,
    FenceGeometryOut,
    FencePieceOut,
    FenceSlipOut,
    FenceStageOut,
    PartOut,
    PushAlignRequest,
    PushAlignResponse,
    PushDiskEncounterRequest,
    PushDiskEncounterResponse,
    PushQuasistaticRequest,
    PushQuasistaticResponse,
    QuasiStaticCheckOut,
    QuasiStaticIn,
    QuasiStaticParameterOut,
    SketchIOut,
    ThresholdsOut,
)

REFERENCE = (
    "M. A. Peshkin, Robotic Manipulation Strategies (1990), section 6.8 (characteristic speed "
    "for quasi-static motion), equations (6.1)-(6.7); section 7.4 (non-quasi-static speeds)"
)


def _error_speed(cs: qs.CharacteristicSpeed, name: str) -> ErrorSpeedOut:
    return ErrorSpeedOut(
        characteristic_speed=_f(cs.characteristic_speed, f"{name}.characteristic_speed"),
        ratio=_f(cs.ratio, f"{name}.ratio"),
        permissible_error=_f(cs.permissible_error, f"{name}.permissible_error"),
        error_at_speed=_f(cs.error_at_speed, f"{name}.error_at_speed"),
        within_tolerance=cs.within_tolerance,
        equation=cs.equation,
        section=cs.section,
        formula=cs.formula,
    )



def _quasi_static_parameter(res: qs.QuasiStaticAssessment) -> QuasiStaticParameterOut:
    """(6.7): the characteristic speed of the quasi-static parameter and the ratio to it."""
    return QuasiStaticParameterOut(
        characteristic_speed=_f(res.quasi_static.characteristic_speed, "quasi_static.characteristic_speed"),
        ratio=_f(res.quasi_static.ratio, "quasi_static.ratio"),
        equation=res.quasi_static.equation,
        section=res.quasi_static.section,
        formula=res.quasi_static.formula,
    )

def _message(res: qs.QuasiStaticAssessment, unit: str | None) -> str:
    r = res.quasi_static.ratio
    t = res.thresholds
    coast = (
        f"after release the part slides about {res.translational.error_at_speed:.3g}{' ' + unit if unit else ''} "
        f"or turns about {res.angular.error_at_speed:.3g} rad"
    )
    if res.verdict == "quasi_static":
        return (
            f"quasi-static: speed / v_qs = {r:.3g} <= {t.quasi_static_max_ratio:g} (6.7); {coast}, "
            "so friction dominates inertia and the quasi-static results (chapters 3-4) apply"
        )
    if res.verdict == "transitional":
        return (
            f"transitional: speed / v_qs = {r:.3g} is between {t.quasi_static_max_ratio:g} and "
            f"{t.inertial_min_ratio:g}; {coast}: inertia is no longer negligible, treat the "
            "quasi-static predictions as approximate"
        )
    return (
        f"inertial: speed / v_qs = {r:.3g} >= {t.inertial_min_ratio:g}: inertia is as large as "
        f"friction or larger (6.8.3); {coast}. The quasi-static COR loci do not apply; as the "
        "ratio grows the impact limit (7.4, (7.1); `impact` of /v1/cor/solve) is the better model"
    )


def quasistatic_response(req: PushQuasistaticRequest) -> PushQuasistaticResponse:
    t_start = time.perf_counter()
    shape = exactly_one(req, ("disk_radius", "footprint"))
    g_source = exactly_one(req, ("g", "length_unit"))
    g = req.g if g_source == "g" else qs.gravity(req.length_unit)
    if shape == "disk_radius":
        part = qs.PartGeometry.disk(req.disk_radius)
        cm = None
    else:
        fp = footprint_of(req.footprint, None, ("footprint",))
        part = qs.PartGeometry.polygon(fp)
        cm = _v(fp.center_of_mass, "part.center_of_mass")
    res = qs.assess(
        req.speed, req.mu_s, g, part,
        angular_error=req.angular_error,
        translational_error=req.translational_error,
    )
    spin_factor = part.spin_factor
    return PushQuasistaticResponse(
        verdict=res.verdict,
        message=_message(res, req.length_unit),
        speed=_f(res.speed, "speed"),
        mu_s=_f(res.mu_s, "mu_s"),
        g=_f(res.g, "g"),
        g_source=g_source,
        length_unit=req.length_unit,
        part=PartOut(
            kind=part.kind,
            radius=_f(part.radius, "part.radius"),
            radius_of_gyration=_f(part.radius_of_gyration, "part.radius_of_gyration"),
            mean_distance=_f(part.mean_distance, "part.mean_distance"),
            spin_factor=_f(spin_factor, "part.spin_factor"),
            center_of_mass=cm,
        ),
        angular=_error_speed(res.angular, "angular"),
        translational=_error_speed(res.translational, "translational"),
        quasi_static=_quasi_static_parameter(res),
        thresholds=ThresholdsOut(
            quasi_static_max_ratio=res.thresholds.quasi_static_max_ratio,
            inertial_min_ratio=res.thresholds.inertial_min_ratio,
        ),
        reference=REFERENCE,
        elapsed_ms=(time.perf_counter() - t_start) * 1e3,
    )


# =======================================================================================
# Gross motions: POST /v1/push/align (3.4, 4.3) and POST /v1/push/disk-encounter (4.4)
# =======================================================================================

GROSS_REFERENCE = (
    "M. A. Peshkin, Robotic Manipulation Strategies (1990): 3.4 (aligning a workpiece with a fence, "
    "(3.39)-(3.41)), 4.2 (from instantaneous to gross motion), 4.3 (the fence with contact friction, "
    "(4.2)-(4.8)), 4.4 (a disk pushed aside, (4.9)-(4.24)); 3.1.8 (the circumscribing disk); 6.8 "
    "(quasi-static speeds). Closed forms re-derived in models/gross_motion.py, exact bounds in "
    "models/gross_bounds.py, the fence geometry in models/fence_geometry.py"
)

ALIGN_NOTE = (
    "The bounds are those of the circumscribing disk's COR sketch (book 3.1.8): every pressure "
    "distribution on the disk of radius a about the CM, which includes every distribution on the "
    "footprint, so the part's true push lies between the shortest and the longest exact push (up to "
    "their quadrature error and the sampling of the loci, n_points). The "
    "book's closed forms take the tips of {COR}_(alpha+-nu) and the tip line instead of the exact "
    "slowest CORs: they are approximations, not bounds (the exact longest push exceeds them by up to a "
    "few per cent at large mu_c, models/gross_motion.py). With mu_c = 0 the closed forms are exact (the "
    "tip of {COR}_alpha is the slowest COR and r_min the fastest). A stage ends when its edge is flush; "
    "the part stops when the frictionless line of force through the CM meets that edge."
)

ENCOUNTER_NOTE = (
    "The disk of 4.4 is the book's exact case (no circumscribing approximation). (4.16) takes the "
    "intersection of the tip line with the sticking line as the lower end of the sticking locus: it "
    "neglects the dip of that end below the tip line (too low) and overestimates in sketch i (too "
    "high), 4.4.1.2; the exact bounds take the ends from the exact sketch. (4.18) is re-derived as "
    "pi/2 - beta_initial (the OCR prints a pi/(2 - beta_initial)), an exact upper bound."
)

STAGE_FIELDS = {
    "beta_initial": ("orientation",),
    "beta_final": ("orientation",),
    "cor_of_beta": ("orientation",),
    "alpha": ("fence_angle",),
    "disk_radius": ("footprint",),
    "contact_distance": ("footprint",),
}
"""Where an InvalidInput of a stage's bound (named in the fence frame) is located in the
request."""

QUADRATURE_WARN_REL = 0.01
"""The message warns when an exact bound's quadrature error estimate exceeds this fraction."""

PIECE_EQUATIONS = {
    "frictionless": "(3.41)",
    "sticking": "(4.8)",
    "slipping_down": "(4.6) corrected, tip of {COR}_(alpha+nu)",
    "slipping_up": "(4.6) corrected, tip of {COR}_(alpha-nu)",
}


def gross_cost_s(n_bounds: int, n_nodes: int, n_points: int) -> float:
    """Predicted seconds of ``n_bounds`` exact bounds (service.limits cost model): each
    builds n_nodes + n_nodes // 2 sketches."""
    sketches = n_bounds * (n_nodes + max(2, n_nodes // 2))
    return sketches * (GROSS_SKETCH_COST_S + GROSS_SKETCH_COST_PER_POINT_S * n_points)


def check_budget(predicted: float, limit: float) -> None:
    if predicted > limit:
        raise FieldError(
            ("time_limit_s",),
            f"the exact bounds are predicted to take {predicted:.3g} s, more than time_limit_s = {limit:g} s: "
            f"lower n_nodes or n_points, use method closed_form, or raise time_limit_s (at most "
            f"{MAX_TIME_LIMIT_S:g} s)",
        )


class _Clock:
    """Time spent since the request started, checked before each exact bound."""

    def __init__(self, limit: float) -> None:
        self.start = time.perf_counter()
        self.limit = limit
        self.deadline = self.start + limit

    def elapsed(self) -> float:
        return time.perf_counter() - self.start

    def check(self, what: str) -> None:
        spent = self.elapsed()
        if spent > self.limit:
            raise FieldError(
                ("time_limit_s",),
                f"ran out after {spent:.3g} s (time_limit_s = {self.limit:g} s) before {what}: lower n_nodes "
                "or n_points, or raise time_limit_s",
            )


def quasi_static_check(qin: QuasiStaticIn | None, part: qs.PartGeometry) -> QuasiStaticCheckOut | None:
    """The verdict of 6.8 for the pusher's speed (as POST /v1/push/quasistatic, with the
    book's permissible errors), or None when no speed was given."""
    if qin is None:
        return None
    given = [name for name in ("g", "length_unit") if getattr(qin, name) is not None]
    if len(given) != 1:
        where = "g" if not given else given[1]
        raise FieldError(("quasi_static", where), "give exactly one of g or length_unit")
    g = qin.g if given[0] == "g" else qs.gravity(qin.length_unit)
    with located(prefix=("quasi_static",)):
        res = qs.assess(qin.speed, qin.mu_s, g, part)
    return QuasiStaticCheckOut(
        within_quasi_static=res.verdict == "quasi_static",
        verdict=res.verdict,
        message=_message(res, qin.length_unit),
        speed=_f(res.speed, "quasi_static.speed"),
        mu_s=_f(res.mu_s, "quasi_static.mu_s"),
        g=_f(res.g, "quasi_static.g"),
        g_source=given[0],
        length_unit=qin.length_unit,
        quasi_static=_quasi_static_parameter(res),
        angular=_error_speed(res.angular, "quasi_static.angular"),
        translational=_error_speed(res.translational, "quasi_static.translational"),
    )


def _diff(exact: float | None, closed: float | None) -> float | None:
    return None if exact is None or closed is None else exact - closed


def _opt(value, what: str) -> float | None:
    return None if value is None else _f(value, what)


def _request_index(request_vertices, fp: Footprint):
    """Footprint.create reverses a clockwise outline: map its vertex indices back to the
    request's."""
    n = len(fp.vertices)
    same = np.array_equal(np.asarray(request_vertices, dtype=float), fp.vertices)
    return (lambda i: int(i)) if same else (lambda i: n - 1 - int(i))


def _fence_stage(
    al: fg.FenceAlignment, st: fg.FenceStage, number: int, req: PushAlignRequest, clock: _Clock, index,
    slip_direction: list[float],
) -> FenceStageOut:
    a, c, alpha, bi, bf, mu = al.disk_radius, st.contact_distance, al.alpha, st.beta_initial, st.beta_final, req.mu_c
    closed = req.method != "exact"
    exact = req.method != "closed_form"
    frictionless = fg.frictionless_push_bounds(a, c, alpha, bi, bf) if mu == 0.0 else None
    long_cf = short_cf = pieces = transitions = None
    if closed:
        if frictionless is not None:
            long_cf, short_cf = frictionless
            pieces = [FencePieceOut(beta_start=bi, beta_end=bf, regime="frictionless", push=_f(long_cf, "push"),
                                    equation=PIECE_EQUATIONS["frictionless"])]
            transitions = []
        else:
            bound = gm.fence_push_bound(a, c, alpha, bi, bf, mu)
            long_cf = bound.total
            pieces = [FencePieceOut(beta_start=p.beta_start, beta_end=p.beta_end, regime=p.regime,
                                    push=_f(p.push, "push"), equation=PIECE_EQUATIONS[p.regime]) for p in bound.pieces]
            transitions = [float(t) for t in bound.transitions]
    long_ex = short_ex = long_err = short_err = long_t = short_t = None
    long_src = short_src = slip = None
    if exact:
        if st.rotation == 0.0:
            long_ex = short_ex = long_err = short_err = 0.0
            slip = FenceSlipOut(most_positive=0.0, most_negative=0.0, quadrature_error_positive=0.0,
                                quadrature_error_negative=0.0, direction=slip_direction, exact_time_s=0.0)
        else:
            clock.check(f"the exact bounds of stage {number}")
            # mu_c = 0: the push bounds are the closed forms (3.41) and r_min; the slip needs
            # the frictionless locus (cheap). mu_c > 0: one exact sketch per node serves all four.
            which = gb.FENCE_BOUNDS[2:] if frictionless is not None else gb.FENCE_BOUNDS
            bounds = gb.fence_bounds_exact(a, c, alpha, bi, bf, mu, n_nodes=req.n_nodes, n_points=req.n_points,
                                           which=which, checkpoint=clock.check)
            if frictionless is not None:
                long_ex, short_ex = frictionless
                long_err = short_err = 0.0
            else:
                lb, sb = bounds["push_max"], bounds["push_min"]
                long_ex, long_err, long_t, long_src = lb.value, lb.quadrature_error, lb.solve_time_s, sorted(set(lb.sources))
                short_ex, short_err, short_t, short_src = sb.value, sb.quadrature_error, sb.solve_time_s, sorted(set(sb.sources))
            hi, lo = bounds["slip_max"], bounds["slip_min"]
            slip = FenceSlipOut(
                most_positive=_f(hi.value, "slip.most_positive"), most_negative=_f(lo.value, "slip.most_negative"),
                quadrature_error_positive=_f(hi.quadrature_error, "slip.quadrature_error_positive"),
                quadrature_error_negative=_f(lo.quadrature_error, "slip.quadrature_error_negative"),
                direction=slip_direction, exact_time_s=lo.solve_time_s,
            )
    long_eq = "(3.41)" if mu == 0.0 else "4.3 composite: (4.8) sticking + (4.6) corrected slipping"
    short_eq = "r_min push ((3.31); not in the book)" if mu == 0.0 else None
    return FenceStageOut(
        contact_vertex_index=index(st.contact_index),
        flush_edge_vertex_indices=[index(st.contact_index), index(st.flush_index)],
        flush_edge_is_polygon_edge=st.flush_is_polygon_edge,
        flush_edge_stable=st.flush_edge_stable,
        contact_distance=_f(c, "contact_distance"),
        contact_fence_frame=_v(st.contact_fence_frame, "contact_fence_frame"),
        beta_initial=bi, beta_final=bf, vertex_edge_angle=st.vertex_edge_angle, rotation=st.rotation,
        orientation_initial=st.orientation_initial, orientation_final=st.orientation_final,
        longest_push=FenceBoundOut(
            exact=_opt(long_ex, "longest_push.exact"), quadrature_error=_opt(long_err, "longest_push.quadrature_error"),
            closed_form=_opt(long_cf, "longest_push.closed_form"), equation=long_eq if closed else None,
            difference=_opt(_diff(long_ex, long_cf), "longest_push.difference"),
            pieces=pieces, transitions=transitions, exact_sources=long_src, exact_time_s=long_t,
        ),
        shortest_push=FenceBoundOut(
            exact=_opt(short_ex, "shortest_push.exact"), quadrature_error=_opt(short_err, "shortest_push.quadrature_error"),
            closed_form=_opt(short_cf, "shortest_push.closed_form"), equation=short_eq if closed else None,
            difference=_opt(_diff(short_ex, short_cf), "shortest_push.difference"),
            exact_sources=short_src, exact_time_s=short_t,
        ),
        slip=slip,
    )


def _fence_slip_direction(al: fg.FenceAlignment, push_direction: float) -> list[float]:
    """alpha_hat of the fence frame in the world: (cos alpha, sin alpha) in the frame (push
    along +x), reflected back (y -> -y) when the problem was mirrored, turned by the push
    direction."""
    y = -math.sin(al.alpha) if al.mirrored else math.sin(al.alpha)
    cp, sp = math.cos(push_direction), math.sin(push_direction)
    x0 = math.cos(al.alpha)
    return [cp * x0 - sp * y, sp * x0 + cp * y]


def _slip_total(stages: list[FenceStageOut], direction: list[float] | None) -> FenceSlipOut | None:
    if direction is None or any(s.slip is None for s in stages):
        return None
    slips = [s.slip for s in stages]
    return FenceSlipOut(
        most_positive=_f(sum(s.most_positive for s in slips), "slip.most_positive"),
        most_negative=_f(sum(s.most_negative for s in slips), "slip.most_negative"),
        quadrature_error_positive=_f(sum(s.quadrature_error_positive for s in slips), "slip.quadrature_error_positive"),
        quadrature_error_negative=_f(sum(s.quadrature_error_negative for s in slips), "slip.quadrature_error_negative"),
        direction=direction, exact_time_s=sum(s.exact_time_s or 0.0 for s in slips),
    )


def _total(stages: list[FenceStageOut], which: str, field: str, computed: bool) -> float | None:
    """Sum of a bound over the stages; None when some stage lacks it (or, with no stages,
    when the method did not compute it: then nothing turns and it is 0)."""
    values = [getattr(getattr(s, which), field) for s in stages]
    if not stages:
        return 0.0 if computed else None
    if any(v is None for v in values):
        return None
    return _f(sum(values), f"{which}.{field}")


def _align_message(al: fg.FenceAlignment, stages: list[FenceStageOut], longest: BoundOut, index) -> str:
    if al.already_flush:
        i, j = (index(k) for k in al.final_edge)
        return (f"edge [{i}, {j}] is already flush with the fence and the line of force through the CM meets it: "
                "the part does not turn (zero push)")
    first = stages[0]
    i, j = al.final_edge
    text = (
        f"the fence touches vertex {first.contact_vertex_index} first; the part turns "
        f"{'clockwise' if al.sense == 'cw' else 'counter-clockwise'} by {al.total_rotation:.6g} rad in "
        f"{len(stages)} stage{'s' if len(stages) > 1 else ''} until edge [{index(i)}, {index(j)}] is flush"
    )
    if al.mirrored:
        text += " (reflected onto the book's clockwise case)"
    bits = []
    if longest.closed_form is not None:
        bits.append(f"closed form {longest.closed_form:.6g}")
    if longest.exact is not None:
        bits.append(f"exact {longest.exact:.6g}")
    if bits:
        text += "; longest push: " + ", ".join(bits)
    return text + _quadrature_warning([longest])


def _quadrature_warning(bounds: list[BoundOut]) -> str:
    """A remark when an exact bound's error estimate exceeds QUADRATURE_WARN_REL of it (an
    integrand with a near-singularity, e.g. (4.8) or (4.16) as beta_initial -> 0)."""
    worst = max(
        ((b.quadrature_error / abs(b.exact)) for b in bounds
         if b.exact is not None and b.quadrature_error is not None and b.exact != 0.0),
        default=0.0,
    )
    if worst <= QUADRATURE_WARN_REL:
        return ""
    return (f"; warning: an exact bound's quadrature error estimate is {100 * worst:.3g} % of it "
            "(the integrand has a kink or varies fast, e.g. near beta = 0): raise n_nodes")


def align_response(req: PushAlignRequest) -> PushAlignResponse:
    clock = _Clock(req.time_limit_s)
    fp = footprint_of(req.footprint, req.center_of_mass, ("footprint",))
    if not fp.circumradius >= GROSS_MIN_LENGTH:
        raise FieldError(
            ("footprint",),
            f"is too small: its circumradius {fp.circumradius:.6g} is below {GROSS_MIN_LENGTH:g} "
            "(lengths squared would underflow)",
        )
    index = _request_index(req.footprint, fp)
    with located():
        al = fg.fence_alignment(fp, req.orientation, req.fence_angle, req.push_direction)
        fg.require_friction_frame(al, req.mu_c)
    n_exact = sum(1 for s in al.stages if s.rotation > 0.0)
    # one set of exact sketches per turning stage serves all four bounds (push and slip)
    n_bounds = n_exact if (req.method != "closed_form" and req.mu_c > 0.0) else 0
    predicted = gross_cost_s(n_bounds, req.n_nodes, req.n_points)
    check_budget(predicted, req.time_limit_s)
    with located(rename=STAGE_FIELDS):
        slip_direction = _fence_slip_direction(al, req.push_direction)
        stages = [_fence_stage(al, st, k + 1, req, clock, index, slip_direction) for k, st in enumerate(al.stages)]
    closed = req.method != "exact"
    exact = req.method != "closed_form"
    long_ex, long_cf = _total(stages, "longest_push", "exact", exact), _total(stages, "longest_push", "closed_form", closed)
    short_ex = _total(stages, "shortest_push", "exact", exact)
    short_cf = _total(stages, "shortest_push", "closed_form", closed and req.mu_c == 0.0)
    longest = BoundOut(
        exact=long_ex, quadrature_error=_total(stages, "longest_push", "quadrature_error", exact),
        closed_form=long_cf, equation=stages[0].longest_push.equation if stages else None,
        difference=_opt(_diff(long_ex, long_cf), "longest_push.difference"),
    )
    shortest = BoundOut(
        exact=short_ex, quadrature_error=_total(stages, "shortest_push", "quadrature_error", exact),
        closed_form=short_cf, equation=stages[0].shortest_push.equation if stages else None,
        difference=_opt(_diff(short_ex, short_cf), "shortest_push.difference"),
    )

    def edge(ids):
        return FenceEdgeOut(vertex_indices=[index(k) for k in ids],
                            points=[_v(al.initial_vertices[k], "geometry.points") for k in ids])

    geometry = FenceGeometryOut(
        disk_radius=_f(al.disk_radius, "disk_radius"),
        center_of_mass=_v(al.center_of_mass, "center_of_mass"),
        alpha=al.alpha, alpha_unmirrored=al.alpha_unmirrored,
        fence_normal=_v(al.fence_normal, "fence_normal"),
        sense=al.sense, mirrored=al.mirrored,
        first_contact=edge((al.first_contact_index,)),
        already_flush=al.already_flush,
        initial_flush_edge=None if al.initial_flush_edge is None else [index(k) for k in al.initial_flush_edge],
        final_edge=edge(al.final_edge),
        total_rotation=al.total_rotation, final_orientation=al.final_orientation,
        below_line_of_motion=any(s.beta_initial <= 0.0 for s in al.stages),
    )
    return PushAlignResponse(
        message=_align_message(al, stages, longest, index),
        method=req.method, mu_c=req.mu_c, nu=math.atan(req.mu_c),
        geometry=geometry, stages=stages, longest_push=longest, shortest_push=shortest,
        slip=_slip_total(stages, slip_direction if exact else None),
        quasi_static=quasi_static_check(req.quasi_static, qs.PartGeometry.polygon(fp)),
        note=ALIGN_NOTE, reference=GROSS_REFERENCE,
        n_nodes=req.n_nodes, n_points=req.n_points, time_limit_s=req.time_limit_s,
        predicted_time_s=predicted, elapsed_ms=clock.elapsed() * 1e3,
    )


def disk_encounter_response(req: PushDiskEncounterRequest) -> PushDiskEncounterResponse:
    clock = _Clock(req.time_limit_s)
    source = exactly_one(req, ("beta_initial", "offset"))
    a = req.disk_radius
    if source == "offset":
        with located():
            beta = fg.encounter_beta_from_offset(a, req.offset)
        offset = req.offset
    else:
        beta = req.beta_initial
        offset = 2.0 * a * math.sin(0.25 * math.pi - 0.5 * beta) ** 2  # a (1 - sin beta), no cancellation
    exact = req.method != "closed_form"
    closed = req.method != "exact"
    predicted = gross_cost_s(1 if exact else 0, req.n_nodes, req.n_points)
    check_budget(predicted, req.time_limit_s)
    mu = req.mu_c
    with located():
        book_length = gm.encounter_length_max(beta, a) if closed else None
        book_rotation = gm.rotation_max(beta) if closed else None
        bounds = gb.encounter_bounds_exact(
            a, beta, mu, n_nodes=req.n_nodes, n_points=req.n_points, checkpoint=clock.check,
        ) if exact else None
        frictionless = gm.encounter_length_frictionless(beta, a)
        onset = gm.sketch_i_onset(mu)

    def bound(key: str, book: float | None, equation: str | None) -> BoundOut:
        ex = bounds[key] if bounds is not None else None
        value = None if ex is None else ex.value
        return BoundOut(
            exact=_opt(value, f"{key}.exact"),
            quadrature_error=None if ex is None else _f(ex.quadrature_error, f"{key}.quadrature_error"),
            closed_form=_opt(book, f"{key}.closed_form"), equation=equation if book is not None else None,
            difference=_opt(_diff(value, book), f"{key}.difference"),
        )

    at_start = bool(gm.sketch_i(beta, mu))
    occurs = onset < 0.5 * math.pi
    sketch_i = SketchIOut(
        onset_beta=onset, at_start=at_start, occurs=occurs,
        note=(
            "tan beta > 2 mu_c (4.17): the tip of {COR}_(alpha+nu) lies left of the sticking line, the lower "
            "end of the sticking locus is no longer near the tip line, and (4.16) overestimates; "
            + ("the whole encounter is in sketch i" if at_start else
               f"sketch i begins at beta = {onset:.6g} rad, before the disk is left at pi/2 (4.4.1.2)")
        ),
    )
    length_max = bound("length_max", book_length, "(4.16)")
    message = (
        f"a disk of radius {a:.6g} met at beta = {beta:.6g} rad (offset {offset:.6g}) with mu_c = {mu:.6g}: "
        + (f"the encounter lasts at most {length_max.exact:.6g} (exact)" if length_max.exact is not None else
           f"the encounter lasts at most {length_max.closed_form:.6g} by (4.16)")
        + f"; the disk turns at most pi/2 - beta = {0.5 * math.pi - beta:.6g} rad; sketch i "
        + ("from the start" if at_start else f"from beta = {onset:.6g}")
    )
    length_min = bound("length_min", None, None)
    rotation_max = bound("rotation_max", book_rotation, "(4.18), re-derived: pi/2 - beta_initial")
    rotation_min = bound("rotation_min", None, None)
    message += _quadrature_warning([length_max, length_min, rotation_max, rotation_min])
    return PushDiskEncounterResponse(
        message=message, method=req.method, disk_radius=a, beta_initial=beta, beta_final=0.5 * math.pi,
        offset=_f(offset, "offset"), beta_source=source, mu_c=mu, nu=math.atan(mu),
        length_greatest=length_max,
        length_least=length_min,
        length_frictionless=_f(frictionless, "length_frictionless"),
        rotation_greatest=rotation_max,
        rotation_least=rotation_min,
        sketch_i=sketch_i,
        quasi_static=quasi_static_check(req.quasi_static, qs.PartGeometry.disk(a)),
        note=ENCOUNTER_NOTE, reference=GROSS_REFERENCE,
        n_nodes=req.n_nodes, n_points=req.n_points, time_limit_s=req.time_limit_s,
        predicted_time_s=predicted, elapsed_ms=clock.elapsed() * 1e3,
    )
