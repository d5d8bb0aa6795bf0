"""Request and response schemas of the spiral endpoints (book 4.5): ``POST
/v1/spiral/critical-radius`` (r*(beta), beta*(r), d*(r), b_inf; figure 4-19) and ``POST
/v1/spiral/schedule`` (the fastest guaranteed spiral on OR-Tools, the recursion (4.26),
the pusher's path, the approach to b_inf of figure 4-21, an optional simulation check).

A disk of radius a lies somewhere within radius b_1 of a centre; a point pusher circles
the centre on a shrinking spiral and herds it in. Lengths in the client's unit, angles in
radians, speeds in length per second. Conventions as in :mod:`service.common.fields`:
strict finite numbers, unknown fields rejected, null counts as absent.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, StrictBool

from service.common.fields import Point, TimeLimit
from service.common.responses import ELAPSED_MS_DESCRIPTION, Out
from service.limits import (
    MAX_DISK_RADIUS,
    MAX_MU_C,
    SPIRAL_DEFAULT_POINTS_PER_REVOLUTION,
    SPIRAL_DEFAULT_RESOLUTION,
    SPIRAL_DEFAULT_TIME_LIMIT_S,
    SPIRAL_MAX_BETAS,
    SPIRAL_MAX_POINTS_PER_REVOLUTION,
    SPIRAL_MAX_RADIUS_REL,
    SPIRAL_MAX_RESOLUTION,
    SPIRAL_MAX_SIMULATED,
    SPIRAL_MIN_BETA,
    SPIRAL_MIN_LENGTH,
    SPIRAL_MIN_POINTS_PER_REVOLUTION,
    SPIRAL_MIN_RESOLUTION,
    SPIRAL_SWEEP_MARGIN_REL,
    TIME_LIMIT_CAP_TEXT,
)

SpiralMethod = Literal["exact", "sweep", "tip_line"]
SpiralLength = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=SPIRAL_MIN_LENGTH, le=MAX_DISK_RADIUS)]
PositiveLength = Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0.0, le=MAX_DISK_RADIUS * SPIRAL_MAX_RADIUS_REL)]
MuCPositive = Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0.0, le=MAX_MU_C)]
Beta = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=SPIRAL_MIN_BETA, lt=0.5 * math.pi)]

REFERENCE = (
    "M. A. Peshkin, Robotic Manipulation Strategies (1990): 4.5 (spiral localization of a disk: "
    "4.5.2 the critical case, 4.5.3 r*(beta) and (4.24), 4.5.4 b_inf (4.25), 4.5.5 the recursion (4.26), "
    "figures 4-19 and 4-21); 4.1.4 (the sticking locus). Re-derived, with the findings against the "
    "printed text, in the service's docs/mechanics.md (spiral localization)"
)

METHOD_DESCRIPTION = (
    "How r*(beta), the distance from the pusher's line to the lower end of the sticking locus "
    "(4.5.3), is found. 'sweep' (default): the book's force-angle sweep over the analytic loci (4.1.4); "
    "not certified, within ~1e-4 a of the exact value (schedules add `safety_margin`). 'exact': the "
    "certified lower end (a witness pressure distribution inside, a dual certificate outside; the "
    "outside end of each bracket is used, ~0.8 s per collision parameter). 'tip_line': the book's "
    "approximation 2a / sin(beta), independent of mu_c (it misses b_inf = a(1 + mu_c) for mu_c < 1 and "
    "understates r* near mu_c = 1)."
)


class SpiralCriticalRadiusRequest(BaseModel):
    """r*(beta) for a disk of radius `disk_radius` and pusher friction `mu_c` (4.5.3): at
    the collision parameters `betas`, or on the grid of figure 4-19 (dense near grazing and
    around the slope kink) for pusher radii up to `max_radius`; with `radii`, the inverse
    beta*(r) and the critical distance from grazing d*(r) (4.24)."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={"examples": [{"disk_radius": 1.0, "mu_c": 0.25, "betas": [0.3, 0.8, 1.3]}]},
    )

    disk_radius: SpiralLength = Field(description=f"Radius a of the disk, [{SPIRAL_MIN_LENGTH:g}, {MAX_DISK_RADIUS:g}].")
    mu_c: MuCPositive = Field(description=f"Pusher-disk friction, (0, {MAX_MU_C:g}].")
    betas: list[Beta] | None = Field(
        default=None, min_length=1, max_length=SPIRAL_MAX_BETAS,
        description=f"Collision parameters (rad) in [{SPIRAL_MIN_BETA:g}, pi/2): beta = pi/2 is a grazing touch; "
        f"at most {SPIRAL_MAX_BETAS}. Default: the grid of figure 4-19 up to `max_radius` (cached per mu_c).",
    )
    max_radius: PositiveLength | None = Field(
        default=None,
        description=f"Without `betas`: the grid covers pusher radii up to this (default 100 a, at most "
        f"{SPIRAL_MAX_RADIUS_REL:g} a).",
    )
    radii: list[PositiveLength] | None = Field(
        default=None, min_length=1, max_length=SPIRAL_MAX_BETAS,
        description="Pusher circle radii r for the inverse beta*(r) and d*(r) (from the table's safe envelope).",
    )
    method: SpiralMethod = Field(default="sweep", description=METHOD_DESCRIPTION)
    time_limit_s: TimeLimit = Field(
        default=SPIRAL_DEFAULT_TIME_LIMIT_S,
        description=f"Time budget, seconds, {TIME_LIMIT_CAP_TEXT}. The table is built from grazing downwards, so a "
        "cut table covers beta >= `stopped_at_beta` (the radii below some size) and says so.",
    )


