"""Jobs for long work (``POST /v1/jobs``): an expensive operation's body run later, its
state and answer kept in a SQLite file (:mod:`service.runtime.jobstore`) so that a restart
loses nothing queued or finished.

:class:`DeferredRunner` — in every web process, a loop that claims queued jobs while the
server has a free *job place* (service.runtime.slots: all the server's slots but one, so
jobs never take the last slot from interactive requests; on a one-slot server, that slot),
runs each like an expensive request (it waits for a slot of the server, behind every
waiting request and never refused, runs in a solver worker under its time limit counted
from when it gets the slot; its run time is measured apart from the requests', so a job's
predicted end, and with it the Retry-After of the requests it delays, comes from jobs of
its own kind), writes a heartbeat and looks for a cancellation four times a second: a
cancelled job's worker is ended (Pebble) and replaced, so its slot is free within half a
second. A running job whose heartbeat stops (its server or web process died) is queued
again, at most ``MAX_ATTEMPTS`` times, then failed.

A jobs file that fails (a full disk, a read-only place, a file that is not a database) is
said once per change in the log and by the readiness probe, never a traceback per round: the
loop goes on, claims nothing while it cannot, and an ended job whose end could not be
written is written when the file works again (nothing accepted is lost; if its heartbeat went
stale meanwhile it was queued again and runs again). A file found unusable at start turns
the jobs off for this process's life (:attr:`DeferredRunner.off`): the routes answer 503
saying why, the rest of the service serves as usual.

Which operations can be deferred, and how, each route module says (``DEFERRABLE``, a
mapping of operation ids to :class:`Deferrable`); the app gathers them.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import json
import logging
import os
import time
import uuid
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import anyio
from pebble import ProcessExpired
from pydantic import BaseModel
from starlette.requests import Request

from service.runtime.admission import Gate, RunQueue
from service.runtime.deadline import Deadline
from service.runtime.jobs import (
    CLIENT_GONE,
    MEASURED_STATUSES,
    Job,
    Reply,
    Runner,
    crash_reply,
    deadline_reply,
    execute,
)
from service.runtime.jobstore import JobStore
from service.runtime.metrics import observe_backends
from service.store import StorageFault

log = logging.getLogger("service")

POLL_S = 0.25
"""How often a web process looks for queued jobs and for cancellations of its own."""


def json_answer(req: Any) -> tuple[Any, bool]:
    """A route job's arguments ``(req, svg)`` for a job: its answer is JSON."""
    return req, False


def request_only(req: Any) -> tuple[Any]:
    """A route job's arguments when the request is all it takes."""
    return (req,)


def _time_limit(req: Any) -> float | None:
    """The request's ``time_limit_s`` when it gave one (its model's default is a request's,
    not a job's: None, the jobs' cap)."""
    if "time_limit_s" not in req.model_fields_set or req.time_limit_s is None:
        return None
    return float(req.time_limit_s)


def _no_cost_key(req: Any) -> str:
    return ""


def _one_slot(req: Any) -> int:
    return 1


@dataclass(frozen=True)
class Deferrable:
    """How to run an operation as a job: its ``route`` ("POST /v1/..."; the job's run time
    counts in the same cost model as the route's requests), its request ``model``, its
    route's ``job`` function (``job(*args, deadline)``), the ``args`` before the deadline
    made from the validated request, the request's own time limit (``limit``; None: the
    jobs' cap), the key of its cost (``cost``, as the route's) and the most slots it can use
    (``width``, as the route's)."""

    route: str
    model: type[BaseModel]
    job: Job
    args: Callable[[Any], tuple[Any, ...]]
    limit: Callable[[Any], float | None] = _time_limit
    cost: Callable[[Any], str] = _no_cost_key
    width: Callable[[Any], int] = _one_slot


def deferred_runner(request: Request) -> DeferredRunner:
    """The app's jobs loop of this web process (made by :func:`service.app.create_app`)."""
    run: DeferredRunner = request.app.state.deferred
    return run


@dataclass
class Running:
    """A job this process runs: its task, whether it was cancelled, and the server's job
    place it holds (None without solver workers)."""

    job_id: str
    place: int | None = None
    task: asyncio.Task[None] | None = None
    cancelled: bool = False


