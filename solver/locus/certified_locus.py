"""Certified COR loci: the frictionless disk's analytic boundary checked point by point, and
the exact locus of a polygon footprint traced by certified brackets (book 3.3, 3.3.13, 7.5).

A *bracket* is a pair of points r_in, r_out a distance ``tol.boundary_bracket`` * L apart,
with r_in certified inside the locus (a witness support, :mod:`solver.locus.membership`) and
r_out certified outside (a dual functional with a branch-and-bound lower bound over the
whole footprint). The true boundary then crosses the segment between them.

* :func:`certified_disk_boundary` brackets each point b_k of the analytic boundary of
  :mod:`models.locus.cor_disk` (book (3.30), (3.35), and the perimeter arcs) along its outward
  normal: r_in = b_k - delta nu_k, r_out = b_k + delta nu_k. Both inside, or both outside,
  would be a point where the analytic boundary is wrong (book 3.3.13 notes that the
  derivation of the quotient-locus boundary was only checked empirically).
* :func:`certified_polygon_boundary` traces the locus of a simple polygon along rays from
  a certified inside centre (the CM when it is a COR, i.e. when it lies in the footprint:
  a point mass there turns the part about it). The circumscribing disk's locus contains the
  polygon's (7.5), so its analytic boundary gives the outer end of each ray.

Inside decisions here use a strict witness residual (``STRICT_WITNESS_RESIDUAL``): a
polished witness satisfies the membership equations to rounding, while the general
``tol.membership_residual`` can admit points a little outside the locus where the
equations are insensitive to r (near the tip for small |alpha . c| / a).
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass

import numpy as np
from scipy.optimize import nnls

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.core.mpp import membership_columns
from models.core.scene import PushScene
from models.core.support import Support, uniform_polygon_support
from models.locus.cor_disk import disk_cor_locus
from solver.certify.witness import heaviest_points
from solver.core.budget import UNLIMITED, Budget
from solver.core.tolerances import SOLVER_DEFAULT, SolverTolerances
from solver.locus.membership import MembershipResult, membership, outline_of
from solver.motion.forward import solve_forward

STRICT_WITNESS_RESIDUAL = 1e-12
"""Largest L1 residual of an inside witness in a certified bracket (polished witnesses
reach about 1e-16)."""

DISK_REFERENCE_POINTS = 2048
"""Points of the circumscribing disk's analytic boundary used for the outer ray ends."""

SCAN_POINTS = 8
"""Uncertified probes along each ray before the bracket refinement (non-star check)."""

MAX_WIDENINGS = 3
"""Times a bracket whose ends fail certification is widened (doubled) and re-certified."""

MAX_RAY_PROBES = 80
"""Most uncertified probes spent narrowing one ray's crossing."""

NEWTON_STEP_REL = 1e-7
"""Forward-difference step (/ L) of the columns in the Newton estimate of a crossing."""


def _strict(tol: SolverTolerances) -> SolverTolerances:
    return dataclasses.replace(tol, membership_residual=min(tol.membership_residual, STRICT_WITNESS_RESIDUAL))


WARM_PER_RESULT = 16
"""Support points (largest weights first) passed on from each previous query."""


def _warm(*results: MembershipResult | None) -> np.ndarray | None:
    """Warm-start points for the next query: the heaviest support points of ``results``."""
    pts = [heaviest_points(r.witness_points, r.witness_weights, WARM_PER_RESULT)
           for r in results if r is not None and r.witness_points.size]
    return np.vstack(pts) if pts else None


def _verdict(inner: MembershipResult, outer: MembershipResult) -> str:
    a, b = inner.status, outer.status
    if a == "inside" and b == "outside":
        return "bracketed"
    if a == "inside" and b == "inside":
        return "both_inside"
    if a == "outside" and b == "outside":
        return "both_outside"
    if a == "outside" and b == "inside":
        return "reversed"
    return "undecided"


@dataclass(frozen=True)
class BracketPair:
    """One certified bracket: ``inner`` at ``point - delta normal``, ``outer`` at
    ``point + delta normal`` (world). ``verdict``: "bracketed" (inner inside, outer outside),
    "both_inside", "both_outside", "reversed" (a boundary claim proven wrong) or
    "undecided"."""

    point: np.ndarray
    normal: np.ndarray
    inner: MembershipResult
    outer: MembershipResult
    verdict: str


