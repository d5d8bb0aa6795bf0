"""The exact sticking locus along the sticking line (book 4.1.4, 3.3.11.1): every COR on
the line through the contact perpendicular to the push that a sticking push can have, as
intervals whose ends are bracketed to ``tol.boundary_bracket`` L and certified (a witness
inside, a dual outside; each query is :func:`solver.sketch.sticking.decide_on_line`).

The book writes the locus as the union over force angles phi in [-nu, nu] of the
frictionless loci {COR}_phi cut by the line, approximates its lower end by the tip line
(3.3.11.1) and has no method for its upper end. Here: a sound search range
(:func:`sticking_search_range`), feasible seeds from forward solves of random tripods, a
scan of uncertified probes, and each end of every run of feasible probes narrowed and
certified (:func:`_bracket_end`). Positions are world lengths along J p from the contact.

Findings (tests/solver/sketch/test_sticking_locus.py, docs/benchmarks.md): see
:mod:`solver.sketch.sticking`.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass

import numpy as np

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.core.mpp import perp
from models.core.scene import PushScene
from models.core.support import random_balanced_tripods, uniform_disk_support, uniform_polygon_support
from models.locus.cor_disk import disk_cor_locus
from solver.certify.colgen import MAX_WARM_POINTS
from solver.certify.witness import heaviest_points
from solver.core.budget import UNLIMITED, Budget
from solver.core.tolerances import SOLVER_DEFAULT, SolverTolerances
from solver.motion.forward import solve_forward, solve_forward_batch
from solver.sketch.sticking import StickingGeometry, StickingResult, decide_on_line, sticking_geometry

STRICT_WITNESS_RESIDUAL = 1e-12
"""Largest witness residual of an inside end of a locus bracket."""

SCAN_POINTS = 96
"""Uncertified probes of the locus scan (asinh-spaced about the CM's foot on the line)."""

SEED_TRIPODS = 256
"""Random balanced tripods (3.3.3) whose sticking-mode forward CORs seed the scan."""

SEARCH_LIMIT = 1e4
"""|s| / L searched when no bound applies (the contact, the CM and p are collinear and the
friction cone holds a line of force through the CM: the locus may be unbounded)."""

RANGE_MARGIN = 1e-6
"""Relative margin added outside the sound search range for the outermost probes."""

MAX_BRACKET_ROUNDS = 200
"""Cap on probes spent narrowing one end of an interval."""

MAX_WIDENINGS = 12
"""Times an end whose outside point cannot be certified is widened (the bracket doubled)
and re-certified. Far from the footprint (|s| >> L) a move of delta changes the geometry
by about delta/|s| only, so the dual margin of a point delta beyond the end shrinks like
delta L/|s|; the bracket then ends wider than the target ("wide")."""

WARM_PER_RESULT = 16
"""Support points (heaviest first) passed on from a previous query as warm columns."""


@dataclass(frozen=True)
class LocusEnd:
    """One end of an interval of the sticking locus.

    ``status``: "bracketed" (``feasible`` inside with a witness and ``infeasible`` outside,
    ``width`` <= tol.boundary_bracket * L apart; ``certified`` when the outside end has a
    branch-and-bound dual), "wide" (as bracketed, but the outside end had to be moved out
    beyond the target width before it could be certified: ``width`` says how wide),
    "contact" (the interval runs up to within half the target width of the contact point,
    which is excluded: no push turns the part about it), "search_limit" (still feasible at
    the search cap: the locus may be unbounded), or "undecided" (time limit, or a query the
    solver could not decide; the bracket reached is reported).
    Positions are world lengths along J p from the contact; ``position`` is the bracket's
    midpoint and ``point`` its world point.
    """

    side: str
    status: str
    position: float
    point: np.ndarray
    feasible_position: float | None
    infeasible_position: float | None
    width: float
    certified: bool
    feasible: StickingResult | None
    infeasible: StickingResult | None


@dataclass(frozen=True)
class StickingInterval:
    lower: LocusEnd
    upper: LocusEnd


@dataclass(frozen=True)
class TipLineEstimate:
    """The book's approximation of the sticking locus's end by the tip line (4.1.4,
    3.3.11.1): ``position`` where the tip line (of the scene's disk,
    :func:`models.locus.cor_disk.disk_cor_locus`) meets the sticking line (None if parallel),
    ``end`` the end on its side ("lower" for s < 0), ``error`` = exact end - estimate
    (world length, None if no interval lies on that side), ``error_bound`` the exact end's
    half bracket, ``beyond`` whether the exact end lies farther from the contact than the
    tip line (the book's "dip")."""

    position: float | None
    point: np.ndarray | None
    end: str | None
    error: float | None
    error_bound: float | None
    beyond: bool | None


@dataclass(frozen=True)
class StickingLocus:
    """The sticking locus (4.1.4) along the sticking line.

    ``intervals``: the feasible intervals found (a scan, then bracketed ends), ordered by
    position; ``lower``/``upper`` the outermost ends; ``multiple_intervals`` when the scan
    found more than one. ``search_range`` (world lengths along J p): a sound outer bound of
    the locus (``search_bound`` names the bounds that gave it, see
    :func:`sticking_search_range`) or the search cap.
    ``scan_positions``/``scan_status``: the probes. ``seed_positions``: sticking CORs of
    random tripods and uniform pressure (forward solves) used as feasible seeds.
    ``status``: "found", "empty" (no feasible probe: the scan can miss a locus narrower
    than its spacing; an empty search range is sound), or "incomplete" (time limit or an
    undecided end). ``time_limited``: the time limit stopped the computation.
    ``translation_sticks``: a pure translation along p (the COR at infinity on the sticking
    line) is a sticking motion: the line through c along p passes through the CM (within
    ``translation_rel``) and p lies in the friction cone. It is not part of ``intervals``.
    """

    status: str
    mu_c: float
    friction_angle: float
    contact_point: np.ndarray
    direction: np.ndarray
    length_scale: float
    intervals: tuple[StickingInterval, ...]
    lower: LocusEnd | None
    upper: LocusEnd | None
    multiple_intervals: bool
    search_range: tuple[float, float]
    search_bound: str
    scan_positions: np.ndarray
    scan_status: tuple[str, ...]
    seed_positions: np.ndarray
    tip_line: TipLineEstimate
    n_queries: int
    solve_time_s: float
    time_limited: bool
    complete: bool
    message: str
    translation_sticks: bool = False


def _min_lever(geo: StickingGeometry) -> float:
    """min over |phi| <= nu of |alpha_phi . c| / L (alpha turned by phi with the cone)."""
    a = float(geo.t @ geo.c)
    b = float(perp(geo.t) @ geo.c)
    nu = geo.nu
    vals = [abs(a * math.cos(ph) + b * math.sin(ph)) for ph in (-nu, nu)]
    # zero of a cos phi + b sin phi in (-pi/2, pi/2]
    zero = math.pi / 2 if b == 0.0 else math.atan(-a / b)
    if abs(zero) <= nu:
        return 0.0
    return min(vals)


def _search_range(geo: StickingGeometry) -> tuple[float, float, str]:
    """A sound outer bound [lo, hi] (/ L) of the sticking locus along the line.

    * footprint: with a point mass at r, r lies in the footprint, inside the unit disk;
    * moment (ii): for r outside the footprint, |d - (+-J p)| <= 2 |w - c| / |s|, so
      |sum P (w - c) . d + c . J p| <= 2 D^2 / |s| with D = max |w - c| over the footprint;
      (ii) then needs |s| <= 2 D^2 / |c . J p|;
    * disk loci: each {COR}_phi of the circumscribing disk lies within
      max(1, 1 / |alpha_phi . c|) of the CM (3.37, and a for |alpha . c| >= a), and the
      footprint's loci lie in its disk's (7.5).
    The result is the intersection of the moment and disk bounds, joined with the
    footprint's chord; when neither bounds the line, +-SEARCH_LIMIT.
    """
    cx, cy = float(geo.c[0]), float(geo.c[1])
    names = []
    # footprint chord: |r| <= 1 with r = (cx, cy + s)
    chord = None
    if abs(cx) <= 1.0:
        hh = math.sqrt((1.0 - cx) * (1.0 + cx))
        chord = (-cy - hh, -cy + hh)
    lo, hi = -math.inf, math.inf
    if abs(cy) > 0.0:
        sm = 2.0 * geo.reach**2 / abs(cy)
        lo, hi = -sm, sm
        names.append("moment")
    g = _min_lever(geo)
    if g > 0.0:
        big_r = 1.0 / min(1.0, g)
        if big_r < abs(cx):
            dl, dh = math.inf, -math.inf  # the line misses every locus
        else:
            hh = math.sqrt((big_r - abs(cx)) * (big_r + abs(cx)))
            dl, dh = -cy - hh, -cy + hh
        lo, hi = max(lo, dl), min(hi, dh)
        names.append("disk_loci")
    if not names:
        lo, hi = -SEARCH_LIMIT, SEARCH_LIMIT
        names.append("cap")
    if chord is not None:
        if lo > hi:
            lo, hi = chord
        else:
            lo, hi = min(lo, chord[0]), max(hi, chord[1])
        names.append("footprint")
    return lo, hi, "+".join(names)


def sticking_search_range(
    scene: PushScene, mu_c: float, footprint: Footprint | None = None, tol: SolverTolerances = SOLVER_DEFAULT
) -> tuple[float, float, str]:
    """A sound outer bound (lo, hi) of the sticking locus's positions s (world lengths along
    J p from the contact) and the names of the bounds that gave it ("moment", "disk_loci",
    "footprint", joined by "+"; see :func:`_search_range`), or +-SEARCH_LIMIT L with "cap"
    when neither the moment nor the disk-loci bound applies."""
    geo = sticking_geometry(scene, footprint, mu_c, tol)
    lo, hi, how = _search_range(geo)
    return lo * geo.length, hi * geo.length, how


def _tip_line(scene: PushScene) -> tuple[float | None, np.ndarray | None]:
    loc = disk_cor_locus(scene, outputs=("tip_line",))
    tl = loc.tip_line
    if tl is None:
        return None, None
    e2 = perp(np.asarray(scene.push_hat))
    nrm = perp(tl.direction)
    den = float(e2 @ nrm)
    if abs(den) <= scene.tolerances.grazing_sin:
        return None, None
    s = float((tl.point - scene.contact_point) @ nrm) / den
    return s, scene.contact_point + s * e2


def _seed_positions(geo: StickingGeometry, footprint, n_tripods: int, seed: int, tol) -> np.ndarray:
    """Positions (/ L) of sticking-mode forward CORs of random tripods (3.3.3) and of
    uniform pressure: feasible points to seed the scan."""
    scene = geo.scene
    mu = geo.mu_c if math.isfinite(geo.mu_c) else 1e300
    out = []
    e2 = perp(np.asarray(scene.push_hat))
    if n_tripods > 0:
        try:
            rng = np.random.default_rng(seed)
            pts, wts = random_balanced_tripods(rng, n_tripods, geo.length, scene.center_of_mass, footprint)
            b = solve_forward_batch(scene, pts, wts, mu_c=mu, tol=tol, check_centroid=False)
            ok = (b.mode == 1) & b.converged & np.all(np.isfinite(b.cor), axis=1)
            out.append((b.cor[ok] - scene.contact_point) @ e2)
        except InvalidInput:
            pass
    try:
        if footprint is None:
            support = uniform_disk_support(scene.disk_radius, scene.center_of_mass, rings=8)
        else:
            support = uniform_polygon_support(footprint, subdivisions=4)
        f = solve_forward(scene, support, mu_c=mu, tol=tol)
        if f.mode == "sticking" and f.cor is not None and f.status == "optimal":
            out.append(np.array([(f.cor - scene.contact_point) @ e2]))
    except InvalidInput:
        pass
    if not out:
        return np.zeros(0)
    return np.concatenate(out) / geo.length


class _LineSearch:
    """Queries along the sticking line (positions / L), cached, with warm starts."""

    def __init__(self, geo: StickingGeometry, tol: SolverTolerances, budget: Budget):
        self.geo = geo
        self.tol = dataclasses.replace(tol, membership_residual=min(tol.membership_residual, STRICT_WITNESS_RESIDUAL))
        self.budget = budget
        self.n_queries = 0
        self.warm: np.ndarray | None = None
        self.cache: dict[tuple[float, bool, bool], StickingResult] = {}

    def expired(self) -> bool:
        return self.budget.expired()

    def __call__(self, s: float, certify: bool = False, verify: bool = False) -> StickingResult:
        key = (float(s), certify, verify)
        if key in self.cache:
            return self.cache[key]
        self.n_queries += 1
        res = decide_on_line(self.geo, self.geo.point(s), self.tol, self.budget, self.warm, verify, certify)
        if res.witness_points.size:
            new = heaviest_points(res.witness_points, res.witness_weights, WARM_PER_RESULT)
            self.warm = new if self.warm is None else np.vstack([new, self.warm])[:MAX_WARM_POINTS]
        self.cache[key] = res
        return res


def _local_position(geo: StickingGeometry, res: StickingResult) -> float:
    return res.position / geo.length


@dataclass
class _Bracket:
    """The state of one end's bracket: the inside and outside positions (line coordinates),
    what the outside one is ("probe", "contact", "limit"), whether uncertified probes (the
    grid's grading) are still trusted and the bisection goes on, the certified queries at
    both ends and the end's status."""

    s_in: float
    s_out: float
    out_kind: str
    trust_grid: bool = True
    bisecting: bool = True
    nudges: int = 0
    widenings: int = 0
    res_in: StickingResult | None = None
    res_out: StickingResult | None = None
    status: str = "undecided"


def _bisection_step(search: _LineSearch, br: _Bracket, target: float, outward: float) -> None:
    """Halve the bracket with a probe at its middle; a probe within rounding of the end
    (undecided) is stepped around by a quarter and a half of ``target`` on either side, and
    the bisection stops when neither moves the bracket."""
    geo = search.geo
    mid = 0.5 * (br.s_in + br.s_out)
    if mid in (br.s_in, br.s_out, 0.0):
        br.bisecting = False
        return
    res = search(mid, certify=not br.trust_grid)
    if res.status == "undecided" and br.trust_grid:
        res = search(mid, certify=True)
    sm = _local_position(geo, res)
    if res.status == "inside":
        br.s_in = sm
        return
    if res.status == "outside":
        br.s_out, br.out_kind = sm, "probe"
        return
    moved = False
    for frac in (0.25, 0.5):
        s_try = mid + outward * frac * target
        if (s_try - mid) * (br.s_out - s_try) > 0.0:
            r_try = search(s_try, certify=not br.trust_grid)
            if r_try.status == "outside":
                br.s_out, br.out_kind, moved = _local_position(geo, r_try), "probe", True
                break
    for frac in (0.25, 0.5):
        s_try = mid - outward * frac * target
        if (s_try - br.s_in) * (mid - s_try) > 0.0:
            r_try = search(s_try, certify=not br.trust_grid)
            if r_try.status == "inside":
                br.s_in, moved = _local_position(geo, r_try), True
                break
    br.bisecting = moved


def _step_outwards(search: _LineSearch, br: _Bracket, target: float, outward: float) -> None:
    """The grid's "outside" end was certified inside: the grid is no longer trusted here;
    certified probes step outwards, doubling, to a certified outside point (or the contact
    point), and the bisection starts again."""
    br.trust_grid = False
    step = max(target, abs(br.s_out - br.s_in))
    br.s_in = br.s_out
    for _ in range(64):
        s_try = br.s_in + outward * step
        if (s_try > 0.0) != (br.s_in > 0.0):
            br.s_out, br.out_kind = 0.0, "contact"
            break
        r_try = search(s_try, certify=True)
        if r_try.status == "inside":
            br.s_in = _local_position(search.geo, r_try)
            step *= 2.0
            continue
        br.s_out, br.out_kind = _local_position(search.geo, r_try), "probe"
        break
    br.nudges = br.widenings = 0
    br.bisecting = True


def _certify_ends(search: _LineSearch, br: _Bracket, target: float, outward: float) -> bool:
    """Certify both ends of the narrowed bracket (the witness re-verified by a forward solve,
    a branch-and-bound dual); True when the end is settled, False to go on with a moved or
    widened bracket."""
    br.res_in = search(br.s_in, certify=True, verify=True)
    if br.res_in.status != "inside":
        return True
    if br.out_kind == "contact":
        br.status = "contact"
        return True
    br.res_out = search(br.s_out, certify=True)
    if br.res_out.status == "outside":
        br.status = "bracketed" if abs(br.s_out - br.s_in) <= target * (1.0 + 1e-9) else "wide"
        return True
    if br.res_out.status == "inside":
        if br.out_kind == "limit":
            br.s_in, br.res_in = br.s_out, search(br.s_out, certify=True, verify=True)
            br.status = "search_limit"
            return True
        _step_outwards(search, br, target, outward)
        return False
    # an undecided outside end: nudged outwards twice, then the bracket doubled
    if br.out_kind == "limit":
        return True
    if br.nudges < 2 and abs(br.s_out - br.s_in) <= 0.75 * target:
        br.nudges += 1
        s_new = br.s_out + outward * 0.25 * target
    elif br.widenings < MAX_WIDENINGS:
        br.widenings += 1
        s_new = br.s_in + 2.0 * (br.s_out - br.s_in)
    else:
        return True
    if (s_new > 0.0) != (br.s_in > 0.0):
        s_new, br.out_kind = 0.0, "contact"
    br.s_out = s_new
    return False


def _bracket_end(search: _LineSearch, side: str, s_in: float, s_out: float, out_kind: str) -> LocusEnd:
    """Narrow [s_in (inside), s_out] to half the bracket width with uncertified probes, then
    certify both ends (the witness re-verified by a forward solve, a branch-and-bound dual).

    ``out_kind``: "probe" (s_out was decided outside, possibly by grid pricing only),
    "contact" (s_out = 0, the contact point) or "limit" (s_out is the search cap).
    A probe within rounding of the end (undecided) is stepped around by a quarter and a
    half of the target width. An outside end too close to the end to certify (its dual
    margin below tol.certificate_margin) is moved outwards by a quarter of the width,
    twice, then the bracket is doubled (status "wide" when it ends wider than the target).
    When the certified query finds the grid's "outside" end inside, the grid is no longer
    trusted for this end: certified probes step outwards, doubling, to a certified outside
    point, and the bisection continues with certified probes."""
    geo = search.geo
    target = search.tol.boundary_bracket
    outward = 1.0 if side == "upper" else -1.0
    br = _Bracket(s_in, s_out, out_kind)
    rounds = 0
    while rounds < MAX_BRACKET_ROUNDS and not search.expired():
        rounds += 1
        if br.bisecting and abs(br.s_out - br.s_in) > 0.5 * target:
            _bisection_step(search, br, target, outward)
            continue
        br.bisecting = False
        if _certify_ends(search, br, target, outward):
            break
    certified = bool(
        br.status in ("bracketed", "wide") and br.res_out is not None and br.res_out.certificate_kind == "dual"
        and br.res_in is not None and br.res_in.certificate_kind == "witness"
    )
    mid = br.s_in if br.status in ("contact", "search_limit") else 0.5 * (br.s_in + br.s_out)
    return LocusEnd(
        side=side,
        status=br.status,
        position=mid * geo.length,
        point=geo.outline.to_world(geo.point(mid)),
        feasible_position=br.s_in * geo.length,
        infeasible_position=None if br.out_kind == "limit" else br.s_out * geo.length,
        width=abs(br.s_out - br.s_in) * geo.length,
        certified=certified,
        feasible=br.res_in,
        infeasible=br.res_out,
    )


def _scan_positions(lo: float, hi: float, centre: float, n: int) -> np.ndarray:
    """n positions in [lo, hi], uniform in asinh(s - centre) (dense near the footprint,
    geometric far out), plus both ends."""
    centre = min(max(centre, lo), hi)
    u0, u1 = math.asinh(lo - centre), math.asinh(hi - centre)
    u = np.linspace(u0, u1, max(n, 2))
    return centre + np.sinh(u)


def _scan(search: _LineSearch, probes: np.ndarray, stop_inside: bool = False
          ) -> tuple[list[float], list[str], bool]:
    """Probe each position (certified only where the grid leaves it undecided), in the
    order given (``stop_inside``: up to the first feasible one): (positions and statuses
    sorted along the line, whether the time limit cut the scan)."""
    scan_s, scan_st = [], []
    time_limited = False
    for s in probes:
        if search.expired():
            time_limited = True
            break
        res = search(float(s))
        if res.status == "undecided":
            res = search(float(s), certify=True)
        scan_s.append(_local_position(search.geo, res))
        scan_st.append(res.status)
        if stop_inside and res.status == "inside":
            break
    order = np.argsort(scan_s)
    return [scan_s[i] for i in order], [scan_st[i] for i in order], time_limited


def _scan_line(search: _LineSearch, probes: np.ndarray, ends: str) -> tuple[list[float], list[str], bool, bool]:
    """The scan of :func:`sticking_locus` (step 3): every probe, or for ``ends="lowest"``
    those below the contact up to the first feasible one, then the rest only if none was.
    (positions, statuses, time-limited, whether only the lowest end is to be found)."""
    if ends != "lowest":
        return (*_scan(search, probes), False)
    scan_s, scan_st, time_limited = _scan(search, probes[probes < 0.0], stop_inside=True)
    if "inside" in scan_st or time_limited:
        return scan_s, scan_st, time_limited, True
    more_s, more_st, time_limited = _scan(search, probes[probes > 0.0])
    return scan_s + more_s, scan_st + more_st, time_limited, False


def _inside_runs(marks: list[tuple[float, str]]) -> list[tuple[int, int]]:
    """The maximal runs (first, last index) of "inside" marks."""
    runs = []
    i = 0
    while i < len(marks):
        if marks[i][1] != "inside":
            i += 1
            continue
        j = i
        while j + 1 < len(marks) and marks[j + 1][1] == "inside":
            j += 1
        runs.append((i, j))
        i = j + 1
    return runs


def _mark_beyond(marks: list[tuple[float, str]], k: int, limit: float, capped: bool) -> tuple[str, float]:
    """(kind, position) of the outside point beyond a run of inside marks: mark ``k``
    ("contact" or a "probe"), or when the run reaches the scan's end the search range's
    end ``limit`` (a hard "limit" when ``capped``)."""
    if 0 <= k < len(marks):
        return ("contact" if marks[k][1] == "contact" else "probe"), marks[k][0]
    return ("limit" if capped else "probe"), limit


def _lowest_end(search: _LineSearch, marks: list[tuple[float, str]], limit: float, capped: bool) -> LocusEnd | None:
    """The lower end of the lowest run of inside marks (:func:`_bracket_end`), None when
    there is none."""
    runs = _inside_runs(marks)
    if not runs:
        return None
    kind, s_out = _mark_beyond(marks, runs[0][0] - 1, limit, capped)
    return _bracket_end(search, "lower", marks[runs[0][0]][0], s_out, kind)


def _intervals(search: _LineSearch, marks: list[tuple[float, str]], limits: tuple[float, float],
               capped: bool) -> list[StickingInterval]:
    """Each run of inside marks bracketed at both ends (:func:`_bracket_end`) against the
    mark beyond it (the contact point, a probe, or the search range's end ``limits``, a
    hard limit when ``capped``); runs that turn out to be one interval are merged."""
    ell = search.geo.length
    intervals: list[StickingInterval] = []
    for i, j in _inside_runs(marks):
        kind_lo, s_out_lo = _mark_beyond(marks, i - 1, limits[0], capped)
        kind_hi, s_out_hi = _mark_beyond(marks, j + 1, limits[1], capped)
        if intervals and intervals[-1].upper.feasible_position is not None and (
            intervals[-1].upper.feasible_position >= marks[i][0] * ell
        ):
            continue  # the previous interval's upper end was found beyond this run already
        lower_end = _bracket_end(search, "lower", marks[i][0], s_out_lo, kind_lo)
        upper_end = _bracket_end(search, "upper", marks[j][0], s_out_hi, kind_hi)
        if intervals and lower_end.feasible_position <= intervals[-1].upper.feasible_position:
            # one interval split by an undecided or wrongly graded probe: merge
            intervals[-1] = StickingInterval(intervals[-1].lower, upper_end)
        else:
            intervals.append(StickingInterval(lower_end, upper_end))
    return intervals


def sticking_locus(
    scene: PushScene,
    mu_c: float,
    footprint: Footprint | None = None,
    tol: SolverTolerances = SOLVER_DEFAULT,
    budget: Budget = UNLIMITED,
    scan_points: int = SCAN_POINTS,
    seed_tripods: int = SEED_TRIPODS,
    seed: int = 0,
    ends: str = "all",
) -> StickingLocus:
    """The sticking locus along the sticking line (book 4.1.4), each end bracketed to
    tol.boundary_bracket * L by a (feasible, infeasible) pair of queries.

    1. A sound search range (:func:`sticking_search_range`).
    2. Feasible seeds: sticking-mode forward CORs of ``seed_tripods`` random tripods (3.3.3,
       seeded by ``seed``) and of uniform pressure.
    3. A scan of ``scan_points`` uncertified probes over the range plus the seeds; maximal
       runs of feasible probes (never across the contact point, s = 0) are the intervals.
       A locus piece narrower than the scan's spacing that no seed hits can be missed.
    4. Each interval end is narrowed by bisection with uncertified probes and certified at
       both ends of its final bracket (:func:`_bracket_end`).
    5. The tip line's crossing (3.3.11.1) and its error against the exact end on its side.

    ``ends="lowest"``: the lowest end only (what r*(beta) of 4.5.3 needs), see
    :func:`_scan_line`; it is bracketed from the same pair of probes as with "all";
    ``intervals`` is then empty, ``upper`` None, ``multiple_intervals`` False (not looked
    for) and the message says so; with nothing feasible below the contact, as "all".
    """
    if ends not in ("all", "lowest"):
        raise InvalidInput("ends", 'must be "all" or "lowest"')
    t0 = time.perf_counter()
    geo = sticking_geometry(scene, footprint, mu_c, tol)
    mu = geo.mu_c
    ell = geo.length
    search = _LineSearch(geo, tol, budget)
    lo, hi, bound_name = _search_range(geo)
    s_tip, tip_point = _tip_line(scene)
    e2_world = perp(np.asarray(scene.push_hat))
    # translation along p: friction -p at the CM, balanced by a force along p through c
    translation = bool(
        abs(float(geo.c[1])) <= scene.tolerances.translation_rel
        and float(np.min(geo.cone @ np.array([1.0, 0.0]))) >= 0.0
    )

    def finish(status, intervals, scan_s, scan_st, seeds, message, time_limited, lowest=None):
        if translation:
            message += "; a pure translation along the push sticks (COR at infinity on the line)"
        lower = intervals[0].lower if intervals else lowest
        upper = intervals[-1].upper if intervals else None
        tip = _tip_estimate(s_tip, tip_point, intervals)
        complete = status in ("found", "empty") and not time_limited
        return StickingLocus(
            status=status, mu_c=mu, friction_angle=geo.nu, contact_point=np.asarray(scene.contact_point, float).copy(),
            direction=e2_world, length_scale=ell, intervals=tuple(intervals), lower=lower, upper=upper,
            multiple_intervals=len(intervals) > 1, search_range=(lo * ell, hi * ell), search_bound=bound_name,
            scan_positions=np.asarray(scan_s, dtype=float) * ell, scan_status=tuple(scan_st),
            seed_positions=np.asarray(seeds, dtype=float) * ell, tip_line=tip, n_queries=search.n_queries,
            solve_time_s=time.perf_counter() - t0, time_limited=time_limited, complete=complete, message=message,
            translation_sticks=translation,
        )

    if not lo <= hi:
        msg = "the sticking line misses every frictionless locus of the cone (sound bound)"
        return finish("empty", [], [], [], [], msg, False)

    seeds = _seed_positions(geo, footprint, seed_tripods, seed, tol)
    seeds = seeds[(seeds >= lo) & (seeds <= hi) & (seeds != 0.0)]
    if seeds.size > 32:
        seeds = np.quantile(seeds, np.linspace(0.0, 1.0, 32))
    capped = bound_name == "cap"
    margin = RANGE_MARGIN * max(1.0, hi - lo)
    lo_p, hi_p = (lo, hi) if capped else (lo - margin, hi + margin)
    centre = float(np.clip(-geo.c[1], lo, hi))
    probes = np.concatenate([_scan_positions(lo_p, hi_p, centre, scan_points), seeds])
    scan_s, scan_st, time_limited, lowest_only = _scan_line(search, np.unique(probes[probes != 0.0]), ends)
    # runs of "inside" separated by outside/undecided probes and by the contact point
    marks = sorted([*zip(scan_s, scan_st), (0.0, "contact")], key=lambda m: m[0])
    if lowest_only:
        end = _lowest_end(search, marks, lo_p, capped)
        time_limited = time_limited or search.expired()
        status = "incomplete" if time_limited or end is None or end.status == "undecided" else "found"
        msg = (f"the lowest end only: the scan stopped at the first feasible probe below the contact "
               f"(upper ends not computed); {scan_st.count('undecided')} undecided scan probe(s)")
        return finish(status, [], scan_s, scan_st, seeds, msg, time_limited, lowest=end)
    intervals = _intervals(search, marks, (lo_p, hi_p), capped)
    incomplete = time_limited
    for iv in intervals:
        if iv.lower.status == "undecided" or iv.upper.status == "undecided":
            incomplete = True
    time_limited = time_limited or search.expired()
    if not intervals:
        status = "incomplete" if time_limited else "empty"
        msg = "no feasible probe on the sticking line" + (" (time limit)" if time_limited else "")
        return finish(status, [], scan_s, scan_st, seeds, msg, time_limited)
    undecided_probes = scan_st.count("undecided")
    msg = f"{len(intervals)} interval(s); {undecided_probes} undecided scan probe(s)"
    return finish("incomplete" if incomplete else "found", intervals, scan_s, scan_st, seeds, msg, time_limited)


def _tip_estimate(s_tip, tip_point, intervals) -> TipLineEstimate:
    if s_tip is None:
        return TipLineEstimate(None, None, None, None, None, None)
    if s_tip < 0.0:
        side = [iv.lower for iv in intervals if iv.lower.position < 0.0]
        end = side[0] if side else None
        name = "lower"
    else:
        side = [iv.upper for iv in intervals if iv.upper.position > 0.0]
        end = side[-1] if side else None
        name = "upper"
    if end is None or end.status not in ("bracketed", "wide", "contact"):
        return TipLineEstimate(s_tip, tip_point, name, None, None, None)
    err = end.position - s_tip
    return TipLineEstimate(s_tip, tip_point, name, err, 0.5 * end.width, abs(end.position) > abs(s_tip))
