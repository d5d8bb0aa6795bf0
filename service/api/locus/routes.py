"""``POST /v1/cor/locus`` (the COR locus of a pushed workpiece, book chapter 3) and
``POST /v1/cor/membership`` (can r be its COR? with a certificate).

Each route: request -> problem (:mod:`service.api.locus.convert`) -> one solver call
(:func:`solver.locus.cor_locus.cor_locus`, :func:`solver.locus.membership.decide_membership`)
-> response or picture. Plain ``def``: FastAPI runs them in its thread pool, so a long
certificate does not block the event loop.
"""

from __future__ import annotations

from fastapi import APIRouter, Query
from fastapi.responses import Response

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
from service.common.fields import ResponseFormat
from service.common.inputs import located
from service.common.responses import INVALID_INPUT, SVG_MEDIA_TYPE, json_or_svg
from service.errors import FieldError
from solver import Budget, decide_membership
from solver import cor_locus as locus_of

router = APIRouter(tags=["cor"])


@router.post(
    "/v1/cor/locus",
    operation_id="cor_locus",
    summary="COR locus of a pushed sliding workpiece",
    response_model=CorLocusResponse,
    responses={
        **json_or_svg("The COR locus: JSON (default) or, with `format=svg`, an SVG picture."),
        **INVALID_INPUT,
    },
)
def cor_locus(
    req: CorLocusRequest,
    response_format: ResponseFormat = Query(
        "json",
        alias="format",
        description="`json` (default) for the numbers, `svg` for a picture of the push and its locus.",
    ),
):
    """Locus of the centres of rotation (COR) of a workpiece sliding on a table, pushed
    by a frictionless pusher at `contact_point` along an edge at `edge_angle`, for all
    pressure distributions on the disk of radius a about the centre of mass (Peshkin
    1990, sections 3.1-3.3). All input and output is in the world frame, radians.

    With `method` 'certified' the answer also holds certified brackets of the boundary
    (minimum-power membership queries, book 3.3.13 and 7.5): of the analytic disk boundary,
    or of the exact locus of the polygon `footprint`."""
    budget = Budget.of(req.time_limit_s)
    svg = response_format == "svg"
    if svg and req.method == "certified":
        raise FieldError(("format",), "the SVG picture shows the analytic locus only; use format json "
                         "with method certified", where="query")
    prep, problem = locus_problem(req, all_outputs=svg)
    result = locus_of(problem, budget)
    body = locus_response(prep, result, req.time_limit_s, budget.elapsed() * 1e3)  # also the NaN/inf guard
    if svg:
        return Response(content=render_locus_svg(prep, result.analytic), media_type=SVG_MEDIA_TYPE)
    return body


@router.post(
    "/v1/cor/membership",
    operation_id="cor_membership",
    summary="Can r be the COR of this push? With a certificate",
    response_model=MembershipResponse,
    responses=INVALID_INPUT,
)
def cor_membership(req: MembershipRequest) -> MembershipResponse:
    """Decides whether the point `cor` is the centre of rotation of the push for some
    pressure distribution on the disk (or the polygon `footprint`), frictionless pusher
    (book 3.3.2-3.3.13). 'inside' comes with a witness support (re-verified by the forward
    solver), 'outside' with a dual functional and a branch-and-bound lower bound over the
    whole outline; 'undecided' when the time limit or the iteration caps are reached, or
    the point is within the tolerances of the locus boundary."""
    budget = Budget.of(req.time_limit_s)
    problem = membership_problem(req)
    with located():
        res = decide_membership(problem, budget)
    return membership_response(req, problem, res, budget.elapsed() * 1e3)
