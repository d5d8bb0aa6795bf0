"""The FastAPI application: ``uvicorn service.app:app``."""

from __future__ import annotations

import importlib
import os
import shutil
import tempfile
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager

import anyio
from fastapi import FastAPI
from fastapi.middleware.cors import CORSMiddleware
from fastapi_offline import FastAPIOffline

from service import __version__, errors
from service.api import ROUTE_MODULES
from service.common.bodies import INLINE_STATE, body_limits
from service.runtime import logs
from service.runtime.access import PUBLIC_PATHS, Access, ApiKeys, KeyRates
from service.runtime.context import RequestContext
from service.runtime.deferred import DeferredRunner
from service.runtime.intake import Intake
from service.runtime.jobs import Runner
from service.runtime.jobstore import JobStore
from service.runtime.slots import SLOT_DIR_ENV
from service.settings import Settings
from service.store import result_store
from solver import KERNEL_MODULES

DESCRIPTION = """\
Planning service for pushed sliding workpieces, after M. A. Peshkin, *Robotic Manipulation
Strategies* (1990), chapters 2-5. World frame: x right, y up, angles in radians CCW;
lengths in any consistent unit. Errors share one body, `{"detail": [{"loc": [...], "msg":
..., "type": ...}], "request_id": ...}`: 422 invalid input (naming the field), 413 a body
over the limit, 408 a request not sent in time, 503 busy (retry after `Retry-After`
seconds), 504 the time limit ran out (with what was finished); with API keys on, 401
without a known key and 429 past the key's rate. A time limit covers waiting, solving and
rendering. Long work can run as a job (`POST /v1/jobs`).
"""

OPERATION_ORDER = (
    "healthz",
    "readyz",
    "metrics",
    "cor_locus",
    "cor_solve",
    "cor_membership",
    "cor_tripod_statistics",
    "mpp_particle",
    "push_quasistatic",
    "push_align",
    "push_disk_encounter",
    "cor_sketch",
    "spiral_critical_radius",
    "spiral_schedule",
    "feeder_map",
    "feeder_simulate",
    "feeder_design",
    "scenes_analyze",
    "feeder_catalogue",
    "jobs_submit",
    "jobs_get",
    "jobs_cancel",
    "jobs_list",
)
"""The order of the operations in the OpenAPI document (openapi.yaml, stable for clients
who diff it): the order in which they were published, not the resources' order."""


def _published(app: FastAPI, time_limit_cap_s: float) -> None:
    """Make ``app.openapi()`` list the paths in :data:`OPERATION_ORDER` (FastAPI lists them
    by router) and state the deployment's cap as the ``maximum`` of every ``time_limit_s``
    (the schemas take up to the hard maximum; the runner refuses past the cap). FastAPI's
    documented way to adjust the document is to wrap ``app.openapi``."""
    generate = app.openapi

    def openapi() -> dict:
        schema = generate()
        paths = schema["paths"]

        def published(path: str) -> int:
            return min(OPERATION_ORDER.index(op["operationId"]) for op in paths[path].values())

        schema["paths"] = {path: paths[path] for path in sorted(paths, key=published)}
        for component in schema.get("components", {}).get("schemas", {}).values():
            limit = component.get("properties", {}).get("time_limit_s")
            for branch in [] if limit is None else [limit, *limit.get("anyOf", [])]:
                if "maximum" in branch:
                    branch["maximum"] = time_limit_cap_s
            if isinstance(limit, dict) and isinstance(limit.get("default"), (int, float)):
                limit["default"] = min(limit["default"], time_limit_cap_s)  # what the runner does
        _access_answers(schema)
        return schema

    app.openapi = openapi  # type: ignore[method-assign]


SECURITY_SCHEMES = {
    "ApiKey": {"type": "apiKey", "in": "header", "name": "X-API-Key",
               "description": "One of the deployment's API keys (PESHKIN_API_KEYS), when it has any."},
    "Bearer": {"type": "http", "scheme": "bearer",
               "description": "The same key as a bearer token: Authorization: Bearer <key>."},
}
"""How a client shows its key (service.runtime.access)."""

ERROR_JSON = {"application/json": {"schema": {"$ref": "#/components/schemas/ErrorResponse"}}}
ACCESS_ANSWERS = {
    "401": {"description": "Only when the deployment has API keys: no key, or an unknown one (type "
                           "\"unauthorized\").", "content": ERROR_JSON},
    "429": {"description": "Only when the deployment has API keys: the key's rate is used up (type "
                           "\"rate_limited\"; POST /v1/jobs also when 100 of the key's jobs are queued); retry "
                           "after the `Retry-After` header's seconds.", "content": ERROR_JSON,
            "headers": {"Retry-After": {"description": "Seconds to wait before retrying.",
                                        "schema": {"type": "integer"}}}},
}