class CriticalPointOut(Out):
    beta: float = Field(description="Collision parameter (rad).")
    beta_over_pi: float = Field(description="beta / pi, the abscissa of figure 4-19.")
    distance_from_grazing: float = Field(description="d = a (1 - sin beta) (4.24).")
    r_star: float | None = Field(
        description="r*(beta): the radius to use ('exact': the certified outside end, a safe upper bound); null "
        "when this point could not be decided."
    )
    midpoint: float | None = Field(description="'exact': the bracket's midpoint.")
    lower_bound: float | None = Field(description="'exact': the certified inside end of the bracket.")
    bracket_width: float | None = Field(description="'exact': the bracket width.")
    certified: bool = Field(
        description="Whether r_star carries its certificate (method 'exact', both bracket ends certified); always "
        "false for 'sweep' and 'tip_line'."
    )
    status: str = Field(description="'bracketed', 'wide', ... (exact), or 'approximate'.")
    tip_line_radius: float = Field(description="The book's tip-line approximation 2a / sin(beta).")
    tip_line_error: float | None = Field(description="tip_line_radius - r_star (negative: the tip line is unsafe here).")


class LimitOut(Out):
    closed_form: float = Field(description="(4.25): a (1 + mu_c) for mu_c <= 1, 2a above.")
    numeric: float | None = Field(description="r*(pi/2 - delta) by the request's method (the limit beta -> pi/2).")
    delta: float = Field(description="pi/2 - beta of the numerical limit.")
    difference: float | None = Field(description="numeric - closed_form.")
    tip_line: float = Field(description="The tip line's limit, 2a for every mu_c.")


class InverseOut(Out):
    radius: float = Field(description="The pusher circle's radius r.")
    beta_star: float | None = Field(
        description="beta*(r): the smallest tabulated collision parameter whose whole tail beta' >= beta has "
        "r*(beta') <= r (4.5.3); null when r is below every r* (no guarantee, r < b_inf)."
    )
    distance_star: float = Field(description="d*(r) = a (1 - sin beta*) (4.24); 0 when there is no guarantee.")
    beta_below: float | None = Field(
        description="The largest collision parameter known to have no guarantee at r: the true beta*(r) lies in "
        "(beta_below, beta_star]. beta_star is bisected from the table's points with the table's method (to 1e-4 "
        "rad, at most 16 evaluations, fewer when the time limit comes); null when beta_star is the table's first."
    )
    steps: int = Field(description="r* evaluations spent refining beta_star between the table's points.")


