"""Method 'certified' of ``POST /v1/cor/locus``: certified brackets of the COR locus
boundary (solver.locus.certified_locus), under the request's time limit. Points or rays not
reached in time are reported as not done."""

from __future__ import annotations

import math
import time

import numpy as np

from models.footprint import Footprint
from models.scene import PushScene
from service.convert import _f, _v
from service.schemas import BracketOut, CertifiedLocusOut
from solver.core.budget import Budget
from solver.locus.certified_locus import certified_disk_boundary, certified_polygon_boundary


def _point(p) -> list[float] | None:
    arr = np.asarray(p, dtype=float)
    return arr.tolist() if np.all(np.isfinite(arr)) else None


def certified_disk(scene: PushScene, n_points: int, time_limit_s: float) -> CertifiedLocusOut:
    """certified_disk_boundary(scene, n_points) under the time limit."""
    t0 = time.perf_counter()
    res = certified_disk_boundary(scene, n_points=n_points, budget=Budget.of(time_limit_s))
    ring, pairs, delta = res.boundary, res.pairs, res.delta
    return CertifiedLocusOut(
        region="disk",
        n_requested=len(ring),
        n_done=len(pairs),
        n_certified=res.n_certified,
        complete=res.complete,
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
        wrong=list(res.wrong),
        undecided=list(res.undecided),
        multi_crossing=[],
        centre=None,
        time_limit_s=time_limit_s,
        solve_time_ms=(time.perf_counter() - t0) * 1e3,
    )


def certified_polygon(scene: PushScene, footprint: Footprint, n_rays: int, time_limit_s: float) -> CertifiedLocusOut:
    """certified_polygon_boundary(scene, footprint, n_rays) under the time limit."""
    t0 = time.perf_counter()
    res = certified_polygon_boundary(scene, footprint, n_rays=n_rays, budget=Budget.of(time_limit_s))
    rays = list(res.rays)
    centre = res.centre
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
        bracket_width=_f(res.width, "certified.bracket_width"),
        wrong=[],
        undecided=[i for i, r in enumerate(rays) if r.verdict != "bracketed"],
        multi_crossing=[i for i, r in enumerate(rays) if r.crossings > 1],
        centre=_v(centre, "certified.centre"),
        time_limit_s=time_limit_s,
        solve_time_ms=(time.perf_counter() - t0) * 1e3,
    )