@dataclass(frozen=True)
class CertifiedDiskBoundary:
    """The analytic disk boundary (:func:`models.locus.cor_disk.disk_cor_locus`) with a certified
    bracket at each point.

    ``delta`` (world length): half the bracket; where the pair is "bracketed" the true
    boundary passes within ``delta`` of the analytic point (``max_error_bound``, None if no
    pair is bracketed). ``wrong``: indices whose pair proves the analytic boundary wrong
    there (both ends on one side, or reversed); ``undecided``: indices with an undecided end.
    """

    boundary: np.ndarray
    normals: np.ndarray
    delta: float
    length_scale: float
    relative_moment_arm: float
    pairs: tuple[BracketPair, ...]
    n_certified: int
    wrong: tuple[int, ...]
    undecided: tuple[int, ...]
    max_error_bound: float | None
    solve_time_s: float
    complete: bool = True

    @property
    def status(self) -> str:
        """"wrong" (a pair proves the analytic boundary wrong), "certified" (every point
        bracketed), else "incomplete" (points undecided or not reached in time)."""
        if self.wrong:
            return "wrong"
        return "certified" if self.complete and self.n_certified == len(self.boundary) else "incomplete"

    @property
    def message(self) -> str:
        text = f"{self.n_certified} of {len(self.boundary)} boundary points bracketed within {self.delta:.3g}"
        if len(self.pairs) < len(self.boundary):
            text += f"; {len(self.boundary) - len(self.pairs)} not reached in time"
        if self.wrong:
            text += f"; the analytic boundary is wrong at {list(self.wrong)}"
        if self.undecided:
            text += f"; undecided at {list(self.undecided)}"
        return text


def outward_normals(ring: np.ndarray) -> np.ndarray:
    """Unit outward normals of a closed counter-clockwise polyline from central differences."""
    tangent = np.roll(ring, -1, axis=0) - np.roll(ring, 1, axis=0)
    normal = np.stack([tangent[:, 1], -tangent[:, 0]], axis=1)
    return normal / np.linalg.norm(normal, axis=1)[:, None]


def certify_brackets(
    scene: PushScene,
    points,
    normals,
    delta: float,
    footprint: Footprint | None = None,
    tol: SolverTolerances = SOLVER_DEFAULT,
    budget: Budget = UNLIMITED,
) -> tuple[BracketPair, ...]:
    """Certify r_in = p - delta nu and r_out = p + delta nu for each claimed boundary point
    p (world) with unit outward normal nu. Consecutive queries are warm-started with the
    heaviest support points of the previous pair, and the compiled master is reused.
    Stops before a new point once ``budget`` has expired or cannot afford another point
    (:class:`solver.core.budget.Steps`; at least one point is always done); the pairs done
    so far are returned."""
    strict = _strict(tol)
    pairs = []
    prev_in = prev_out = None
    steps = budget.steps()
    for b, nu in zip(np.asarray(points, dtype=float), np.asarray(normals, dtype=float)):
        if not steps.another() and pairs:
            break
        inner = membership(scene, b - delta * nu, footprint, tol=strict, warm_points=_warm(prev_in, prev_out),
                           verify_witness=False)
        outer = membership(scene, b + delta * nu, footprint, tol=strict, warm_points=_warm(inner, prev_out),
                           verify_witness=False)
        pairs.append(BracketPair(b.copy(), nu.copy(), inner, outer, _verdict(inner, outer)))
        prev_in, prev_out = inner, outer
    return tuple(pairs)