class SpiralCriticalRadiusResponse(Out):
    message: str = Field(
        description="The table in words (collision parameters done, time limit, dropped points, increases of r*) and "
        "b_inf numerically against (4.25)."
    )
    disk_radius: float = Field(
        description="Radius a of the disk, as given (request's length unit)."
    )
    mu_c: float = Field(
        description="Pusher-disk friction coefficient, as given."
    )
    nu: float = Field(description="atan(mu_c).")
    method: SpiralMethod = Field(
        description="How r* was found, as asked: 'sweep', 'exact' or 'tip_line'."
    )
    points: list[CriticalPointOut] = Field(description="r*(beta) at each collision parameter, ascending in beta.")
    b_inf: LimitOut = Field(description="The limiting radius (4.5.4).")
    inverse: list[InverseOut] | None = Field(description="beta*(r), d*(r) at the requested `radii`.")
    kink_beta: float | None = Field(
        description="Where the lower end of the sticking locus leaves the disk (the slope kink of 1/r*, "
        "figure 4-19); null when not located (tip line, explicit betas, or mu_c >= 1)."
    )
    sketch_change_beta: float = Field(description="atan(2 mu_c): above it the sketch is type i (4.17).")
    monotone: bool = Field(description="r* never increases with beta on this table (the envelope's assumption).")
    complete: bool = Field(
        description="Whether every planned collision parameter of the table was evaluated."
    )
    time_limited: bool = Field(
        description="Whether the time limit stopped the table early (it then covers beta >= `stopped_at_beta` only)."
    )
    stopped_at_beta: float | None = Field(
        description="The smallest collision parameter the table reached before the time limit, radians (it covers "
        "beta >= this); null when not time-limited."
    )
    from_cache: bool = Field(description="The table came from the service's cache (computed for a = 1, scaled).")
    reference: str = Field(
        description="The book's sections, equations and figures the answer rests on, as text."
    )
    time_limit_s: float = Field(
        description="The request's time limit (its `time_limit_s` or the route's default), seconds."
    )
    elapsed_ms: float = Field(description=ELAPSED_MS_DESCRIPTION)


# ---------------------------------------------------------------------------------------
# POST /v1/spiral/schedule
# ---------------------------------------------------------------------------------------

Objective = Literal["revolutions", "length", "time"]
Backend = Literal["min_cost_flow", "cp_sat"]
SupportKind = Literal["tripod", "rim", "dipod", "cloud"]


class SimulationIn(BaseModel):
    """Push disks with random pressure distributions along the planned spiral with the
    forward solver (issue check of 4.5): none may be pushed out, all must end inside the
    final radius."""

    model_config = ConfigDict(extra="forbid")

    n_supports: Annotated[int, Field(strict=True, ge=1, le=SPIRAL_MAX_SIMULATED)] = Field(
        default=8, description=f"Random supports simulated, 1..{SPIRAL_MAX_SIMULATED}."
    )
    seed: Annotated[int, Field(strict=True, ge=0, le=2**63 - 1)] = Field(default=0, description="Random seed.")
    kind: SupportKind = Field(
        default="tripod",
        description="'tripod' (book figure 3-5), 'rim' (tripods on the rim), 'dipod' (two points on a diameter: "
        "the extremes of the sketch), 'cloud' (8 random points).",
    )


