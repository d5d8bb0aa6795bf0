"""``POST /v1/jobs`` (run an expensive operation later: 202 and where to ask), ``GET
/v1/jobs/{id}`` (its state, progress and answer), ``DELETE /v1/jobs/{id}`` (cancel it: its
worker is stopped) and ``GET /v1/jobs`` (the caller's jobs). The work is done by each web
process's :class:`service.runtime.deferred.DeferredRunner`; the jobs live in its SQLite file.
With API keys on, a client sees only the jobs of its own key."""

from __future__ import annotations

import json
import time
from datetime import datetime, timezone
from typing import Any

import anyio
from fastapi import APIRouter, Query, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from pydantic import ValidationError

from service.api.jobs.schemas import JobListOut, JobOut, JobProgressOut, JobRequest
from service.common.bodies import BodyRoute
from service.common.responses import BUSY, INVALID_INPUT, ErrorResponse
from service.errors import error_body
from service.runtime.deferred import FINISHED, MAX_QUEUED_PER_CLIENT, DeferredRunner, deferred_runner

router = APIRouter(tags=["jobs"], route_class=BodyRoute)
NOT_FOUND = {404: {"model": ErrorResponse, "description": "No such job (or not yours, with API keys on)."}}
ANSWERS = {**INVALID_INPUT, **BUSY}


def owner_of(request: Request) -> str:
    """The caller's key id ('' with keys off: everyone's jobs are everyone's)."""
    return str(request.scope.get("state", {}).get("client") or "")


def _iso(t: float | None) -> str | None:
    return None if t is None else datetime.fromtimestamp(t, tz=timezone.utc).isoformat()


def _progress(run: DeferredRunner, row: dict[str, Any]) -> JobProgressOut:
    if row["state"] in FINISHED:
        return JobProgressOut(stage="finished", fraction=1.0, eta_s=0.0, estimated=False)
    if row["state"] == "queued":
        return JobProgressOut(stage="queued", fraction=None, eta_s=None, estimated=True)
    if row["ran"] is None:  # claimed, waiting for a solver slot
        return JobProgressOut(stage="waiting", fraction=0.0, eta_s=None, estimated=True)
    cost = row["predicted"]
    if not cost:
        return JobProgressOut(stage="running", fraction=None, eta_s=None, estimated=True)
    ran = max(time.time() - float(row["ran"]), 0.0)
    return JobProgressOut(stage="running", fraction=min(ran / cost, 0.99), eta_s=max(cost - ran, 0.0), estimated=True)


def job_out(run: DeferredRunner, row: dict[str, Any], with_result: bool = True) -> JobOut:
    result = None
    if with_result and row["result"] is not None and row["media_type"] == "application/json":
        result = json.loads(row["result"])
    return JobOut(
        id=row["id"], location=f"/v1/jobs/{row['id']}", operation=row["operation"], state=row["state"],
        created_at=_iso(row["created"]) or "", started_at=_iso(row["started"]), finished_at=_iso(row["finished"]),
        expires_at=_iso(row["expires"]), attempts=row["attempts"], message=row["message"] or "",
        progress=_progress(run, row), status_code=row["status"], result=result,
    )


def _not_found(job_id: str) -> JSONResponse:
    return JSONResponse(error_body(["path", "job_id"], f"no job {job_id!r} (or not yours)", "not_found"),
                        status_code=404)


@router.post("/v1/jobs", operation_id="jobs_submit", status_code=202, response_model=JobOut,
             summary="Run an expensive operation later", responses={**ANSWERS, 202: {"headers": {"Location": {
                 "description": "/v1/jobs/<id>", "schema": {"type": "string"}}}}})
async def submit(req: JobRequest, request: Request) -> JSONResponse:
    """Checks the operation's body at once (422 at `body.body.<field>`; 429 when 100 of your
    jobs are queued already), queues the job
    (kept in the server's SQLite file: a restart loses nothing queued or finished) and
    answers 202 with its id and where to ask. It runs when a solver slot is free, under the
    operation's own time limit counted from its start (up to the jobs' cap), with the same
    answer as the operation's route (JSON)."""
    run = deferred_runner(request)
    try:
        run.operations[req.operation].model.model_validate(req.body)
    except ValidationError as exc:
        raise RequestValidationError([{**e, "loc": ("body", "body", *e["loc"])}
                                      for e in exc.errors(include_url=False)]) from None
    owner = owner_of(request)
    if await anyio.to_thread.run_sync(run.store.queued_of, owner) >= MAX_QUEUED_PER_CLIENT:
        return JSONResponse(error_body([], f"{MAX_QUEUED_PER_CLIENT} of your jobs are queued already; retry when "
                                           "some have started", "too_many_jobs"), status_code=429,
                            headers={"Retry-After": "10"})
    job_id = await anyio.to_thread.run_sync(run.store.submit, req.operation, req.body, owner)
    row = await anyio.to_thread.run_sync(run.store.get, job_id)
    assert row is not None
    out = job_out(run, row)
    return JSONResponse(out.model_dump(mode="json"), status_code=202, headers={"Location": out.location})


@router.get("/v1/jobs/{job_id}", operation_id="jobs_get", response_model=JobOut, summary="A job's state and answer",
            responses={**ANSWERS, **NOT_FOUND})
async def get_job(job_id: str, request: Request) -> JobOut | JSONResponse:
    """State, progress (stage, an estimated fraction and time to go) and, once it ended, the
    operation's answer (`result`, with its `status_code`)."""
    run = deferred_runner(request)
    row = await anyio.to_thread.run_sync(run.store.get, job_id, owner_of(request))
    return _not_found(job_id) if row is None else job_out(run, row)


@router.delete("/v1/jobs/{job_id}", operation_id="jobs_cancel", response_model=JobOut, summary="Cancel a job",
               responses={**ANSWERS, **NOT_FOUND})
async def cancel_job(job_id: str, request: Request) -> JobOut | JSONResponse:
    """A queued job is cancelled at once; a running one within half a second (its solver
    worker is ended and replaced, its slot freed); an ended one stays as it is. Answers the
    job as it is now (`GET` again to see a running one cancelled)."""
    run = deferred_runner(request)
    owner = owner_of(request)
    row = await anyio.to_thread.run_sync(run.store.get, job_id, owner)
    if row is None:
        return _not_found(job_id)
    await anyio.to_thread.run_sync(run.store.cancel, job_id, run.ttl_s)
    row = await anyio.to_thread.run_sync(run.store.get, job_id, owner)
    return _not_found(job_id) if row is None else job_out(run, row)


@router.get("/v1/jobs", operation_id="jobs_list", response_model=JobListOut, summary="Your jobs", responses=ANSWERS)
async def list_jobs(request: Request, limit: int = Query(100, ge=1, le=1000, description="Most jobs listed.")
                    ) -> JobListOut:
    """Your jobs (every job, with API keys off), newest first, without their results."""
    run = deferred_runner(request)
    rows = await anyio.to_thread.run_sync(run.store.list, owner_of(request) or None, limit)
    return JobListOut(jobs=[job_out(run, r, with_result=False) for r in rows])
