"""Certified COR sketches (book 4.1): of a polygon footprint itself (on the exact loci of
3.3.13/7.5), and of a disk with exactly computed sticking-locus ends.

The disk sketch of :mod:`models.sketch.disk_sketch` bounds a polygon part by its circumscribing
disk (3.1.8), whose loci contain the polygon's (7.5). Here every piece of the sketch is the
polygon's own, each certified by the minimum-power engine:

* {COR}_(alpha +- nu): the frictionless locus of the scene whose edge is turned by +-nu
  (:func:`models.sketch.disk_sketch.force_scene`), traced along rays from a certified inside
  centre with certified brackets (:func:`solver.locus.certified_locus.certified_polygon_boundary`).
  A wrapped locus (its sense is not the part's by Mason's rule with the cone, 1.6.2) holds
  no consistent COR and is not traced; a translation (force line through the CM) has none;
* the slipping loci: the traced loci cut by the same consistency half-planes as the disk's
  (4.1.3, :func:`models.sketch.disk_sketch.assemble_sketch`);
* the sticking locus: both ends exact and certified on the footprint
  (:func:`solver.sketch.sticking_locus.sticking_locus` with the footprint: a convex feasibility problem
  in the pressure distribution, 4.1.4);
* the elementary configurations (4.1.5) and the letter of figure 4-6 (4.1.6) as for the
  disk; the "tip" of a traced locus is its boundary point farthest from the CM (the disk
  locus's tip is that point).

Without a footprint (a disk-bounded part) the elementary loci are the analytic disk loci
(3.30, 3.35; confirmed point by point by certificates in tests/solver/locus/test_certified_locus.py)
and only the sticking locus differs from :func:`models.sketch.disk_sketch.cor_sketch`: its ends are
the exact certified ones instead of the book's force-angle sweep.

Everything is in the world frame. The result says which pieces were certified and, with a
time limit, how far it got.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from models.core.footprint import Footprint
from models.core.scene import PushScene
from models.sketch.disk_sketch import (
    CorSketch,
    ElementaryLocus,
    StickingLocus,
    assemble_sketch,
    check_mu_c,
    classify_locus,
    disk_elementary_locus,
    force_scene,
    sketch_sense,
)
from solver.core.budget import UNLIMITED, Budget
from solver.core.tolerances import SOLVER_DEFAULT, SolverTolerances
from solver.locus.certified_locus import (
    CertifiedPolygonBoundary,
    PolygonTrace,
    RayCrossing,
    certified_polygon_boundary,
    polygon_trace,
    trace_ray,
)
from solver.sketch.sticking_locus import StickingLocus as ExactStickingLocus
from solver.sketch.sticking_locus import sticking_locus

DEFAULT_N_POINTS = 512
"""Boundary points of an analytic disk locus (no footprint)."""

DEFAULT_RAYS = 32
"""Rays traced per elementary locus."""

REFINE_RAYS = 12
"""Most extra rays spent deciding whether a traced locus crosses the sticking line (4.1.5):
bisecting the angular gap next to the traced point nearest to it."""

REACH = 1.0
"""Refinement stops when the nearest traced point is farther from the sticking line than
REACH times the arc length of the gap next to it (a locus bulging that far between two
neighbouring rays would be unusual)."""

MIN_REFINE_GAP = 1e-3
"""Smallest angular gap (rad) that is still bisected."""

MIN_TRACED_POINTS = 3
"""Fewest certified ray crossings that still make a locus polygon."""


@dataclass(frozen=True)
class CertifiedSketch:
    """A certified sketch (module docstring).

    ``sketch``: the assembled :class:`models.sketch.disk_sketch.CorSketch` (its sticking phi_low /
    phi_high are None: the exact ends have no single force angle). ``plus_trace`` /
    ``minus_trace``: the certified traces of {COR}_(alpha+-nu) (None when not traced:
    wrapped, translation, a disk's analytic locus, or out of time). ``sticking``: the exact
    sticking locus. ``footprint``: the polygon, or None for a disk.
    ``complete``: every traced ray and both sticking ends certified, nothing skipped for
    time. ``time_limited``: the time limit cut something short. ``message`` says what."""

    sketch: CorSketch
    plus_trace: CertifiedPolygonBoundary | None
    minus_trace: CertifiedPolygonBoundary | None
    sticking: ExactStickingLocus | None
    footprint: Footprint | None
    n_rays: int
    complete: bool
    time_limited: bool
    solve_time_s: float
    message: str

    @property
    def status(self) -> str:
        """"certified", "time_limited" or "incomplete" (a piece not certified)."""
        if self.complete:
            return "certified"
        return "time_limited" if self.time_limited else "incomplete"


def _farthest_from(points: np.ndarray, centre: np.ndarray) -> np.ndarray:
    d = np.einsum("ij,ij->i", points - centre, points - centre)
    return points[int(np.argmax(d))].copy()


def _traced_locus(
    scene: PushScene, footprint: Footprint, sigma: float, mu_c: float, sense: str, n_rays: int,
    tol: SolverTolerances, budget: Budget,
) -> tuple[ElementaryLocus, CertifiedPolygonBoundary | None, list[str]]:
    nu = math.atan(mu_c)
    turned, m_sign = force_scene(scene, sigma * nu)
    own = {1: "cw", -1: "ccw", 0: "none"}[m_sign]
    if m_sign == 0 or own != sense:
        return classify_locus(scene, sigma, mu_c, sense, m_sign, None, None), None, []
    state = polygon_trace(turned, footprint, tol)  # one certified centre for the uniform and the added rays
    trace = certified_polygon_boundary(turned, footprint, n_rays=n_rays, tol=tol, budget=budget, trace=state)
    rays = _refine_near_sticking_line(scene, state, trace, budget)
    issues = []
    pts = np.array([r.point for r in rays if np.all(np.isfinite(r.point))]).reshape(-1, 2)
    extra = [r for r in rays if all(r is not q for q in trace.rays)]
    if any(r.verdict != "bracketed" for r in extra):
        issues.append(f"{{COR}}_(alpha{'+' if sigma > 0 else '-'}nu): a refining ray was not certified")
    if not trace.complete:
        issues.append(f"{{COR}}_(alpha{'+' if sigma > 0 else '-'}nu): {len(trace.rays)} of {n_rays} rays traced in time")
    if trace.uncertified_rays:
        issues.append(f"{{COR}}_(alpha{'+' if sigma > 0 else '-'}nu): rays {list(trace.uncertified_rays)} not certified")
    if len(pts) < MIN_TRACED_POINTS:
        issues.append(f"{{COR}}_(alpha{'+' if sigma > 0 else '-'}nu): too few certified crossings to draw it")
        return classify_locus(scene, sigma, mu_c, sense, m_sign, None, None), trace, issues
    tip = _farthest_from(pts, scene.center_of_mass)
    return classify_locus(scene, sigma, mu_c, sense, m_sign, pts, tip), trace, issues


def _angle(ray: RayCrossing) -> float:
    return math.atan2(float(ray.direction[1]), float(ray.direction[0])) % (2.0 * math.pi)


def _refine_near_sticking_line(
    scene: PushScene, state: PolygonTrace, trace: CertifiedPolygonBoundary, budget: Budget,
) -> list[RayCrossing]:
    """The traced rays, ordered by angle, plus up to REFINE_RAYS rays that decide whether
    the locus crosses the sticking line (the configuration of 4.1.5 depends on it): while
    every certified point lies on one side of the line, bisect the wider angular gap next
    to the point nearest to it, until the line is farther than REACH times that gap's arc.
    A crossing this misses is not detected (the traced polygon is what the sketch uses)."""
    rays = sorted((r for r in trace.rays), key=_angle)
    if not rays:
        return rays
    c, p = scene.contact_point, scene.push_hat
    steps = budget.steps()
    for _ in range(REFINE_RAYS):
        if not steps.another():
            break
        ok = [i for i, r in enumerate(rays) if np.all(np.isfinite(r.point))]
        if len(ok) < MIN_TRACED_POINTS:
            break
        side = np.array([float((rays[i].point - c) @ p) for i in ok])
        if side.min() < 0.0 < side.max():
            break  # crosses
        k = ok[int(np.argmin(np.abs(side)))]
        a_k = _angle(rays[k])
        gaps = []
        for j in ((k - 1) % len(rays), (k + 1) % len(rays)):
            gap = (a_k - _angle(rays[j])) % (2.0 * math.pi) if j == (k - 1) % len(rays) else (
                _angle(rays[j]) - a_k) % (2.0 * math.pi)
            gaps.append((gap, j))
        gap, j = max(gaps)
        reach = gap * float(np.linalg.norm(rays[k].point - trace.centre))
        if gap < MIN_REFINE_GAP or abs(float((rays[k].point - c) @ p)) > REACH * reach:
            break  # the line lies farther than the gap's arc: a chord there will not reach it
        mid = a_k + (0.5 * gap if j == (k + 1) % len(rays) else -0.5 * gap)
        new = trace_ray(state, np.array([math.cos(mid), math.sin(mid)]))
        rays = sorted(rays + [new], key=_angle)
    return rays


def _sticking_of(exact: ExactStickingLocus, scene: PushScene) -> StickingLocus | None:
    """The exact locus as the sketch's segment: from the lowest to the highest end found
    (several intervals are reported by the exact locus; the sketch keeps their hull)."""
    if exact.lower is None or exact.upper is None:
        return None
    return StickingLocus(
        t_low=float(exact.lower.position), t_high=float(exact.upper.position),
        low=np.asarray(exact.lower.point, dtype=float), high=np.asarray(exact.upper.point, dtype=float),
        phi_low=None, phi_high=None,
    )


def certified_sketch(
    scene: PushScene,
    mu_c: float,
    footprint: Footprint | None = None,
    n_rays: int = DEFAULT_RAYS,
    n_points: int = DEFAULT_N_POINTS,
    tol: SolverTolerances = SOLVER_DEFAULT,
    budget: Budget = UNLIMITED,
) -> CertifiedSketch:
    """The COR sketch (4.1) with certified pieces (module docstring): of ``footprint``
    itself (``n_rays`` rays per traced locus), or, without one, of the scene's disk with
    exact sticking ends (``n_points`` per analytic locus). ``budget`` bounds the whole
    computation: the pieces are computed in the order sticking locus, {COR}_(alpha+nu),
    {COR}_(alpha-nu), each with the time that remains."""
    check_mu_c(mu_c)
    t0 = time.perf_counter()
    sense = sketch_sense(scene, mu_c)
    issues: list[str] = []
    exact = None
    stick = None
    if sense != "none":
        exact = sticking_locus(scene, mu_c, footprint=footprint, tol=tol, budget=budget)
        stick = _sticking_of(exact, scene)
        if exact.status != "found" or not exact.complete:
            issues.append(f"sticking locus: {exact.status} ({exact.message})")
    traces = []
    loci = []
    for sigma in (1.0, -1.0):
        if footprint is None:
            loci.append(disk_elementary_locus(scene, sigma, mu_c, sense, n_points))
            traces.append(None)
            continue
        loc, trace, more = _traced_locus(scene, footprint, sigma, mu_c, sense, n_rays, tol, budget)
        loci.append(loc)
        traces.append(trace)
        issues += more
    sketch = assemble_sketch(scene, mu_c, sense, loci[0], loci[1], stick)
    time_limited = bool(
        (exact is not None and exact.time_limited) or any(t is not None and not t.complete for t in traces)
    )
    return CertifiedSketch(
        sketch=sketch, plus_trace=traces[0], minus_trace=traces[1], sticking=exact, footprint=footprint,
        n_rays=n_rays, complete=not issues, time_limited=time_limited, solve_time_s=time.perf_counter() - t0,
        message="; ".join(issues) if issues else "every piece certified",
    )
