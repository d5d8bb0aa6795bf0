"""Spiral localization of a disk (book 4.5): the critical radius r*(beta), the limiting
radius b_inf, and the fastest guaranteed spiral as a shortest path solved by OR-Tools.

Critical radius (4.5.2-4.5.3). In the frame of models.gross_bounds.encounter_scene (disk
radius a, CM at the origin, contact a(-cos beta, sin beta), push along +x, pusher line
y = a sin beta) the sticking line is the vertical through the contact, and positions on
it are s = (r - c) . J p. The pusher centre PC must lie below the lower end of the
sticking locus (figure 4-18), so r*(beta) = -s_lower, the distance from the pusher line
to that end. Three ways to get it (``method``):

* "exact": solver/sticking.py's certified lower end (convex feasibility in the pressure
  distribution, a witness inside and a branch-and-bound dual outside). The safe value is
  the OUTSIDE (infeasible) end of the bracket: PC there is certainly below the locus. The
  midpoint and the bracket width are reported beside it.
* "sweep": the book's construction (4.1.4), a sweep of the force angle over the cone with
  the analytic loci (models/cor_sketch.py), exact up to the loci's polygon resolution
  (~1e-5 a at 1024 points, from the inscribed polygons: it errs slightly low, not safe).
* "tip_line": the book's approximation, r* = 2a / sin beta (4.13), independent of mu_c.

(4.5.4) b_inf = r*(beta -> pi/2); :func:`limiting_radius_check` compares the numerical
limit (at beta = pi/2 - grazing_delta; exactly pi/2 is a grazing touch and is refused)
with (4.25). (4.5.5) the schedule: models/spiral.py holds the envelope, the recursion
(4.26) and the grid graph; :func:`spiral_schedule` solves the shortest path on OR-Tools
(SimpleMinCostFlow, or CP-SAT with a time limit) and certifies it by shortest-path
potentials (an LP dual whose bound equals the objective).

Findings (tests/solver/test_spiral.py, docs/benchmarks.md "Spiral localization (4.5)"):
* (4.25) holds: the exact r*(pi/2 - 1e-6) is a(1 + mu_c) for mu_c <= 1 and 2a above,
  within ~1e-6 a.
* The tip line's grazing limit is 2a for every mu_c: for mu_c < 1 it overstates b_inf by
  a(1 - mu_c) (safe but slow); near mu_c = 1 at mid beta it understates r* (unsafe).
* Near grazing r* - b_inf is linear in pi/2 - beta for mu_c < 1 and mu_c > 1 (so
  b_n - b_inf ~ 1/n eventually) and quadratic at mu_c = 1; figure 4-21's "n^-1.6" is a
  pre-asymptotic slope (see the benchmark for the fits).
"""

from __future__ import annotations

import math
import time
import threading
from collections import OrderedDict
from dataclasses import dataclass, replace

import numpy as np

from models.cor_sketch import sticking_locus_sweep
from models.errors import InvalidInput
from models.gross_bounds import encounter_scene
from models.spiral import (
    SPIRAL_DEFAULT,
    CriticalEnvelope,
    SpiralRecursion,
    SpiralTolerances,
    arc_costs,
    critical_envelope,
    distance_from_grazing,
    fastest_spiral,
    greedy_on_graph,
    limiting_radius,
    schedule_graph,
    schedule_grid,
    shortest_path_potentials,
    spiral_path_length,
    tip_line_critical_radius,
)
from models.tolerances import SOLVER_DEFAULT, SolverTolerances
from solver.errors import SolverError
from solver.sticking import sticking_locus

METHODS = ("exact", "sweep", "tip_line")
"""Ways to compute r*(beta) (module docstring)."""

SWEEP_POINTS = 1024
"""Boundary points of each analytic locus in the "sweep" method (error ~1e-5 a)."""

KINK_SWEEP_POINTS = 256
"""Boundary points of the sweeps that locate the slope kink of r*(beta) (4.5.3)."""

KINK_ITERATIONS = 12
"""Bisection steps locating the kink (bracket (pi/2 - 0.3) / 2^12 ~ 3e-4 rad)."""