class SpiralScheduleRequest(BaseModel):
    """The fastest guaranteed spiral (4.5.5) from `start_radius` b_1 down to `target`:
    every revolution n satisfies b_{n-1} - b_n <= d*(b_n) (4.26), so a disk of radius a
    anywhere within b_1 - a is herded in and never pushed out; planned as a certified
    shortest path on OR-Tools (fewest revolutions, or shortest path / time), with the
    book's recursion beside it."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={"examples": [{"disk_radius": 1.0, "mu_c": 0.25, "start_radius": 20.0, "target": 3.0}]},
    )

    disk_radius: SpiralLength = Field(description=f"Radius a of the disk, [{SPIRAL_MIN_LENGTH:g}, {MAX_DISK_RADIUS:g}].")
    mu_c: MuCPositive = Field(description=f"Pusher-disk friction, (0, {MAX_MU_C:g}].")
    start_radius: PositiveLength = Field(
        description=f"b_1: the first revolution's radius (the disk lies within b_1 - a); at most "
        f"{SPIRAL_MAX_RADIUS_REL:g} a."
    )
    target: PositiveLength = Field(
        description="The radius to localise to: the last revolution's radius b_N <= target. Must exceed b_inf "
        "(4.25), the smallest radius with any guarantee."
    )
    method: SpiralMethod = Field(default="sweep", description=METHOD_DESCRIPTION)
    safety_margin: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0.0, le=1.0)] | None = Field(
        default=None,
        description=f"Added to every r* (in units of a) before planning. Default {SPIRAL_SWEEP_MARGIN_REL:g} for "
        "'sweep' (about 10x its measured error), 0 for 'exact' and 'tip_line'.",
    )
    objective: Objective = Field(
        default="revolutions",
        description="'revolutions' (fewest, ties broken by length), 'length' (shortest pusher path) or 'time' "
        "(= length / speed; needs `speed`).",
    )
    min_step: PositiveLength | None = Field(
        default=None, description="A robot limit: every revolution shrinks the radius by at least this."
    )
    max_step: PositiveLength | None = Field(default=None, description="A robot limit: by at most this.")
    speed: PositiveLength | None = Field(default=None, description="Pusher speed (length/s): times are reported.")
    backend: Backend = Field(
        default="min_cost_flow",
        description="OR-Tools solver of the shortest path: 'min_cost_flow' (SimpleMinCostFlow) or 'cp_sat' (time "
        "limit inside the search).",
    )
    resolution: Annotated[int, Field(strict=True, ge=SPIRAL_MIN_RESOLUTION, le=SPIRAL_MAX_RESOLUTION)] = Field(
        default=SPIRAL_DEFAULT_RESOLUTION,
        description="Grid radii per safe step of the OR-Tools graph (the recursion is continuous).",
    )
    center: Point = Field(default=[0.0, 0.0], description="Centre of the spiral, world frame.")
    clockwise: StrictBool = Field(default=True, description="Direction of travel of the pusher.")
    start_angle: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=-100.0, le=100.0)] = Field(
        default=0.5 * math.pi, description="Polar angle (rad) of the pusher's start about the centre."
    )
    points_per_revolution: Annotated[
        int, Field(strict=True, ge=SPIRAL_MIN_POINTS_PER_REVOLUTION, le=SPIRAL_MAX_POINTS_PER_REVOLUTION)
    ] = Field(default=SPIRAL_DEFAULT_POINTS_PER_REVOLUTION, description="Polyline points per revolution.")
    include_path: StrictBool = Field(default=True, description="Return the pusher's path as a polyline.")
    simulate: SimulationIn | None = Field(default=None, description="Optional simulation check of the schedule.")
    time_limit_s: TimeLimit = Field(
        default=SPIRAL_DEFAULT_TIME_LIMIT_S,
        description=f"Time budget, seconds, {TIME_LIMIT_CAP_TEXT}, shared by the table, the schedule and the simulation.",
    )


class CertificateOut(Out):
    certified: bool = Field(description="Dual feasible potentials whose bound equals the schedule's cost: optimal.")
    primal_cost: int = Field(description="The schedule's cost in integer units (see cost_unit).")
    dual_bound: int = Field(description="The shortest-path potentials' lower bound on every schedule's cost.")
    gap: int = Field(
        description="primal_cost - dual_bound, in integer cost units (see cost_unit); 0 when the schedule is "
        "certified optimal."
    )
    min_reduced_cost: int = Field(description=">= 0: the potentials are dual feasible.")
    n_arcs_checked: int = Field(
        description="Number of arcs (revolutions of the grid from radii reachable from b_1) whose reduced cost was "
        "checked."
    )
    cost_unit: float = Field(description="Length per cost unit ('length'), or 1 revolution.")
    revolution_weight: int | None = Field(
        description="Objective 'revolutions': the cost of one revolution, in units of cost_unit (a revolution costs "
        "this plus its length, so the fewest revolutions come first and the shortest of them second); null when "
        "each revolution costs 1."
    )
    path_potentials: list[int] = Field(
        description="The shortest-path potentials (the dual weights) at the schedule's radii, b_1 first (0) to the "
        "target (= dual_bound): each of the schedule's revolutions has reduced cost 0, every revolution of the grid "
        ">= 0 (min_reduced_cost), which proves that no schedule on the grid costs less."
    )


class ScheduleOut(Out):
    solver_status: str = Field(description="'OPTIMAL', 'FEASIBLE' (stopped early), 'INFEASIBLE', 'TIME_LIMIT'.")
    optimal_among: str = Field(
        description="What 'optimal' is relative to: the schedules whose radii lie on the grid (n_nodes radii, "
        "holding the recursion's, so never worse than the recursion (4.26)) and that are safe by the table's r*."
    )
    stopped_early: bool = Field(
        description="Whether the time limit stopped the search before optimality was proven: CP-SAT 'FEASIBLE' or "
        "'UNKNOWN', or 'TIME_LIMIT' before solving."
    )
    objective: Objective = Field(
        description="The objective asked for: 'revolutions' (fewest, ties by length), 'length' (shortest path) or "
        "'time' (length / speed)."
    )
    objective_value: float | None = Field(
        description="The objective's value: revolutions, path length (request's length unit) or time (seconds); null "
        "when no schedule was found."
    )
    backend: Backend = Field(
        description="OR-Tools solver used: 'min_cost_flow' (SimpleMinCostFlow) or 'cp_sat'."
    )
    radii: list[float] = Field(description="b_1 ... b_N, one per revolution (grid radii).")
    steps: list[float] = Field(description="b_{n-1} - b_n.")
    revolutions: int = Field(
        description="Number of revolutions N, one per radius b_1 ... b_N (the last is the final circle); 0 when no "
        "schedule was found."
    )
    path_length: float | None = Field(
        description="Length of the pusher's path along the schedule, final circle included (request's length unit); "
        "null when no schedule was found."
    )
    path_length_error: float | None = Field(
        description="Upper bound on the quadrature error of path_length (request's length unit); null when no "
        "schedule was found."
    )
    time_s: float | None = Field(
        description="Time to run the path at `speed`, path_length / speed, seconds; null without a speed or without a "
        "schedule."
    )
    certificate: CertificateOut | None = Field(
        description="The optimality certificate by shortest-path potentials, in integer arc costs; null when no "
        "schedule was found."
    )
    greedy_revolutions: int | None = Field(description="The greedy recursion on the same grid.")
    greedy_path_length: float | None = Field(
        description="Path length of the greedy recursion on the same grid (request's length unit); null when the "
        "greedy recursion finds no path."
    )
    max_step_excess: float | None = Field(description="max_n (b_{n-1} - b_n - d*(b_n)) <= 0: every revolution safe.")
    n_nodes: int = Field(
        description="Number of grid radii (nodes of the OR-Tools graph), the recursion's radii included."
    )
    n_arcs: int = Field(
        description="Number of arcs of the graph: safe revolutions between grid radii within the step limits."
    )
    grid_kind: str = Field(
        description="How the grid of radii was made: 'adaptive' (`resolution` radii per safe step) or 'uniform' (a "
        "fixed spacing)."
    )
    min_spacing: float = Field(
        description="Smallest gap between neighbouring grid radii (request's length unit)."
    )
    max_spacing: float = Field(
        description="Largest gap between neighbouring grid radii (request's length unit)."
    )
    solve_time_s: float = Field(
        description="Time OR-Tools took to solve the shortest path, seconds (0 when it did not run)."
    )
    total_time_s: float = Field(
        description="Time for the whole schedule: the recursion, the grid, the graph, its costs and the solve, "
        "seconds."
    )
    message: str = Field(
        description="The solve in words: status, grid size and safe revolutions, whether stopped early or certified "
        "optimal, or why there is no schedule."
    )


class RecursionOut(Out):
    radii: list[float] = Field(description="The book's (4.26), b_n = b_{n-1} - d*(b_n), exactly on the envelope.")
    revolutions: int = Field(
        description="Number of revolutions N of the recursion, one per radius b_1 ... b_N (the last is the final "
        "circle)."
    )
    stop_reason: str = Field(description="'target', 'stalled' (at the table's floor) or 'max_revolutions'.")
    reached_target: bool = Field(
        description="Whether the recursion reached a radius at or below the target (stop_reason 'target')."
    )
    path_length: float = Field(
        description="Length of the pusher's path along the recursion's radii, final circle included (request's length "
        "unit)."
    )
    time_s: float | None = Field(
        description="Time to run that path at `speed`, path_length / speed, seconds; null without a speed."
    )
    max_step_excess: float = Field(
        description="max_n (b_{n-1} - b_n - d*(b_n)) (request's length unit): <= 0 when every revolution is safe."
    )


class TipLineScheduleOut(Out):
    """The spiral schedule of (4.26) with the book's tip-line approximation of r*."""

    revolutions: int = Field(description="Revolutions of (4.26) with the tip line's d* (closed form).")
    final_radius: float = Field(description="The radius it ends at (the request's length unit, from the centre).")
    reaches_target: bool = Field(description="False: the tip line stalls at 2a above the target.")
    unsafe_revolutions: int = Field(
        description="Its revolutions shown unsafe by the request's r* table: some collision parameter the step "
        "allows has r* above the new radius (no margin)."
    )
    revolutions_difference: int | None = Field(description="Tip line minus the OR-Tools schedule.")


