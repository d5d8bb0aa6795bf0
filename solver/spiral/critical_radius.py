"""Spiral localization of a disk (book 4.5): the critical radius r*(beta), its table and
the limiting radius b_inf.

Critical radius (4.5.2-4.5.3). In the frame of models.push.gross_bounds.encounter_scene (disk
radius a, CM at the origin, contact a(-cos beta, sin beta), push along +x, pusher line
y = a sin beta) the sticking line is the vertical through the contact, and positions on
it are s = (r - c) . J p. The pusher centre PC must lie below the lower end of the
sticking locus (figure 4-18), so r*(beta) = -s_lower, the distance from the pusher line
to that end. Three ways to get it (``method``):

* "exact": solver/sketch/sticking.py's certified lower end (convex feasibility in the pressure
  distribution, a witness inside and a branch-and-bound dual outside). The safe value is
  the OUTSIDE (infeasible) end of the bracket: PC there is certainly below the locus. The
  midpoint and the bracket width are reported beside it.
* "sweep": the book's construction (4.1.4), a sweep of the force angle over the cone with
  the analytic loci (models/sketch/disk_sketch.py), exact up to the loci's polygon resolution
  (~1e-5 a at 1024 points, from the inscribed polygons: it errs slightly low, not safe).
* "tip_line": the book's approximation, r* = 2a / sin beta (4.13), independent of mu_c.

(4.5.4) b_inf = r*(beta -> pi/2); :func:`limiting_radius_check` compares the numerical
limit (at beta = pi/2 - grazing_delta; exactly pi/2 is a grazing touch and is refused)
with (4.25). (4.5.5) the schedule: models/spiral/ holds the envelope (critical.py), the
recursion (4.26) (path.py) and the grid graph (graph.py); :func:`spiral_schedule` solves the shortest path on OR-Tools
(SimpleMinCostFlow, or CP-SAT with a time limit) and certifies it by shortest-path
potentials (an LP dual whose bound equals the objective).

Findings (tests/solver/spiral/test_critical_radius.py, docs/benchmarks.md "Spiral localization (4.5)"):
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
import threading
import time
from collections import OrderedDict
from dataclasses import dataclass, field, replace

import numpy as np

from models.core.errors import InvalidInput
from models.core.tolerances import SPIRAL_DEFAULT, SpiralTolerances
from models.push.gross_bounds import encounter_scene
from models.sketch.disk_sketch import sticking_locus_sweep
from models.spiral.critical import (
    CriticalEnvelope,
    critical_envelope,
    distance_from_grazing,
    limiting_radius,
    tip_line_critical_radius,
)
from solver.core.budget import UNLIMITED, Budget
from solver.core.store import ResultStore
from solver.core.tolerances import SOLVER_DEFAULT, SolverTolerances
from solver.sketch.sticking_locus import sticking_locus
from solver.sketch.sweep import sticking_spans

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
solver/sketch/sticking.py can miss it (mu_c = 0.01 needs ~400 probes, 0.003 ~2000)."""

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
                    budget: Budget = UNLIMITED, sweep_points: int = SWEEP_POINTS, seed: int = 0) -> CriticalRadius:
    """r*(beta): the distance from the pusher's line to the lower end of the sticking locus
    (4.5.3), by ``method`` "exact" | "sweep" | "tip_line" (module docstring). An exact locus
    that comes back empty is rescanned with more probes (EMPTY_RETRY_SCAN) while ``budget``
    lasts."""
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
        st = sticking_locus_sweep(scene, mu, int(sweep_points), sticking_spans)
        dt = time.perf_counter() - t0
        if st is None:
            return CriticalRadius(a, beta, mu, method, None, None, None, None, False, "empty", d, tip, None, dt,
                                  "the sweep found no sticking locus")
        r = -float(st.t_low)
        return CriticalRadius(a, beta, mu, method, r, None, None, None, False, "approximate", d, tip, r > kink_at, dt,
                              f"force-angle sweep (4.1.4) with {int(sweep_points)}-point loci; not certified")
    loc = sticking_locus(scene, mu, tol=tol, budget=budget, seed=seed, ends="lowest")
    retries = []
    for n_scan in EMPTY_RETRY_SCAN:
        if loc.status != "empty" or loc.search_range[0] > loc.search_range[1]:  # empty range: sound
            break
        if budget.expired():
            break
        retries.append(n_scan)
        loc = sticking_locus(scene, mu, tol=tol, budget=budget, seed=seed, scan_points=n_scan, ends="lowest")
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
              iterations: int = KINK_ITERATIONS, budget: Budget = UNLIMITED) -> float | None:
    """The collision parameter where the lower end of the sticking locus crosses the disk's
    rim, r*(beta) = 2a sin(beta): there 1/r*(beta) has its slope discontinuity (4.5.3,
    "the discontinuity in slope of the COR locus boundary at r = a"). By bisection on the
    sweep; None when there is no crossing (mu_c >= ~1: b_inf = 2a, the end stays outside)
    or no sticking locus. The bisection stops early when ``budget`` expires: the result
    only places refinement points of the grid, never a radius."""
    lo, hi = 0.3, 0.5 * math.pi - 1e-3

    def f(b):
        st = sticking_locus_sweep(encounter_scene(a, b), mu_c, sweep_points, sticking_spans)
        return math.nan if st is None else -float(st.t_low) - 2.0 * a * math.sin(b)

    if not (f(lo) > 0.0 and f(hi) < 0.0):
        return None
    for _ in range(iterations):
        if budget.expired():
            break
        mid = 0.5 * (lo + hi)
        if f(mid) > 0.0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@dataclass(frozen=True)