EMPTY_RETRY_SCAN = (384, 1536)
"""Scan probes of the retries when the exact sticking locus comes back empty: for small
mu_c near grazing the locus is ~2 mu_c a long and the default 96-probe scan of
solver/sticking.py can miss it (mu_c = 0.01 needs ~400 probes, 0.003 ~2000)."""

MIN_BETA = 1e-3
"""Smallest collision parameter accepted: r* ~ 2a / beta, so beta = 1e-3 is r* ~ 2000 a."""


def _check(a, beta, mu_c) -> tuple[float, float, float]:
    a = float(a)
    if not (math.isfinite(a) and a > 0.0):
        raise InvalidInput("a", "the disk radius must be a positive finite number")
    beta = float(beta)
    if not math.isfinite(beta) or beta >= 0.5 * math.pi or beta < MIN_BETA:
        raise InvalidInput(
            "beta",
            f"must lie in [{MIN_BETA:g}, pi/2): beta = pi/2 is a grazing touch (no pushing force); "
            "use pi/2 - 1e-6 for the limit (4.5.4)",
        )
    mu = float(mu_c)
    if not (math.isfinite(mu) and mu > 0.0):
        raise InvalidInput("mu_c", "must be a positive finite number (mu_c -> 0 gives b_inf -> a, (4.25))")
    return a, beta, mu


# --------------------------------------------------------------------------------------
# r*(beta)


@dataclass(frozen=True)
class CriticalRadius:
    """r*(beta) (4.5.3) for disk radius ``a`` and pusher friction ``mu_c``.

    ``radius``: the value to use (None if the computation failed): for "exact" the
    outside end of the certified bracket (a safe upper bound), for "sweep"/"tip_line" the
    approximation. ``midpoint``/``lower_bound``/``bracket_width``: the exact bracket
    (lower_bound = the inside end; None for the approximations). ``certified``: the bracket's
    outside end has a dual certificate. ``status``: the sticking end's status ("bracketed",
    "wide", ...) or "approximate". ``distance_from_grazing`` d = a(1 - sin beta) (4.24).
    ``tip_line_radius`` = 2a / sin beta beside it. ``end_beyond_disk``: the lower end lies
    outside the disk (r* > 2a sin beta); the slope kink of r* (4.5.3) is where it crosses.
    """

    a: float
    beta: float
    mu_c: float
    method: str
    radius: float | None
    midpoint: float | None
    lower_bound: float | None
    bracket_width: float | None
    certified: bool
    status: str
    distance_from_grazing: float
    tip_line_radius: float
    end_beyond_disk: bool | None
    solve_time_s: float
    message: str


