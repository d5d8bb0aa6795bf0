"""Schema <-> domain conversion of the spiral endpoints (book 4.5; no mechanics here).

``POST /v1/spiral/critical-radius``: request -> :func:`solver.spiral.critical_radius.critical_radius_table`
(explicit betas) or the cached table of figure 4-19's grid
(:func:`solver.spiral.critical_radius.cached_critical_radius_table`), the limit beta -> pi/2 against
(4.25), and the inverse beta*(r), d*(r) on the table's safe envelope.
``POST /v1/spiral/schedule``: request -> the cached table (with the safety margin) ->
:func:`solver.spiral.schedule.plan_spiral` (the OR-Tools schedule and the recursion (4.26)), the
tip-line recursion beside it, the power-law fit of figure 4-21, the pusher polyline
(:func:`models.spiral.spiral_polyline`) and, if asked, the simulation check
(:func:`solver.sim.spiral.spiral_check`). Numbers leave as plain floats, never NaN.
"""

from __future__ import annotations

import math
import time

import numpy as np

from dataclasses import replace

from models.errors import InvalidInput
from models.tolerances import SPIRAL_DEFAULT
from models.spiral import (
    CriticalEnvelope,
    PowerLawFit,
    limiting_radius,
    power_law_fit,
    spiral_polyline,
    tip_line_critical_radius,
    tip_line_spiral,
    unsafe_revolutions,
)
from service.convert import _f, _v
from service.convert_mpp import located
from service.errors import FieldError
from service.limits import (
    SPIRAL_MAX_ARCS,
    SPIRAL_MAX_NODES,
    SPIRAL_MAX_REVOLUTIONS,
    SPIRAL_MAX_PATH_POINTS,
    SPIRAL_MAX_RADIUS_REL,
    SPIRAL_MIN_POINTS_PER_REVOLUTION,
    SPIRAL_SWEEP_MARGIN_REL,
    SPIRAL_SWEEP_POINTS,
)
from service.schemas_spiral import (
    REFERENCE,
    CertificateOut,
    CriticalPointOut,
    FitOut,
    InverseOut,
    LimitOut,
    PathOut,
    RecursionOut,
    ScheduleOut,
    SimulationOut,
    SpiralCriticalRadiusRequest,
    SpiralCriticalRadiusResponse,
    SpiralScheduleRequest,
    SpiralScheduleResponse,
    TableOut,
    TipLineOut,
)
from solver.core.budget import Budget
from solver.spiral.critical_radius import (
    CriticalRadiusTable,
    cached_critical_radius_table,
    critical_radius_table,
    limiting_radius_check,
)
from solver.spiral.schedule import SpiralPlan, plan_spiral
from solver.sim.spiral import spiral_check, spiral_path

SERVICE_SPIRAL_TOL = replace(SPIRAL_DEFAULT, max_revolutions=SPIRAL_MAX_REVOLUTIONS)
"""The spiral tolerances of the service: the recursion stops at SPIRAL_MAX_REVOLUTIONS."""

LIMIT_BETA_MATCH = 1e-12
"""The table's last beta is the limit point pi/2 - grazing_delta (4.5.4) when this close
to it (radians): its r* is then the numerical b_inf, no extra solve."""

DEFAULT_MAX_RADIUS_REL = 100.0
"""Default reach of the table of figure 4-19, in units of a (the book's b_1 = 100 a)."""


def _opt(x, what: str):
    return None if x is None or (isinstance(x, float) and math.isnan(x)) else _f(x, what)


def _clock(limit: float):
    t0 = time.perf_counter()
    return t0, (lambda: max(0.0, limit - (time.perf_counter() - t0)))


def _check_reach(value: float, a: float, field: str) -> None:
    if value / a > SPIRAL_MAX_RADIUS_REL:
        raise FieldError((field,), f"is {value / a:.6g} a; at most {SPIRAL_MAX_RADIUS_REL:g} disk radii")


def _table(a: float, mu_c: float, method: str, r_max: float, limit: float, margin_rel: float = 0.0):
    return cached_critical_radius_table(a, mu_c, method, r_max, budget=Budget.of(limit), sweep_points=SPIRAL_SWEEP_POINTS,
                                        margin_rel=margin_rel)


def _monotone(env: CriticalEnvelope | None) -> bool:
    return env is not None and env.n_violations == 0


# ---------------------------------------------------------------------------------------
# POST /v1/spiral/critical-radius
# ---------------------------------------------------------------------------------------


