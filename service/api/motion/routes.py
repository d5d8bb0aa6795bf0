"""``POST /v1/cor/solve`` (motions for known pressure distributions) and ``POST
/v1/cor/tripod-statistics`` (CORs of random tripods, figures 3-5 and 7-2).

Each route hands its job to a solver worker (:mod:`service.runtime.jobs`). Each job:
request -> problem (:mod:`service.api.motion.convert`) -> one solver call
(:func:`solver.motion.solve.solve_motion`,
:func:`solver.motion.statistics.tripod_statistics`) with the request's budget -> response.
"""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter, Request
from fastapi.responses import Response

from service.api.motion.convert import (
    motion_errors_located,
    motion_problem,
    solve_response,
    tripod_problem,
    tripod_statistics_response,
)
from service.api.motion.schemas import (
    CorSolveRequest,
    CorSolveResponse,
    TripodStatisticsRequest,
    TripodStatisticsResponse,
)
from service.common.binary import in_msgpack, msgpack_openapi, wants_msgpack
from service.common.bodies import BodyReader, BodyRoute, in_worker, large_bodies
from service.common.inputs import located
from service.common.responses import IN_WORKER
from service.runtime.deadline import Deadline
from service.runtime.deferred import Deferrable, request_only
from service.runtime.jobs import Job, runner
from solver import solve_motion, tripod_statistics

router = APIRouter(tags=["cor"], route_class=BodyRoute)


async def _large(request: Request, read: BodyReader) -> Response:
    """A body over the inline limit: refused before it is read when the request would be
    refused anyway, else read and decoded in the solver worker (service.common.bodies)."""
    refused = runner(request).refused_now(request)
    if refused is not None:
        return refused
    return await _answered(request, SOLVE_RAW, await read())


async def _answered(request: Request, job: Job, req: Any) -> Response:
    """The job's answer in the encoding the client accepts (JSON or msgpack); either way it
    says that it depends on ``Accept`` (a cache must not give one client the other's)."""
    if wants_msgpack(request):
        response = await runner(request).expensive_job(request, in_msgpack, job, req)
    else:
        response = await runner(request).expensive_job(request, job, req)
    response.headers["vary"] = "Accept"
    return response


@router.post(
    "/v1/cor/solve",
    operation_id="cor_solve",
    summary="Motion of a pushed workpiece for a known pressure distribution",
    response_model=CorSolveResponse,
    responses=IN_WORKER,
    openapi_extra=msgpack_openapi("CorSolveRequest", "CorSolveResponse"),
)
@large_bodies(_large)
async def cor_solve(req: CorSolveRequest, request: Request) -> Response:
    """The motion (COR, rotation and slip per unit push, contact mode, forces) that
    minimises the frictional power (book 3.2-3.3.3; with pusher friction mu_c, 4.1), for
    one support, a batch of supports (as objects or as columns), or a modelled uniform
    pressure (figure 7-1). The body and the answer may be msgpack (`Content-Type`,
    `Accept: application/msgpack`). A body over the inline limit (2 MiB by default) is
    decoded and checked in the solver worker that solves it, never in a web process."""
    return await _answered(request, solve_job, req)


def solve_job(req: CorSolveRequest, deadline: Deadline) -> CorSolveResponse:
    budget = deadline.budget()
    mr = motion_problem(req)
    with motion_errors_located(mr):
        result = solve_motion(mr.problem, budget)
    return solve_response(req, mr, result, budget.elapsed() * 1e3)


SOLVE_RAW = in_worker(solve_job, CorSolveRequest)
""":func:`solve_job` of a body decoded in the worker (bodies over the inline limit)."""


@router.post(
    "/v1/cor/tripod-statistics",
    operation_id="cor_tripod_statistics",
    summary="CORs of random tripod supports (figures 3-5, 7-2)",
    response_model=TripodStatisticsResponse,
    responses=IN_WORKER,
    openapi_extra=msgpack_openapi("TripodStatisticsRequest", "TripodStatisticsResponse"),
)
async def cor_tripod_statistics(req: TripodStatisticsRequest, request: Request) -> Response:
    """Random balanced tripods (3.3.3) on the disk or a polygon, seeded: their CORs
    (figure 3-5) and optionally where the sticking CORs fall along the sticking line for a
    large mu_c (figure 7-2). Statistics of a model of pressure distributions, not of the
    locus (7.7). The body and the answer may be msgpack."""
    return await _answered(request, tripod_statistics_job, req)


def tripod_statistics_job(req: TripodStatisticsRequest, deadline: Deadline) -> TripodStatisticsResponse:
    budget = deadline.budget()
    problem = tripod_problem(req)
    with located():
        stats = tripod_statistics(problem, budget)
    return tripod_statistics_response(req, stats, budget.elapsed() * 1e3)


DEFERRABLE = {
    "cor_solve": Deferrable("POST /v1/cor/solve", CorSolveRequest, solve_job, request_only),
    "cor_tripod_statistics": Deferrable("POST /v1/cor/tripod-statistics", TripodStatisticsRequest,
                                        tripod_statistics_job, request_only),
}
"""The operations ``POST /v1/jobs`` runs later (service.runtime.deferred)."""