def critical_radius(a: float, beta: float, mu_c: float, method: str = "exact", tol: SolverTolerances = SOLVER_DEFAULT,
                    time_limit_s: float | None = None, sweep_points: int = SWEEP_POINTS, seed: int = 0) -> CriticalRadius:
    """r*(beta): the distance from the pusher's line to the lower end of the sticking locus
    (4.5.3), by ``method`` "exact" | "sweep" | "tip_line" (module docstring). An exact locus
    that comes back empty is rescanned with more probes (EMPTY_RETRY_SCAN) while time is left."""
    a, beta, mu = _check(a, beta, mu_c)
    if method not in METHODS:
        raise InvalidInput("method", f"must be one of {', '.join(METHODS)}")
    t0 = time.perf_counter()
    d = float(distance_from_grazing(a, beta))
    tip = float(tip_line_critical_radius(a, beta))
    kink_at = 2.0 * a * math.sin(beta)
    if method == "tip_line":
        return CriticalRadius(a, beta, mu, method, tip, None, None, None, False, "approximate", d, tip, tip > kink_at,
                              time.perf_counter() - t0, "the book's tip-line approximation 2a/sin(beta) (4.13)")
    scene = encounter_scene(a, beta)
    if method == "sweep":
        st = sticking_locus_sweep(scene, mu, int(sweep_points))
        dt = time.perf_counter() - t0
        if st is None:
            return CriticalRadius(a, beta, mu, method, None, None, None, None, False, "empty", d, tip, None, dt,
                                  "the sweep found no sticking locus")
        r = -float(st.t_low)
        return CriticalRadius(a, beta, mu, method, r, None, None, None, False, "approximate", d, tip, r > kink_at, dt,
                              f"force-angle sweep (4.1.4) with {int(sweep_points)}-point loci; not certified")
    loc = sticking_locus(scene, mu, tol=tol, time_limit_s=time_limit_s, seed=seed)
    retries = []
    for n_scan in EMPTY_RETRY_SCAN:
        if loc.status != "empty" or loc.search_range[0] > loc.search_range[1]:  # empty range: sound
            break
        left = None if time_limit_s is None else float(time_limit_s) - (time.perf_counter() - t0)
        if left is not None and left <= 0.0:
            break
        retries.append(n_scan)
        loc = sticking_locus(scene, mu, tol=tol, time_limit_s=left, seed=seed, scan_points=n_scan)
    dt = time.perf_counter() - t0
    end = loc.lower
    if end is None or end.position >= 0.0:
        return CriticalRadius(a, beta, mu, method, None, None, None, None, False, loc.status, d, tip, None, dt,
                              f"no lower end below the contact: {loc.message}")
    ok = end.certified and end.infeasible_position is not None and end.feasible_position is not None
    radius = -float(end.infeasible_position) if end.infeasible_position is not None else None
    lower = -float(end.feasible_position) if end.feasible_position is not None else None
    msg = "certified bracket; radius = its outside end" if ok else f"not certified ({end.status}): {loc.message}"
    if retries:
        msg += f" (found after rescanning the sticking line with {retries[-1]} probes)"
    return CriticalRadius(a, beta, mu, method, radius if ok else None, -float(end.position), lower, float(end.width),
                          bool(ok), end.status, d, tip, None if radius is None else radius > kink_at, dt, msg)


# --------------------------------------------------------------------------------------
# Tables over beta


def sketch_change_beta(mu_c: float) -> float:
    """(4.17): the sketch turns into type i once tan(beta) > 2 mu_c; r*(beta) bends there."""
    return math.atan(2.0 * float(mu_c))


def kink_beta(a: float, mu_c: float, sweep_points: int = KINK_SWEEP_POINTS,
              iterations: int = KINK_ITERATIONS, deadline: float | None = None) -> float | None:
    """The collision parameter where the lower end of the sticking locus crosses the disk's
    rim, r*(beta) = 2a sin(beta): there 1/r*(beta) has its slope discontinuity (4.5.3,
    "the discontinuity in slope of the COR locus boundary at r = a"). By bisection on the
    sweep; None when there is no crossing (mu_c >= ~1: b_inf = 2a, the end stays outside)
    or no sticking locus. The bisection stops early at ``deadline`` (a time.perf_counter()
    value): the result only places refinement points of the grid, never a radius."""
    lo, hi = 0.3, 0.5 * math.pi - 1e-3

    def f(b):
        st = sticking_locus_sweep(encounter_scene(a, b), mu_c, sweep_points)
        return math.nan if st is None else -float(st.t_low) - 2.0 * a * math.sin(b)

    if not (f(lo) > 0.0 and f(hi) < 0.0):
        return None
    for _ in range(iterations):
        if deadline is not None and time.perf_counter() > deadline:
            break
        mid = 0.5 * (lo + hi)
        if f(mid) > 0.0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def beta_grid(a: float, r_max: float, grazing_delta: float = SPIRAL_DEFAULT.grazing_delta, n_low: int = 12,
              n_mid: int = 10, n_grazing: int = 16, refine: tuple[float, ...] = (), n_refine: int = 4,
              refine_width: float = 0.04) -> np.ndarray:
    """A beta grid for a table: geometric from beta_min (where the tip line gives r_max,
    r* ~ 2a/sin beta, less 10 % so the table reaches r_max) to 0.4, uniform to pi/2 - 0.1,
    geometric in pi/2 - beta from 0.1 down to ``grazing_delta`` (dense near grazing), and
    ``n_refine`` points on each side of every beta in ``refine`` (the kinks), geometrically
    within ``refine_width``."""
    beta_min = max(MIN_BETA, 0.9 * math.asin(min(1.0, 2.0 * float(a) / float(r_max))))
    parts = [np.geomspace(beta_min, 0.4, max(n_low, 2)), np.linspace(0.4, 0.5 * math.pi - 0.1, max(n_mid, 2)),
             0.5 * math.pi - np.geomspace(0.1, grazing_delta, max(n_grazing, 2))]
    for b in refine:
        if b is None:
            continue
        off = refine_width * np.geomspace(1e-3, 1.0, max(n_refine, 1))
        parts.append(np.concatenate([b - off, [b], b + off]))
    g = np.unique(np.concatenate(parts))
    return g[(g >= beta_min) & (g <= 0.5 * math.pi - grazing_delta)]


