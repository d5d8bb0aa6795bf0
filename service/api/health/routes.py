"""``GET /healthz``: the liveness probe."""

from __future__ import annotations

from fastapi import APIRouter

from service import __version__
from service.api.health.schemas import HealthResponse

router = APIRouter(tags=["health"])


@router.get("/healthz", operation_id="healthz", response_model=HealthResponse, summary="Liveness probe")
async def healthz() -> HealthResponse:
    """Always `{"status": "ok", "version": ...}` while the process serves requests."""
    return HealthResponse(status="ok", version=__version__)
