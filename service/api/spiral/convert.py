"""Schema <-> problem <-> schema of the spiral endpoints (book 4.5; no mechanics here).

``POST /v1/spiral/critical-radius``: request ->
:class:`solver.spiral.critical_radius.CriticalRadiusProblem` (explicit betas, or the cached
table of figure 4-19's grid) -> the points, b_inf against (4.25) and the inverse beta*(r),
d*(r). ``POST /v1/spiral/schedule``: request (checked against the service's limits) ->
:class:`solver.spiral.plan.SpiralProblem` -> the schedule, the recursion (4.26), the
tip-line recursion, the fit of figure 4-21, the pusher's polyline and the simulation check.
Numbers leave as plain floats, never NaN.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from models.core.tolerances import SPIRAL_DEFAULT
from service.api.spiral.schemas import (
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
    TipLineScheduleOut,
)
from service.common.numbers import known, listed
from service.errors import FieldError
from service.limits import (
    SPIRAL_MAX_ARCS,
    SPIRAL_MAX_NODES,
    SPIRAL_MAX_PATH_POINTS,
    SPIRAL_MAX_RADIUS_REL,
    SPIRAL_MAX_REVOLUTIONS,
    SPIRAL_MIN_POINTS_PER_REVOLUTION,
    SPIRAL_SWEEP_MARGIN_REL,
    SPIRAL_SWEEP_POINTS,
)
from solver import (
    CriticalRadii,
    CriticalRadiusProblem,
    CriticalRadiusTable,
    PathQuery,
    SimulationQuery,
    SpiralPlan,
    SpiralProblem,
    SpiralSchedule,
)

SERVICE_SPIRAL_TOL = replace(SPIRAL_DEFAULT, max_revolutions=SPIRAL_MAX_REVOLUTIONS)
"""The spiral tolerances of the service: the recursion stops at SPIRAL_MAX_REVOLUTIONS."""


def _check_reach(value: float, a: float, field: str) -> None:
    if value / a > SPIRAL_MAX_RADIUS_REL:
        raise FieldError((field,), f"is {value / a:.6g} a; at most {SPIRAL_MAX_RADIUS_REL:g} disk radii")


def _monotone(tab: CriticalRadiusTable) -> bool:
    return tab.envelope is not None and tab.envelope.n_violations == 0


# ---------------------------------------------------------------------------------------
# POST /v1/spiral/critical-radius
# ---------------------------------------------------------------------------------------


def critical_radius_problem(req: SpiralCriticalRadiusRequest) -> CriticalRadiusProblem:
    if req.betas is not None and req.max_radius is not None:
        raise FieldError(("max_radius",), "give betas or max_radius, not both")
    if req.max_radius is not None:
        _check_reach(req.max_radius, req.disk_radius, "max_radius")
    return CriticalRadiusProblem(
        req.disk_radius, req.mu_c, req.method, betas=None if req.betas is None else tuple(req.betas),
        max_radius=req.max_radius, radii=None if req.radii is None else tuple(req.radii),
        sweep_points=SPIRAL_SWEEP_POINTS,
    )


def critical_radius_response(req: SpiralCriticalRadiusRequest, res: CriticalRadii,
                             elapsed_ms: float) -> SpiralCriticalRadiusResponse:
    tab = res.table
    a, mu = req.disk_radius, req.mu_c
    points = []
    for k, beta in enumerate(tab.betas):
        r = tab.radii[k]
        r_star = None if not math.isfinite(r) else r
        tip = float(res.tip_line_radii[k])
        points.append(CriticalPointOut(
            beta=float(beta), beta_over_pi=float(beta) / math.pi,
            distance_from_grazing=a * (1.0 - math.sin(beta)),
            r_star=r_star, midpoint=known(float(tab.midpoints[k])),
            lower_bound=None if tab.method != "exact" or not math.isfinite(tab.widths[k]) else tab.midpoints[k] - 0.5 * tab.widths[k],
            bracket_width=known(float(tab.widths[k])),
            certified=bool(tab.certified[k]), status=tab.statuses[k],
            tip_line_radius=tip,
            tip_line_error=None if r_star is None else tip - r_star,
        ))
    inverse = None
    if res.inverse is not None:
        inverse = [
            InverseOut(radius=q.radius, beta_star=known(q.beta_star),
                       distance_star=q.distance_star, beta_below=q.beta_below,
                       steps=q.steps)
            for q in res.inverse
        ]
    numeric, closed = res.b_inf_numeric, res.b_inf_closed_form
    msg = tab.message
    if numeric is not None:
        msg += f"; b_inf = {numeric:.9g} numerically, (4.25) gives {closed:.9g}"
    return SpiralCriticalRadiusResponse(
        message=msg, disk_radius=a, mu_c=mu, nu=math.atan(mu), method=req.method, points=points,
        b_inf=LimitOut(closed_form=closed, numeric=numeric, delta=res.grazing_delta,
                       difference=None if numeric is None else numeric - closed, tip_line=2.0 * a),
        inverse=inverse, kink_beta=tab.kink_beta, sketch_change_beta=tab.sketch_change_beta,
        monotone=_monotone(tab), complete=tab.complete, time_limited=tab.time_limited,
        stopped_at_beta=tab.stopped_at_beta, from_cache=res.from_cache, reference=REFERENCE,
        time_limit_s=req.time_limit_s, elapsed_ms=elapsed_ms,
    )


# ---------------------------------------------------------------------------------------
# POST /v1/spiral/schedule
# ---------------------------------------------------------------------------------------


def schedule_problem(req: SpiralScheduleRequest) -> SpiralProblem:
    """Check the service's limits and build the problem of ``req``."""
    a, b_1, target = req.disk_radius, req.start_radius, req.target
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
    path = None
    if req.include_path:
        path = PathQuery(req.points_per_revolution, SPIRAL_MIN_POINTS_PER_REVOLUTION, SPIRAL_MAX_PATH_POINTS)
    sim = None
    if req.simulate is not None:
        sim = SimulationQuery(req.simulate.n_supports, req.simulate.seed, req.simulate.kind)
    return SpiralProblem(
        a, req.mu_c, b_1, target, method=req.method, safety_margin=margin, objective=req.objective,
        min_step=req.min_step, max_step=req.max_step, speed=req.speed, backend=req.backend,
        resolution=req.resolution, center=(req.center[0], req.center[1]), clockwise=req.clockwise,
        start_angle=req.start_angle, path=path, simulate=sim, cached=True, sweep_points=SPIRAL_SWEEP_POINTS,
        max_nodes=SPIRAL_MAX_NODES, max_arcs=SPIRAL_MAX_ARCS, spiral_tol=SERVICE_SPIRAL_TOL,
    )