@dataclass(frozen=True)
class CriticalRadiusTable:
    """r*(beta) on a grid (4.5.3, figure 4-19), evaluated from grazing downwards so that a
    time limit leaves a usable table of [stopped_at_beta, pi/2).

    ``betas`` (ascending, the evaluated points), ``radii`` (the safe value of each, nan if
    none), ``midpoints``, ``widths``, ``certified``, ``statuses``, ``times``;
    ``envelope``: the safe envelope built from the usable points (certified ones for
    "exact"; all for the approximations), None if there is none; ``dropped_betas``: the
    unusable ones. ``kink_beta`` (the rim crossing) and ``sketch_change_beta`` (4.17) were
    refined around. ``complete``: every planned beta done; ``time_limited``: the time limit
    stopped it at ``stopped_at_beta`` with ``n_done`` of ``n_planned``."""

    a: float
    mu_c: float
    method: str
    betas: np.ndarray
    radii: np.ndarray
    midpoints: np.ndarray
    widths: np.ndarray
    certified: np.ndarray
    statuses: tuple[str, ...]
    times: np.ndarray
    envelope: CriticalEnvelope | None
    dropped_betas: np.ndarray
    kink_beta: float | None
    sketch_change_beta: float
    complete: bool
    time_limited: bool
    stopped_at_beta: float | None
    n_planned: int
    n_done: int
    solve_time_s: float
    message: str
    margin: float = 0.0


