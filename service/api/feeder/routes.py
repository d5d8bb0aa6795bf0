"""``POST /v1/feeder/map`` (configuration maps of fences and their product, book 5.1-5.2),
``POST /v1/feeder/simulate`` (one part through the fences, quasi-statically),
``POST /v1/feeder/design`` (the shortest sequence of fences that orients a part, 5.3-5.4)
and ``POST /v1/feeder/catalogue`` (a design for each of many parts, in parallel on Ray).

Each route hands its job to a solver worker: request -> problem
(:mod:`service.api.feeder.convert`) -> one solver call (:func:`solver.feeder_map`,
:func:`solver.feeder_simulate`, :func:`solver.feeder_design`, :func:`solver.feeder_catalogue`) with the request's budget -> response.
"""

from __future__ import annotations

import os

from fastapi import APIRouter, Query, Request
from fastapi.responses import Response

from service.api.feeder.convert import (
    catalogue_problem,
    catalogue_response,
    design_problem,
    design_response,
    map_problem,
    map_response,
    simulate_problem,
    simulate_response,
)
from service.api.feeder.render import BeltPicture, render_belt_svg, render_maps_svg, render_runs_svg
from service.api.feeder.schemas import (
    FeederCatalogueRequest,
    FeederCatalogueResponse,
    FeederDesignRequest,
    FeederDesignResponse,
    FeederMapRequest,
    FeederMapResponse,
    FeederSimulateRequest,
    FeederSimulateResponse,
)
from service.common.bodies import BodyRoute
from service.common.fields import ResponseFormat
from service.common.inputs import located
from service.common.responses import IN_WORKER, SVG_MEDIA_TYPE, json_or_svg
from service.errors import nothing_computed
from service.runtime.deadline import Deadline
from service.runtime.deferred import Deferrable, json_answer, request_only
from service.runtime.jobs import runner
from service.runtime.slots import SERVER_PID_ENV, SLOT_DIR_ENV
from service.settings import Settings
from solver import RayPool, feeder_catalogue, feeder_design, feeder_map, feeder_simulate

router = APIRouter(tags=["feeder"], route_class=BodyRoute)
FORMAT = Query("json", alias="format", description="`json` (default) or `svg` for a picture.")


@router.post(
    "/v1/feeder/map",
    operation_id="feeder_map",
    summary="Configuration maps of fences on a belt and their product (book 5.1-5.2)",
    response_model=FeederMapResponse,
    responses={**json_or_svg("JSON (default) or, with `format=svg`, the maps as figure 1-8 and their product "
                             "as figure 5-2."), **IN_WORKER},
)
async def feeder_map_route(req: FeederMapRequest, request: Request,
                           response_format: ResponseFormat = FORMAT) -> Response:
    """For each fence, every final orientation possible from each initial one over all
    pressure distributions (bands and kernels, bounded with the part's circumscribing
    disk, or on request with its own loci), the orientations that may jam (6.4) or that a short fence may not align (1.8.6),
    and the map of the whole sequence with its code sets (5.4, 5.5); optionally the
    product's boolean matrix (5.1)."""
    return await runner(request).expensive_job(request, map_job, req, response_format == "svg",
                                               time_limit_s=req.deadline_s, cost_key=req.bound)


def map_job(req: FeederMapRequest, svg: bool, deadline: Deadline) -> FeederMapResponse | Response:
    budget = deadline.budget()
    problem = map_problem(req)
    with located():
        result = feeder_map(problem, budget)
    if not result.maps and not result.complete:
        raise nothing_computed("the first fence map", budget.limit_s, budget.elapsed())
    if svg and result.maps:
        by = "the circumscribing disk" if result.bound == "disk" else "the part's own loci"
        title = (f"Configuration maps (5.1-5.2), bounded with {by}"
                 f"{'' if result.complete else ' (time limit: ' + str(len(result.maps)) + ' of ' + str(len(problem.fences)) + ' fences)'}")
        return Response(content=render_maps_svg(problem.part, result.maps, result.product, title),
                        media_type=SVG_MEDIA_TYPE)
    return map_response(result, budget.elapsed() * 1e3)