class BetaGrid:
    """How dense the beta grid of a table is (:func:`beta_grid`): ``n_low`` points
    geometric from beta_min to 0.4, ``n_mid`` uniform to pi/2 - 0.1, ``n_grazing``
    geometric in pi/2 - beta from 0.1 down to the grazing delta, and ``n_refine`` points on
    each side of every kink, geometric within ``refine_width`` (rad)."""

    n_low: int = 12
    n_mid: int = 10
    n_grazing: int = 16
    n_refine: int = 4
    refine_width: float = 0.04


BETA_GRID = BetaGrid()
"""The default grid of a table (figure 4-19)."""


def beta_grid(a: float, r_max: float, grazing_delta: float = SPIRAL_DEFAULT.grazing_delta,
              refine: tuple[float | None, ...] = (), grid: BetaGrid = BETA_GRID) -> np.ndarray:
    """A beta grid for a table: geometric from beta_min (where the tip line gives r_max,
    r* ~ 2a/sin beta, less 10 % so the table reaches r_max) to 0.4, uniform to pi/2 - 0.1,
    geometric in pi/2 - beta from 0.1 down to ``grazing_delta`` (dense near grazing), and
    ``grid.n_refine`` points on each side of every beta in ``refine`` (the kinks),
    geometrically within ``grid.refine_width``."""
    beta_min = max(MIN_BETA, 0.9 * math.asin(min(1.0, 2.0 * float(a) / float(r_max))))
    parts = [np.geomspace(beta_min, 0.4, max(grid.n_low, 2)), np.linspace(0.4, 0.5 * math.pi - 0.1, max(grid.n_mid, 2)),
             0.5 * math.pi - np.geomspace(0.1, grazing_delta, max(grid.n_grazing, 2))]
    for b in refine:
        if b is None:
            continue
        off = grid.refine_width * np.geomspace(1e-3, 1.0, max(grid.n_refine, 1))
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

    @property
    def status(self) -> str:
        """"complete", "time_limited" (the budget stopped it) or "partial" (points not usable)."""
        if self.complete:
            return "complete"
        return "time_limited" if self.time_limited else "partial"


STORE_VERSION = 1
"""Version of the stored r* rows and kinks: raise it when their computation changes."""


def _store_namespace(kind: str, mu: float, method: str, sweep_points: int, tol: SolverTolerances) -> str:
    """Where rows of one table kind live: everything that determines r*(beta) at a = 1."""
    return f"{kind}/v{STORE_VERSION}/{method}/mu={mu!r}/sweep={sweep_points}/tol={hash(tol) & 0xFFFFFFFF:08x}"


LENGTH_FIELDS = ("radius", "midpoint", "lower_bound", "bracket_width", "distance_from_grazing", "tip_line_radius")
"""The fields of a :class:`CriticalRadius` that scale with the disk radius a (stored at a = 1)."""