class FitOut(Out):
    exponent: float = Field(
        description="k of (b_n - b_floor) ~ C n^-k over the revolutions within a of the floor (figure 4-21; the "
        "book reads ~1.6 at mu_c 0.25 from b_1 = 100 a; the exponent drifts towards 1 as n grows)."
    )
    coefficient: float = Field(description="C (length).")
    n_min: int = Field(
        description="First revolution of the fit range (revolutions counted from 1 at b_1)."
    )
    n_max: int = Field(
        description="Last revolution of the fit range (revolutions counted from 1 at b_1)."
    )
    n_points: int = Field(
        description="Number of revolutions fitted (those in [n_min, n_max] above the floor)."
    )
    rms_residual: float = Field(
        description="Root mean square residual of the least-squares fit of log(b_n - b_floor), natural-log units."
    )
    local_exponent_min: float = Field(
        description="Smallest local exponent -d log(b_n - b_floor) / d log n between consecutive fitted revolutions."
    )
    local_exponent_max: float = Field(
        description="Largest local exponent -d log(b_n - b_floor) / d log n between consecutive fitted revolutions."
    )


class PathOut(Out):
    points: list[list[float]] = Field(description="The pusher path [[x, y], ...], world frame.")
    points_per_revolution: int = Field(description="Used (lowered for very long schedules).")
    max_chord_deviation: float = Field(description="Upper bound on the distance between the path and its chords.")
    polyline_length: float = Field(
        description="Length of the returned polyline, the sum of its chords (request's length unit)."
    )
    clockwise: bool = Field(
        description="Whether the pusher travels clockwise about the centre (the request's `clockwise`)."
    )


