"""``POST /v1/cor/sketch``: the COR sketch of a push with pusher friction (book 4.1).

Thin: schema -> :func:`service.convert_sketch.prepare_sketch` (the scene, as for
``/v1/cor/locus``) -> :func:`models.locus.cor_sketch.cor_sketch` (or, method ``certified``,
:func:`solver.locus.certified_sketch.certified_sketch`) -> schema or SVG picture. Plain ``def``:
FastAPI runs it in its thread pool (a sketch takes a few hundred milliseconds, a certified
one seconds).
"""

from __future__ import annotations

import time

from fastapi import APIRouter, Query
from fastapi.responses import Response

from models.locus.cor_disk import disk_cor_locus
from models.locus.cor_sketch import cor_sketch
from solver.core.budget import Budget
from solver.locus.certified_sketch import certified_sketch
from service.convert_sketch import prepare_sketch, sketch_response
from service.render_sketch import render_sketch_svg
from service.schemas import ErrorResponse, ResponseFormat
from service.schemas_sketch import CorSketchRequest, CorSketchResponse

router = APIRouter()

SVG_MEDIA_TYPE = "image/svg+xml"


@router.post(
    "/v1/cor/sketch",
    operation_id="cor_sketch",
    tags=["cor"],
    summary="COR sketch with pusher friction: sticking and slipping loci (book 4.1)",
    response_model=CorSketchResponse,
    responses={
        200: {
            "description": "The COR sketch: JSON (default) or, with `format=svg`, an SVG picture.",
            "content": {SVG_MEDIA_TYPE: {"schema": {"type": "string"}}},
        },
        422: {"model": ErrorResponse, "description": "Invalid input: the body names the field and the reason."},
    },
)
def cor_sketch_route(
    req: CorSketchRequest,
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
    start = time.perf_counter()
    prep = prepare_sketch(req)
    certified = None
    if req.method == "certified":
        certified = certified_sketch(prep.scene, req.mu_c, footprint=prep.footprint, n_rays=req.n_rays,
                                     n_points=prep.n_points, budget=Budget.of(req.time_limit_s))
        sketch = certified.sketch
    else:
        sketch = cor_sketch(prep.scene, req.mu_c, n_points=req.n_points)
    elapsed_ms = (time.perf_counter() - start) * 1e3
    body = sketch_response(prep, sketch, elapsed_ms, certified)  # also the NaN/inf guard of the picture
    if response_format == "svg":
        tip_line = disk_cor_locus(prep.scene, outputs=["tip_line"]).tip_line
        return Response(content=render_sketch_svg(prep, sketch, tip_line), media_type=SVG_MEDIA_TYPE)
    return body
