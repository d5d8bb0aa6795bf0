"""``POST /v1/jobs`` (run an expensive operation later: 202 and where to ask), ``GET
/v1/jobs/{id}`` (its state, progress and answer), ``DELETE /v1/jobs/{id}`` (cancel it: its
worker is stopped; an ended job is forgotten, its answer deleted) and ``GET /v1/jobs`` (the
caller's jobs). The work is done by each web process's
:class:`service.runtime.deferred.DeferredRunner`; the jobs live in its SQLite file
(:mod:`service.runtime.jobstore`). With API keys on, a client sees only the jobs of its own
key. A jobs file that cannot be used is an answer, not a 500: 507 when it (or its disk) is
full or a client's jobs keep all they may, 503 when it is read-only, broken or missing,
each with the file and the reason.
"""

from __future__ import annotations

import asyncio
import time
from collections.abc import Callable
from datetime import datetime, timezone
from typing import Any, TypeVar

import anyio
from fastapi import APIRouter, Query, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse, Response
from pydantic import ValidationError

from service.api.jobs.schemas import JobListOut, JobOut, JobProgressOut, JobRequest
from service.common.bodies import BodyRoute
from service.common.responses import BUSY, INVALID_INPUT, ErrorResponse
from service.errors import error_body
from service.runtime.deferred import DeferredRunner, deferred_runner
from service.runtime.jobstore import FINISHED, MAX_QUEUED_PER_CLIENT, OverQuota
from service.store import StorageFault

T = TypeVar("T")

router = APIRouter(tags=["jobs"], route_class=BodyRoute)
NOT_FOUND = {404: {"model": ErrorResponse, "description": "No such job (or not yours, with API keys on)."}}
STORAGE = {507: {"model": ErrorResponse, "description": "The jobs file (or its disk) is full, or your jobs keep all "
                 "they may (type \"storage_full\" or \"storage_quota\", naming the cap)."}}
ANSWERS = {**INVALID_INPUT, **BUSY, **STORAGE}
INSUFFICIENT_STORAGE = 507
CANCEL_WAIT_S = 1.5
"""How long DELETE of a running job waits for it to be cancelled before answering."""


def storage_response(fault: StorageFault) -> JSONResponse:
    """The answer when the jobs file fails: 507 when full (retry when space returns), else
    503 (the jobs are off until the operator mends the file)."""
    if fault.kind == "full":
        return JSONResponse(error_body([], f"the jobs file {fault.path} cannot take more: {fault.reason}; retry when "
                                           "space returns", "storage_full"), status_code=INSUFFICIENT_STORAGE,
                            headers={"Retry-After": "60"})
    return JSONResponse(error_body([], f"jobs are off on this server: the jobs file {fault.path} is {fault.words} "
                                       f"({fault.reason}); the other operations are served as usual",
                                   "jobs_unavailable"), status_code=503, headers={"Retry-After": "60"})


async def _stored(run: DeferredRunner, work: Callable[..., T], *args: Any) -> T:
    """``work(*args)`` on the jobs file, off the event loop; :class:`StorageFault` when the
    jobs are off or the file fails."""
    if run.off is not None:
        raise run.off
    return await anyio.to_thread.run_sync(work, *args)


def owner_of(request: Request) -> str:
    """The caller's key id ('' with keys off: everyone's jobs are everyone's)."""
    return str(request.scope.get("state", {}).get("client") or "")


def _iso(t: float | None) -> str | None:
    return None if t is None else datetime.fromtimestamp(t, tz=timezone.utc).isoformat()


def _progress(row: dict[str, Any]) -> JobProgressOut:
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


def job_out(row: dict[str, Any]) -> JobOut:
    """The job without its answer (``result`` null)."""
    return JobOut(
        id=row["id"], location=f"/v1/jobs/{row['id']}", operation=row["operation"], state=row["state"],
        created_at=_iso(row["created"]) or "", started_at=_iso(row["started"]), finished_at=_iso(row["finished"]),
        expires_at=_iso(row["expires"]), attempts=row["attempts"], message=row["message"] or "",
        cancel_requested=bool(row.get("cancel")), progress=_progress(row), status_code=row["status"], result=None,
    )


def job_response(row: dict[str, Any], status_code: int = 200, headers: dict[str, str] | None = None) -> Response:
    """The job as JSON with its answer, the stored bytes spliced in as they are (an answer
    of megabytes is never decoded and encoded again in the web process)."""
    text = job_out(row).model_dump_json()
    result = row["result"]
    if result is not None and row["media_type"] == "application/json":
        assert text.endswith('"result":null}')
        body = text[: -len("null}")].encode() + bytes(result) + b"}"
    else:
        body = text.encode()
    return Response(body, status_code=status_code, media_type="application/json", headers=headers)