def certified_disk_boundary(
    scene: PushScene, n_points: int = 64, tol: SolverTolerances = SOLVER_DEFAULT, budget: Budget = UNLIMITED
) -> CertifiedDiskBoundary:
    """Certify the analytic frictionless-disk boundary of ``scene`` at ``n_points`` points
    (book (3.30), (3.35) and the perimeter arcs; see :mod:`models.locus.cor_disk`), with
    delta = ``tol.boundary_bracket`` * a / 2 on either side along the polyline's normal.
    Once ``budget`` expires the points not reached are left out (``complete`` False;
    ``pairs`` cover the first points of ``boundary``)."""
    t0 = time.perf_counter()
    if scene.is_translation:
        raise InvalidInput("contact_point", "the line of force passes through the CM: the only COR is at infinity")
    ring = disk_cor_locus(scene, outputs=["boundary"], n_points=n_points).boundary
    normals = outward_normals(ring)
    ell = scene.disk_radius
    delta = 0.5 * tol.boundary_bracket * ell
    pairs = certify_brackets(scene, ring, normals, delta, None, tol, budget)
    verdicts = [p.verdict for p in pairs]
    n_ok = verdicts.count("bracketed")
    return CertifiedDiskBoundary(
        boundary=ring,
        normals=normals,
        delta=delta,
        length_scale=ell,
        relative_moment_arm=scene.relative_moment_arm,
        pairs=pairs,
        n_certified=n_ok,
        wrong=tuple(i for i, v in enumerate(verdicts) if v in ("both_inside", "both_outside", "reversed")),
        undecided=tuple(i for i, v in enumerate(verdicts) if v == "undecided"),
        max_error_bound=delta if n_ok else None,
        complete=len(pairs) == len(ring),
        solve_time_s=time.perf_counter() - t0,
    )


# --------------------------------------------------------------------------------------
# Polygon footprints


@dataclass(frozen=True)
class RayCrossing:
    """The traced crossing on one ray from the centre. ``scan`` holds the uncertified
    probe pattern (True = inside) at ``scan_t`` (distances / L); ``crossings`` counts its
    inside-to-outside changes (more than one: the locus is not star-shaped from the
    centre along this ray, as far as the uncertified scan can tell). ``inner``/``outer``
    certify the final bracket [t_in, t_out] (/ L) around the outermost crossing; ``point``
    is its midpoint (world), NaN unless the verdict is "bracketed"."""

    direction: np.ndarray
    scan_t: np.ndarray
    scan: np.ndarray
    crossings: int
    t_in: float
    t_out: float
    point: np.ndarray
    inner: MembershipResult | None
    outer: MembershipResult | None
    verdict: str
    probes: int


@dataclass(frozen=True)
class CertifiedPolygonBoundary:
    """The COR locus of a polygon footprint traced along ``n_rays`` rays from ``centre``.

    ``boundary`` (n_rays, 2) world: the midpoints of the final brackets (NaN where a ray
    was not certified). ``width``: bracket length (world). ``multi_crossing_rays``: rays
    whose scan saw more than one crossing.
    """

    centre: np.ndarray
    centre_result: MembershipResult
    boundary: np.ndarray
    rays: tuple[RayCrossing, ...]
    width: float
    length_scale: float
    n_certified: int
    multi_crossing_rays: tuple[int, ...]
    uncertified_rays: tuple[int, ...]
    solve_time_s: float
    n_requested: int = 0
    complete: bool = True

    @property
    def status(self) -> str:
        """"certified" (every requested ray bracketed) or "incomplete"."""
        return "certified" if self.complete and self.n_certified == len(self.rays) else "incomplete"

    @property
    def message(self) -> str:
        text = f"{self.n_certified} of {self.n_requested} rays bracketed within {self.width:.3g}"
        if len(self.rays) < self.n_requested:
            text += f"; {self.n_requested - len(self.rays)} not started in time"
        if self.multi_crossing_rays:
            text += f"; rays {list(self.multi_crossing_rays)} cross the boundary more than once"
        return text