def _row_at(r: CriticalRadius, a: float) -> dict:
    """The row, as a dict, of the disk of radius ``a`` (its lengths are per r.a)."""
    row = {k: getattr(r, k) for k in CriticalRadius.__dataclass_fields__}
    return {**row, **{k: None if row[k] is None else row[k] / r.a * a for k in LENGTH_FIELDS}, "a": a}


def _stored_row(store: ResultStore | None, namespace: str, a: float, beta: float) -> CriticalRadius | None:
    """The row at ``beta`` computed before (stored at a = 1), scaled to ``a``."""
    if store is None:
        return None
    got = store.get(namespace, repr(float(beta)))
    if got is None:
        return None
    try:
        return CriticalRadius(**_row_at(CriticalRadius(**got), a))
    except TypeError:  # written by another layout: not this version's
        return None


def critical_radius_table(a: float, mu_c: float, method: str = "exact", betas=None, r_max: float | None = None,
                          budget: Budget = UNLIMITED, tol: SolverTolerances = SOLVER_DEFAULT,
                          spiral_tol: SpiralTolerances = SPIRAL_DEFAULT, sweep_points: int = SWEEP_POINTS,
                          find_kink: bool = True, grid: BetaGrid = BETA_GRID,
                          margin_rel: float = 0.0, store: ResultStore | None = None) -> CriticalRadiusTable:
    """r*(beta) over ``betas`` (default :func:`beta_grid` with ``grid`` for radii up to
    ``r_max``, default 100 a, refined around the kink (:func:`kink_beta`, if ``find_kink``)
    and the sketch change (4.17)), by ``method``; stops when ``budget`` expires (checked between
    points and passed down to each exact solve) and says how far it got. ``margin_rel``:
    the envelope (what schedules use) takes r* + margin_rel * a, a safety margin for the
    uncertified methods (the reported radii are unchanged). ``store``: rows (at a = 1, per
    beta) and the kink computed before are taken from it and new ones put in as they are
    computed, so a table cut by the time limit is kept and a later request extends it."""
    a, _, mu = _check(a, 1.0, mu_c)
    rows_ns = _store_namespace("rstar", mu, method, sweep_points, tol)
    if method not in METHODS:
        raise InvalidInput("method", f"must be one of {', '.join(METHODS)}")
    t0 = time.perf_counter()
    kink = None
    change = sketch_change_beta(mu)
    if betas is None:
        if find_kink and method != "tip_line":
            kink_ns = _store_namespace("kink", mu, "sweep", KINK_SWEEP_POINTS, tol)
            known = None if store is None else store.get(kink_ns, "beta")
            if known is not None:
                kink = known["beta"]
            else:
                kink = kink_beta(a, mu, budget=budget)
                if store is not None and not budget.expired():
                    store.put(kink_ns, "beta", {"beta": kink})
        planned = beta_grid(a, 100.0 * a if r_max is None else float(r_max), spiral_tol.grazing_delta,
                            refine=(kink, change), grid=grid)
    else:
        planned = np.unique(np.asarray(betas, dtype=float).ravel())
        for b in planned:
            _check(a, b, mu)
    rows = []
    time_limited = False
    for b in planned[::-1]:
        if budget.expired():
            time_limited = True
            break
        res = _stored_row(store, rows_ns, a, float(b))
        if res is None:
            res = critical_radius(a, float(b), mu, method, tol=tol, budget=budget, sweep_points=sweep_points)
            if method == "exact" and not res.certified and budget.expired():
                time_limited = True
                break
            if store is not None and method != "tip_line":
                store.put(rows_ns, repr(float(b)), _row_at(res, 1.0))
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
    msg = f"{n} of {planned.size} collision parameters ({method})"
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
        dropped_betas=bet[~usable], kink_beta=kink, sketch_change_beta=change, complete=n == planned.size,
        time_limited=time_limited, stopped_at_beta=float(bet[0]) if (time_limited and n) else None,
        n_planned=int(planned.size), n_done=n, solve_time_s=time.perf_counter() - t0, message=msg, margin=margin,
    )