def table_partial(tab: CriticalRadiusTable) -> dict:
    """The 504's ``partial``: how far the r* table got."""
    env = tab.envelope
    return {"table": {
        "n_points": int(tab.betas.size), "complete": tab.complete, "time_limited": tab.time_limited,
        "covers_radius": None if env is None else env.envelope[0],
        "stopped_at_beta": tab.stopped_at_beta, "message": tab.message,
    }}


def _schedule_out(s: SpiralSchedule) -> ScheduleOut:
    c = s.certificate
    cert = None if c is None else CertificateOut(
        certified=c.certified, primal_cost=c.primal_cost, dual_bound=c.dual_bound, gap=c.gap,
        min_reduced_cost=c.min_reduced_cost, n_arcs_checked=c.n_arcs_checked, cost_unit=c.cost_unit,
        revolution_weight=c.revolution_weight, path_potentials=list(c.path_potentials),
    )
    return ScheduleOut(
        solver_status=s.solver_status,
        optimal_among=(f"schedules on the {s.grid_kind} grid of {s.n_nodes} radii (holding the recursion's radii) that are "
                       "safe by this r* table"), stopped_early=s.stopped_early, objective=s.objective,
        objective_value=known(s.objective_value), backend=s.backend,
        radii=listed(s.radii), steps=listed(s.steps), revolutions=s.revolutions,
        path_length=known(s.path_length),
        path_length_error=known(s.path_length_error),
        time_s=known(s.time_s), certificate=cert, greedy_revolutions=s.greedy_revolutions,
        greedy_path_length=known(s.greedy_path_length),
        max_step_excess=known(s.max_step_excess), n_nodes=s.n_nodes, n_arcs=s.n_arcs,
        grid_kind=s.grid_kind, min_spacing=s.min_spacing, max_spacing=s.max_spacing,
        solve_time_s=s.solve_time_s, total_time_s=s.total_time_s, message=s.message,
    )


