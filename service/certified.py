"""Method 'certified' of ``POST /v1/cor/locus``: certified brackets of the COR locus
boundary (solver.certified_locus), run under the request's time limit.

The solver's ``certified_disk_boundary`` and ``certified_polygon_boundary`` run to the end;
to answer within ``time_limit_s`` this module runs the same steps with the solver's
public building blocks (``certify_brackets`` on chunks of the analytic ring;
``polygon_trace`` + ``trace_ray`` ray by ray), checking the clock in between, with the
same warm starts, so a run that finishes in time gives exactly the solver's answer
(tests/service/test_locus_certified.py checks that). Points or rays not reached are
reported as not done.
"""

from __future__ import annotations

import math
import time

import numpy as np

from models.cor_disk import disk_cor_locus
from models.footprint import Footprint
from models.scene import PushScene
from models.tolerances import SOLVER_DEFAULT
from service.convert import _f, _v
from service.limits import CERTIFIED_CHUNK
from service.schemas import BracketOut, CertifiedLocusOut

# No public equivalents yet: the solver's outward normals of the analytic ring and its
# warm-start selection, so that the chunked run equals certified_*_boundary exactly.
from solver.certified_locus import _outward_normals, _warm, certify_brackets, polygon_trace, trace_ray


def _point(p) -> list[float] | None:
    arr = np.asarray(p, dtype=float)
    return arr.tolist() if np.all(np.isfinite(arr)) else None


def certified_disk(scene: PushScene, n_points: int, time_limit_s: float) -> CertifiedLocusOut:
    """certified_disk_boundary(scene, n_points), chunk by chunk until the time limit."""
    t0 = time.perf_counter()
    deadline = t0 + time_limit_s
    tol = SOLVER_DEFAULT
    ring = disk_cor_locus(scene, outputs=["boundary"], n_points=n_points).boundary
    normals = _outward_normals(ring)
    delta = 0.5 * tol.boundary_bracket * scene.disk_radius
    pairs = []
    for start in range(0, len(ring), CERTIFIED_CHUNK):
        if pairs and time.perf_counter() > deadline:
            break
        stop = start + CERTIFIED_CHUNK
        pairs.extend(certify_brackets(scene, ring[start:stop], normals[start:stop], delta, None, tol))
    verdicts = [p.verdict for p in pairs]
    return CertifiedLocusOut(
        region="disk",
        n_requested=len(ring),
        n_done=len(pairs),
        n_certified=verdicts.count("bracketed"),
        complete=len(pairs) == len(ring),
        boundary=[_v(p.point, "certified.boundary") for p in pairs],
        brackets=[
            BracketOut(
                point=_v(p.point, "certified.point"),
                inner=_v(p.inner.cor, "certified.inner"),
                outer=_v(p.outer.cor, "certified.outer"),
                inner_status=p.inner.status,
                outer_status=p.outer.status,
                verdict=p.verdict,
            )
            for p in pairs
        ],
        bracket_width=_f(2.0 * delta, "certified.bracket_width"),
        wrong=[i for i, v in enumerate(verdicts) if v in ("both_inside", "both_outside", "reversed")],
        undecided=[i for i, v in enumerate(verdicts) if v == "undecided"],
        multi_crossing=[],
        centre=None,
        time_limit_s=time_limit_s,
        solve_time_ms=(time.perf_counter() - t0) * 1e3,
    )


def certified_polygon(scene: PushScene, footprint: Footprint, n_rays: int, time_limit_s: float) -> CertifiedLocusOut:
    """certified_polygon_boundary(scene, footprint, n_rays), ray by ray until the time limit."""
    t0 = time.perf_counter()
    deadline = t0 + time_limit_s
    trace = polygon_trace(scene, footprint, SOLVER_DEFAULT)
    rays = []
    warm_prev = None
    for k in range(n_rays):
        if time.perf_counter() > deadline:
            break
        ang = 2.0 * math.pi * k / n_rays
        ray = trace_ray(trace, np.array([math.cos(ang), math.sin(ang)]), warm_prev)
        warm_prev = _warm(ray.inner, ray.outer)
        rays.append(ray)
    centre = trace.centre
    brackets = []
    for ray in rays:
        ok = math.isfinite(ray.t_in) and math.isfinite(ray.t_out) and ray.inner is not None
        brackets.append(BracketOut(
            point=_point(ray.point),
            inner=_point(ray.inner.cor) if ok else None,
            outer=_point(ray.outer.cor) if ok else None,
            inner_status=ray.inner.status if ray.inner is not None else None,
            outer_status=ray.outer.status if ray.outer is not None else None,
            verdict=ray.verdict,
            crossings=int(ray.crossings),
        ))
    return CertifiedLocusOut(
        region="polygon",
        n_requested=n_rays,
        n_done=len(rays),
        n_certified=sum(r.verdict == "bracketed" for r in rays),
        complete=len(rays) == n_rays,
        boundary=[_point(r.point) for r in rays],
        brackets=brackets,
        bracket_width=_f(trace.width, "certified.bracket_width"),
        wrong=[],
        undecided=[i for i, r in enumerate(rays) if r.verdict != "bracketed"],
        multi_crossing=[i for i, r in enumerate(rays) if r.crossings > 1],
        centre=_v(centre, "certified.centre"),
        time_limit_s=time_limit_s,
        solve_time_ms=(time.perf_counter() - t0) * 1e3,
    )
