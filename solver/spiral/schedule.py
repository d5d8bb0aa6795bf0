"""The fastest guaranteed spiral of spiral localization (book 4.5.5) as a shortest path
solved by OR-Tools (SimpleMinCostFlow, or CP-SAT with a time limit) and certified by
shortest-path potentials (an LP dual whose bound equals the objective). The critical
radius it rests on is :mod:`solver.spiral.critical_radius`; the envelope, the recursion
(4.26) and the grid graph are :mod:`models.spiral.critical`, :mod:`models.spiral.path` and
:mod:`models.spiral.graph`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from models.core.errors import InvalidInput
from models.core.tolerances import SPIRAL_DEFAULT, SpiralTolerances
from models.spiral.critical import CriticalEnvelope
from models.spiral.graph import (
    ScheduleGraph,
    arc_costs,
    greedy_on_graph,
    schedule_graph,
    schedule_grid,
    shortest_path_potentials,
)
from models.spiral.path import SpiralRecursion, fastest_spiral, spiral_path_length
from solver.core.backends import in_backend
from solver.core.budget import UNLIMITED, Budget
from solver.core.errors import SolverError
from solver.spiral.critical_radius import envelope_of

# --------------------------------------------------------------------------------------
# The fastest guaranteed spiral on OR-Tools (4.5.5)

OBJECTIVES = ("revolutions", "length", "time")
BACKENDS = ("min_cost_flow", "cp_sat")

CP_SAT_MAX_ARCS = 300_000
"""Largest graph handed to CP-SAT (one Boolean per arc)."""


@dataclass(frozen=True)
class ScheduleCertificate:
    """Optimality certificate of a grid schedule, in the integer arc costs (exact):
    shortest-path potentials pi (pi_{b_1} = 0) with every arc's reduced cost c_ij + pi_i -
    pi_j >= 0 (``min_reduced_cost``, over arcs from reachable nodes) make pi_target a lower
    bound (``dual_bound``) on the cost of every schedule; ``primal_cost`` is the solver's
    schedule's cost, recomputed from its arcs. ``certified`` = dual feasible and gap 0.
    The costs are those of the revolutions from b_1 to the target (the final circle is
    common to all schedules and left out). ``cost_unit``: world length per cost unit;
    "revolutions" costs each revolution ``revolution_weight`` plus its length in units of
    cost_unit (a lexicographic objective: the weight exceeds the length of any path with
    the fewest revolutions), or 1 per revolution when ``revolution_weight`` is None."""

    primal_cost: int
    dual_bound: int
    gap: int
    min_reduced_cost: int
    n_arcs_checked: int
    cost_unit: float
    certified: bool
    revolution_weight: int | None = None
    path_potentials: tuple[int, ...] = ()
    """pi at the schedule's radii, b_1 first (0) to the target (= dual_bound): along the
    schedule every arc's reduced cost is 0, which is why its cost equals the bound."""


@dataclass(frozen=True)
class SpiralSchedule:
    """The fastest guaranteed spiral on a grid of radii (4.5.5), solved on OR-Tools.

    ``radii`` b_1 ... b_N (grid points, b_N = target); ``revolutions`` = N (the last is
    the final circle, models/spiral/path.py); ``steps``; ``path_length`` (+ its quadrature error
    bound ``path_length_error``); ``time_s`` = path_length / speed. ``objective`` and
    ``objective_value`` (revolutions, or the length). ``solver_status``: "OPTIMAL",
    "FEASIBLE" (CP-SAT stopped by the time limit: ``stopped_early``), "INFEASIBLE" (no safe
    schedule on this grid), or "TIME_LIMIT" (stopped before solving). ``certificate``.
    ``greedy_*``: the greedy recursion on the same grid (optimal without a minimum step, so
    it must match); ``recursion``: the book's continuous recursion (4.26) with the same
    maximum step, ignoring a minimum step (its radii are elementwise <= those of any
    schedule without a minimum step, and its revolutions a lower bound in any case). ``max_step_excess`` =
    max_n (b_{n-1} - b_n - D(b_n)) <= 0 (safety of every revolution)."""

    objective: str
    backend: str
    solver_status: str
    stopped_early: bool
    radii: np.ndarray
    steps: np.ndarray
    revolutions: int
    path_length: float | None
    path_length_error: float | None
    speed: float | None
    time_s: float | None
    objective_value: float | None
    certificate: ScheduleCertificate | None
    greedy_revolutions: int | None
    greedy_path_length: float | None
    recursion: SpiralRecursion | None
    max_step_excess: float | None
    b_1: float
    target: float
    b_floor: float
    min_step: float | None
    max_step: float | None
    n_nodes: int
    n_arcs: int
    grid_kind: str
    min_spacing: float
    max_spacing: float
    build_time_s: float
    solve_time_s: float
    total_time_s: float
    message: str

    @property
    def status(self) -> str:
        """The solver's status ("OPTIMAL", "FEASIBLE", "INFEASIBLE", "TIME_LIMIT", ...)."""
        return self.solver_status

    @property
    def complete(self) -> bool:
        """An optimal schedule was found (and certified by the potentials)."""
        return self.solver_status == "OPTIMAL" and not self.stopped_early


