"""Running a route's job under the request's deadline, and answering with what it gave.

A job is a top-level function ``job(*args, deadline) -> answer`` of a route module: the
route's whole computation (problem, solver, conversion, picture), with a
:class:`~service.runtime.deadline.Deadline` from which it makes its solver budget. Its
answer (a pydantic response model or a Starlette ``Response``) or the error it raised
becomes a :class:`Reply` — status, media type, body bytes — where the job ran, so a worker
sends back bytes, not objects. The web process then only relays them.

Expensive jobs enter the expensive gate (or are refused 503) and run in a solver worker
(:mod:`service.runtime.pool`); the route awaits the first of: the reply, the client going
away (the job is cancelled and its worker ended), or the deadline plus a grace (the job is
cancelled; the answer is a 504). Cheap jobs (closed forms of a millisecond or less) run at
once on the web process's event loop: no thread hand-off, no lock contention.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import dataclasses
import logging
import math
import signal
import time
from collections.abc import Callable, Coroutine, Sequence
from dataclasses import dataclass
from typing import Any

import anyio
from pebble import ProcessExpired
from pydantic import BaseModel
from starlette.requests import Request
from starlette.responses import JSONResponse, Response

from service.errors import BUSY, GATEWAY_TIMEOUT, FieldError, busy_response, error_body, limit_advice, response_for
from service.runtime.admission import DEFAULT_ADMISSION, Gate, Refused, RunQueue, Ticket
from service.runtime.deadline import Deadline, arrival
from service.runtime.metrics import observe_backends
from service.runtime.pool import SolverPool
from service.runtime.slots import Slots
from service.settings import Settings
from solver import close_ledger, open_ledger

log = logging.getLogger("service")

Job = Callable[..., Any]

WARM_UP_TIMEOUT_S = 120.0
"""How long the startup waits for the first solver worker (the imports of the solver stack)."""

CLIENT_GONE = 499
"""Status of the answer to a client that went away (never seen by it; for the log)."""


@dataclass(frozen=True)
class Reply:
    """An HTTP answer as bytes (what a worker sends back), with the model that answered
    (the answer's ``method``, when it has one) and the job's seconds per numerical back end
    (:mod:`solver.core.backends`; ``other``: the rest), for the log and the metrics."""

    status: int
    media_type: str | None
    body: bytes
    headers: tuple[tuple[str, str], ...] = ()
    model: str | None = None
    backends: tuple[tuple[str, float], ...] = ()

    def response(self) -> Response:
        return Response(content=self.body, status_code=self.status, media_type=self.media_type,
                        headers=dict(self.headers))


def reply_of(answer: Any) -> Reply:
    """The bytes of a job's answer: a ``Response`` as it is, a pydantic model as JSON by
    alias, serialised by pydantic-core (the fields FastAPI would send for the route's
    ``response_model``, ten times faster than the standard library's encoder)."""
    if isinstance(answer, BaseModel):
        model = getattr(answer, "method", None)
        return Reply(200, "application/json", answer.model_dump_json(by_alias=True).encode(),
                     model=model if isinstance(model, str) else None)
    if not isinstance(answer, Response):
        raise TypeError(f"a job must answer a pydantic model or a Response, not {type(answer).__name__}")
    headers = tuple((k, v) for k, v in answer.headers.items() if k.lower() not in ("content-length", "content-type"))
    return Reply(answer.status_code, answer.media_type, bytes(answer.body), headers)


def execute(job: Job, args: tuple[Any, ...], deadline: Deadline, where: str) -> Reply:
    """Run ``job(*args, deadline)`` and make its answer, or the answer to its error, a
    Reply with the job's time per back end. This is what a worker runs; nothing it raises
    leaves it."""
    open_ledger()
    t0 = time.perf_counter()
    try:
        reply = reply_of(job(*args, deadline))
    except Exception as exc:  # every error becomes its HTTP answer (service.errors)
        reply = reply_of(response_for(exc, where))
    spent = close_ledger()
    spent["other"] = max(time.perf_counter() - t0 - sum(spent.values()), 0.0)
    return dataclasses.replace(reply, backends=tuple(spent.items()))


def delivered(request: Request, reply: Reply) -> Response:
    """The response of a job's reply; its model and back-end times noted for the log and the
    metrics."""
    if reply.model is not None:
        request.state.model = reply.model
    observe_backends(dict(reply.backends))
    return reply.response()


def deadline_reply(deadline: Deadline, what: str) -> Reply:
    """The 504 of a job whose worker did not answer by the deadline and its grace: the worker
    was stopped, so nothing it completed is known."""
    body = error_body(
        ["body", "time_limit_s"],
        f"no answer within the time limit of {deadline.limit_s:g} s ({what}; what it had completed was lost with "
        f"it); ask for less work, or {limit_advice(deadline.limit_s)}",
        "time_limit",
    )
    body.update(reached=what, time_limit_s=deadline.limit_s, elapsed_s=deadline.elapsed(), partial=None)
    return reply_of(JSONResponse(body, status_code=GATEWAY_TIMEOUT))


FAULT_SIGNALS = frozenset({signal.SIGSEGV, signal.SIGBUS, signal.SIGABRT, signal.SIGFPE, signal.SIGILL})
"""Signals a process raises on itself when its code fails (a fault: a bug to report)."""


def crash_reply(exc: BaseException, retry_after_s: int) -> Reply:
    """The answer when the worker running the job died. A fault of its own (a segmentation
    fault in a native library, an abort) is a bug: 500. A worker stopped from outside by a
    signal (the out-of-memory killer, an operator's kill) lost the work but not through a
    fault of the request: 503 with ``Retry-After``. The worker is replaced either way."""
    code = getattr(exc, "exitcode", None)
    if isinstance(code, int) and code < 0 and -code not in FAULT_SIGNALS:
        try:
            name = signal.Signals(-code).name
        except ValueError:
            name = f"signal {-code}"
        return reply_of(JSONResponse(
            error_body([], f"the solver worker running this request was stopped by {name} (the system's "
                           f"out-of-memory killer or an operator); nothing was computed; retry after "
                           f"{retry_after_s} s", "worker_lost"),
            status_code=BUSY, headers={"Retry-After": str(retry_after_s)},
        ))
    return reply_of(JSONResponse(
        error_body([], f"the solver worker running this request ended abnormally ({exc}); this is a bug",
                   "internal_error"),
        status_code=500,
    ))


async def client_gone(request: Request) -> None:
    """Returns when the client has disconnected (the body has been read by then)."""
    while True:
        message = await request.receive()
        if message["type"] == "http.disconnect":
            return


@dataclass(frozen=True)
class Runner:
    """What a route needs to run a job: the gate of requests in flight, and either the
    queue of the server's slots with this web process's solver workers (``pool``), or (no
    pool, as in most tests) a gate for expensive jobs run in the web process's threads."""

    requests: Gate
    expensive: Gate | RunQueue
    pool: SolverPool | None
    max_time_limit_s: float
    grace_s: float
    retry_after_s: int

    @classmethod
    def from_settings(cls, settings: Settings, preload: Sequence[str] = ()) -> Runner:
        """The runner of ``settings``; its solver workers import the modules ``preload``
        names (the routes, whose jobs they run) once, before they are forked. Every web
        process has a worker per slot of the server, so that it can use them all."""
        workers = settings.solver_processes()
        expensive: Gate | RunQueue
        if workers > 0:
            pool: SolverPool | None = SolverPool(workers, settings.worker_max_tasks, preload)
            expensive = RunQueue(Slots.of_server(workers), settings.solver_queue,
                                 dataclasses.replace(DEFAULT_ADMISSION, max_wait_s=settings.solver_queue_wait_s))
        else:
            pool, expensive = None, Gate("expensive", 1 + settings.solver_queue)
        return cls(
            requests=Gate("requests", settings.max_requests_in_flight),
            expensive=expensive,
            pool=pool,
            max_time_limit_s=settings.max_time_limit_s,
            grace_s=settings.deadline_grace_s,
            retry_after_s=settings.retry_after_s,
        )

    async def start(self) -> None:
        """Open the slots and start the solver workers (at the app's startup)."""
        if isinstance(self.expensive, RunQueue):
            self.expensive.slots.open()
        if self.pool is not None:
            await anyio.to_thread.run_sync(self.pool.warm_up, WARM_UP_TIMEOUT_S)

    def close(self) -> None:
        if self.pool is not None:
            self.pool.close()
        if isinstance(self.expensive, RunQueue):
            self.expensive.slots.close()

    def deadline(self, request: Request, time_limit_s: float | None, asked: bool = True) -> Deadline:
        """The request's deadline: ``time_limit_s`` after its arrival (None: the cap). A
        limit past the deployment's cap is refused (422 at time_limit_s) when the client
        ``asked`` for it, and lowered to the cap when it is a route's default."""
        cap = self.max_time_limit_s
        if time_limit_s is not None and time_limit_s > cap and asked:
            raise FieldError(("time_limit_s",), f"must be at most {cap:g} s, this deployment's cap "
                             "(PESHKIN_MAX_TIME_LIMIT_S)", kind="less_than_equal")
        limit = cap if time_limit_s is None else min(float(time_limit_s), cap)
        return Deadline.starting(arrival(request.scope), limit)

    def request_deadline(self, request: Request, args: tuple[Any, ...], time_limit_s: float | None) -> Deadline:
        """:meth:`deadline` of a job one of whose arguments is the request's model (a limit
        the client left out is the route's default)."""
        model = next((arg for arg in args if isinstance(arg, BaseModel)), None)
        asked = not isinstance(model, BaseModel) or (
            "time_limit_s" in model.model_fields_set and getattr(model, "time_limit_s", None) is not None)
        return self.deadline(request, time_limit_s, asked)

    async def cheap_job(self, request: Request, job: Job, *args: Any, time_limit_s: float | None = None) -> Response:
        """Run a cheap job at once, on the event loop."""
        return delivered(request, execute(job, args, self.request_deadline(request, args, time_limit_s),
                                          where(request)))

    async def expensive_job(self, request: Request, job: Job, *args: Any, time_limit_s: float | None = None,
                            cost_key: str = "", anytime: bool = False, width: int = 1) -> Response:
        """Run an expensive job in a solver worker (or a thread), under the deadline.
        ``cost_key``: what of the request, besides its route, decides the job's cost (the
        queue measures costs per route and key); ``anytime``: the job refines until its
        limit and answers what it has (admitted when it can run a useful part of its limit,
        service.runtime.admission); ``width``: the most slots it can use (its parallel
        tasks; it runs with those it gets, ``Deadline.slots``)."""
        deadline = self.request_deadline(request, args, time_limit_s)
        queue = self.expensive
        if isinstance(queue, Gate):
            if not queue.try_enter():
                return busy_response(queue.name, self.retry_after_s)
            try:
                reply = await anyio.to_thread.run_sync(execute, job, args, deadline, where(request))
            finally:
                queue.leave()
            return delivered(request, reply)
        try:
            ticket = await self.queued(request, queue.enter(f"{where(request)} {cost_key}".rstrip(), deadline,
                                                            anytime, width))
        except Refused as refused:
            return self._busy(request, refused)
        if ticket is None:
            log.info("client gone on %s after %.3g s in the queue", where(request), deadline.elapsed())
            return Reply(CLIENT_GONE, None, b"").response()
        reply = Reply(CLIENT_GONE, None, b"")
        try:
            reply = await self.in_worker(request, job, args, ticket.granted)
        finally:  # only a job that ran to its answer or its deadline tells its cost
            queue.leave(ticket, measured=reply.status in MEASURED_STATUSES)
        return delivered(request, reply)

    def refused_now(self, request: Request, time_limit_s: float | None = None, cost_key: str = "",
                    anytime: bool = False) -> Response | None:
        """The 503 that an expensive job of this request would get now (None: it would be
        admitted), asked before a large body is read: a request refused anyway is answered
        without reading its body into the web process (the server discards the rest as it
        arrives, so the client gets its 503 on a connection that stays usable)."""
        queue = self.expensive
        if not isinstance(queue, RunQueue):
            return None
        deadline = self.deadline(request, time_limit_s, asked=False)
        refused = queue.refusal_now(f"{where(request)} {cost_key}".rstrip(), deadline, anytime)
        return None if refused is None else self._busy(request, refused, " before reading its body")

    def _busy(self, request: Request, refused: Refused, when: str = "") -> Response:
        """The 503 of a refusal, its Retry-After the predicted wait (at least the setting's)."""
        retry = max(self.retry_after_s, math.ceil(refused.retry_after_s))
        log.info("refused %s%s: %s", where(request), when, refused.reason)
        return busy_response(self.expensive.name, retry, refused.reason)

    async def queued(self, request: Request, enter: Coroutine[Any, Any, Ticket]) -> Ticket | None:
        """The request's slot (``enter``: its wait in the queue; :class:`Refused` passes
        through); None when its client went away while it waited. Whatever ends the wait
        (this task cancelled too), a slot taken for nobody is given back and a place in the
        queue is left."""
        queue = self.expensive
        assert isinstance(queue, RunQueue)
        entering = asyncio.ensure_future(enter)
        gone = asyncio.ensure_future(client_gone(request))
        try:
            await asyncio.wait({entering, gone}, return_when=asyncio.FIRST_COMPLETED)
        except BaseException:
            gone.cancel()
            abandon(queue, entering)
            raise
        gone.cancel()
        if not entering.done():
            abandon(queue, entering)
            return None
        return entering.result()

    async def in_worker(self, request: Request, job: Job, args: tuple[Any, ...], deadline: Deadline) -> Reply:
        assert self.pool is not None
        wait_s = deadline.remaining() + self.grace_s
        future = self.pool.schedule(execute, (job, args, deadline, where(request)), timeout=wait_s)
        answer = asyncio.wrap_future(future)
        gone = asyncio.ensure_future(client_gone(request))
        try:
            done, _ = await asyncio.wait({answer, gone}, timeout=wait_s, return_when=asyncio.FIRST_COMPLETED)
        finally:
            gone.cancel()
        if answer in done:
            try:
                reply: Reply = answer.result()
                return reply
            except ProcessExpired as exc:
                log.error("solver worker died on %s: %s", where(request), exc)
                return crash_reply(exc, self.retry_after_s)
            except (TimeoutError, concurrent.futures.TimeoutError):
                return deadline_reply(deadline, "the solver worker was stopped at the deadline")
        future.cancel()  # a running task's worker is ended and replaced
        if gone in done:
            log.info("client gone on %s after %.3g s: its job was cancelled", where(request), deadline.elapsed())
            return Reply(CLIENT_GONE, None, b"")
        return deadline_reply(deadline, "the solver worker had not answered by the deadline")


MEASURED_STATUSES = frozenset({200, GATEWAY_TIMEOUT})
"""Answers whose run time is a job's cost: served, or stopped at the deadline (not a quick
refusal of the input, a lost worker or a client gone)."""


def abandon(queue: RunQueue, entering: asyncio.Future[Ticket]) -> None:
    """Give up a request's wait for a slot: cancel it (it leaves the queue), or, when it
    got its slot already, give the slot back unmeasured."""
    if not entering.done():
        entering.cancel()
    elif not entering.cancelled() and entering.exception() is None:
        queue.leave(entering.result(), measured=False)


def where(request: Request) -> str:
    return f"{request.method} {request.url.path}"


def runner(request: Request) -> Runner:
    """The app's runner (made by :func:`service.app.create_app`)."""
    run: Runner = request.app.state.runner
    return run