@router.post(
    "/v1/feeder/simulate",
    operation_id="feeder_simulate",
    summary="One part with a known support through a sequence of fences (book 5.1, 6.5)",
    response_model=FeederSimulateResponse,
    responses={**json_or_svg("JSON (default) or, with `format=svg`, a top view of each fence's run."), **IN_WORKER},
)
async def feeder_simulate_route(req: FeederSimulateRequest, request: Request,
                                response_format: ResponseFormat = FORMAT) -> Response:
    """The part drifts with the belt onto each fence, turns on a vertex, slides flush or
    jams, and turns off the fence's end, each motion from the forward minimum-power solve
    (3.7, 4.1); the final orientation of one fence is the initial one of the next. Events,
    a sampled trajectory, and whether each outcome lies in its fence's map."""
    return await runner(request).expensive_job(request, simulate_job, req, response_format == "svg",
                                               time_limit_s=req.time_limit_s)


def simulate_job(req: FeederSimulateRequest, svg: bool, deadline: Deadline) -> FeederSimulateResponse | Response:
    budget = deadline.budget()
    problem = simulate_problem(req)
    with located():
        result = feeder_simulate(problem, budget)
    if svg and result.runs and result.placed:
        n = len(result.segments)
        picture = BeltPicture([(seg.root, seg.end) for seg in result.segments], None, [result.runs])
        return Response(content=render_belt_svg(problem.part, picture, f"A part through {n} placed "
                                                f"fence{'s' if n > 1 else ''}: {result.message}"),
                        media_type=SVG_MEDIA_TYPE)
    if svg and result.runs:
        segs = result.segments[:len(result.runs)]
        return Response(content=render_runs_svg(problem.part, result.runs, segs,
                                                f"A part through {len(segs)} fence{'s' if len(segs) > 1 else ''}: "
                                                f"{result.message}"), media_type=SVG_MEDIA_TYPE)
    return simulate_response(req, result, budget.elapsed() * 1e3)


@router.post(
    "/v1/feeder/design",
    operation_id="feeder_design",
    summary="The shortest sequence of fences that brings a part to one orientation (book 5.3-5.4)",
    response_model=FeederDesignResponse,
    responses={**json_or_svg("JSON (default) or, with `format=svg`, the design's maps fence by fence and their "
                             "product, as in figure 5-4."), **IN_WORKER},
)
async def feeder_design_route(req: FeederDesignRequest, request: Request,
                              response_format: ResponseFormat = FORMAT) -> Response:
    """The maps of candidate fences (both sides of the belt, a range of angles), the
    shortest design by a breadth-first search over their code sets with exact pruning,
    the most robust of the shortest (the largest margin, 1.8.6), optionally proven again by
    CP-SAT, and optionally validated by simulated parts. With a belt the design is searched
    as placed: each fence's reach in the search, the goal given, a reject gate when fences
    alone cannot (7.1), the guaranteed yield per pass and the shortest belt; its validation
    runs on the placed belt. Past the time limit: what was established (the depth proven,
    the design if found)."""
    return await runner(request).expensive_job(request, design_job, req, response_format == "svg",
                                               time_limit_s=req.time_limit_s)