def critical_radius_table(a: float, mu_c: float, method: str = "exact", betas=None, r_max: float | None = None,
                          time_limit_s: float | None = None, tol: SolverTolerances = SOLVER_DEFAULT,
                          spiral_tol: SpiralTolerances = SPIRAL_DEFAULT, sweep_points: int = SWEEP_POINTS,
                          find_kink: bool = True, grid_kwargs: dict | None = None,
                          margin_rel: float = 0.0) -> CriticalRadiusTable:
    """r*(beta) over ``betas`` (default :func:`beta_grid` for radii up to ``r_max``,
    default 100 a, refined around the kink (:func:`kink_beta`, if ``find_kink``) and the
    sketch change (4.17)), by ``method``; stops at ``time_limit_s`` (checked between
    points and passed down to each exact solve) and says how far it got. ``margin_rel``:
    the envelope (what schedules use) takes r* + margin_rel * a, a safety margin for the
    uncertified methods (the reported radii are unchanged)."""
    a, _, mu = _check(a, 1.0, mu_c)
    if method not in METHODS:
        raise InvalidInput("method", f"must be one of {', '.join(METHODS)}")
    t0 = time.perf_counter()
    deadline = None if time_limit_s is None else t0 + float(time_limit_s)
    kink = None
    change = sketch_change_beta(mu)
    if betas is None:
        if find_kink and method != "tip_line":
            kink = kink_beta(a, mu, deadline=deadline)
        grid = beta_grid(a, 100.0 * a if r_max is None else float(r_max), spiral_tol.grazing_delta,
                         refine=(kink, change), **(grid_kwargs or {}))
    else:
        grid = np.unique(np.asarray(betas, dtype=float).ravel())
        for b in grid:
            _check(a, b, mu)
    rows = []
    time_limited = False
    for b in grid[::-1]:
        remaining = None if deadline is None else deadline - time.perf_counter()
        if remaining is not None and remaining <= 0.0:
            time_limited = True
            break
        res = critical_radius(a, float(b), mu, method, tol=tol, time_limit_s=remaining, sweep_points=sweep_points)
        if method == "exact" and not res.certified and remaining is not None and deadline - time.perf_counter() <= 0.0:
            time_limited = True
            break
        rows.append(res)
    rows = rows[::-1]
    n = len(rows)
    bet = np.array([r.beta for r in rows])
    rad = np.array([np.nan if r.radius is None else r.radius for r in rows])
    mid = np.array([np.nan if r.midpoint is None else r.midpoint for r in rows])
    wid = np.array([np.nan if r.bracket_width is None else r.bracket_width for r in rows])
    cert = np.array([r.certified for r in rows], dtype=bool)
    usable = np.isfinite(rad) & (cert if method == "exact" else True)
    if not (math.isfinite(margin_rel) and margin_rel >= 0.0):
        raise InvalidInput("margin", "must be a finite number >= 0")
    margin = float(margin_rel) * a
    env = critical_envelope(bet[usable], rad[usable] + margin, a, spiral_tol) if usable.any() else None
    msg = f"{n} of {grid.size} collision parameters ({method})"
    if margin > 0.0:
        msg += f"; schedules use r* + {margin:.3g}"
    if time_limited:
        msg += (f"; time limit reached: the table covers beta >= {bet[0]:.6g} only" if n
                else "; time limit reached before the first collision parameter was decided")
    if (~usable).any():
        msg += f"; {int((~usable).sum())} point(s) not usable (not certified) were dropped"
    if env is not None and env.n_violations:
        msg += f"; r* increases {env.n_violations} time(s) along the grid (max {env.max_increase:.3g}): the envelope covers it"
    return CriticalRadiusTable(
        a=a, mu_c=mu, method=method, betas=bet, radii=rad, midpoints=mid, widths=wid, certified=cert,
        statuses=tuple(r.status for r in rows), times=np.array([r.solve_time_s for r in rows]), envelope=env,
        dropped_betas=bet[~usable], kink_beta=kink, sketch_change_beta=change, complete=n == grid.size,
        time_limited=time_limited, stopped_at_beta=float(bet[0]) if (time_limited and n) else None,
        n_planned=int(grid.size), n_done=n, solve_time_s=time.perf_counter() - t0, message=msg, margin=margin,
    )


# --------------------------------------------------------------------------------------
# Cached tables (r* scales with a: one table per mu_c at a = 1 serves every disk)

TABLE_CACHE_SIZE = 32
"""Complete critical-radius tables kept (at a = 1), most recently used first out last."""

R_MAX_BUCKETS = (10.0, 30.0, 100.0, 300.0, 1000.0, 3000.0, 10000.0)
"""r_max / a is rounded up to one of these, so nearby requests share a table."""

_TABLES: OrderedDict = OrderedDict()
_TABLES_LOCK = threading.Lock()


def scale_table(table: CriticalRadiusTable, a: float) -> CriticalRadiusTable:
    """The table of the disk of radius ``a`` from one of radius ``table.a``: r*, its
    bracket, the margin and the envelope scale with a (4.5.3 is a length per a); the
    angles do not."""
    k = float(a) / table.a
    env = table.envelope
    if env is not None:
        env = replace(env, a=float(a), radii=env.radii * k, envelope=env.envelope * k, distances=env.distances * k,
                      max_increase=env.max_increase * k, b_floor=env.b_floor * k)
    return replace(table, a=float(a), radii=table.radii * k, midpoints=table.midpoints * k, widths=table.widths * k,
                   envelope=env, margin=table.margin * k)


