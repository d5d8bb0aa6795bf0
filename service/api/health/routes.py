"""``GET /healthz`` (liveness: the process serves requests), ``GET /readyz`` (readiness:
it has room for more work) and ``GET /metrics`` (Prometheus)."""

from __future__ import annotations

import anyio
from fastapi import APIRouter, Request
from fastapi.responses import JSONResponse, Response

from service import __version__
from service.api.health.schemas import GateOut, HealthResponse, ReadyResponse, StorageOut
from service.common.bodies import BodyRoute
from service.runtime.deferred import deferred_runner
from service.runtime.jobs import runner
from service.runtime.jobstore import STATES
from service.runtime.metrics import CONTENT_TYPE, exposition, observe_jobs, observe_work
from service.store import StorageFault, result_store

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
    expensive work for its solver workers) have room; `degraded` (200) when a file of the
    service (the jobs file, the result store) fails, so its feature is off or waits while
    requests are served; `saturated` (503) when a gate is full, so that a load balancer
    sends new requests elsewhere. The gates' use and refusals (for this web process) and the
    files' states are shown to operators (everyone on a deployment without keys)."""
    run = runner(request)
    gates = [run.requests.state(), run.expensive.state()]
    files = storage_states(request)
    full = any(g.full for g in gates)
    status = "saturated" if full else "degraded" if any(f.state != "ok" for f in files) else "ready"
    operator = bool(request.scope.get("state", {}).get("operator", True))
    body = ReadyResponse(
        status=status,
        version=__version__,
        solver_workers=(0 if run.pool is None else run.pool.workers) if operator else None,
        gates=[GateOut(name=g.name, in_use=g.in_use, capacity=g.capacity, admitted=g.admitted, refused=g.refused)
               for g in gates] if operator else None,
        storage=files if operator else None,
    )
    return JSONResponse(body.model_dump(mode="json"), status_code=503 if full else 200)


def storage_states(request: Request) -> list[StorageOut]:
    """The jobs file's state (off when found unusable at start) and the result store's."""
    deferred = deferred_runner(request)
    jobs = deferred.store.health.state()
    if deferred.off is not None:
        jobs = {**jobs, "state": "off", "reason": f"{deferred.off.kind}: {deferred.off.reason}"}
    out = [StorageOut(**jobs)]
    store = result_store()
    if store is not None:
        out.append(StorageOut(**store.health.state()))
    return out


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
    (every web process; see `service/runtime/metrics.py`). Needs an operator key when keys are on
    (PESHKIN_OPERATOR_KEYS; 403 to another key)."""
    observe_work(runner(request).expensive)
    deferred = deferred_runner(request)
    if deferred.off is None:
        try:
            observe_jobs(await anyio.to_thread.run_sync(deferred.store.counts), STATES)
        except StorageFault:  # the jobs file fails: said by /readyz and the log; the other samples stand
            pass
    return Response(exposition(), media_type=CONTENT_TYPE)