# --------------------------------------------------------------------------------------
# Cached tables (r* scales with a: one table per mu_c at a = 1 serves every disk)

TABLE_CACHE_SIZE = 32
"""Complete critical-radius tables kept (at a = 1), most recently used first out last."""

R_MAX_BUCKETS = (10.0, 30.0, 100.0, 300.0, 1000.0, 3000.0, 10000.0)
"""r_max / a is rounded up to one of these, so nearby requests share a table."""

_TABLES: OrderedDict = OrderedDict()
_TABLES_LOCK = threading.Lock()


def cached_table_count() -> int:
    """How many complete tables the cache holds (at most TABLE_CACHE_SIZE)."""
    with _TABLES_LOCK:
        return len(_TABLES)


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


def cached_critical_radius_table(a: float, mu_c: float, method: str, r_max: float, budget: Budget = UNLIMITED,
                                 sweep_points: int = SWEEP_POINTS, margin_rel: float = 0.0,
                                 tol: SolverTolerances = SOLVER_DEFAULT,
                                 store: ResultStore | None = None) -> tuple[CriticalRadiusTable, bool]:
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
    tab = critical_radius_table(1.0, mu_c, method, r_max=bucket, budget=budget, tol=tol,
                                sweep_points=sweep_points, margin_rel=margin_rel, store=store)
    if tab.complete and tab.envelope is not None:
        with _TABLES_LOCK:
            _TABLES[key] = tab
            while len(_TABLES) > TABLE_CACHE_SIZE:
                _TABLES.popitem(last=False)
    return scale_table(tab, a), False


def envelope_of(table_or_envelope) -> CriticalEnvelope:
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
    return envelope_of(table).beta_star(r)


def critical_distance(table, r):
    """d*(r) (4.5.3 with 4.24): the critical distance from grazing at pusher radius r."""
    return envelope_of(table).d_star(r)


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
# One call: r*(beta), its inverse and b_inf (4.5.3-4.5.4)

DEFAULT_REACH_REL = 100.0
"""Default reach of the table of figure 4-19, in units of a (the book's b_1 = 100 a)."""

LIMIT_BETA_MATCH = 1e-12
"""The table's last beta is the limit point pi/2 - grazing_delta (4.5.4) when this close
to it (radians): its r* is then the numerical b_inf, no extra solve."""


@dataclass(frozen=True)
class CriticalRadiusProblem:
    """r*(beta) of a disk of radius ``disk_radius`` with pusher friction ``mu_c`` by
    ``method``: at the collision parameters ``betas`` (computed for this problem), or on
    the grid of figure 4-19 for pusher radii up to ``max_radius`` (default 100 a; through
    the cache of complete tables at a = 1); with ``radii``, the inverse beta*(r) and d*(r)
    (4.24) on the table's safe envelope. ``sweep_points``: locus points of the sweep."""

    disk_radius: float
    mu_c: float
    method: str = "sweep"
    betas: tuple[float, ...] | None = None
    max_radius: float | None = None
    radii: tuple[float, ...] | None = None
    sweep_points: int = SWEEP_POINTS
    tol: SolverTolerances = SOLVER_DEFAULT
    spiral_tol: SpiralTolerances = SPIRAL_DEFAULT
    store: ResultStore | None = field(default=None, compare=False)
    """Where r* rows outlive the process (the service's SQLite store), or None."""

    def __post_init__(self) -> None:
        if self.betas is not None and self.max_radius is not None:
            raise InvalidInput("max_radius", "give betas or max_radius, not both")


INVERSE_BETA_TOL = 1e-4
"""Width (rad) to which beta*(r) is bisected between two table points."""
INVERSE_MAX_STEPS = 16
"""Most r* evaluations spent on one beta*(r)."""


@dataclass(frozen=True)
class InversePoint:
    """beta*(r) (4.5.3) and d*(r) = a (1 - sin beta*) (4.24) at pusher radius ``r``. The
    table gives the smallest tabulated beta with a guarantee; between it and the table
    point below (``beta_below``, no guarantee) r*(beta) = r is bisected with the table's
    method (``steps`` evaluations, fewer when the time ran out), assuming r* decreases
    there (the table's ``monotone`` says whether it does on the grid). The true beta*(r)
    lies in (``beta_below``, ``beta_star``]; nan beta_star: r is below every r*."""

    radius: float
    beta_star: float
    distance_star: float
    beta_below: float | None
    steps: int