def _solve_min_cost_flow(graph, costs):
    from ortools.graph.python import min_cost_flow

    n = graph.x.size
    mcf = min_cost_flow.SimpleMinCostFlow()
    arcs = mcf.add_arcs_with_capacity_and_unit_cost(graph.tails, graph.heads, np.ones(graph.n_arcs, dtype=np.int64),
                                                    costs)
    mcf.set_nodes_supplies(np.array([n - 1, 0]), np.array([1, -1]))
    with in_backend("ortools"):
        status = mcf.solve()
    names = {mcf.OPTIMAL: "OPTIMAL", mcf.FEASIBLE: "FEASIBLE", mcf.INFEASIBLE: "INFEASIBLE",
             mcf.UNBALANCED: "UNBALANCED", mcf.NOT_SOLVED: "NOT_SOLVED", mcf.BAD_RESULT: "BAD_RESULT",
             mcf.BAD_COST_RANGE: "BAD_COST_RANGE", mcf.BAD_CAPACITY_RANGE: "BAD_CAPACITY_RANGE"}
    name = names.get(status, str(status))
    if status != mcf.OPTIMAL:
        return name, None, False
    used = np.nonzero(mcf.flows(arcs) > 0)[0]
    return name, used, False


def _solve_cp_sat(graph, costs, hint_arcs, time_limit_s):
    from ortools.sat.python import cp_model

    n = graph.x.size
    model = cp_model.CpModel()
    xs = [model.new_bool_var(f"a{k}") for k in range(graph.n_arcs)]
    out_of = [[] for _ in range(n)]
    into = [[] for _ in range(n)]
    for k, (t, h) in enumerate(zip(graph.tails.tolist(), graph.heads.tolist())):
        out_of[t].append(xs[k])
        into[h].append(xs[k])
    for v in range(n):
        supply = 1 if v == n - 1 else (-1 if v == 0 else 0)
        model.add(sum(out_of[v]) - sum(into[v]) == supply)
    model.minimize(cp_model.LinearExpr.weighted_sum(xs, costs.tolist()))
    if hint_arcs is not None:
        hint = set(hint_arcs.tolist())
        for k, v in enumerate(xs):
            model.add_hint(v, k in hint)
    solver = cp_model.CpSolver()
    if time_limit_s is not None:
        solver.parameters.max_time_in_seconds = max(float(time_limit_s), 1e-3)
    solver.parameters.num_workers = 1
    with in_backend("ortools"):
        status = solver.solve(model)
    name = solver.status_name(status)
    if status not in (cp_model.OPTIMAL, cp_model.FEASIBLE):
        return name, None, status == cp_model.UNKNOWN
    used = np.array([k for k, v in enumerate(xs) if solver.boolean_value(v)], dtype=np.int64)
    return name, used, status == cp_model.FEASIBLE


def _path_from_arcs(graph, used) -> np.ndarray:
    nxt = dict(zip(graph.tails[used].tolist(), graph.heads[used].tolist()))
    node = graph.x.size - 1
    path = [node]
    while node != 0:
        if node not in nxt or len(path) > graph.x.size:
            raise SolverError("the solver's flow is not a path from b_1 to the target")
        node = nxt[node]
        path.append(node)
    return np.asarray(path)


def _arc_index(graph):
    cnt = np.maximum(graph.hi - graph.lo + 1, 0)
    off = np.r_[0, np.cumsum(cnt)]

    def index(i, j):
        return int(off[j] + (i - graph.lo[j]))

    return index


def _checked_request(env: CriticalEnvelope, b_1: float, target: float, objective: str, min_step: float | None,
                     max_step: float | None, speed: float | None, backend: str) -> tuple[float, float]:
    """(b_1, target) as floats; InvalidInput naming the argument that cannot be planned."""
    if objective not in OBJECTIVES:
        raise InvalidInput("objective", f"must be one of {', '.join(OBJECTIVES)}")
    if backend not in BACKENDS:
        raise InvalidInput("backend", f"must be one of {', '.join(BACKENDS)}")
    if objective == "time" and speed is None:
        raise InvalidInput("speed", "the 'time' objective needs the pusher speed")
    if speed is not None and not (math.isfinite(float(speed)) and float(speed) > 0.0):
        raise InvalidInput("speed", "must be a positive finite speed")
    for name, v in (("min_step", min_step), ("max_step", max_step)):
        if v is not None and not (math.isfinite(float(v)) and float(v) > 0.0):
            raise InvalidInput(name, "must be a positive finite length")
    if min_step is not None and max_step is not None and float(min_step) > float(max_step):
        raise InvalidInput("min_step", "must not exceed max_step")
    b_1, target = float(b_1), float(target)
    if not (math.isfinite(b_1) and math.isfinite(target) and 0.0 < target < b_1):
        raise InvalidInput("target", "need 0 < target < b_1")
    if target < env.b_floor:
        raise InvalidInput(
            "target",
            f"is below {env.b_floor:.9g}, the smallest radius with any guarantee in this table (its b_inf, 4.5.4): "
            "no spiral can localize the disk further",
        )
    return b_1, target