def ray_exit(ring: np.ndarray, centre: np.ndarray, direction: np.ndarray) -> float:
    """Largest t with centre + t direction on the closed polyline ``ring`` (world)."""
    a = ring - centre
    b = np.roll(ring, -1, axis=0) - centre
    e = b - a
    den = direction[0] * e[:, 1] - direction[1] * e[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (a[:, 0] * e[:, 1] - a[:, 1] * e[:, 0]) / den
        lam = (a[:, 0] * direction[1] - a[:, 1] * direction[0]) / den
    ok = (den != 0.0) & (lam >= 0.0) & (lam <= 1.0) & (t > 0.0)
    return float(np.max(t[ok])) if np.any(ok) else math.nan


def _centre(scene: PushScene, footprint: Footprint, tol: SolverTolerances):
    """A certified inside point: the CM if it is a COR (always when the CM lies in the
    footprint: a point mass there), else the forward COR (3.7) of uniform pressure (when
    the CM is the area centroid) or of the vertices weighted by non-negative least squares
    to put their centroid at the CM (3.1.5)."""
    strict = _strict(tol)
    res = membership(scene, scene.center_of_mass, footprint, tol=strict, verify_witness=False)
    if res.status == "inside":
        return res
    try:
        # uniform pressure (CM at the area centroid): its COR lies well inside the locus
        support = uniform_polygon_support(footprint, subdivisions=4)
    except InvalidInput:
        v = footprint.vertices - scene.center_of_mass
        balance = np.vstack([np.ones(len(v)), v.T / footprint.circumradius])
        weights = nnls(balance, np.array([1.0, 0.0, 0.0]))[0]
        support = Support.create(footprint.vertices, weights, scene.center_of_mass, tol)
    cor = solve_forward(scene, support, tol=tol).cor
    if cor is None:
        raise InvalidInput("contact_point", "the push translates the part: no bounded COR locus to trace")
    res = membership(scene, cor, footprint, tol=strict, verify_witness=False)
    if res.status != "inside":
        raise InvalidInput("workpiece", "found no certified inside point to trace the locus from")
    return res


def _stack(*arrays) -> np.ndarray | None:
    parts = [a for a in arrays if a is not None and np.size(a)]
    return np.vstack(parts) if parts else None


class _RayProber:
    """Uncertified membership probes (column generation with grid pricing) along one ray,
    warm-started with the support points of the centre, the previous ray and its own last
    probe. ``count`` counts all queries made for the ray."""

    def __init__(self, scene, footprint, centre, direction, tol, warm):
        self.scene, self.footprint, self.centre, self.direction, self.tol = scene, footprint, centre, direction, tol
        self.base = warm
        self.warm = warm
        self.count = 0

    def __call__(self, t: float) -> MembershipResult:
        res = membership(self.scene, self.centre + t * self.direction, self.footprint, tol=self.tol,
                         warm_points=self.warm, verify_witness=False, certify=False)
        self.count += 1
        self.warm = _stack(_warm(res), self.base)
        return res


def _residual_slope(scene: PushScene, ell: float, res: MembershipResult, direction: np.ndarray) -> float:
    """d e / d t of the restricted master's optimum e = -y . b along the ray at an outside
    probe: by the envelope theorem sum_j P_j y . dG_j/dt (plus the point mass's term) with
    the probe's support P and dual y held fixed; the columns' derivative is a forward
    difference of :func:`models.core.mpp.membership_columns`. NaN when unusable."""
    y = res.dual
    if y is None or not y[0] < 0.0 or res.witness_points.size == 0:
        return math.nan
    cm = scene.center_of_mass
    r = res.cor - cm
    w = res.witness_points - cm
    h = NEWTON_STEP_REL * ell
    g0 = membership_columns(r, w, scene.contact_rel, scene.alpha_hat, ell)
    g1 = membership_columns(r + h * direction, w, scene.contact_rel, scene.alpha_hat, ell)
    slope = float(res.witness_weights @ (y @ (g1 - g0))) / h
    p0, z = res.point_mass_at_cor, res.point_mass_subgradient
    if p0 > 0.0:
        dpm = np.concatenate([[0.0], p0 * direction / ell, float(scene.alpha_hat @ direction) * z / ell])
        slope += float(y @ dpm)
    return slope * res.witness_residual / -y[0]  # y was scaled into |y|_inf <= 1


def _crossing_estimate(outs: list) -> float:
    """Estimate of the crossing from outside probes (t, e, de/dt), nearest first: the root
    of the quadratic through the nearest probe's value and slope and the next probe's value
    (the residual is convex past the boundary, so Newton alone undershoots), else Newton."""
    if not outs:
        return math.nan
    t0, e0, d0 = outs[0]
    if not d0 > 0.0:
        return math.nan
    if len(outs) > 1:
        t1, e1, _ = outs[1]
        dt = t1 - t0
        c = (e1 - e0 - d0 * dt) / (dt * dt)
        disc = d0 * d0 - 4.0 * c * e0
        if c > 0.0 and disc >= 0.0:
            return t0 - 2.0 * e0 / (d0 + math.sqrt(disc))
    return t0 - e0 / d0


def _refine_crossing(
    probe: _RayProber, ell: float, t_in: float, t_out: float, width: float, max_probes: int = MAX_RAY_PROBES
):
    """Narrow [t_in, t_out] (inside, outside) to ``width`` around the crossing.

    Each outside probe gives the residual and its slope (:func:`_residual_slope`); the
    crossing estimate t* (:func:`_crossing_estimate`) is probed at t* -+ 0.45 width, which
    closes the bracket when t* is good and tightens it otherwise. When a round does not
    halve the bracket, a step an eighth of the way out from t_in (estimates from outside
    fall short of the crossing) brings an outside probe closer. After two such rounds in a
    row the estimates are dropped for plain bisection (a residual that jumps, as where the
    locus meets the footprint's outline). An "undecided" probe (residual between the
    thresholds) counts as outside.
    """
    outs: list = []

    def record(t, res):
        nonlocal t_in, t_out
        if res.status == "inside":
            t_in = max(t_in, t)
        else:
            t_out = min(t_out, t)
            outs.append((t, res.witness_residual, _residual_slope(probe.scene, ell, res, probe.direction)))
            outs.sort(key=lambda o: o[0])

    res = probe(t_out)
    if res.status == "inside":  # the one-round scan was too pessimistic here
        t_in, t_out = t_out, t_out + max(width, t_out - t_in)
        res = probe(t_out)
    record(t_out, res)
    fails = 0
    while t_out - t_in > width and probe.count < max_probes:
        before = t_out - t_in
        root = _crossing_estimate(outs)
        if fails < 2 and t_in < root < t_out:
            for q in (max(t_in, root - 0.45 * width), min(t_out, root + 0.45 * width)):
                if t_in < q < t_out and t_out - t_in > width:
                    record(q, probe(q))
            fails = 0 if t_out - t_in <= 0.5 * before else fails + 1
            if t_out - t_in > 0.5 * before and t_out - t_in > width:
                q = t_in + max(0.5 * width, 0.125 * (t_out - t_in))
                record(q, probe(q))
        else:
            # no usable estimate (e.g. the residual jumps where the locus meets the
            # footprint's outline): bisection
            mid = 0.5 * (t_in + t_out)
            record(mid, probe(mid))
    return t_in, t_out


@dataclass(frozen=True)
class PolygonTrace:
    """What tracing rays of one polygon's locus needs: the certified centre, the
    circumscribing disk's analytic boundary (outer bound, 7.5), widths and tolerances.
    Build it with :func:`polygon_trace`."""

    scene: PushScene
    footprint: Footprint
    length_scale: float
    width: float
    centre: np.ndarray
    centre_result: MembershipResult
    disk_ring: np.ndarray
    tol: SolverTolerances
    scan_points: int


def polygon_trace(
    scene: PushScene, footprint: Footprint, tol: SolverTolerances = SOLVER_DEFAULT, scan_points: int = SCAN_POINTS
) -> PolygonTrace:
    """Prepare :func:`trace_ray` for ``footprint`` (its CM must be the scene's)."""
    if scene.is_translation:
        raise InvalidInput("contact_point", "the line of force passes through the CM: the only COR is at infinity")
    ell = outline_of(scene, footprint, tol).length
    centre_res = _centre(scene, footprint, tol)
    disk_scene = PushScene.create(
        ell, scene.contact_point, scene.edge_angle, scene.push_direction, scene.center_of_mass, scene.tolerances
    )
    ring = disk_cor_locus(disk_scene, outputs=["boundary"], n_points=DISK_REFERENCE_POINTS).boundary
    return PolygonTrace(scene, footprint, ell, tol.boundary_bracket * ell, centre_res.cor, centre_res, ring, tol,
                        scan_points)


def trace_ray(trace: PolygonTrace, direction, warm_points=None) -> RayCrossing:
    """The certified crossing of the locus boundary along the ray from ``trace.centre`` in
    ``direction`` (world unit vector): scan, refine (:func:`_refine_crossing`), certify the
    final pair (widened up to ``MAX_WIDENINGS`` times if needed)."""
    scene, footprint, ell, width = trace.scene, trace.footprint, trace.length_scale, trace.width
    centre = trace.centre
    direction = np.asarray(direction, dtype=float) / float(np.linalg.norm(direction))
    strict = _strict(trace.tol)
    scan_tol = dataclasses.replace(trace.tol, max_cg_iter=1)
    t_disk = ray_exit(trace.disk_ring, centre, direction)
    t_max = (t_disk if math.isfinite(t_disk) else 2.0 * ell) + 4.0 * width
    scan_t = t_max * np.arange(1, trace.scan_points + 1) / trace.scan_points
    scan = np.array([
        membership(scene, centre + t * direction, footprint, tol=scan_tol, verify_witness=False,
                   certify=False).status == "inside"
        for t in scan_t
    ])
    pattern = np.concatenate([[True], scan])  # the centre is inside
    crossings = int(np.sum(pattern[:-1] & ~pattern[1:]))
    last_in = int(np.nonzero(pattern)[0][-1])
    all_t = np.concatenate([[0.0], scan_t])
    prober = _RayProber(scene, footprint, centre, direction, strict,
                        _stack(trace.centre_result.witness_points, warm_points))
    prober.count = trace.scan_points
    nan_point = np.full(2, np.nan)
    if last_in == len(all_t) - 1:
        # inside up to beyond the circumscribing disk's locus: impossible by 7.5
        return RayCrossing(direction, scan_t / ell, scan, crossings, all_t[-1] / ell, math.nan, nan_point,
                           None, None, "undecided", prober.count)
    t_in, t_out = _refine_crossing(prober, ell, all_t[last_in], all_t[last_in + 1], width)
    mid = 0.5 * (t_in + t_out)
    half = 0.5 * max(t_out - t_in, width)
    for attempt in range(MAX_WIDENINGS + 1):
        if attempt:
            half *= 2.0
        inner = membership(scene, centre + (mid - half) * direction, footprint, tol=strict,
                           warm_points=prober.warm, verify_witness=False)
        outer = membership(scene, centre + (mid + half) * direction, footprint, tol=strict,
                           warm_points=_stack(_warm(inner), prober.warm), verify_witness=False)
        prober.count += 2
        verdict = _verdict(inner, outer)
        if verdict == "bracketed":
            break
    point = centre + mid * direction if verdict == "bracketed" else nan_point
    return RayCrossing(direction, scan_t / ell, scan, crossings, (mid - half) / ell, (mid + half) / ell, point,
                       inner, outer, verdict, prober.count)


def certified_polygon_boundary(
    scene: PushScene,
    footprint: Footprint,
    n_rays: int = 64,
    tol: SolverTolerances = SOLVER_DEFAULT,
    scan_points: int = SCAN_POINTS,
    budget: Budget = UNLIMITED,
    trace: PolygonTrace | None = None,
) -> CertifiedPolygonBoundary:
    """Trace the exact COR locus of a simple polygon footprint (frictionless pusher).

    Along each of ``n_rays`` rays from the centre (see :func:`_centre`): the ray's exit
    from the circumscribing disk's analytic locus (which contains this one, 7.5) bounds it;
    ``scan_points`` one-round probes on restricted columns give the in/out pattern; the
    outermost inside-to-outside change is narrowed with uncertified column-generation
    probes (:func:`_refine_crossing`: Newton-type estimates from the residual past the
    boundary, bisection as a fallback) to ``tol.boundary_bracket`` * L, and the final pair
    is certified. A failed certification widens the pair (up to ``MAX_WIDENINGS`` times).
    The result is honest about non-star-shaped loci only as far as the scan can see.
    Once ``budget`` expires, or cannot afford another ray (the longest so far:
    :class:`solver.core.budget.Steps`), the rays not started are left out (``complete``
    False). ``trace``: a :func:`polygon_trace` of the same scene and footprint already built (the
    caller traces more rays with it), else one is built here.
    """
    t_start = time.perf_counter()
    if trace is None:
        trace = polygon_trace(scene, footprint, tol, scan_points)
    rays = []
    warm_prev = None  # support points near the previous ray's crossing
    steps = budget.steps()
    for k in range(n_rays):
        if not steps.another():
            break
        ang = 2.0 * math.pi * k / n_rays
        ray = trace_ray(trace, np.array([math.cos(ang), math.sin(ang)]), warm_prev)
        warm_prev = _warm(ray.inner, ray.outer)
        rays.append(ray)
    return CertifiedPolygonBoundary(
        centre=trace.centre,
        centre_result=trace.centre_result,
        boundary=np.array([r.point for r in rays]),
        rays=tuple(rays),
        width=trace.width,
        length_scale=trace.length_scale,
        n_certified=sum(r.verdict == "bracketed" for r in rays),
        multi_crossing_rays=tuple(i for i, r in enumerate(rays) if r.crossings > 1),
        uncertified_rays=tuple(i for i, r in enumerate(rays) if r.verdict != "bracketed"),
        solve_time_s=time.perf_counter() - t_start,
        n_requested=n_rays,
        complete=len(rays) == n_rays,
    )