class SimulationOut(Out):
    n: int = Field(
        description="Number of simulated disks (the request's `simulate.n_supports`), run or not."
    )
    all_inside: bool = Field(description="Every run completed, none pushed out, all inside the promised radius.")
    escaped: int = Field(
        description="Number of runs in which the disk was pushed out of the spiral."
    )
    escaped_runs: list[int] = Field(
        description="Indices of the runs in which the disk was pushed out."
    )
    outside_promise_runs: list[int] = Field(
        description="Indices of the runs that ran but did not end completed with the disk inside the promised radius "
        "(escaped or cut short included)."
    )
    promised_radius: float = Field(description="The final revolution's radius: the disk must end inside it.")
    max_final_extent: float | None = Field(description="max over runs of |CM - centre| + a at the end.")
    margin: float | None = Field(description="promised_radius - max_final_extent.")
    contacts: int = Field(
        description="Number of pusher-disk contacts (collisions) over all runs."
    )
    statuses: dict[str, int] = Field(
        description="Runs per status: 'completed', 'in_contact_at_end', 'escaped', 'time_limit', 'step_limit', "
        "'solver_error', 'not_run' (skipped by the time limit)."
    )
    forward_solves: int = Field(
        description="Number of forward minimum-power solves of the disk's motion over all runs."
    )
    solver_failures: int = Field(
        description="Number of runs ended by a solver error (status 'solver_error')."
    )
    wall_time_s: float = Field(
        description="Wall-clock time the simulation took, seconds."
    )
    seed: int = Field(
        description="Seed of the random supports and starts (the request's `simulate.seed`)."
    )
    kind: SupportKind = Field(
        description="Kind of random support simulated, as asked: 'tripod', 'rim', 'dipod' or 'cloud'."
    )