def schedule_response(req: SpiralScheduleRequest, plan: SpiralPlan, elapsed_ms: float) -> SpiralScheduleResponse:
    a, mu, b_1, target = req.disk_radius, req.mu_c, req.start_radius, req.target
    tab = plan.table
    env = tab.envelope
    sched = _schedule_out(plan.schedule)
    rec = plan.recursion
    tip_radii = plan.tip_line.radii
    schedule_revs = None if not sched.radii else sched.revolutions
    tip = TipLineScheduleOut(
        revolutions=int(tip_radii.size), final_radius=tip_radii[-1],
        reaches_target=bool(tip_radii[-1] <= target), unsafe_revolutions=plan.tip_line.unsafe_revolutions,
        revolutions_difference=None if schedule_revs is None else int(tip_radii.size) - schedule_revs,
    )
    f = plan.fit
    fit = None if f is None else FitOut(
        exponent=f.exponent, coefficient=f.coefficient, n_min=f.n_min, n_max=f.n_max, n_points=f.n_points,
        rms_residual=f.rms_residual, local_exponent_min=f.local_exponent_range[0],
        local_exponent_max=f.local_exponent_range[1],
    )
    path = None
    if plan.polyline is not None:
        poly = plan.polyline
        path = PathOut(points=listed(poly.points), points_per_revolution=poly.points_per_revolution,
                       max_chord_deviation=poly.max_chord_deviation,
                       polyline_length=poly.polyline_length, clockwise=req.clockwise)
    sim = None
    if plan.simulation is not None:
        batch = plan.simulation
        sim = SimulationOut(
            n=batch.n, all_inside=batch.all_inside, escaped=batch.escaped, escaped_runs=list(batch.escaped_indices),
            outside_promise_runs=list(batch.outside_promise_indices),
            promised_radius=batch.promised_radius,
            max_final_extent=known(batch.max_final_extent),
            margin=known(batch.margin), contacts=batch.contacts,
            statuses={str(k): int(v) for k, v in batch.statuses.items()}, forward_solves=batch.forward_solves,
            solver_failures=batch.solver_failures, wall_time_s=batch.wall_time_s, seed=req.simulate.seed,
            kind=req.simulate.kind,
        )
    covers = float(env.envelope[0])
    table = TableOut(n_points=int(tab.betas.size), betas=listed(tab.betas),
                     radii=[float(r) if np.isfinite(r) else None for r in tab.radii],
                     certified=[bool(c) for c in tab.certified], complete=tab.complete, time_limited=tab.time_limited,
                     covers_radius=covers, from_cache=plan.from_cache,
                     monotone=_monotone(tab), message=tab.message)
    msg = _schedule_message(sched, rec, tip, b_1, target, covers, sim)
    return SpiralScheduleResponse(
        message=msg, disk_radius=a, mu_c=mu, method=req.method, safety_margin=plan.problem.safety_margin,
        b_inf=plan.b_inf_closed_form, b_floor=plan.b_floor, table=table, schedule=sched,
        recursion=RecursionOut(radii=listed(rec.radii), revolutions=rec.revolutions,
                               stop_reason=rec.stop_reason, reached_target=rec.reached_target,
                               path_length=rec.path_length,
                               time_s=known(rec.time_s),
                               max_step_excess=rec.max_step_excess),
        tip_line=tip, fit=fit, path=path, simulation=sim, reference=REFERENCE, time_limit_s=req.time_limit_s,
        elapsed_ms=elapsed_ms,
    )


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
        text += "; " + simulation_summary(sim.n, sim.escaped, sim.statuses, sim.all_inside)
    return text


def simulation_summary(n: int, escaped: int, statuses: dict[str, int], all_inside: bool) -> str:
    """The simulation check in words, counting only the runs that ran: "kept" are the runs
    that ran and were not pushed out; runs the time limit left out are said as not run."""
    not_run = int(statuses.get("not_run", 0))
    ran = n - not_run
    if ran == 0:
        return f"simulation: none of the {n} runs ran (time limit)"
    text = f"simulation: {ran - escaped} of the {ran} runs that ran kept"
    if not_run:
        text += f", {not_run} of {n} not run (time limit)"
    return text + (", all inside the final radius" if all_inside else "")
