"""Pushing over HTTP: is a push slow enough to be quasi-static (book 6.8)? How far must a
fence push to align a part (3.4, 4.3)? How long does a moving point push a disk aside
(4.4)?

Each route: request -> problem (:mod:`service.api.push.convert`) -> one call
(:func:`models.push.quasistatic.assess`, a closed form; :func:`solver.push.align.align`,
:func:`solver.push.disk_encounter.disk_encounter`, which take the request's budget) ->
response. The closed form runs in the web process, the bounds (seconds) in a solver
worker (:mod:`service.runtime.jobs`).
"""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import Response

from models.push.quasistatic import assess
from service.api.push.convert import (
    ALIGN_FIELDS,
    ENCOUNTER_FIELDS,
    align_partial,
    align_problem,
    align_response,
    encounter_partial,
    encounter_problem,
    encounter_response,
    quasistatic_inputs,
    quasistatic_response,
)
from service.api.push.schemas import (
    PushAlignRequest,
    PushAlignResponse,
    PushDiskEncounterRequest,
    PushDiskEncounterResponse,
    PushQuasistaticRequest,
    PushQuasistaticResponse,
)
from service.common.bodies import BodyRoute
from service.common.inputs import located
from service.common.responses import BUSY, IN_WORKER, INVALID_INPUT
from service.errors import time_limited
from service.runtime.deadline import Deadline
from service.runtime.deferred import Deferrable, request_only
from service.runtime.jobs import runner
from solver import align, disk_encounter

router = APIRouter(tags=["push"], route_class=BodyRoute)

GROSS_TIME_LIMIT_HINT = "lower n_nodes or n_points"


@router.post(
    "/v1/push/quasistatic",
    operation_id="push_quasistatic",
    summary="Characteristic speeds for quasi-static motion (book 6.8)",
    response_model=PushQuasistaticResponse,
    responses={**INVALID_INPUT, **BUSY},
)
async def push_quasistatic(req: PushQuasistaticRequest, request: Request) -> Response:
    """The book's characteristic speeds of a push: for a permissible angular error (6.3),
    for a permissible displacement (6.6), and the quasi-static parameter (6.7), each with
    the ratio speed / characteristic speed and what the part coasts after release at that
    speed; the verdict is on the quasi-static parameter (quasi_static, transitional,
    inertial)."""
    return await runner(request).cheap_job(request, quasistatic_job, req)


def quasistatic_job(req: PushQuasistaticRequest, deadline: Deadline) -> PushQuasistaticResponse:
    budget = deadline.budget()
    inputs = quasistatic_inputs(req)
    res = assess(req.speed, req.mu_s, inputs.g, inputs.part, angular_error=req.angular_error,
                 translational_error=req.translational_error)
    return quasistatic_response(req, inputs, res, budget.elapsed() * 1e3)


@router.post(
    "/v1/push/align",
    operation_id="push_align",
    summary="Fence alignment: how far a fence must push until an edge is flush (book 3.4, 4.3)",
    response_model=PushAlignResponse,
    responses=IN_WORKER,
)
async def push_align(req: PushAlignRequest, request: Request) -> Response:
    """A fence advancing along `push_direction` meets a polygonal part and turns it until an
    edge lies flush. The answer gives the book's geometry (the contact vertex, a, c, alpha,
    beta_initial, beta_final, the flush edge, the sense; a counter-clockwise turn reflected
    onto the book's clockwise case), the book's closed-form longest push ((3.41) for
    mu_c = 0, the composite of 4.3 with its pieces and transitions for mu_c > 0), the exact
    longest and shortest pushes from the exact COR sketch of the circumscribing disk with
    their quadrature error estimates, their difference, and optionally whether the speed is
    quasi-static (6.8)."""
    return await runner(request).expensive_job(request, align_job, req, time_limit_s=req.time_limit_s)


def align_job(req: PushAlignRequest, deadline: Deadline) -> PushAlignResponse:
    budget = deadline.budget()
    problem = align_problem(req)
    with time_limited(align_partial(problem), GROSS_TIME_LIMIT_HINT), located(rename=ALIGN_FIELDS):
        result = align(problem, budget)
    return align_response(req, result, budget.elapsed() * 1e3)


@router.post(
    "/v1/push/disk-encounter",
    operation_id="push_disk_encounter",
    summary="A point pushing a disk aside: length and rotation of the encounter (book 4.4)",
    response_model=PushDiskEncounterResponse,
    responses=IN_WORKER,
)
async def push_disk_encounter(req: PushDiskEncounterRequest, request: Request) -> Response:
    """A point pusher moving in a line meets a disk at collision parameter beta_initial (or
    at an offset d from grazing, (4.24)) and pushes it aside until it is tangent to the
    path. The answer gives the greatest and least length of the encounter and the greatest
    and least rotation of the disk from the exact COR sketch, the book's (4.16) and (4.18)
    beside the greatest with the differences, where sketch i begins (4.17), and optionally
    whether the speed is quasi-static (6.8)."""
    return await runner(request).expensive_job(request, encounter_job, req, time_limit_s=req.time_limit_s)


def encounter_job(req: PushDiskEncounterRequest, deadline: Deadline) -> PushDiskEncounterResponse:
    budget = deadline.budget()
    problem = encounter_problem(req)
    with time_limited(encounter_partial(req), GROSS_TIME_LIMIT_HINT), located(rename=ENCOUNTER_FIELDS):
        result = disk_encounter(problem, budget)
    return encounter_response(req, result, budget.elapsed() * 1e3)


DEFERRABLE = {
    "push_align": Deferrable("POST /v1/push/align", PushAlignRequest, align_job, request_only),
    "push_disk_encounter": Deferrable("POST /v1/push/disk-encounter", PushDiskEncounterRequest, encounter_job, request_only),
}
"""The operations ``POST /v1/jobs`` runs later (service.runtime.deferred)."""
