"""Schema <-> problem <-> schema of the feeder routes (no mechanics here)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from models.core.footprint import Footprint
from models.feeder.arcs import TWO_PI, Arcs
from models.feeder.fence import Fence, FenceMap, feeder_part
from models.feeder.gate import GateSpec
from models.feeder.placed import Goal, PlacedDesign
from service.api.feeder.schemas import (
    FeederCatalogueItemOut,
    FeederCatalogueRequest,
    FeederCatalogueResponse,
    FeederCpSatOut,
    FeederDesignFenceOut,
    FeederDesignOut,
    FeederDesignRequest,
    FeederDesignResponse,
    FeederDesignSettingsIn,
    FeederEventOut,
    FeederFenceBandOut,
    FeederFenceIn,
    FeederFenceMapOut,
    FeederFenceRunOut,
    FeederGateIn,
    FeederGateOut,
    FeederGoalIn,
    FeederLayoutOut,
    FeederMapRequest,
    FeederMapResponse,
    FeederMatrixOut,
    FeederPartBoundOut,
    FeederPartIn,
    FeederPlacedFenceOut,
    FeederProductBandOut,
    FeederProductOut,
    FeederPushPlanOut,
    FeederRelaxedOut,
    FeederSimulateRequest,
    FeederSimulateResponse,
    FeederValidationOut,
)
from service.common.inputs import located
from service.common.numbers import design_margin
from service.errors import FieldError
from service.limits import FEEDER_MAX_CANDIDATES, FEEDER_MAX_FENCE_LENGTH_RADII, FEEDER_MAX_WORLD_RADII
from solver import (
    BeltSpec,
    FeederCatalogueProblem,
    FeederCatalogueResult,
    FeederDesignProblem,
    FeederDesignResult,
    FeederMapProblem,
    FeederMapResult,
    FeederSimProblem,
    FeederSimResult,
    FeederSimSettings,
    FenceRun,
    PartBoundCost,
    PartBoundSettings,
    RayPool,
    Relaxation,
    angle_count,
)

AT_MOST = "must be at most {limit:g} part radii"
WITHIN = "must lie within {limit:g} part radii of the origin"
CENTROID_REL = 1e-6
"""The support's weighted centroid must lie this close (times the part's radius) to the CM."""


def part_of(p: FeederPartIn) -> Footprint:
    """The part in its body frame; an outline the footprint refuses is refused at
    part.vertices, a centre of mass at part.center_of_mass."""
    with located(("part",), rename={"workpiece": ("part", "vertices")}):
        return feeder_part(p.vertices, p.center_of_mass)


def mu_of(mu_c: float | None, mu_c_range: list[float] | None, loc: tuple) -> float | tuple[float, float]:
    """One mu_c, or an interval (low, high), from a request that gives exactly one of them."""
    if (mu_c is None) == (mu_c_range is None):
        raise FieldError((*loc, "mu_c"), "give exactly one of mu_c or mu_c_range")
    return mu_c if mu_c is not None else (mu_c_range[0], mu_c_range[1])  # type: ignore[index]


def at_most_radii(value: float, part: Footprint, limit: float, loc: tuple, message: str = AT_MOST) -> None:
    """Refuse a length (or a distance from the origin) beyond ``limit`` part radii."""
    if value > limit * part.circumradius:
        raise FieldError(loc, message.format(limit=limit))


def fence_of(f: FeederFenceIn, i: int) -> Fence:
    mu = mu_of(f.mu_c, f.mu_c_range, ("fences", i))
    with located(rename={"fence_angle": ("fences", i, "angle"),
                         "mu_c": ("fences", i, "mu_c" if f.mu_c is not None else "mu_c_range"),
                         "reach": ("fences", i, "reach")}):
        return Fence.create(f.angle, mu, reach=f.reach)


def map_fence_of(f: FeederFenceIn, i: int, part: Footprint) -> Fence:
    if f.reach is not None:
        at_most_radii(f.reach, part, FEEDER_MAX_FENCE_LENGTH_RADII, ("fences", i, "reach"))
    return fence_of(f, i)


def map_problem(req: FeederMapRequest) -> FeederMapProblem:
    part = part_of(req.part)
    if req.part_bound is not None and req.bound != "part":
        raise FieldError(("part_bound",), "is only used with bound \"part\"")
    settings = PartBoundSettings() if req.part_bound is None else PartBoundSettings(
        contacts=req.part_bound.contacts, max_rays_per_aim=req.part_bound.max_rays_per_aim)
    return FeederMapProblem(part, tuple(map_fence_of(f, i, part) for i, f in enumerate(req.fences)), req.resolution,
                            bound=req.bound, part_bound=settings)


def arcs_out(a: Arcs) -> list[list[float]]:
    return [[float(s), float(w)] for s, w in a.arcs]


def part_bound_out(cost: PartBoundCost | None) -> FeederPartBoundOut | None:
    if cost is None:
        return None
    return FeederPartBoundOut(loci=cost.loci, dipods=cost.dipods, rays=cost.rays, rays_bracketed=cost.rays_bracketed,
                              solver_failures=cost.solver_failures, seconds=cost.seconds)


def fence_map_out(fm: FenceMap, cost: PartBoundCost | None = None) -> FeederFenceMapOut:
    bands = []
    for j, turn, band, kernel in zip(fm.final_edges, fm.turns, fm.map.bands, fm.map.kernels):
        bands.append(FeederFenceBandOut(band=arcs_out(band), kernel=arcs_out(kernel), edge=j,
                                  vertex=fm.part.input_index(fm.part.hull_indices[j]), turn_least=turn.least, turn_most=turn.most,
                                  contact_lost=turn.contact_lost))
    return FeederFenceMapOut(angle=fm.fence.angle, mu_c_range=[fm.fence.mu_low, fm.fence.mu_high],
                       jams_possible=fm.fence.may_jam(), bands=bands, jam=arcs_out(fm.map.jam),
                       reach=fm.fence.reach, unaligned=arcs_out(fm.map.unaligned), notes=list(fm.notes),
                       locus_evaluations=sum(t.locus_evaluations for t in fm.turns), part_bound=part_bound_out(cost))


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
    costs = res.part_bound_costs or (None,) * len(res.maps)
    return FeederMapResponse(fences=[fence_map_out(m, c) for m, c in zip(res.maps, costs)], product=product,
                             matrix=matrix, bound=res.bound, status=res.status, complete=res.complete, message=res.message,
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
    if np.hypot(*(centroid - cm)) > CENTROID_REL * part.circumradius:
        raise FieldError(("support", "points"), "their weighted centroid must be the centre of mass "
                         f"(it is {np.hypot(*(centroid - cm)) / part.circumradius:.3g} part radii away)")
    fences = []
    for i, f in enumerate(req.fences):
        fences.append((fence_of(FeederFenceIn(angle=f.angle, mu_c=f.mu_c), i), f.mu_c))
    length = req.fence_length
    if length is not None:
        at_most_radii(length, part, FEEDER_MAX_FENCE_LENGTH_RADII, ("fence_length",))
    placements, start = placed_fences(req, part)
    return FeederSimProblem(part, tuple(fences), pts - cm, w, req.theta_initial, length,
                            FeederSimSettings(max_steps=req.max_steps), req.check_map, placements, start)


def placed_fences(req: FeederSimulateRequest,
                  part: Footprint) -> tuple[tuple[tuple[np.ndarray, float], ...] | None, np.ndarray | None]:
    """Each fence's (end, length) when every one has ``end`` and ``length``, and the start;
    (None, None) when none has; anything between is refused."""
    placed = [f.end is not None or f.length is not None for f in req.fences]
    if not any(placed):
        if req.start is not None:
            raise FieldError(("start",), "only with placed fences (each with end and length)")
        return None, None
    if req.fence_length is not None:
        raise FieldError(("fence_length",), "placed fences give their own length")
    placements = []
    for i, f in enumerate(req.fences):
        for name, value in (("end", f.end), ("length", f.length)):
            if value is None:
                raise FieldError(("fences", i, name), "give end and length for every fence or for none")
        assert f.end is not None and f.length is not None
        at_most_radii(math.hypot(*f.end), part, FEEDER_MAX_WORLD_RADII, ("fences", i, "end"), WITHIN)
        at_most_radii(f.length, part, FEEDER_MAX_FENCE_LENGTH_RADII, ("fences", i, "length"))
        placements.append((np.asarray(f.end, dtype=float), float(f.length)))
    start = None if req.start is None else np.asarray(req.start, dtype=float)
    if start is not None:
        at_most_radii(math.hypot(*start), part, FEEDER_MAX_WORLD_RADII, ("start",), WITHIN)
    return tuple(placements), start


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


def design_settings(d: FeederDesignSettingsIn, part: Footprint, loc: tuple = (), on_belt: bool = False
                    ) -> FeederDesignProblem:
    """The design problem of ``part`` with the search settings ``d`` (at ``loc`` in the
    request; ``on_belt``: the design is placed, so the sides are free unless asked)."""
    a = d.angles
    if a.max < a.min:
        raise FieldError((*loc, "angles", "max"), "must be at least angles.min")
    count = 2 * angle_count(a.min, a.max, a.step)
    if count > FEEDER_MAX_CANDIDATES:
        raise FieldError((*loc, "angles", "step"), f"gives {count:g} candidate fences; at most "
                         f"{FEEDER_MAX_CANDIDATES} (both sides together)")
    given = mu_of(d.mu_c, d.mu_c_range, loc)
    mu = given if isinstance(given, tuple) else (given, given)
    if not mu[0] <= mu[1]:
        raise FieldError((*loc, "mu_c_range"), "must be [low, high] with low <= high")
    return FeederDesignProblem(
        part=part, angle_min=a.min, angle_max=a.max, angle_step=a.step, mu_c=(float(mu[0]), float(mu[1])),
        max_depth=d.max_depth, alternate=not on_belt if d.alternate is None else d.alternate,
        prove_with_cp_sat=d.prove_with_cp_sat,
        validation_parts=d.validation_parts, seed=d.seed)


def design_problem(req: FeederDesignRequest) -> FeederDesignProblem:
    part = part_of(req.part)
    problem = design_settings(req, part, on_belt=req.belt is not None)
    if req.belt is not None:  # the belt's own checks are the solver's (models/feeder/placed.py)
        for name in ("width", "clearance", "spacing", "entry_x", "entry_spread"):
            value = getattr(req.belt, name)
            if value is not None:
                at_most_radii(abs(value), part, FEEDER_MAX_WORLD_RADII, ("belt", name))
    elif req.goal is not None or req.gate is not None:
        raise FieldError(("goal" if req.goal is not None else "gate",), "needs a belt: goals and gates are for "
                                                                        "designs placed on one")
    with located(rename={"goal": ("goal",), "gate.features": ("gate", "features"), "gate.margin": ("gate", "margin"),
                         "gate.min_yield": ("gate", "min_yield"), "goal.side": ("goal", "side"),
                         "goal.tolerance": ("goal", "tolerance")}):
        goal = goal_of(req.goal, part)
        asked = req.gate if "gate" in req.model_fields_set or req.belt is None else FeederGateIn()
        gate = None if asked is None else gate_of(asked, part)
    b = req.belt
    return dataclasses.replace(
        problem, belt=None if b is None else BeltSpec(b.width, b.clearance, b.spacing, b.entry_x, b.entry_spread),
        goal=goal, gate=gate, min_yield=req.min_yield)


def catalogue_problem(req: FeederCatalogueRequest, pool: RayPool) -> FeederCatalogueProblem:
    """Every part (errors at ``parts[i]``) and the one design request, to run on ``pool``."""
    parts = []
    for i, p in enumerate(req.parts):
        with located(("parts", i), rename={"workpiece": ("parts", i, "vertices")}):
            parts.append(feeder_part(p.vertices, p.center_of_mass))
    return FeederCatalogueProblem(tuple(parts), design_settings(req.design, parts[0], ("design",)), pool)


def catalogue_response(req: FeederCatalogueRequest, result: FeederCatalogueResult,
                       elapsed_ms: float) -> FeederCatalogueResponse:
    items = []
    for p, res in zip(req.parts, result.designs):
        if res is None:
            items.append(FeederCatalogueItemOut(name=p.name, status="not_finished", fences=None, depth_proven=None,
                                                margin=None, validation_parts=0, validation_in_band=0,
                                                solve_time_ms=None))
            continue
        d, v = res.design, res.validation
        items.append(FeederCatalogueItemOut(
            name=p.name, status="ok" if res.status == "ok" else "time_limit",
            fences=None if d is None else _fences_out(res, d.fences),
            depth_proven=None if res.search is None else res.search.depth_proven,
            margin=None if d is None else design_margin(d.margin),
            validation_parts=0 if v is None else v.simulated, validation_in_band=0 if v is None else v.in_band,
            solve_time_ms=res.solve_time_s * 1e3))
    run = result.run
    return FeederCatalogueResponse(status=result.status, designs=items, finished=run.finished, backend=run.backend,
                                   cpus=run.cpus, nodes=run.nodes, solve_time_ms=result.solve_time_s * 1e3,
                                   elapsed_ms=elapsed_ms)


def goal_of(g: FeederGoalIn | None, part: Footprint) -> Goal:
    """The goal: intervals in [0, 2 pi) (each shorter than a turn), or an edge of the outline
    against a guide."""
    if g is None:
        return Goal()
    if (g.accepted is None) == (g.edge is None):
        raise FieldError(("goal",), "give exactly one of accepted or edge")
    if g.edge is not None:
        if g.edge >= len(part.vertices):
            raise FieldError(("goal", "edge"), f"must be below the outline's {len(part.vertices)} edges")
        j = part.hull_edge_of_input(g.edge)
        if j is None:
            raise FieldError(("goal", "edge"), "is not on the part's convex hull: it never lies against a guide")
        return Goal.edge_against_guide(part, j, g.side, g.tolerance)
    arcs = []
    for i, (start, end) in enumerate(g.accepted or []):
        if not 0.0 <= start < TWO_PI:
            raise FieldError(("goal", "accepted", i, 0), "must be in [0, 2 pi)")
        if not start < end < start + TWO_PI:
            raise FieldError(("goal", "accepted", i, 1), "must lie after start by less than 2 pi")
        arcs.append((start, end - start))
    return Goal(Arcs.of(arcs))


def gate_of(g: FeederGateIn, part: Footprint) -> GateSpec:
    """The gate allowed: a margin no two silhouettes can clear (their extents differ by less
    than the part's diameter) is refused."""
    if g.margin is not None and 2.0 * g.margin >= 2.0 * part.circumradius:
        raise FieldError(("gate", "margin"), "no gate can realise it: two silhouettes' extents differ by less than "
                                             "the part's diameter, twice the margin is more")
    return GateSpec(tuple(dict.fromkeys(g.features)), g.margin, g.min_yield, g.max_depth)


def _fences_out(res: FeederDesignResult, fences: tuple[int, ...]) -> list[FeederDesignFenceOut]:
    """A design's fences (indices into the candidates' maps) as answered: angle and side."""
    return [FeederDesignFenceOut(angle=res.maps[f].fence.angle, side=res.maps[f].fence.side) for f in fences]


def _design_out(res: FeederDesignResult) -> FeederDesignOut | None:
    d = res.design
    if d is None or res.final_set is None:
        return None
    last = res.maps[d.fences[-1]]
    out = FeederDesignOut(
        fences=_fences_out(res, d.fences),
        final_band=arcs_out(res.final_set), final_edges=sorted(last.final_edges[j] for j in d.final_bands),
        margin=design_margin(d.margin))
    if isinstance(d, PlacedDesign) and res.accepted_set is not None:
        out.accepted_band = arcs_out(res.accepted_set)
        out.accepted_edges = sorted(last.final_edges[j] for j in d.accepted_bands)
        out.guaranteed_yield = d.guaranteed_yield
        out.expected_passes = 1.0 / d.guaranteed_yield if d.guaranteed_yield > 0.0 else None
        out.lost = d.lost.measure
        out.slivers = d.slivers
    return out


def _layout_out(res: FeederDesignResult) -> FeederLayoutOut | None:
    pl = res.placement
    d = res.design
    if pl is None or not isinstance(d, PlacedDesign):
        return None
    fences = [FeederPlacedFenceOut(angle=f.angle, side=f.side, root=[float(f.root[0]), float(f.root[1])],
                                   end=[float(f.end[0]), float(f.end[1])], length=f.length, reach=f.reach,
                                   reach_needed=f.reach_needed, binding=list(b))
              for f, b in zip(pl.fences, pl.binding)]
    gate = None
    if d.gate is not None and pl.gate_y is not None:
        gate = FeederGateOut(feature=d.gate.feature, rule=d.gate.rule, threshold=d.gate.threshold,
                             margin=d.gate.margin, y=pl.gate_y)
    return FeederLayoutOut(belt_width=pl.belt.width, gap=pl.belt.gap, entry_x=pl.belt.entry_x,
                           entry_spread=pl.belt.entry_spread, belt_length=pl.length, fences=fences, gate=gate)


def _relaxed_out(r: Relaxation) -> FeederRelaxedOut:
    d = r.design
    placed = isinstance(d, PlacedDesign)
    return FeederRelaxedOut(setting=r.setting, searched=r.result is not None,  # type: ignore[arg-type]
                            fences=None if d is None else len(d.fences),
                            gated=(d.gate is not None) if placed else None,
                            guaranteed_yield=d.guaranteed_yield if placed else None)


def design_response(res: FeederDesignResult, elapsed_ms: float) -> FeederDesignResponse:
    cp = None
    if res.cp_sat is not None:
        cp = FeederCpSatOut(depth_proven=res.cp_sat.depth_proven, statuses=list(res.cp_sat.statuses),
                            complete=res.cp_sat.complete, solve_time_ms=res.cp_sat.solve_time_s * 1e3)
    val = None
    if res.validation is not None:
        v = res.validation
        val = FeederValidationOut(parts=v.parts, in_band=v.in_band, outside=v.outside, unflushed=v.unflushed,
                                  unfinished=v.unfinished, cut=v.cut, missed=v.missed, on_belt=v.on_belt,
                                  off_belt=v.off_belt,
                                  rejected=v.rejected, unflushed_gated=v.unflushed_gated, rate=None if math.isnan(v.rate) else v.rate,
                                  yield_per_pass=v.yield_per_pass if v.on_belt and v.simulated else None,
                                  succeeded=v.succeeded if v.on_belt and v.simulated else None)
    base = None
    if res.baseline is not None:
        b = res.baseline
        base = FeederPushPlanOut(pushes=None if b.alphas is None else 1 + len(b.alphas),
                                 alphas=None if b.alphas is None else list(b.alphas),
                                 tolerance=b.tolerance if math.isfinite(b.tolerance) and b.alphas else None,
                                 solve_time_ms=b.solve_time_s * 1e3, complete=b.complete)
    search = res.search if res.placed_search is None else res.placed_search
    progress = res.progress
    return FeederDesignResponse(
        design=_design_out(res),
        depth_proven=search.depth_proven if search is not None else (progress.depth_proven if progress else 0),
        exhausted=bool(search is not None and search.exhausted),
        fences_only_exhausted=res.fences_only_exhausted,
        relaxed=[_relaxed_out(r) for r in res.relaxed],
        candidates=len(res.maps),
        nodes=search.nodes if search is not None else (progress.nodes if progress else 0),
        pruned=search.pruned if search is not None else (progress.pruned if progress else 0),
        cp_sat=cp, validation=val, layout=_layout_out(res), push_plan_baseline=base,
        timings_ms={k: v * 1e3 for k, v in res.timings.items()},
        status=res.status, complete=res.complete, message=res.message,
        solve_time_ms=res.solve_time_s * 1e3, elapsed_ms=elapsed_ms)
