"""Pushing regimes over HTTP: is a push slow enough to be quasi-static (book 6.8)?

Thin: schema -> :mod:`service.convert_push` -> :mod:`models.quasistatic` -> schema.
"""

from __future__ import annotations

from fastapi import APIRouter

from service.convert_push import quasistatic_response
from service.schemas import ErrorResponse
from service.schemas_push import PushQuasistaticRequest, PushQuasistaticResponse

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
