"""``GET /healthz`` (liveness: the process serves requests), ``GET /readyz`` (readiness:
it has room for more work) and ``GET /metrics`` (Prometheus)."""

from __future__ import annotations

import anyio
from fastapi import APIRouter, Request
from fastapi.responses import JSONResponse, Response

from service import __version__
from service.api.health.schemas import GateOut, HealthResponse, ReadyResponse
from service.common.bodies import BodyRoute
from service.runtime.deferred import STATES, deferred_runner
from service.runtime.jobs import runner
from service.runtime.metrics import CONTENT_TYPE, exposition, observe_jobs, observe_work

router = APIRouter(tags=["health"], route_class=BodyRoute)


@router.get("/healthz", operation_id="healthz", response_model=HealthResponse, summary="Liveness probe")
async def healthz() -> HealthResponse:
    """Always `{"status": "ok", "version": ...}` while the process serves requests."""
    return HealthResponse(status="ok", version=__version__)


@router.get(
    "/readyz",
    operation_id="readyz",
    response_model=ReadyResponse,
    summary="Readiness probe: room for more work",
    responses={503: {"model": ReadyResponse, "description": "Saturated: a gate is full; new work would be refused."}},
)
async def readyz(request: Request) -> JSONResponse:
    """`ready` (200) while both admission gates (requests in flight in this web process,
    expensive work for its solver workers) have room; `saturated` (503) when one is full, so that a
    load balancer sends new requests elsewhere. The gates' use and refusals are listed
    (for this web process)."""
    run = runner(request)
    gates = [run.requests.state(), run.expensive.state()]
    full = any(g.full for g in gates)
    body = ReadyResponse(
        status="saturated" if full else "ready",
        version=__version__,
        solver_workers=0 if run.pool is None else run.pool.workers,
        gates=[GateOut(name=g.name, in_use=g.in_use, capacity=g.capacity, admitted=g.admitted, refused=g.refused)
               for g in gates],
    )
    return JSONResponse(body.model_dump(mode="json"), status_code=503 if full else 200)


@router.get(
    "/metrics",
    operation_id="metrics",
    summary="Prometheus metrics",
    response_class=Response,
    responses={200: {"content": {"text/plain": {"schema": {"type": "string"}}},
                     "description": "The samples in Prometheus's text exposition format (version 0.0.4)."}},
)
async def metrics(request: Request) -> Response:
    """Requests by route and status, latency histograms, the queue of expensive work, solver
    slots busy, jobs (`/v1/jobs`) by state and solver time by numerical back end, for the whole server
    (every web process; see `service/runtime/metrics.py`). Needs an API key when keys are on."""
    observe_work(runner(request).expensive)
    observe_jobs(await anyio.to_thread.run_sync(deferred_runner(request).store.counts), STATES)
    return Response(exposition(), media_type=CONTENT_TYPE)
