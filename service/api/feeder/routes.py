"""``POST /v1/feeder/map`` (configuration maps of fences and their product, book 5.1-5.2)
and ``POST /v1/feeder/simulate`` (one part through the fences, quasi-statically).

Each route hands its job to a solver worker: request -> problem
(:mod:`service.api.feeder.convert`) -> one solver call (:func:`solver.feeder_map`,
:func:`solver.feeder_simulate`) with the request's budget -> response.
"""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import Response

from service.api.feeder.convert import map_problem, map_response, simulate_problem, simulate_response
from service.api.feeder.schemas import (
    FeederMapRequest,
    FeederMapResponse,
    FeederSimulateRequest,
    FeederSimulateResponse,
)
from service.common.inputs import located
from service.common.responses import IN_WORKER
from service.runtime.deadline import Deadline
from service.runtime.jobs import runner
from solver import feeder_map, feeder_simulate

router = APIRouter(tags=["feeder"])


@router.post(
    "/v1/feeder/map",
    operation_id="feeder_map",
    summary="Configuration maps of fences on a belt and their product (book 5.1-5.2)",
    response_model=FeederMapResponse,
    responses=IN_WORKER,
)
async def feeder_map_route(req: FeederMapRequest, request: Request) -> Response:
    """For each fence, every final orientation possible from each initial one over all
    pressure distributions (bands and kernels, bounded with the part's circumscribing
    disk), the orientations that may jam (6.4), and the map of the whole sequence with its
    code sets (5.4, 5.5); optionally the product's boolean matrix (5.1)."""
    return await runner(request).expensive_job(request, map_job, req, time_limit_s=req.time_limit_s)


def map_job(req: FeederMapRequest, deadline: Deadline) -> FeederMapResponse:
    budget = deadline.budget()
    problem = map_problem(req)
    with located():
        result = feeder_map(problem, budget)
    return map_response(result, budget.elapsed() * 1e3)


@router.post(
    "/v1/feeder/simulate",
    operation_id="feeder_simulate",
    summary="One part with a known support through a sequence of fences (book 5.1, 6.5)",
    response_model=FeederSimulateResponse,
    responses=IN_WORKER,
)
async def feeder_simulate_route(req: FeederSimulateRequest, request: Request) -> Response:
    """The part drifts with the belt onto each fence, turns on a vertex, slides flush or
    jams, and turns off the fence's end, each motion from the forward minimum-power solve
    (3.7, 4.1); the final orientation of one fence is the initial one of the next. Events,
    a sampled trajectory, and whether each outcome lies in its fence's map."""
    return await runner(request).expensive_job(request, simulate_job, req, time_limit_s=req.time_limit_s)


def simulate_job(req: FeederSimulateRequest, deadline: Deadline) -> FeederSimulateResponse:
    budget = deadline.budget()
    problem = simulate_problem(req)
    with located():
        result = feeder_simulate(problem, budget)
    return simulate_response(req, result, budget.elapsed() * 1e3)