def _not_found(job_id: str) -> JSONResponse:
    return JSONResponse(error_body(["path", "job_id"], f"no job {job_id!r} (or not yours)", "not_found"),
                        status_code=404)


@router.post("/v1/jobs", operation_id="jobs_submit", status_code=202, response_model=JobOut,
             summary="Run an expensive operation later", responses={**ANSWERS, 202: {"headers": {"Location": {
                 "description": "/v1/jobs/<id>", "schema": {"type": "string"}}}}})
async def submit(req: JobRequest, request: Request) -> Response:
    """Checks the operation's body at once (422 at `body.body.<field>`; 429 when 100 of your
    jobs are queued already; 507 when the jobs file is full or your jobs keep all they may),
    queues the job (kept in the server's SQLite file: a restart loses nothing queued or
    finished) and answers 202 with its id and where to ask. It runs when a solver slot is
    free, under the operation's own time limit counted from its start (up to the jobs' cap),
    with the same answer as the operation's route (JSON)."""
    run = deferred_runner(request)
    try:
        run.operations[req.operation].model.model_validate(req.body)
    except ValidationError as exc:
        raise RequestValidationError([{**e, "loc": ("body", "body", *e["loc"])}
                                      for e in exc.errors(include_url=False)]) from None
    owner = owner_of(request)
    try:
        if await _stored(run, run.store.queued_of, owner) >= MAX_QUEUED_PER_CLIENT:
            return JSONResponse(error_body([], f"{MAX_QUEUED_PER_CLIENT} of your jobs are queued already; retry when "
                                               "some have started", "too_many_jobs"), status_code=429,
                                headers={"Retry-After": "10"})
        job_id = await _stored(run, run.store.submit, req.operation, req.body, owner)
        row = await _stored(run, run.store.get, job_id)
    except StorageFault as fault:
        return storage_response(fault)
    except OverQuota as quota:
        return JSONResponse(error_body([], str(quota), "storage_quota"), status_code=INSUFFICIENT_STORAGE)
    assert row is not None
    return job_response(row, 202, {"Location": f"/v1/jobs/{job_id}"})


@router.get("/v1/jobs/{job_id}", operation_id="jobs_get", response_model=JobOut, summary="A job's state and answer",
            responses={**ANSWERS, **NOT_FOUND})
async def get_job(job_id: str, request: Request) -> Response:
    """State, progress (stage, an estimated fraction and time to go) and, once it ended, the
    operation's answer (`result`, with its `status_code`)."""
    run = deferred_runner(request)
    try:
        row = await _stored(run, run.store.get, job_id, owner_of(request))
    except StorageFault as fault:
        return storage_response(fault)
    return _not_found(job_id) if row is None else job_response(row)


@router.delete("/v1/jobs/{job_id}", operation_id="jobs_cancel", response_model=JobOut, summary="Cancel a job",
               responses={**ANSWERS, **NOT_FOUND})
async def cancel_job(job_id: str, request: Request) -> Response:
    """A queued job is cancelled at once; a running one within about a second (its solver
    worker is ended and replaced, its slot freed: the answer waits up to 1.5 s for that and
    says `cancel_requested` if it is still running); an ended one is forgotten, its answer
    deleted (what it kept no longer counts against your jobs' storage), and answered as it
    was."""
    run = deferred_runner(request)
    owner = owner_of(request)
    try:
        row = await _stored(run, run.store.get, job_id, owner)
        if row is None:
            return _not_found(job_id)
        if row["state"] in FINISHED:
            await _stored(run, run.store.remove, job_id)
            return job_response(row)
        await _stored(run, run.store.cancel, job_id, run.ttl_s)
        ends = time.monotonic() + CANCEL_WAIT_S
        while True:
            row = await _stored(run, run.store.get, job_id, owner)
            if row is None or row["state"] in FINISHED or time.monotonic() >= ends:
                break
            await asyncio.sleep(0.05)
    except StorageFault as fault:
        return storage_response(fault)
    return _not_found(job_id) if row is None else job_response(row)


@router.get("/v1/jobs", operation_id="jobs_list", response_model=JobListOut, summary="Your jobs", responses=ANSWERS)
async def list_jobs(request: Request, limit: int = Query(100, ge=1, le=1000, description="Most jobs listed.")
                    ) -> JobListOut | JSONResponse:
    """Your jobs (every job, with API keys off), newest first, without their results."""
    run = deferred_runner(request)
    try:
        rows = await _stored(run, run.store.list, owner_of(request) or None, limit)
    except StorageFault as fault:
        return storage_response(fault)
    return JobListOut(jobs=[job_out(r) for r in rows])
