"""Pushing over HTTP: is a push slow enough to be quasi-static (book 6.8)? How far must a
fence push to align a part (3.4, 4.3)? How long does a moving point push a disk aside
(4.4)?

Thin: schema -> :mod:`service.convert_push` -> :mod:`models.gross.quasistatic`,
:mod:`models.gross.fence_geometry`, :mod:`models.gross.gross_motion`, :mod:`models.gross.gross_bounds` ->
schema. Plain ``def``: FastAPI runs them in its thread pool (an exact bound takes seconds).
"""

from __future__ import annotations

from fastapi import APIRouter

from service.convert_push import align_response, disk_encounter_response, quasistatic_response
from service.schemas import ErrorResponse
from service.schemas_push import (
    PushAlignRequest,
    PushAlignResponse,
    PushDiskEncounterRequest,
    PushDiskEncounterResponse,
    PushQuasistaticRequest,
    PushQuasistaticResponse,
)

router = APIRouter()

ERRORS = {422: {"model": ErrorResponse, "description": "Invalid input: the body names the field and the reason."}}


@router.post(
    "/v1/push/quasistatic",
    operation_id="push_quasistatic",
    tags=["push"],
    summary="Characteristic speeds for quasi-static motion (book 6.8)",
    response_model=PushQuasistaticResponse,
    responses=ERRORS,
)
def push_quasistatic(req: PushQuasistaticRequest) -> PushQuasistaticResponse:
    """The book's characteristic speeds of a push: for a permissible angular error (6.3),
    for a permissible displacement (6.6), and the quasi-static parameter (6.7), each with
    the ratio speed / characteristic speed and what the part coasts after release at that
    speed; the verdict is on the quasi-static parameter (quasi_static, transitional,
    inertial)."""
    return quasistatic_response(req)


@router.post(
    "/v1/push/align",
    operation_id="push_align",
    tags=["push"],
    summary="Fence alignment: how far a fence must push until an edge is flush (book 3.4, 4.3)",
    response_model=PushAlignResponse,
    responses=ERRORS,
)
def push_align(req: PushAlignRequest) -> PushAlignResponse:
    """A fence advancing along `push_direction` meets a polygonal part and turns it until an
    edge lies flush. The answer gives the book's geometry (the contact vertex, a, c, alpha,
    beta_initial, beta_final, the flush edge, the sense; a counter-clockwise turn reflected
    onto the book's clockwise case), the book's closed-form longest push ((3.41) for
    mu_c = 0, the composite of 4.3 with its pieces and transitions for mu_c > 0), the exact
    longest and shortest pushes from the exact COR sketch of the circumscribing disk with
    their quadrature error estimates, their difference, and optionally whether the speed is
    quasi-static (6.8)."""
    return align_response(req)


@router.post(
    "/v1/push/disk-encounter",
    operation_id="push_disk_encounter",
    tags=["push"],
    summary="A point pushing a disk aside: length and rotation of the encounter (book 4.4)",
    response_model=PushDiskEncounterResponse,
    responses=ERRORS,
)
def push_disk_encounter(req: PushDiskEncounterRequest) -> PushDiskEncounterResponse:
    """A point pusher moving in a line meets a disk at collision parameter beta_initial (or
    at an offset d from grazing, (4.24)) and pushes it aside until it is tangent to the
    path. The answer gives the greatest and least length of the encounter and the greatest
    and least rotation of the disk from the exact COR sketch, the book's (4.16) and (4.18)
    beside the greatest with the differences, where sketch i begins (4.17), and optionally
    whether the speed is quasi-static (6.8)."""
    return disk_encounter_response(req)