def design_job(req: FeederDesignRequest, svg: bool, deadline: Deadline) -> FeederDesignResponse | Response:
    budget = deadline.budget()
    problem = design_problem(req)
    with located(rename={"belt.width": ("belt", "width"), "belt.entry_x": ("belt", "entry_x"),
                         "belt.spacing": ("belt", "spacing"), "belt.clearance": ("belt", "clearance"),
                         "belt.entry_spread": ("belt", "entry_spread"), "validation_parts": ("validation_parts",),
                         "min_yield": ("min_yield",)}):
        result = feeder_design(problem, budget)
    if not result.maps and not result.complete:
        raise nothing_computed("the first candidate fence's map", budget.limit_s, budget.elapsed())
    design = result.design
    if svg and design is not None:
        maps = [result.maps[f] for f in design.fences]
        title = f"A feeder of {len(maps)} fence{'s' if len(maps) > 1 else ''} (5.4): each fence's map and their product"
        belt = None
        if result.placement is not None:
            examples = result.validation.examples if result.validation is not None else ()
            belt = BeltPicture([(f.root, f.end) for f in result.placement.fences], result.placement.belt.width,
                               [r.runs for r in examples], result.placement.gate_y)
        return Response(content=render_maps_svg(problem.part, maps, result.product, title, belt),
                        media_type=SVG_MEDIA_TYPE)
    return design_response(result, budget.elapsed() * 1e3)


@router.post(
    "/v1/feeder/catalogue",
    operation_id="feeder_catalogue",
    summary="Feeder designs for a catalogue of parts, in parallel on Ray (book 5.3-5.4)",
    response_model=FeederCatalogueResponse,
    responses=IN_WORKER,
)
async def feeder_catalogue_route(req: FeederCatalogueRequest, request: Request) -> Response:
    """One design request for many parts: each part's design (as /v1/feeder/design, without
    a belt) and its validation by simulated parts, run in parallel on Ray (a local Ray of
    PESHKIN_RAY_WORKERS CPUs, or the cluster at PESHKIN_RAY_ADDRESS). Long catalogues are
    best submitted as jobs (POST /v1/jobs, operation feeder_catalogue)."""
    return await runner(request).expensive_job(request, catalogue_job, req, time_limit_s=req.time_limit_s,
                                               anytime=True, width=catalogue_width(req))


def catalogue_width(req: FeederCatalogueRequest) -> int:
    """The solver slots a catalogue can use: one per part on the server's own Ray (up to its
    CPUs); one (the driver) on a cluster or without Ray."""
    settings = Settings.from_env()
    if settings.ray_address or settings.ray_cpus() == 0:
        return 1
    return max(1, min(len(req.parts), settings.ray_cpus()))


def catalogue_job(req: FeederCatalogueRequest, deadline: Deadline) -> FeederCatalogueResponse:
    """The catalogue on the cluster at PESHKIN_RAY_ADDRESS, or on the server's one local Ray
    with as many tasks at once as it was given slots (service.runtime.admission)."""
    budget = deadline.budget()
    settings = Settings.from_env()
    cluster = settings.ray_address or None
    server = os.environ.get(SERVER_PID_ENV)
    pool = RayPool(workers=settings.ray_cpus(), address=cluster, parallel=0 if cluster else deadline.slots,
                   server_dir=os.environ.get(SLOT_DIR_ENV) or None, server_pid=int(server) if server else None)
    problem = catalogue_problem(req, pool)
    with located():
        result = feeder_catalogue(problem, budget)
    if result.run.finished == 0:
        raise nothing_computed("the first part's design", budget.limit_s, budget.elapsed())
    return catalogue_response(req, result, budget.elapsed() * 1e3)


DEFERRABLE = {
    "feeder_map": Deferrable("POST /v1/feeder/map", FeederMapRequest, map_job, json_answer,
                             cost=lambda req: req.bound),
    "feeder_simulate": Deferrable("POST /v1/feeder/simulate", FeederSimulateRequest, simulate_job, json_answer),
    "feeder_design": Deferrable("POST /v1/feeder/design", FeederDesignRequest, design_job, json_answer),
    "feeder_catalogue": Deferrable("POST /v1/feeder/catalogue", FeederCatalogueRequest, catalogue_job,
                                   request_only, width=catalogue_width),
}
"""The operations ``POST /v1/jobs`` runs later (service.runtime.deferred)."""
