"""``POST /v1/cor/locus``: the COR locus of a pushed workpiece (book chapter 3)."""

from __future__ import annotations

import dataclasses
import time

from fastapi import APIRouter, Query
from fastapi.responses import Response

from models.locus.cor_disk import OUTPUTS, DiskCorLocus, disk_cor_locus
from service.certified import certified_disk, certified_polygon
from service.convert import PreparedPush, locus_response, prepare
from service.errors import FieldError
from service.render import render_locus_svg
from service.schemas import CorLocusRequest, CorLocusResponse, ErrorResponse, ResponseFormat

router = APIRouter(tags=["cor"])

SVG_MEDIA_TYPE = "image/svg+xml"


def compute_locus(req: CorLocusRequest, all_outputs: bool = False) -> tuple[PreparedPush, DiskCorLocus, float]:
    """Scene from the request, then the model; returns the time spent in milliseconds."""
    start = time.perf_counter()
    prep = prepare(req, extra_outputs=OUTPUTS if all_outputs else ())
    locus = disk_cor_locus(prep.scene, outputs=prep.outputs, n_points=prep.n_points)
    elapsed_ms = (time.perf_counter() - start) * 1e3
    return prep, locus, elapsed_ms


@router.post(
    "/v1/cor/locus",
    operation_id="cor_locus",
    summary="COR locus of a pushed sliding workpiece",
    response_model=CorLocusResponse,
    responses={
        200: {
            "description": "The COR locus: JSON (default) or, with `format=svg`, an SVG picture.",
            "content": {SVG_MEDIA_TYPE: {"schema": {"type": "string"}}},
        },
        422: {"model": ErrorResponse, "description": "Invalid input: the body names the field and the reason."},
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
    if req.method == "certified":
        if response_format == "svg":
            raise FieldError(("format",), "the SVG picture shows the analytic locus only; use format json "
                             "with method certified", where="query")
        start = time.perf_counter()
        prep, locus, _ = compute_locus(req)
        warnings = list(prep.warnings)
        certified = None
        if prep.scene.is_translation:
            warnings.append("method certified: nothing to certify, the push translates the part (COR at infinity)")
        elif prep.footprint is None:
            certified = certified_disk(prep.scene, req.n_certified, req.time_limit_s)
        else:
            certified = certified_polygon(prep.scene, prep.footprint, req.n_certified, req.time_limit_s)
        if certified is not None and not certified.complete:
            warnings.append(
                f"method certified: time limit {req.time_limit_s:g} s reached after {certified.n_done} of "
                f"{certified.n_requested} {'points' if certified.region == 'disk' else 'rays'}"
            )
        prep = dataclasses.replace(prep, warnings=tuple(warnings))
        return locus_response(prep, locus, (time.perf_counter() - start) * 1e3, "certified", certified)
    if response_format == "svg":
        prep, locus, elapsed_ms = compute_locus(req, all_outputs=True)
        locus_response(prep, locus, elapsed_ms)  # same NaN/inf guard as the JSON answer
        return Response(content=render_locus_svg(prep, locus), media_type=SVG_MEDIA_TYPE)
    prep, locus, elapsed_ms = compute_locus(req)
    return locus_response(prep, locus, elapsed_ms)