def cached_critical_radius_table(a: float, mu_c: float, method: str, r_max: float, time_limit_s: float | None = None,
                                 sweep_points: int = SWEEP_POINTS, margin_rel: float = 0.0,
                                 tol: SolverTolerances = SOLVER_DEFAULT) -> tuple[CriticalRadiusTable, bool]:
    """:func:`critical_radius_table` through a cache of complete tables at a = 1, keyed
    by (mu_c, method, r_max / a rounded up to R_MAX_BUCKETS, sweep_points, margin_rel, tol).
    Returns (table scaled to ``a``, whether it came from the cache). A table cut short by
    the time limit is returned but not kept."""
    a = float(a)
    rel = float(r_max) / a
    bucket = next((b for b in R_MAX_BUCKETS if b >= rel), rel)
    key = (float(mu_c), method, bucket, int(sweep_points), float(margin_rel), tol)
    with _TABLES_LOCK:
        hit = _TABLES.get(key)
        if hit is not None:
            _TABLES.move_to_end(key)
    if hit is not None:
        return scale_table(hit, a), True
    tab = critical_radius_table(1.0, mu_c, method, r_max=bucket, time_limit_s=time_limit_s, tol=tol,
                                sweep_points=sweep_points, margin_rel=margin_rel)
    if tab.complete and tab.envelope is not None:
        with _TABLES_LOCK:
            _TABLES[key] = tab
            while len(_TABLES) > TABLE_CACHE_SIZE:
                _TABLES.popitem(last=False)
    return scale_table(tab, a), False


def _envelope_of(table_or_envelope) -> CriticalEnvelope:
    if isinstance(table_or_envelope, CriticalEnvelope):
        return table_or_envelope
    if isinstance(table_or_envelope, CriticalRadiusTable):
        if table_or_envelope.envelope is None:
            raise InvalidInput("table", "the table has no usable critical radius")
        return table_or_envelope.envelope
    raise InvalidInput("table", "need a CriticalRadiusTable or a CriticalEnvelope")


def critical_beta(table, r):
    """beta*(r) (4.5.3): the smallest collision parameter (of the table) with a guarantee at
    pusher radius r, over the safe envelope; nan below the table's floor."""
    return _envelope_of(table).beta_star(r)


def critical_distance(table, r):
    """d*(r) (4.5.3 with 4.24): the critical distance from grazing at pusher radius r."""
    return _envelope_of(table).d_star(r)


# --------------------------------------------------------------------------------------
# b_inf (4.25)


@dataclass(frozen=True)
class LimitingRadiusCheck:
    """The numerical limit r*(pi/2 - delta) (4.5.4) against (4.25). ``numeric`` is the
    method's value (for "exact" the safe outside end), ``midpoint`` the exact bracket's
    midpoint, ``difference`` = numeric - closed_form."""

    a: float
    mu_c: float
    method: str
    delta: float
    numeric: float | None
    midpoint: float | None
    closed_form: float
    difference: float | None
    certified: bool
    solve_time_s: float


def limiting_radius_check(a: float, mu_c: float, method: str = "exact", tol: SolverTolerances = SOLVER_DEFAULT,
                          spiral_tol: SpiralTolerances = SPIRAL_DEFAULT) -> LimitingRadiusCheck:
    """b_inf numerically, r*(beta) at beta = pi/2 - grazing_delta, against (4.25)."""
    delta = spiral_tol.grazing_delta
    res = critical_radius(a, 0.5 * math.pi - delta, mu_c, method, tol=tol)
    closed = limiting_radius(a, mu_c)
    return LimitingRadiusCheck(
        a=float(a), mu_c=float(mu_c), method=method, delta=delta, numeric=res.radius,
        midpoint=res.midpoint if res.midpoint is not None else res.radius, closed_form=closed,
        difference=None if res.radius is None else res.radius - closed, certified=res.certified,
        solve_time_s=res.solve_time_s,
    )


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


