"""Schema <-> problem <-> schema of the feeder routes (no mechanics here)."""

from __future__ import annotations

import numpy as np

from models.feeder.arcs import Arcs
from models.feeder.fence import Fence, FenceMap, Part
from service.api.feeder.schemas import (
    FeederEventOut,
    FeederFenceBandOut,
    FeederFenceIn,
    FeederFenceMapOut,
    FeederFenceRunOut,
    FeederMapRequest,
    FeederMapResponse,
    FeederMatrixOut,
    FeederPartIn,
    FeederProductBandOut,
    FeederProductOut,
    FeederSimulateRequest,
    FeederSimulateResponse,
)
from service.common.inputs import located
from service.errors import FieldError
from service.limits import FEEDER_MAX_FENCE_LENGTH_RADII
from solver import FeederMapProblem, FeederMapResult, FeederSimProblem, FeederSimResult, FeederSimSettings, FenceRun

CENTROID_REL = 1e-6
"""The support's weighted centroid must lie this close (times the part's radius) to the CM."""


def part_of(p: FeederPartIn) -> Part:
    with located(("part",)):
        return Part.create(p.vertices, p.center_of_mass)


def fence_of(f: FeederFenceIn, i: int) -> Fence:
    mu: float | tuple[float, float]
    if f.mu_c is not None and f.mu_c_range is None:
        mu = f.mu_c
    elif f.mu_c is None and f.mu_c_range is not None:
        mu = (f.mu_c_range[0], f.mu_c_range[1])
    else:
        raise FieldError(("fences", i, "mu_c"), "give exactly one of mu_c or mu_c_range")
    with located(rename={"fence_angle": ("fences", i, "angle"),
                         "mu_c": ("fences", i, "mu_c" if f.mu_c is not None else "mu_c_range"),
                         "reach": ("fences", i, "reach")}):
        return Fence.create(f.angle, mu, reach=f.reach)


def map_fence_of(f: FeederFenceIn, i: int, part: Part) -> Fence:
    if f.reach is not None and f.reach > FEEDER_MAX_FENCE_LENGTH_RADII * part.radius:
        raise FieldError(("fences", i, "reach"), f"must be at most {FEEDER_MAX_FENCE_LENGTH_RADII:g} part radii")
    return fence_of(f, i)


def map_problem(req: FeederMapRequest) -> FeederMapProblem:
    part = part_of(req.part)
    return FeederMapProblem(part, tuple(map_fence_of(f, i, part) for i, f in enumerate(req.fences)), req.resolution)


def arcs_out(a: Arcs) -> list[list[float]]:
    return [[float(s), float(w)] for s, w in a.arcs]


def fence_map_out(fm: FenceMap) -> FeederFenceMapOut:
    bands = []
    for j, turn, band, kernel in zip(fm.final_edges, fm.turns, fm.map.bands, fm.map.kernels):
        bands.append(FeederFenceBandOut(band=arcs_out(band), kernel=arcs_out(kernel), edge=j,
                                  vertex=fm.part.vertex_index[j], turn_least=turn.least, turn_most=turn.most,
                                  contact_lost=turn.contact_lost))
    return FeederFenceMapOut(angle=fm.fence.angle, mu_c_range=[fm.fence.mu_low, fm.fence.mu_high],
                       jams_possible=fm.fence.may_jam(), bands=bands, jam=arcs_out(fm.map.jam),
                       reach=fm.fence.reach, unaligned=arcs_out(fm.map.unaligned), notes=list(fm.notes),
                       locus_evaluations=sum(t.locus_evaluations for t in fm.turns))


def map_response(res: FeederMapResult, elapsed_ms: float) -> FeederMapResponse:
    product = None
    if res.product is not None:
        codes = res.product.code_sets or tuple(frozenset({j}) for j in range(len(res.product.bands)))
        product = FeederProductOut(
            bands=[FeederProductBandOut(band=arcs_out(b), kernel=arcs_out(k), code_set=sorted(c))
                   for b, k, c in zip(res.product.bands, res.product.kernels, codes)],
            jam=arcs_out(res.product.jam), unaligned=arcs_out(res.product.unaligned))
    matrix = None
    if res.matrix is not None:
        rows = ["".join("1" if x else "0" for x in row) for row in res.matrix]
        matrix = FeederMatrixOut(resolution=int(res.matrix.shape[0]), rows=rows)
    return FeederMapResponse(fences=[fence_map_out(m) for m in res.maps], product=product, matrix=matrix,
                             bound="disk", status=res.status, complete=res.complete, message=res.message,
                             solve_time_ms=res.solve_time_s * 1e3, elapsed_ms=elapsed_ms)


def simulate_problem(req: FeederSimulateRequest) -> FeederSimProblem:
    part = part_of(req.part)
    cm = np.asarray(req.part.center_of_mass, dtype=float)
    pts = np.asarray(req.support.points, dtype=float)
    w = np.asarray(req.support.weights, dtype=float)
    if len(w) != len(pts):
        raise FieldError(("support", "weights"), "need one weight per support point")
    if w.sum() <= 0.0:
        raise FieldError(("support", "weights"), "must not all be 0")
    centroid = (w[:, None] * pts).sum(axis=0) / w.sum()
    if np.hypot(*(centroid - cm)) > CENTROID_REL * part.radius:
        raise FieldError(("support", "points"), "their weighted centroid must be the centre of mass "
                         f"(it is {np.hypot(*(centroid - cm)) / part.radius:.3g} part radii away)")
    fences = []
    for i, f in enumerate(req.fences):
        fences.append((fence_of(FeederFenceIn(angle=f.angle, mu_c=f.mu_c), i), f.mu_c))
    length = req.fence_length
    if length is not None and length > FEEDER_MAX_FENCE_LENGTH_RADII * part.radius:
        raise FieldError(("fence_length",), f"must be at most {FEEDER_MAX_FENCE_LENGTH_RADII:g} part radii")
    return FeederSimProblem(part, tuple(fences), pts - cm, w, req.theta_initial, length,
                            FeederSimSettings(max_steps=req.max_steps), req.check_map)


def run_out(run: FenceRun, in_map: bool | None, samples: int) -> FeederFenceRunOut:
    n = len(run.pushes)
    idx = np.unique(np.linspace(0, n - 1, min(samples, n)).round().astype(int)) if samples > 0 else np.array([], int)
    traj = [[float(run.pushes[k]), float(run.cms[k][0]), float(run.cms[k][1]), float(run.thetas[k])] for k in idx]
    return FeederFenceRunOut(status=run.status, flushed=run.flushed, theta_initial=run.theta_initial, theta_final=run.theta_final,
                       in_map=in_map, events=[FeederEventOut(push=e.push, kind=e.kind, detail=e.detail) for e in run.events],
                       trajectory=traj, steps=n - 1, forward_solves=run.counts.solves)


def simulate_response(req: FeederSimulateRequest, res: FeederSimResult, elapsed_ms: float) -> FeederSimulateResponse:
    return FeederSimulateResponse(runs=[run_out(r, v, req.trajectory_points) for r, v in zip(res.runs, res.in_map)],
                                  theta_final=res.theta_final, status=res.status, complete=res.complete,
                                  message=res.message, solve_time_ms=res.solve_time_s * 1e3, elapsed_ms=elapsed_ms)
