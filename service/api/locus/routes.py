"""``POST /v1/cor/locus`` (the COR locus of a pushed workpiece, book chapter 3) and
``POST /v1/cor/membership`` (can r be its COR? with a certificate).

Each route hands its job to the runner (:mod:`service.runtime.jobs`): the analytic locus
as JSON is cheap and runs in the web process, certified loci, pictures and membership run
in a solver worker. Each job: request -> problem (:mod:`service.api.locus.convert`) -> one
solver call (:func:`solver.locus.cor_locus.cor_locus`,
:func:`solver.locus.membership.decide_membership`) with the request's budget -> response
or picture.
"""

from __future__ import annotations

import hashlib

from fastapi import APIRouter, Query, Request
from fastapi.responses import Response

from service import __version__
from service.api.locus.convert import (
    locus_problem,
    locus_response,
    membership_problem,
    membership_response,
)
from service.api.locus.render import render_locus_svg
from service.api.locus.schemas import (
    CorLocusRequest,
    CorLocusResponse,
    MembershipRequest,
    MembershipResponse,
)
from service.common.bodies import BodyRoute
from service.common.fields import ResponseFormat
from service.common.inputs import located
from service.common.responses import IN_WORKER, SVG_MEDIA_TYPE, json_or_svg
from service.errors import FieldError, nothing_computed
from service.runtime.deadline import Deadline
from service.runtime.deferred import Deferrable, json_answer, request_only
from service.runtime.jobs import runner
from service.store import result_store
from solver import cor_locus as locus_of
from solver import decide_membership

router = APIRouter(tags=["cor"], route_class=BodyRoute)


@router.post(
    "/v1/cor/locus",
    operation_id="cor_locus",
    summary="COR locus of a pushed sliding workpiece",
    response_model=CorLocusResponse,
    responses={
        **json_or_svg("The COR locus: JSON (default) or, with `format=svg`, an SVG picture."),
        **IN_WORKER,
    },
)
async def cor_locus(
    req: CorLocusRequest,
    request: Request,
    response_format: ResponseFormat = Query(
        "json",
        alias="format",
        description="`json` (default) for the numbers, `svg` for a picture of the push and its locus.",
    ),
) -> Response:
    """Locus of the centres of rotation (COR) of a workpiece sliding on a table, pushed
    by a frictionless pusher at `contact_point` along an edge at `edge_angle`, for all
    pressure distributions on the disk of radius a about the centre of mass (Peshkin
    1990, sections 3.1-3.3). All input and output is in the world frame, radians.

    With `method` 'certified' the answer also holds certified brackets of the boundary
    (minimum-power membership queries, book 3.3.13 and 7.5): of the analytic disk boundary,
    or of the exact locus of the polygon `footprint`."""
    svg = response_format == "svg"
    if svg and req.method == "certified":
        raise FieldError(("format",), "the SVG picture shows the analytic locus only; use format json "
                         "with method certified", where="query")
    run = runner(request)
    if not svg and req.method == "certified":
        kept = kept_locus(req)  # a kept answer is read here, without waiting for a solver slot
        if kept is not None:
            return await run.cheap_job(request, stored_locus_job, req, kept, time_limit_s=req.time_limit_s)
    if svg or req.method == "certified":
        return await run.expensive_job(request, locus_job, req, svg, time_limit_s=req.time_limit_s,
                                       cost_key="svg" if svg else f"certified {req.n_certified}",
                                       anytime=not svg)
    return await run.cheap_job(request, locus_job, req, svg, time_limit_s=req.time_limit_s)


CERTIFIED_NAMESPACE = f"certified-locus/v1/service-{__version__}"
"""Where complete certified loci are kept (service.store): per request, all but its time limit."""


def stored_key(req: CorLocusRequest) -> str:
    """The store's key of a certified locus: the request but for its time limit."""
    return hashlib.sha256(req.model_dump_json(exclude={"time_limit_s"}).encode()).hexdigest()


def kept_locus(req: CorLocusRequest) -> dict | None:
    """The kept answer to this certified-locus request, if the store has one."""
    store = result_store()
    return None if store is None else store.get(CERTIFIED_NAMESPACE, stored_key(req))


def stored_locus_job(req: CorLocusRequest, kept: dict, deadline: Deadline) -> CorLocusResponse:
    return CorLocusResponse.model_validate(kept).model_copy(
        update={"from_store": True, "elapsed_ms": deadline.elapsed() * 1e3})


def locus_job(req: CorLocusRequest, svg: bool, deadline: Deadline) -> CorLocusResponse | Response:
    budget = deadline.budget()
    store = result_store() if (req.method == "certified" and not svg) else None
    prep, problem = locus_problem(req, all_outputs=svg)
    result = locus_of(problem, budget)
    body = locus_response(prep, result, req.time_limit_s, budget.elapsed() * 1e3)  # also the NaN/inf guard
    if body.certified is not None and body.certified.n_done == 0 and not body.certified.complete:
        raise nothing_computed("the first certified point", budget.limit_s, budget.elapsed(),
                               body.model_dump(mode="json"))
    if svg:
        return Response(content=render_locus_svg(prep, result.analytic), media_type=SVG_MEDIA_TYPE)
    if store is not None and body.certified is not None and body.certified.complete:
        store.put(CERTIFIED_NAMESPACE, stored_key(req), body.model_dump(mode="json"))
    return body


@router.post(
    "/v1/cor/membership",
    operation_id="cor_membership",
    summary="Can r be the COR of this push? With a certificate",
    response_model=MembershipResponse,
    responses=IN_WORKER,
)
async def cor_membership(req: MembershipRequest, request: Request) -> Response:
    """Decides whether the point `cor` is the centre of rotation of the push for some
    pressure distribution on the disk (or the polygon `footprint`), frictionless pusher
    (book 3.3.2-3.3.13). 'inside' comes with a witness support (re-verified by the forward
    solver), 'outside' with a dual functional and a branch-and-bound lower bound over the
    whole outline; 'undecided' when the time limit or the iteration caps are reached, or
    the point is within the tolerances of the locus boundary."""
    return await runner(request).expensive_job(request, membership_job, req, time_limit_s=req.time_limit_s)


def membership_job(req: MembershipRequest, deadline: Deadline) -> MembershipResponse:
    budget = deadline.budget()
    problem = membership_problem(req)
    with located():
        res = decide_membership(problem, budget)
    return membership_response(req, problem, res, budget.elapsed() * 1e3)


def _locus_cost(req: CorLocusRequest) -> str:
    return f"certified {req.n_certified}" if req.method == "certified" else ""


DEFERRABLE = {
    "cor_locus": Deferrable("POST /v1/cor/locus", CorLocusRequest, locus_job, json_answer, cost=_locus_cost),
    "cor_membership": Deferrable("POST /v1/cor/membership", MembershipRequest, membership_job, request_only),
}
"""The operations ``POST /v1/jobs`` runs later (service.runtime.deferred)."""