@dataclass(frozen=True)
class SpiralSchedule:
    """The fastest guaranteed spiral on a grid of radii (4.5.5), solved on OR-Tools.

    ``radii`` b_1 ... b_N (grid points, b_N = target); ``revolutions`` = N (the last is
    the final circle, models/spiral.py); ``steps``; ``path_length`` (+ its quadrature error
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


def _solve_min_cost_flow(graph, costs):
    from ortools.graph.python import min_cost_flow

    n = graph.x.size
    mcf = min_cost_flow.SimpleMinCostFlow()
    arcs = mcf.add_arcs_with_capacity_and_unit_cost(graph.tails, graph.heads, np.ones(graph.n_arcs, dtype=np.int64),
                                                    costs)
    mcf.set_nodes_supplies(np.array([n - 1, 0]), np.array([1, -1]))
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


def spiral_schedule(table, b_1: float, target: float, objective: str = "revolutions", min_step: float | None = None,
                    max_step: float | None = None, speed: float | None = None, spacing: float | None = None,
                    resolution: int = 16, max_nodes: int = 200_000, max_arcs: int = 5_000_000,
                    backend: str = "min_cost_flow", time_limit_s: float | None = 30.0,
                    spiral_tol: SpiralTolerances = SPIRAL_DEFAULT) -> SpiralSchedule:
    """The schedule of radii from ``b_1`` down to ``target`` with the fewest revolutions
    (``objective`` "revolutions") or the shortest path ("length"; "time" = length / speed,
    the same optimum, needs ``speed``), every revolution safe (b_{n-1} - b_n <= d*(b_n),
    4.26) and within the robot's ``min_step`` / ``max_step``, as a shortest path over the
    grid of :func:`models.spiral.schedule_grid` (uniform ``spacing`` or adaptive with
    ``resolution`` points per safe step). ``table``: a CriticalRadiusTable or a
    CriticalEnvelope. ``backend`` "min_cost_flow" (OR-Tools SimpleMinCostFlow; the time
    limit is checked between the build and the solve) or "cp_sat" (time limit inside the
    search; FEASIBLE = stopped early). The optimum is certified by shortest-path potentials
    (:class:`ScheduleCertificate`)."""
    t0 = time.perf_counter()
    deadline = None if time_limit_s is None else t0 + float(time_limit_s)
    env = _envelope_of(table)
    a = env.a
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
    x = schedule_grid(env, b_1, target, spacing=spacing, resolution=resolution, max_nodes=max_nodes, max_step=max_step)
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
    weight = None
    if objective == "revolutions":
        # lexicographic: revolutions first, then length (to tie_break_unit_rel a), so that
        # the schedule returned is also the shortest of the fewest-revolution ones
        unit = spiral_tol.tie_break_unit_rel * a
        costs = np.ones(graph.n_arcs, dtype=np.int64)
        pot = shortest_path_potentials(graph, costs)
        tie = arc_costs(graph, "length", unit, spiral_tol.arc_nodes)
        if pot[0] >= 0 and tie.size:
            w = int(pot[0]) * int(tie.max()) + 1  # > the length of any path with pot[0] arcs
            if (w + int(tie.max())) * (int(pot[0]) + 1) * x.size < 2 ** 62:
                weight = w
                costs = tie + w
                pot = shortest_path_potentials(graph, costs)
        if weight is None:
            unit = 1.0
    else:
        unit = spiral_tol.length_unit_rel * a
        costs = arc_costs(graph, "length", unit, spiral_tol.arc_nodes)
        pot = shortest_path_potentials(graph, costs)
    greedy = greedy_on_graph(graph)
    # the book's recursion with the same maximum step; it ignores a minimum step, so it is
    # then only a lower bound on the revolutions
    recursion = fastest_spiral(env, b_1, target, max_step=max_step, speed=speed, tol=spiral_tol)
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
    if deadline is not None and time.perf_counter() > deadline:
        return empty("TIME_LIMIT", True, f"time limit reached after building the graph ({build:.3g} s), before solving")
    t1 = time.perf_counter()
    if backend == "min_cost_flow":
        status, used, stopped = _solve_min_cost_flow(graph, costs)
    else:
        idx = _arc_index(graph)
        hint = None if greedy is None else np.array([idx(i, j) for i, j in zip(greedy[:-1], greedy[1:])])
        remaining = None if deadline is None else deadline - time.perf_counter()
        status, used, stopped = _solve_cp_sat(graph, costs, hint, remaining)
    solve = time.perf_counter() - t1
    if used is None:
        return empty(status, stopped, f"the {backend} solve ended with status {status}")
    path = _path_from_arcs(graph, used)
    primal = int(costs[used].sum())
    reach = pot[graph.tails] >= 0
    rc = costs[reach] + pot[graph.tails[reach]] - pot[graph.heads[reach]]
    min_rc = int(rc.min()) if rc.size else 0
    dual = int(pot[0])
    cert = ScheduleCertificate(primal_cost=primal, dual_bound=dual, gap=primal - dual, min_reduced_cost=min_rc,
                               n_arcs_checked=int(rc.size), cost_unit=unit, certified=bool(min_rc >= 0 and primal == dual),
                               revolution_weight=weight)
    radii = x[path]
    steps = -np.diff(radii)
    excess = float(np.max(steps - env.d_star(radii[1:], max_step))) if steps.size else 0.0
    length, lerr = spiral_path_length(radii, nodes=spiral_tol.arc_nodes)
    value = float(radii.size) if objective == "revolutions" else (length if objective == "length" else length / float(speed))
    msg = f"{status} on a {grid_kind} grid of {x.size} radii and {graph.n_arcs} safe revolutions"
    if stopped:
        msg += "; stopped early by the time limit (best schedule found, gap in the certificate)"
    if cert.certified:
        msg += "; certified optimal by shortest-path potentials"
    return SpiralSchedule(
        objective=objective, backend=backend, solver_status=status, stopped_early=bool(stopped), radii=radii,
        steps=steps, revolutions=int(radii.size), path_length=length, path_length_error=lerr,
        time_s=None if speed is None else length / float(speed), objective_value=value, certificate=cert,
        greedy_revolutions=g_rev, greedy_path_length=g_len, recursion=recursion, max_step_excess=excess,
        build_time_s=build, solve_time_s=solve, total_time_s=time.perf_counter() - t0, message=msg, **common,
    )


@dataclass(frozen=True)
class SpiralPlan:
    """A table and the schedule from it (:func:`plan_spiral`): ``table`` (r*(beta)),
    ``schedule`` (the OR-Tools optimum on the grid; None when no target or the table is
    incomplete below it), ``recursion`` (4.26 on the envelope, from b_1 to the target or
    until it stalls), ``b_inf_closed_form`` (4.25) and the table's floor."""

    table: CriticalRadiusTable
    schedule: SpiralSchedule | None
    recursion: SpiralRecursion | None
    b_inf_closed_form: float
    b_floor: float | None
    solve_time_s: float
    message: str