class TableOut(Out):
    n_points: int = Field(description="Collision parameters in the r* table.")
    betas: list[float] = Field(description="The table's collision parameters beta (rad), ascending.")
    radii: list[float | None] = Field(
        description="r*(beta) at each (request units; null where none was found). The schedule is safe by these."
    )
    certified: list[bool] = Field(description="Whether each r* carries its certificate (method 'exact').")
    complete: bool = Field(
        description="Whether every planned collision parameter of the r* table was evaluated."
    )
    time_limited: bool = Field(
        description="Whether the time limit stopped the table early (it then covers only the collision parameters "
        "nearest grazing)."
    )
    covers_radius: float = Field(
        description="The largest pusher radius the table covers: above it d* is that of its smallest beta (safe, "
        "slower than necessary)."
    )
    from_cache: bool = Field(
        description="Whether the table came from the service's in-memory cache of complete tables (computed for a = 1 "
        "and scaled)."
    )
    monotone: bool = Field(
        description="Whether r* never increases with beta on the table (the envelope's assumption); false when the "
        "table has no usable point."
    )
    message: str = Field(
        description="The table in words: collision parameters done of those planned, the method, the safety margin, "
        "time limit, dropped points, increases of r*."
    )


class SpiralScheduleResponse(Out):
    message: str = Field(
        description="The plan in words: revolutions of the schedule and of (4.26), the tip line's, the table's reach, "
        "and the simulation's outcome."
    )
    disk_radius: float = Field(
        description="Radius a of the disk, as given (request's length unit)."
    )
    mu_c: float = Field(
        description="Pusher-disk friction coefficient, as given."
    )
    method: SpiralMethod = Field(
        description="How r* was found, as asked: 'sweep', 'exact' or 'tip_line'."
    )
    safety_margin: float = Field(description="Added to r* (units of a).")
    b_inf: float = Field(description="(4.25).")
    b_floor: float = Field(description="The table's smallest radius with a guarantee (its b_inf, plus the margin).")
    table: TableOut = Field(description="The r* table the plan rests on.")
    schedule: ScheduleOut | None = Field(description="The OR-Tools optimum on a grid of radii.")
    recursion: RecursionOut = Field(description="The book's recursion (4.26) on the same table.")
    tip_line: TipLineScheduleOut = Field(description="The same with the book's tip-line approximation.")
    fit: FitOut | None = Field(description="The approach to the floor (figure 4-21), when >= 3 revolutions lie above it.")
    path: PathOut | None = Field(
        description="The pusher's path as a world-frame polyline: points, points per revolution, chord deviation, "
        "length, sense; null when `include_path` is false."
    )
    simulation: SimulationOut | None = Field(
        description="The simulation check: random disks pushed along the path by the forward solver; null unless "
        "`simulate` was given."
    )
    reference: str = Field(
        description="The book's sections, equations and figures the answer rests on, as text."
    )
    time_limit_s: float = Field(
        description="The request's time limit (its `time_limit_s` or the route's default), seconds."
    )
    elapsed_ms: float = Field(description=ELAPSED_MS_DESCRIPTION)