def _access_answers(schema: dict) -> None:
    """The API keys in the document: the two ways to show one, optional (keys are on only
    when the deployment has some), and the 401 and 429 of every operation but the probes."""
    schema.setdefault("components", {})["securitySchemes"] = SECURITY_SCHEMES
    for path, item in schema["paths"].items():
        if path in PUBLIC_PATHS:
            continue
        for op in item.values():
            op["security"] = [{}, {"ApiKey": []}, {"Bearer": []}]
            op["responses"].update(ACCESS_ANSWERS)


def create_app(settings: Settings | None = None) -> FastAPI:
    """The app; ``settings`` from the environment when None. Its runner (admission gates
    and solver workers, :mod:`service.runtime`) is made here and closed at shutdown."""
    settings = Settings.from_env() if settings is None else settings
    logs.configure(settings.log_level, settings.log_format)
    if settings.rate_limit is not None and not settings.api_keys:
        raise ValueError("PESHKIN_RATE_LIMIT is per API key: set PESHKIN_API_KEYS too")
    # the solver workers' forkserver loads the compiled kernels once (web processes never do)
    runner = Runner.from_settings(settings, preload=(*ROUTE_MODULES, *KERNEL_MODULES))
    rates = None if settings.rate_limit is None else KeyRates(*settings.rate_limit, os.environ.get(SLOT_DIR_ENV))
    routes = [importlib.import_module(module) for module in ROUTE_MODULES]
    # jobs_path "": a file of the server's own (in its slot directory, shared by its web
    # processes, removed when it stops), or of this process when it runs alone
    server_dir = os.environ.get(SLOT_DIR_ENV)
    own_jobs_dir = None if settings.jobs_path or server_dir else tempfile.mkdtemp(prefix="peshkin-jobs-")
    deferred = DeferredRunner(
        JobStore(settings.jobs_path or os.path.join(server_dir or str(own_jobs_dir), "jobs.sqlite3"),
                 max_bytes=settings.jobs_max_bytes, max_answer_bytes=settings.job_max_answer_bytes,
                 max_client_bytes=settings.job_max_client_bytes),
        runner, {op: spec for module in routes for op, spec in getattr(module, "DEFERRABLE", {}).items()},
        concurrency=settings.job_concurrency(),
        max_time_s=settings.job_max_time_s, ttl_s=settings.job_ttl_s,
    )

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        await runner.start()
        await anyio.to_thread.run_sync(deferred.check)  # the jobs file and the result store, tried at start
        store = result_store()
        if store is not None:
            await anyio.to_thread.run_sync(store.check)
        deferred.start()
        try:
            yield
        finally:
            await deferred.stop()
            runner.close()
            if rates is not None:
                rates.close()
            if own_jobs_dir is not None:
                shutil.rmtree(own_jobs_dir, ignore_errors=True)

    # Swagger UI (/docs) and ReDoc (/redoc) from the package's own copies of their
    # scripts and styles (fastapi-offline): the pages work without the internet.
    app = FastAPIOffline(
        title="Peshkin pushing planner",
        version=__version__,
        description=DESCRIPTION,
        lifespan=lifespan,
    )
    app.state.runner = runner
    app.state.deferred = deferred
    errors.install(app)
    # outermost last: RequestContext (id, log, metrics) > CORS (answers preflights) > Access
    # (keys, rates) > Intake (arrival, body limits, the gate of requests in flight); the
    # routes read their bodies themselves (service.common.bodies)
    inline = min(settings.inline_body_bytes, settings.max_body_bytes)
    setattr(app.state, INLINE_STATE, inline)
    app.add_middleware(Intake, gate=runner.requests, retry_after_s=settings.retry_after_s,
                       body_limits=body_limits([module.router for module in routes], inline, settings.max_body_bytes),
                       default_body_bytes=inline)
    if settings.api_keys or settings.operator_keys:
        app.add_middleware(Access, keys=ApiKeys(settings.api_keys + settings.operator_keys), rates=rates,
                           operators=ApiKeys(settings.operator_keys))
    if settings.cors_origins:
        app.add_middleware(CORSMiddleware, allow_origins=list(settings.cors_origins), allow_methods=["GET", "POST", "DELETE"],
                           allow_headers=["content-type", "x-api-key", "authorization", "x-request-id"],
                           expose_headers=["x-request-id", "retry-after"], max_age=600)
    app.add_middleware(RequestContext, expensive=runner.expensive, log_requests=settings.access_log)
    for module in routes:
        app.include_router(module.router)
    _published(app, settings.max_time_limit_s)
    return app


app = create_app()