def plan_spiral(a: float, mu_c: float, b_1: float, target: float | None = None, method: str = "sweep",
                objective: str = "revolutions", min_step: float | None = None, max_step: float | None = None,
                speed: float | None = None, time_limit_s: float | None = 120.0, backend: str = "min_cost_flow",
                resolution: int = 16, spacing: float | None = None, grid_kwargs: dict | None = None,
                tol: SolverTolerances = SOLVER_DEFAULT, spiral_tol: SpiralTolerances = SPIRAL_DEFAULT,
                table: CriticalRadiusTable | None = None, max_nodes: int = 200_000,
                max_arcs: int = 5_000_000) -> SpiralPlan:
    """One call for the service: the critical-radius table for radii up to ``b_1`` by
    ``method`` (time-limited; or ``table``, already built), the recursion (4.26) and, with
    a ``target``, the certified OR-Tools schedule. The remaining time after the table goes
    to the schedule."""
    t0 = time.perf_counter()
    if table is not None:
        tab = table
    else:
        tab = critical_radius_table(a, mu_c, method, r_max=b_1, time_limit_s=time_limit_s, tol=tol,
                                    spiral_tol=spiral_tol, grid_kwargs=grid_kwargs)
    closed = limiting_radius(a, mu_c)
    if tab.envelope is None:
        return SpiralPlan(tab, None, None, closed, None, time.perf_counter() - t0, tab.message)
    env = tab.envelope
    rec = fastest_spiral(env, b_1, target, max_step=max_step, speed=speed, tol=spiral_tol)
    sched = None
    msg = tab.message
    if target is not None:
        remaining = None if time_limit_s is None else max(float(time_limit_s) - (time.perf_counter() - t0), 1e-3)
        sched = spiral_schedule(env, b_1, target, objective=objective, min_step=min_step, max_step=max_step,
                                speed=speed, spacing=spacing, resolution=resolution, backend=backend,
                                time_limit_s=remaining, spiral_tol=spiral_tol, max_nodes=max_nodes,
                                max_arcs=max_arcs)
        msg += "; " + sched.message
    return SpiralPlan(tab, sched, rec, closed, env.b_floor, time.perf_counter() - t0, msg)
