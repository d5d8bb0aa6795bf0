"""Spiral localization of a disk (book 4.5.5), planned in one call: the critical-radius
table (cached, or computed for the problem), the fastest guaranteed spiral on OR-Tools and
the recursion (4.26) beside it, the tip-line recursion with its unsafe revolutions, the
power law of figure 4-21, the pusher's path as a polyline and, on request, disks with
random pressure distributions pushed along it (:func:`solver.spiral.simulate.spiral_check`).

One budget serves the table, the schedule and the simulation, in that order. A table cut
short by the budget before it covers the start radius raises
:class:`solver.core.errors.TimeLimitReached` (``partial``: the table).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from models.core.errors import InvalidInput
from models.core.tolerances import SPIRAL_DEFAULT, SpiralTolerances
from models.spiral.critical import limiting_radius
from models.spiral.path import (
    PowerLawFit,
    SpiralPolyline,
    SpiralRecursion,
    fastest_spiral,
    power_law_fit,
    spiral_polyline,
    tip_line_spiral,
    unsafe_revolutions,
)
from solver.core.budget import UNLIMITED, Budget
from solver.core.errors import NotConverged, TimeLimitReached
from solver.core.store import ResultStore
from solver.core.tolerances import SOLVER_DEFAULT, SolverTolerances
from solver.spiral.critical_radius import (
    BETA_GRID,
    SWEEP_POINTS,
    BetaGrid,
    CriticalRadiusTable,
    cached_critical_radius_table,
    critical_radius_table,
)
from solver.spiral.schedule import SpiralSchedule, spiral_schedule
from solver.spiral.simulate import SpiralBatch, spiral_check, spiral_path


@dataclass(frozen=True)
class PathQuery:
    """The pusher's path as a polyline with ``points_per_revolution`` points per
    revolution, lowered (not below ``min_points_per_revolution``) so that the path has at
    most ``max_points`` points."""

    points_per_revolution: int = 64
    min_points_per_revolution: int = 8
    max_points: int = 200_000


@dataclass(frozen=True)
class SimulationQuery:
    """The simulation check: ``n_supports`` random supports of ``kind`` (seeded by ``seed``)
    from random starts within b_1 - a, pushed along the planned path by the forward solver."""

    n_supports: int = 8
    seed: int = 0
    kind: str = "tripod"


@dataclass(frozen=True)
class SpiralProblem:
    """Localise a disk of radius ``disk_radius`` (pusher friction ``mu_c``) lying within
    ``start_radius`` - a of ``center``, down to a final radius <= ``target``.

    The table: r*(beta) by ``method`` ("sweep", "exact", "tip_line") with
    ``sweep_points`` per locus, every r* raised by ``safety_margin`` (units of a) for the
    schedule; ``cached``: through the cache of complete tables at a = 1 (default grid and
    spiral tolerances), else computed for this problem on ``grid``. The schedule:
    ``objective`` ("revolutions", "length", "time"), robot limits ``min_step`` /
    ``max_step``, pusher ``speed``, OR-Tools ``backend``, ``resolution`` grid radii per safe
    step (or a uniform ``spacing``), at most ``max_nodes`` / ``max_arcs``. The path:
    ``clockwise`` from ``start_angle`` (rad); ``path`` and ``simulate`` optional."""

    disk_radius: float
    mu_c: float
    start_radius: float
    target: float
    method: str = "sweep"
    safety_margin: float = 0.0
    objective: str = "revolutions"
    min_step: float | None = None
    max_step: float | None = None
    speed: float | None = None
    backend: str = "min_cost_flow"
    resolution: int = 16
    spacing: float | None = None
    center: tuple[float, float] = (0.0, 0.0)
    clockwise: bool = True
    start_angle: float = 0.5 * math.pi
    path: PathQuery | None = None
    simulate: SimulationQuery | None = None
    cached: bool = True
    sweep_points: int = SWEEP_POINTS
    grid: BetaGrid = BETA_GRID
    max_nodes: int = 200_000
    max_arcs: int = 5_000_000
    tol: SolverTolerances = SOLVER_DEFAULT
    spiral_tol: SpiralTolerances = SPIRAL_DEFAULT
    store: ResultStore | None = field(default=None, compare=False)
    """Where the r* rows outlive the process (the service's SQLite store), or None."""


@dataclass(frozen=True)
class TipLineComparison:
    """The recursion (4.26) with the tip line's d* (closed form): its ``radii`` and the
    number of its steps that the problem's own r* table shows unsafe (a witness collision
    parameter each, :func:`models.spiral.path.unsafe_revolutions`)."""

    radii: np.ndarray
    unsafe_revolutions: int


@dataclass(frozen=True)
class SpiralPlan:
    """The plan of a :class:`SpiralProblem`.

    ``table`` (r*(beta), ``from_cache``); ``schedule``: the OR-Tools optimum on the grid;
    ``recursion``: (4.26) on the table's envelope; ``radii``: the schedule's radii, or the
    recursion's when the schedule has none (what the path, the fit and the simulation
    use); ``tip_line``; ``fit``: figure 4-21's power law over the revolutions within a of
    the floor (None when it cannot be fitted); ``polyline`` (None unless asked for);
    ``simulation`` (None unless asked for); ``b_inf_closed_form`` (4.25), ``b_floor``."""

    problem: SpiralProblem
    table: CriticalRadiusTable
    from_cache: bool
    schedule: SpiralSchedule
    recursion: SpiralRecursion
    radii: np.ndarray
    tip_line: TipLineComparison
    fit: PowerLawFit | None
    polyline: SpiralPolyline | None
    simulation: SpiralBatch | None
    b_inf_closed_form: float
    b_floor: float
    solve_time_s: float

    @property
    def status(self) -> str:
        """The schedule's solver status ("OPTIMAL", "FEASIBLE", "INFEASIBLE", "TIME_LIMIT")."""
        return self.schedule.solver_status

    @property
    def complete(self) -> bool:
        sim_done = self.simulation is None or self.simulation.statuses.get("not_run", 0) == 0
        return self.table.complete and not self.schedule.stopped_early and sim_done

    @property
    def message(self) -> str:
        return f"{self.table.message}; {self.schedule.message}"


def _table(problem: SpiralProblem, budget: Budget) -> tuple[CriticalRadiusTable, bool]:
    p = problem
    if p.cached:
        return cached_critical_radius_table(p.disk_radius, p.mu_c, p.method, p.start_radius, budget=budget,
                                            sweep_points=p.sweep_points, margin_rel=p.safety_margin, tol=p.tol,
                                            store=p.store)
    tab = critical_radius_table(p.disk_radius, p.mu_c, p.method, r_max=p.start_radius, budget=budget, tol=p.tol,
                                spiral_tol=p.spiral_tol, sweep_points=p.sweep_points, grid=p.grid,
                                margin_rel=p.safety_margin, store=p.store)
    return tab, False


def fit_near_floor(radii: np.ndarray, floor: float, a: float) -> PowerLawFit | None:
    """Figure 4-21's power law over the revolutions within a of the floor (before that the
    spiral shrinks by almost a per revolution, 4.5.5), or over all when fewer than 3;
    None when it cannot be fitted."""
    near = np.nonzero(radii - floor < a)[0]
    n_min = int(near[0]) + 1 if near.size and radii.size - near[0] >= 3 else 1
    try:
        f = power_law_fit(radii, floor, n_min=n_min)
    except InvalidInput:
        return None
    if not (math.isfinite(f.exponent) and math.isfinite(f.coefficient)):
        return None
    return f


def plan_spiral(problem: SpiralProblem, budget: Budget = UNLIMITED) -> SpiralPlan:
    """The plan of ``problem`` within ``budget`` (module docstring). Raises
    :class:`TimeLimitReached` when the table does not reach the start radius in time,
    :class:`NotConverged` when it has no usable critical radius, and
    ``InvalidInput("target")`` when the target needs more than
    ``spiral_tol.max_revolutions`` revolutions."""
    t0 = time.perf_counter()
    p = problem
    a, mu, b_1, target = p.disk_radius, p.mu_c, p.start_radius, p.target
    tab, cached = _table(p, budget)
    env = tab.envelope
    if env is None:
        if tab.time_limited:
            raise TimeLimitReached("the first collision parameter of the r* table was decided", budget.limit_s,
                                   budget.elapsed(), tab)
        raise NotConverged(f"no usable critical radius: {tab.message}")
    if tab.time_limited and env.envelope[0] < b_1:
        # the table stopped near grazing: above its reach every step would be tiny
        raise TimeLimitReached(
            f"the r* table reached start_radius {b_1:.6g} (it covers pusher radii up to {env.envelope[0]:.6g})",
            budget.limit_s, budget.elapsed(), tab,
        )
    recursion = fastest_spiral(env, b_1, target, max_step=p.max_step, speed=p.speed, tol=p.spiral_tol)
    schedule = spiral_schedule(env, b_1, target, objective=p.objective, min_step=p.min_step, max_step=p.max_step,
                               speed=p.speed, spacing=p.spacing, resolution=p.resolution, backend=p.backend,
                               budget=budget, spiral_tol=p.spiral_tol, max_nodes=p.max_nodes, max_arcs=p.max_arcs)
    if recursion.stop_reason == "max_revolutions":
        raise InvalidInput("target", f"needs more than {p.spiral_tol.max_revolutions} revolutions (the spiral "
                           f"approaches its floor {env.b_floor:.6g} ever more slowly, figure 4-21): raise the target")
    radii = schedule.radii if schedule.radii.size else recursion.radii
    tip_radii = tip_line_spiral(a, b_1, target)
    tip = TipLineComparison(tip_radii, int(np.sum(unsafe_revolutions(tip_radii, tab.betas, tab.radii, a))))
    polyline = None
    if p.path is not None:
        q = p.path
        ppr = max(q.min_points_per_revolution, min(q.points_per_revolution, q.max_points // radii.size))
        polyline = spiral_polyline(radii, ppr, center=p.center, phase=p.start_angle, clockwise=p.clockwise)
    simulation = None
    if p.simulate is not None:
        s = p.simulate
        path = spiral_path(radii, centre=p.center, clockwise=p.clockwise, start_angle=p.start_angle)
        try:
            simulation = spiral_check(path, a, mu, s.n_supports, s.seed, kind=s.kind, promised_radius=float(radii[-1]),
                                      budget=budget)
        except InvalidInput as exc:
            raise InvalidInput(f"simulate.{exc.field}", exc.reason) from exc  # the problem's simulate part
    return SpiralPlan(
        problem=p, table=tab, from_cache=cached, schedule=schedule, recursion=recursion, radii=radii, tip_line=tip,
        fit=fit_near_floor(radii, env.b_floor, a), polyline=polyline, simulation=simulation,
        b_inf_closed_form=limiting_radius(a, mu), b_floor=env.b_floor, solve_time_s=time.perf_counter() - t0,
    )