def _integer_costs(graph: ScheduleGraph, objective: str, a: float, spiral_tol: SpiralTolerances
                   ) -> tuple[np.ndarray, np.ndarray, float, int | None]:
    """The arcs' integer costs, their shortest-path potentials, the cost unit and, for
    "revolutions", the weight of one revolution. Revolutions are lexicographic: first
    their number, then the length (to tie_break_unit_rel a), so that the schedule is also
    the shortest of the fewest-revolution ones (when the weighted costs fit in 62 bits)."""
    weight = None
    if objective == "revolutions":
        unit = spiral_tol.tie_break_unit_rel * a
        costs = np.ones(graph.n_arcs, dtype=np.int64)
        pot = shortest_path_potentials(graph, costs)
        tie = arc_costs(graph, "length", unit, spiral_tol.arc_nodes)
        if pot[0] >= 0 and tie.size:
            w = int(pot[0]) * int(tie.max()) + 1  # > the length of any path with pot[0] arcs
            if (w + int(tie.max())) * (int(pot[0]) + 1) * graph.x.size < 2 ** 62:
                weight = w
                costs = tie + w
                pot = shortest_path_potentials(graph, costs)
        if weight is None:
            unit = 1.0
    else:
        unit = spiral_tol.length_unit_rel * a
        costs = arc_costs(graph, "length", unit, spiral_tol.arc_nodes)
        pot = shortest_path_potentials(graph, costs)
    return costs, pot, unit, weight


def _certificate(graph: ScheduleGraph, costs: np.ndarray, pot: np.ndarray, used: np.ndarray, path: np.ndarray,
                 unit: float, weight: int | None) -> ScheduleCertificate:
    """The optimality certificate of the arcs ``used``: their cost against the dual bound of
    the shortest-path potentials, and the least reduced cost over the reachable arcs."""
    primal = int(costs[used].sum())
    reach = pot[graph.tails] >= 0
    rc = costs[reach] + pot[graph.tails[reach]] - pot[graph.heads[reach]]
    min_rc = int(rc.min()) if rc.size else 0
    dual = int(pot[0])
    return ScheduleCertificate(primal_cost=primal, dual_bound=dual, gap=primal - dual, min_reduced_cost=min_rc,
                               n_arcs_checked=int(rc.size), cost_unit=unit, certified=bool(min_rc >= 0 and primal == dual),
                               revolution_weight=weight, path_potentials=tuple(int(pot[k]) for k in path))