RECOVER_S = 2.0
"""How often a web process queues lost jobs again and drops expired ones."""


@dataclass(frozen=True)
class Ended:
    """The end of a job ran here, to be written to the jobs file."""

    job_id: str
    state: str
    reply: Reply | None
    message: str


@dataclass
class DeferredRunner:
    """The loop of one web process (module docstring): ``runner`` runs the jobs as it runs
    expensive requests; at most ``concurrency`` of this process's jobs at once; each job's
    time limit at most ``max_time_s``; answers kept ``ttl_s``."""

    store: JobStore
    runner: Runner
    operations: dict[str, Deferrable]
    concurrency: int
    max_time_s: float
    ttl_s: float
    name: str = field(default_factory=lambda: f"{os.getpid()}-{uuid.uuid4().hex[:8]}")
    running: dict[str, Running] = field(default_factory=dict)
    unwritten: list[Ended] = field(default_factory=list)
    off: StorageFault | None = None
    _loop_task: asyncio.Task[None] | None = None

    def check(self) -> None:
        """Try the jobs file (at start): one that cannot be used for a reason other than a
        full disk turns the jobs off for this process (:attr:`off`; logged once)."""
        try:
            self.store.check()
            self.off = None
        except StorageFault as fault:
            self.off = None if fault.kind == "full" else fault
            if self.off is not None:
                log.error("jobs are off in this web process: the jobs file %s cannot be used (%s): %s; the rest of "
                          "the service serves as usual", fault.path, fault.kind, fault.reason)

    def start(self) -> None:
        """Start the loop on the running event loop (an app started again, as tests do,
        forgets what ran on an earlier loop); none while the jobs are off."""
        self.running.clear()
        if self.off is None:
            self._loop_task = asyncio.get_running_loop().create_task(self._loop())

    async def stop(self) -> None:
        """Stop claiming and end the jobs running here (not cancelled: their heartbeat
        stops, so another web process, or the server when it starts again, runs them)."""
        loop = asyncio.get_running_loop()
        tasks = [t for t in [self._loop_task, *(r.task for r in self.running.values())]
                 if t is not None and t.get_loop() is loop and not t.done()]
        for task in tasks:
            task.cancel()
        await asyncio.gather(*tasks, return_exceptions=True)
        self._loop_task = None

    async def _loop(self) -> None:
        recovered = 0.0
        while True:
            try:
                while self.unwritten:  # ends that a failing file could not take, oldest first
                    await self._write(self.unwritten[0])
                    self.unwritten.pop(0)
                if time.monotonic() - recovered >= RECOVER_S:
                    await anyio.to_thread.run_sync(self.store.recover, self.ttl_s)
                    recovered = time.monotonic()
                while len(self.running) < self.concurrency and await self._claim_one():
                    pass
                if self.running:
                    for job_id in await anyio.to_thread.run_sync(self.store.beat, self.name, list(self.running)):
                        run = self.running.get(job_id)
                        if run is not None and not run.cancelled and run.task is not None:
                            run.cancelled = True
                            run.task.cancel()  # its worker is ended (the pebble future is cancelled)
            except asyncio.CancelledError:
                raise
            except StorageFault:  # said once per change by the store's health; tried again next round
                pass
            except Exception:  # a bug: the loop must outlive it
                log.exception("the jobs loop failed a round; trying again")
            await asyncio.sleep(POLL_S)

    async def _claim_one(self) -> bool:
        """Claim the oldest queued job and start it, holding one of the server's job places
        (with solver workers); False when there is none, or no place is free."""
        queue = self.runner.expensive
        place = None
        if isinstance(queue, RunQueue):
            place = queue.slots.try_take_place()
            if place is None:
                return False  # jobs hold every job place of the server
        row = None
        try:
            row = await anyio.to_thread.run_sync(self.store.claim, self.name)
        finally:
            if row is None and place is not None:
                queue.slots.give_back_place(place)
        if row is None:
            return False
        if row["id"] in self.running:  # its own job, queued again while it was cut off from the file: still running
            if place is not None:
                queue.slots.give_back_place(place)
            return True
        run = self.running[row["id"]] = Running(row["id"], place)
        run.task = asyncio.get_running_loop().create_task(self._run(run, row))
        return True

    async def _run(self, run: Running, row: dict[str, Any]) -> None:
        try:
            await self._run_holding_place(run, row)
        finally:
            queue = self.runner.expensive
            if run.place is not None and isinstance(queue, RunQueue):
                queue.slots.give_back_place(run.place)

    async def _run_holding_place(self, run: Running, row: dict[str, Any]) -> None:
        state, reply, message = "failed", None, ""
        try:
            spec = self.operations[row["operation"]]
            req = spec.model.model_validate(json.loads(row["body"]))
            asked = spec.limit(req)
            limit = self.max_time_s if asked is None else min(float(asked), self.max_time_s)
            reply = await self._execute(run, spec, req, limit)
            observe_backends(dict(reply.backends))
            state = "succeeded" if reply.status == 200 else "failed"
            message = "" if reply.status == 200 else f"the operation answered {reply.status}"
        except asyncio.CancelledError:
            if not run.cancelled:  # the process stops: the job is run again elsewhere
                self.running.pop(run.job_id, None)
                raise
            state, reply, message = "cancelled", None, "cancelled while it ran; its worker was ended"
        except Exception as exc:  # a job that cannot run fails, saying why
            message = f"could not run: {exc}"
        self.running.pop(run.job_id, None)
        ended = Ended(run.job_id, state, reply, message)
        try:
            await self._write(ended)
        except StorageFault as fault:  # written by the loop when the file works again
            log.warning("job %s %s, but its end cannot be written yet (%s): it will be", run.job_id, state,
                        fault.kind)
            self.unwritten.append(ended)

    async def _write(self, ended: Ended) -> None:
        reply = ended.reply
        await anyio.to_thread.run_sync(
            self.store.finish, self.name, ended.job_id, ended.state, self.ttl_s,
            None if reply is None else reply.status, None if reply is None else reply.media_type,
            None if reply is None else reply.body, ended.message)
        log.info("job %s %s: %s", ended.job_id, ended.state, ended.message or "done")

    async def _execute(self, run: Running, spec: Deferrable, req: Any, limit_s: float) -> Reply:
        """Run the job like an expensive request, in a solver worker under its limit counted
        from its start, once it has a slot of the server (service.runtime.admission: a job
        waits behind every waiting request and is never refused; its run time is measured
        apart from the requests'). Without solver workers (tests), in a thread."""
        queue = self.runner.expensive
        args, where = spec.args(req), f"job {run.job_id} ({spec.route})"
        if isinstance(queue, Gate):
            while not queue.try_enter():
                await asyncio.sleep(POLL_S)
            try:
                deadline = Deadline.starting(time.monotonic(), limit_s)
                await anyio.to_thread.run_sync(self.store.running_for, run.job_id, self.name, None)
                reply: Reply = await anyio.to_thread.run_sync(execute, spec.job, args, deadline, where)
                return reply
            finally:
                queue.leave()
        ticket = await queue.enter_job(f"{spec.route} {spec.cost(req)}".rstrip(), limit_s, spec.width(req))
        reply = Reply(CLIENT_GONE, None, b"")
        try:
            deadline = ticket.granted
            predicted = queue.estimate(ticket.kind, limit_s)
            await anyio.to_thread.run_sync(self.store.running_for, run.job_id, self.name, predicted)
            assert self.runner.pool is not None
            future = self.runner.pool.schedule(execute, (spec.job, args, deadline, where),
                                               timeout=deadline.remaining() + self.runner.grace_s)
            try:
                reply = await asyncio.wrap_future(future)
            except ProcessExpired as exc:
                reply = crash_reply(exc, self.runner.retry_after_s)
            except (TimeoutError, concurrent.futures.TimeoutError):
                reply = deadline_reply(deadline, "the solver worker was stopped at the deadline")
            return reply
        finally:
            queue.leave(ticket, measured=reply.status in MEASURED_STATUSES)