def critical_radius_response(req: SpiralCriticalRadiusRequest) -> tuple[SpiralCriticalRadiusResponse, CriticalRadiusTable]:
    t0, left = _clock(req.time_limit_s)
    a, mu = req.disk_radius, req.mu_c
    with located():
        if req.betas is not None:
            if req.max_radius is not None:
                raise FieldError(("max_radius",), "give betas or max_radius, not both")
            tab = critical_radius_table(a, mu, req.method, betas=req.betas, budget=Budget.of(left()),
                                        sweep_points=SPIRAL_SWEEP_POINTS, find_kink=False)
            cached = False
        else:
            r_max = DEFAULT_MAX_RADIUS_REL * a if req.max_radius is None else req.max_radius
            _check_reach(r_max, a, "max_radius")
            tab, cached = _table(a, mu, req.method, r_max, left())
        lim_delta = 0.5 * math.pi - float(tab.betas[-1]) if tab.betas.size else None
        delta = SPIRAL_DEFAULT.grazing_delta
        if lim_delta is not None and abs(lim_delta - delta) <= LIMIT_BETA_MATCH:
            numeric = tab.radii[-1]
        elif left() > 0.0:
            numeric = limiting_radius_check(a, mu, req.method).numeric
        else:
            numeric = None
    closed = limiting_radius(a, mu)
    tips = tip_line_critical_radius(a, tab.betas) if tab.betas.size else np.empty(0)
    points = []
    for k, beta in enumerate(tab.betas):
        r = tab.radii[k]
        r_star = None if not math.isfinite(r) else _f(r, "points.r_star")
        tip = float(tips[k])
        points.append(CriticalPointOut(
            beta=float(beta), beta_over_pi=float(beta) / math.pi,
            distance_from_grazing=_f(a * (1.0 - math.sin(beta)), "points.distance_from_grazing"),
            r_star=r_star, midpoint=_opt(float(tab.midpoints[k]), "points.midpoint"),
            lower_bound=None if tab.method != "exact" or not math.isfinite(tab.widths[k]) else _f(
                tab.midpoints[k] - 0.5 * tab.widths[k], "points.lower_bound"),
            bracket_width=_opt(float(tab.widths[k]), "points.bracket_width"),
            certified=bool(tab.certified[k]), status=tab.statuses[k],
            tip_line_radius=_f(tip, "points.tip_line_radius"),
            tip_line_error=None if r_star is None else _f(tip - r_star, "points.tip_line_error"),
        ))
    inverse = None
    if req.radii is not None:
        if tab.envelope is None:
            raise FieldError(("radii",), f"no usable critical radius to invert: {tab.message}")
        env = tab.envelope
        inverse = [
            InverseOut(radius=r, beta_star=_opt(float(env.beta_star(r)), "inverse.beta_star"),
                       distance_star=_f(env.d_star(r), "inverse.distance_star"))
            for r in req.radii
        ]
    numeric_f = None if numeric is None or not math.isfinite(numeric) else float(numeric)
    msg = tab.message
    if numeric_f is not None:
        msg += f"; b_inf = {numeric_f:.9g} numerically, (4.25) gives {closed:.9g}"
    return SpiralCriticalRadiusResponse(
        message=msg, disk_radius=a, mu_c=mu, nu=math.atan(mu), method=req.method, points=points,
        b_inf=LimitOut(closed_form=closed, numeric=numeric_f, delta=delta,
                       difference=None if numeric_f is None else numeric_f - closed, tip_line=2.0 * a),
        inverse=inverse, kink_beta=tab.kink_beta, sketch_change_beta=tab.sketch_change_beta,
        monotone=_monotone(tab.envelope), complete=tab.complete, time_limited=tab.time_limited,
        stopped_at_beta=tab.stopped_at_beta, from_cache=cached, reference=REFERENCE,
        time_limit_s=req.time_limit_s, elapsed_ms=(time.perf_counter() - t0) * 1e3,
    ), tab


# ---------------------------------------------------------------------------------------
# POST /v1/spiral/schedule
# ---------------------------------------------------------------------------------------


def _schedule_out(plan: SpiralPlan) -> ScheduleOut | None:
    s = plan.schedule
    if s is None:
        return None
    c = s.certificate
    cert = None if c is None else CertificateOut(
        certified=c.certified, primal_cost=c.primal_cost, dual_bound=c.dual_bound, gap=c.gap,
        min_reduced_cost=c.min_reduced_cost, n_arcs_checked=c.n_arcs_checked, cost_unit=_f(c.cost_unit, "cost_unit"),
    )
    return ScheduleOut(
        solver_status=s.solver_status, stopped_early=s.stopped_early, objective=s.objective,
        objective_value=_opt(s.objective_value, "schedule.objective_value"), backend=s.backend,
        radii=_v(s.radii, "schedule.radii"), steps=_v(s.steps, "schedule.steps"), revolutions=s.revolutions,
        path_length=_opt(s.path_length, "schedule.path_length"),
        path_length_error=_opt(s.path_length_error, "schedule.path_length_error"),
        time_s=_opt(s.time_s, "schedule.time_s"), certificate=cert, greedy_revolutions=s.greedy_revolutions,
        greedy_path_length=_opt(s.greedy_path_length, "schedule.greedy_path_length"),
        max_step_excess=_opt(s.max_step_excess, "schedule.max_step_excess"), n_nodes=s.n_nodes, n_arcs=s.n_arcs,
        grid_kind=s.grid_kind, min_spacing=_f(s.min_spacing, "min_spacing"), max_spacing=_f(s.max_spacing, "max_spacing"),
        solve_time_s=s.solve_time_s, total_time_s=s.total_time_s, message=s.message,
    )