def spiral_schedule(table, b_1: float, target: float, objective: str = "revolutions", min_step: float | None = None,
                    max_step: float | None = None, speed: float | None = None, spacing: float | None = None,
                    resolution: int = 16, max_nodes: int = 200_000, max_arcs: int = 5_000_000,
                    backend: str = "min_cost_flow", budget: Budget = UNLIMITED,
                    spiral_tol: SpiralTolerances = SPIRAL_DEFAULT) -> SpiralSchedule:
    """The schedule of radii from ``b_1`` down to ``target`` with the fewest revolutions
    (``objective`` "revolutions") or the shortest path ("length"; "time" = length / speed,
    the same optimum, needs ``speed``), every revolution safe (b_{n-1} - b_n <= d*(b_n),
    4.26) and within the robot's ``min_step`` / ``max_step``, as a shortest path over the
    grid of :func:`models.spiral.graph.schedule_grid` (uniform ``spacing`` or adaptive with
    ``resolution`` points per safe step). ``table``: a CriticalRadiusTable or a
    CriticalEnvelope. ``backend`` "min_cost_flow" (OR-Tools SimpleMinCostFlow; ``budget``
    is checked between the build and the solve) or "cp_sat" (the remaining time is CP-SAT's
    own limit; FEASIBLE = stopped early). The optimum is certified by shortest-path potentials
    (:class:`ScheduleCertificate`)."""
    t0 = time.perf_counter()
    env = envelope_of(table)
    b_1, target = _checked_request(env, b_1, target, objective, min_step, max_step, speed, backend)
    # the book's recursion with the same maximum step; it ignores a minimum step, so it is
    # then only a lower bound on the revolutions
    recursion = fastest_spiral(env, b_1, target, max_step=max_step, speed=speed, tol=spiral_tol)
    x = schedule_grid(env, b_1, target, spacing=spacing, resolution=resolution, max_nodes=max_nodes, max_step=max_step)
    # the grid holds the recursion's radii, so that the recursion's schedule (its last
    # radius moved up to the target, still safe: x + D(x) is nondecreasing) is a path of
    # the graph and the optimum on the grid is never worse than the recursion
    inner = recursion.radii[(recursion.radii > target) & (recursion.radii < b_1)]
    x = np.unique(np.concatenate([x, inner]))
    graph = schedule_graph(env, x, min_step=min_step, max_step=max_step)
    grid_kind = "uniform" if spacing is not None else "adaptive"
    sp = np.diff(x)
    common = dict(b_1=b_1, target=target, b_floor=env.b_floor, min_step=min_step, max_step=max_step,
                  n_nodes=int(x.size), n_arcs=graph.n_arcs, grid_kind=grid_kind, min_spacing=float(sp.min()),
                  max_spacing=float(sp.max()), speed=None if speed is None else float(speed))
    if graph.n_arcs > max_arcs:
        raise InvalidInput("spacing" if spacing is not None else "resolution",
                           f"the grid has {graph.n_arcs} arcs, more than max_arcs = {max_arcs}: coarsen it")
    if backend == "cp_sat" and graph.n_arcs > CP_SAT_MAX_ARCS:
        raise InvalidInput("backend", f"cp_sat takes at most {CP_SAT_MAX_ARCS} arcs ({graph.n_arcs} here)")
    costs, pot, unit, weight = _integer_costs(graph, objective, env.a, spiral_tol)
    greedy = greedy_on_graph(graph)
    g_rev = g_len = None
    if greedy is not None:
        g_rev = int(greedy.size)
        g_len = spiral_path_length(x[greedy], nodes=spiral_tol.arc_nodes)[0]
    build = time.perf_counter() - t0

    def empty(status, stopped, msg):
        return SpiralSchedule(
            objective=objective, backend=backend, solver_status=status, stopped_early=stopped, radii=np.empty(0),
            steps=np.empty(0), revolutions=0, path_length=None, path_length_error=None, time_s=None,
            objective_value=None, certificate=None, greedy_revolutions=g_rev, greedy_path_length=g_len,
            recursion=recursion, max_step_excess=None, build_time_s=build, solve_time_s=0.0,
            total_time_s=time.perf_counter() - t0, message=msg, **common,
        )

    if pot[0] < 0:
        return empty("INFEASIBLE", False, "no safe schedule reaches the target on this grid: the safe steps near the "
                     "target are shorter than the grid spacing or the minimum step; refine the grid or raise the target")
    if budget.expired():
        return empty("TIME_LIMIT", True, f"time limit reached after building the graph ({build:.3g} s), before solving")
    t1 = time.perf_counter()
    if backend == "min_cost_flow":
        status, used, stopped = _solve_min_cost_flow(graph, costs)
    else:
        idx = _arc_index(graph)
        hint = None if greedy is None else np.array([idx(i, j) for i, j in zip(greedy[:-1], greedy[1:])])
        status, used, stopped = _solve_cp_sat(graph, costs, hint, budget.remaining_or_none())
    solve = time.perf_counter() - t1
    if used is None:
        return empty(status, stopped, f"the {backend} solve ended with status {status}")
    path = _path_from_arcs(graph, used)
    cert = _certificate(graph, costs, pot, used, path, unit, weight)
    radii = x[path]
    steps = -np.diff(radii)
    excess = float(np.max(steps - env.d_star(radii[1:], max_step))) if steps.size else 0.0
    length, lerr = spiral_path_length(radii, nodes=spiral_tol.arc_nodes)
    value = float(radii.size) if objective == "revolutions" else (length if objective == "length" else length / float(speed))
    msg = f"{status} on a {grid_kind} grid of {x.size} radii and {graph.n_arcs} safe revolutions"
    if stopped:
        msg += "; stopped early by the time limit (best schedule found, gap in the certificate)"
    if cert.certified:
        msg += ("; certified optimal by shortest-path potentials, among the schedules whose radii are on this grid "
                "(which holds the recursion's radii, so it is never worse than the recursion (4.26)) and safe by "
                "this r* table")
    return SpiralSchedule(
        objective=objective, backend=backend, solver_status=status, stopped_early=bool(stopped), radii=radii,
        steps=steps, revolutions=int(radii.size), path_length=length, path_length_error=lerr,
        time_s=None if speed is None else length / float(speed), objective_value=value, certificate=cert,
        greedy_revolutions=g_rev, greedy_path_length=g_len, recursion=recursion, max_step_excess=excess,
        build_time_s=build, solve_time_s=solve, total_time_s=time.perf_counter() - t0, message=msg, **common,
    )