def _invert(table: CriticalRadiusTable, r: float, p: CriticalRadiusProblem, budget: Budget) -> InversePoint:
    env = table.envelope
    assert env is not None
    hi = float(env.beta_star(r))
    if not math.isfinite(hi):
        return InversePoint(float(r), hi, 0.0, None, 0)
    below = env.betas[env.betas < hi]
    lo = float(below[-1]) if below.size else None
    steps = 0
    while lo is not None and hi - lo > INVERSE_BETA_TOL and steps < INVERSE_MAX_STEPS and not budget.expired():
        mid = 0.5 * (lo + hi)
        res = critical_radius(table.a, mid, table.mu_c, table.method, tol=p.tol, budget=budget,
                              sweep_points=p.sweep_points)
        steps += 1
        safe = res.radius is not None and res.radius + table.margin <= r and (res.certified or table.method != "exact")
        if safe:
            hi = mid
        else:
            lo = mid
    return InversePoint(float(r), hi, float(distance_from_grazing(table.a, hi)), lo, steps)


@dataclass(frozen=True)
class CriticalRadii:
    """The answer to a :class:`CriticalRadiusProblem`: the ``table`` (``from_cache``), the
    tip line's r* = 2a / sin(beta) (4.13) at its betas, b_inf by (4.25) and numerically
    (r* at pi/2 - ``grazing_delta``; None when there was no time for it), and the inverse
    per asked radius (None unless asked for): :class:`InversePoint`."""

    problem: CriticalRadiusProblem
    table: CriticalRadiusTable
    from_cache: bool
    tip_line_radii: np.ndarray
    b_inf_closed_form: float
    b_inf_numeric: float | None
    grazing_delta: float
    inverse: tuple[InversePoint, ...] | None
    solve_time_s: float

    @property
    def status(self) -> str:
        return "complete" if self.table.complete else "time_limited"

    @property
    def complete(self) -> bool:
        return self.table.complete

    @property
    def message(self) -> str:
        return self.table.message


def critical_radii(problem: CriticalRadiusProblem, budget: Budget = UNLIMITED) -> CriticalRadii:
    """The critical radii of ``problem`` within ``budget``: the table stops early and says
    so; the numerical b_inf is solved only when time is left."""
    t0 = time.perf_counter()
    p = problem
    a, mu = p.disk_radius, p.mu_c
    if p.betas is not None:
        tab = critical_radius_table(a, mu, p.method, betas=p.betas, budget=budget, tol=p.tol, spiral_tol=p.spiral_tol,
                                    sweep_points=p.sweep_points, find_kink=False, store=p.store)
        cached = False
    else:
        r_max = DEFAULT_REACH_REL * a if p.max_radius is None else p.max_radius
        tab, cached = cached_critical_radius_table(a, mu, p.method, r_max, budget=budget, sweep_points=p.sweep_points,
                                                   tol=p.tol, store=p.store)
    delta = p.spiral_tol.grazing_delta
    lim_delta = 0.5 * math.pi - float(tab.betas[-1]) if tab.betas.size else None
    if lim_delta is not None and abs(lim_delta - delta) <= LIMIT_BETA_MATCH:
        numeric = tab.radii[-1]
    elif not budget.expired():
        numeric = limiting_radius_check(a, mu, p.method, tol=p.tol, spiral_tol=p.spiral_tol).numeric
    else:
        numeric = None
    numeric = None if numeric is None or not math.isfinite(numeric) else float(numeric)
    inverse = None
    if p.radii is not None:
        if tab.envelope is None:
            raise InvalidInput("radii", f"no usable critical radius to invert: {tab.message}")
        inverse = tuple(_invert(tab, float(r), p, budget) for r in p.radii)
    tips = tip_line_critical_radius(a, tab.betas) if tab.betas.size else np.empty(0)
    return CriticalRadii(p, tab, cached, np.asarray(tips, dtype=float), limiting_radius(a, mu), numeric, delta,
                         inverse, time.perf_counter() - t0)