def _tip_line(a: float, b_1: float, target: float, tab: CriticalRadiusTable, schedule_revs: int | None) -> TipLineOut:
    radii = tip_line_spiral(a, b_1, target)
    unsafe = int(np.sum(unsafe_revolutions(radii, tab.betas, tab.radii, a)))
    return TipLineOut(
        revolutions=int(radii.size), final_radius=_f(radii[-1], "tip_line.final_radius"),
        reaches_target=bool(radii[-1] <= target), unsafe_revolutions=unsafe,
        revolutions_difference=None if schedule_revs is None else int(radii.size) - schedule_revs,
    ), radii


def _fit(radii: np.ndarray, floor: float, a: float) -> tuple[FitOut | None, PowerLawFit | None]:
    """Figure 4-21's power law over the revolutions within a of the floor (before that the
    spiral shrinks by almost a per revolution, 4.5.5), or over all when fewer than 3."""
    near = np.nonzero(radii - floor < a)[0]
    n_min = int(near[0]) + 1 if near.size and radii.size - near[0] >= 3 else 1
    try:
        f = power_law_fit(radii, floor, n_min=n_min)
    except InvalidInput:
        return None, None
    if not (math.isfinite(f.exponent) and math.isfinite(f.coefficient)):
        return None, None
    return FitOut(
        exponent=f.exponent, coefficient=f.coefficient, n_min=f.n_min, n_max=f.n_max, n_points=f.n_points,
        rms_residual=f.rms_residual, local_exponent_min=f.local_exponent_range[0],
        local_exponent_max=f.local_exponent_range[1],
    ), f


