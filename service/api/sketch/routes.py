"""``POST /v1/cor/sketch``: the COR sketch of a push with pusher friction (book 4.1).

Request -> :func:`service.api.sketch.convert.sketch_problem` (the scene, as for
``/v1/cor/locus``) -> :func:`solver.sketch.cor_sketch.cor_sketch` -> response or picture, in a
solver worker (:mod:`service.runtime.jobs`; a sketch takes a few hundred milliseconds, a
certified one seconds).
"""

from __future__ import annotations

from fastapi import APIRouter, Query, Request
from fastapi.responses import Response

from service.api.sketch.convert import sketch_problem, sketch_response
from service.api.sketch.render import render_sketch_svg
from service.api.sketch.schemas import CorSketchRequest, CorSketchResponse
from service.common.bodies import BodyRoute
from service.common.fields import ResponseFormat
from service.common.responses import IN_WORKER, SVG_MEDIA_TYPE, json_or_svg
from service.runtime.deadline import Deadline
from service.runtime.deferred import Deferrable, json_answer
from service.runtime.jobs import runner
from solver import cor_sketch

router = APIRouter(route_class=BodyRoute)


@router.post(
    "/v1/cor/sketch",
    operation_id="cor_sketch",
    tags=["cor"],
    summary="COR sketch with pusher friction: sticking and slipping loci (book 4.1)",
    response_model=CorSketchResponse,
    responses={
        **json_or_svg("The COR sketch: JSON (default) or, with `format=svg`, an SVG picture."),
        **IN_WORKER,
    },
)
async def cor_sketch_route(
    req: CorSketchRequest,
    request: Request,
    response_format: ResponseFormat = Query(
        "json",
        alias="format",
        description="`json` (default) for the numbers, `svg` for a picture of the sketch.",
    ),
):
    """Every centre of rotation consistent with the force that produces it when the pusher
    has friction mu_c > 0 (Peshkin 1990, 4.1), over all pressure distributions on the disk
    of radius a about the CM: the down- and up-slipping loci (the frictionless loci
    {COR}_(alpha+-nu) of the friction cone's edges cut by the slipping zones), the sticking
    locus on the sticking line, the elementary configurations of {COR}_(alpha+-nu), which
    of the nine sketches of figure 4-6 results and what it implies (must slip up, must
    stick, ...). A polygon is bounded by its circumscribing disk, or, with method
    'certified', sketched itself with every piece certified. World frame, radians."""
    svg = response_format == "svg"
    return await runner(request).expensive_job(request, sketch_job, req, svg, time_limit_s=req.time_limit_s,
                                               anytime=req.method == "certified")


def sketch_job(req: CorSketchRequest, svg: bool, deadline: Deadline) -> CorSketchResponse | Response:
    budget = deadline.budget()
    prep, problem = sketch_problem(req, with_tip_line=svg)
    result = cor_sketch(problem, budget)
    body = sketch_response(prep, result, budget.elapsed() * 1e3)  # also the NaN/inf guard of the picture
    if svg:
        return Response(content=render_sketch_svg(prep, result.sketch, result.tip_line), media_type=SVG_MEDIA_TYPE)
    return body


DEFERRABLE = {"cor_sketch": Deferrable("POST /v1/cor/sketch", CorSketchRequest, sketch_job, json_answer)}
"""The operations ``POST /v1/jobs`` runs later (service.runtime.deferred)."""