def schedule_response(req: SpiralScheduleRequest):
    """(response, the radii used for the path, the tip-line radii, the fit) -- the last
    three for the SVG picture."""
    t0, left = _clock(req.time_limit_s)
    a, mu, b_1, target = req.disk_radius, req.mu_c, req.start_radius, req.target
    _check_reach(b_1, a, "start_radius")
    if not target < b_1:
        raise FieldError(("target",), "must be smaller than start_radius")
    if req.objective == "time" and req.speed is None:
        raise FieldError(("speed",), "the 'time' objective needs the pusher speed")
    if req.max_step is not None and (b_1 - target) / req.max_step > SPIRAL_MAX_REVOLUTIONS:
        raise FieldError(("max_step",), f"would need more than {SPIRAL_MAX_REVOLUTIONS} revolutions from start_radius "
                         "to target")
    if req.min_step is not None and req.max_step is not None and req.min_step > req.max_step:
        raise FieldError(("min_step",), "must not exceed max_step")
    margin = req.safety_margin
    if margin is None:
        margin = SPIRAL_SWEEP_MARGIN_REL if req.method == "sweep" else 0.0
    with located():
        tab, cached = _table(a, mu, req.method, b_1, left(), margin)
        if tab.envelope is None:
            raise FieldError(("time_limit_s",), f"no usable critical radius in time: {tab.message}")
        if tab.time_limited and tab.envelope.envelope[0] < b_1:
            # the table stopped near grazing: above its reach every step would be tiny
            raise FieldError(
                ("time_limit_s",),
                f"the r* table covers pusher radii up to {tab.envelope.envelope[0]:.6g} only in {req.time_limit_s:g} s "
                f"(start_radius {b_1:.6g}); raise time_limit_s (a finished table is cached for later requests)",
            )
        plan = plan_spiral(a, mu, b_1, target, method=req.method, objective=req.objective, min_step=req.min_step,
                           max_step=req.max_step, speed=req.speed, budget=Budget.of(max(left(), 1e-3)),
                           backend=req.backend, resolution=req.resolution, table=tab, max_nodes=SPIRAL_MAX_NODES,
                           max_arcs=SPIRAL_MAX_ARCS, spiral_tol=SERVICE_SPIRAL_TOL)
    env = tab.envelope
    sched = _schedule_out(plan)
    rec = plan.recursion
    if rec.stop_reason == "max_revolutions":
        raise FieldError(("target",), f"needs more than {SPIRAL_MAX_REVOLUTIONS} revolutions (the spiral approaches "
                         f"its floor {env.b_floor:.6g} ever more slowly, figure 4-21): raise the target")
    radii = plan.schedule.radii if (plan.schedule is not None and plan.schedule.radii.size) else rec.radii
    tip, tip_radii = _tip_line(a, b_1, target, tab, None if sched is None or not sched.radii else sched.revolutions)
    fit, fit_raw = _fit(radii, env.b_floor, a)
    path = None
    if req.include_path:
        ppr = max(SPIRAL_MIN_POINTS_PER_REVOLUTION, min(req.points_per_revolution, SPIRAL_MAX_PATH_POINTS // radii.size))
        poly = spiral_polyline(radii, ppr, center=req.center, phase=req.start_angle, clockwise=req.clockwise)
        path = PathOut(points=_v(poly.points, "path.points"), points_per_revolution=ppr,
                       max_chord_deviation=_f(poly.max_chord_deviation, "path.max_chord_deviation"),
                       polyline_length=_f(poly.polyline_length, "path.polyline_length"), clockwise=req.clockwise)
    sim = None
    if req.simulate is not None:
        sp = spiral_path(radii, centre=req.center, clockwise=req.clockwise, start_angle=req.start_angle)
        with located(prefix=("simulate",)):
            batch = spiral_check(sp, a, mu, req.simulate.n_supports, req.simulate.seed, kind=req.simulate.kind,
                                 promised_radius=float(radii[-1]), budget=Budget.of(max(left(), 1e-3)))
        sim = SimulationOut(
            n=batch.n, all_inside=batch.all_inside, escaped=batch.escaped, escaped_runs=list(batch.escaped_indices),
            outside_promise_runs=list(batch.outside_promise_indices),
            promised_radius=_f(batch.promised_radius, "simulation.promised_radius"),
            max_final_extent=_opt(batch.max_final_extent, "simulation.max_final_extent"),
            margin=_opt(batch.margin, "simulation.margin"), contacts=batch.contacts,
            statuses={str(k): int(v) for k, v in batch.statuses.items()}, forward_solves=batch.forward_solves,
            solver_failures=batch.solver_failures, wall_time_s=batch.wall_time_s, seed=req.simulate.seed,
            kind=req.simulate.kind,
        )
    covers = float(env.envelope[0])
    table = TableOut(n_points=int(tab.betas.size), complete=tab.complete, time_limited=tab.time_limited,
                     covers_radius=_f(covers, "table.covers_radius"), from_cache=cached, monotone=_monotone(env),
                     message=tab.message)
    msg = _schedule_message(sched, rec, tip, b_1, target, covers, sim)
    resp = SpiralScheduleResponse(
        message=msg, disk_radius=a, mu_c=mu, method=req.method, safety_margin=margin, b_inf=limiting_radius(a, mu),
        b_floor=_f(env.b_floor, "b_floor"), table=table, schedule=sched,
        recursion=RecursionOut(radii=_v(rec.radii, "recursion.radii"), revolutions=rec.revolutions,
                               stop_reason=rec.stop_reason, reached_target=rec.reached_target,
                               path_length=_f(rec.path_length, "recursion.path_length"),
                               time_s=_opt(rec.time_s, "recursion.time_s"),
                               max_step_excess=_f(rec.max_step_excess, "recursion.max_step_excess")),
        tip_line=tip, fit=fit, path=path, simulation=sim, reference=REFERENCE, time_limit_s=req.time_limit_s,
        elapsed_ms=(time.perf_counter() - t0) * 1e3,
    )
    return resp, radii, tip_radii, fit_raw


def _schedule_message(sched, rec, tip, b_1, target, covers, sim) -> str:
    if sched is not None and sched.radii:
        text = (f"{sched.revolutions} revolutions from {b_1:.6g} to {sched.radii[-1]:.6g} ({sched.solver_status}"
                f"{', certified optimal' if sched.certificate is not None and sched.certificate.certified else ''}); "
                f"the recursion (4.26) takes {rec.revolutions}")
    elif sched is not None:
        text = f"no schedule: {sched.message}; the recursion (4.26) takes {rec.revolutions} ({rec.stop_reason})"
    else:
        text = f"the recursion (4.26) takes {rec.revolutions} revolutions ({rec.stop_reason})"
    text += (f"; the tip line: {tip.revolutions} revolutions"
             f"{'' if tip.reaches_target else ', never reaching the target'}"
             f"{f', {tip.unsafe_revolutions} of them unsafe' if tip.unsafe_revolutions else ''}")
    if covers < b_1:
        text += f"; the r* table covers radii up to {covers:.6g} only (larger ones use its smallest beta: safe, slower)"
    if sim is not None:
        text += (f"; simulation: {sim.n - sim.escaped} of {sim.n} kept"
                 f"{', all inside the final radius' if sim.all_inside else ''}")
    return text
