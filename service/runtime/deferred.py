"""Jobs for long work (``POST /v1/jobs``): an expensive operation's body run later, its
state and answer kept in a SQLite file so that a restart loses nothing queued or finished.

* :class:`JobStore` — the jobs table (the standard library's ``sqlite3``, one connection per
  process and thread, WAL, a busy timeout; every change one statement or one immediate
  transaction, so the web processes of a server, or a restarted server, share it safely).
  States: ``queued`` → ``running`` → ``succeeded`` | ``failed`` | ``cancelled``. A job's
  answer is the operation's own: its status code and JSON body (a 504 with what was
  finished, a 422, ...), kept until ``expires_at``.
* :class:`DeferredRunner` — in every web process, a loop that claims queued jobs while the
  server has a free *job place* (service.runtime.slots: all the server's slots but one, so
  jobs never take the last slot from interactive requests; on a one-slot server, that
  slot), runs each like an expensive request (it waits for a slot of the server, behind
  every waiting request and never refused, runs in a solver worker under its time limit
  counted from when it gets the slot; its run time is measured apart from the requests',
  so a job's predicted end, and with it the Retry-After of the requests it delays, comes
  from jobs of its own kind), writes a heartbeat and looks for a cancellation four times a
  second: a cancelled job's worker is ended (Pebble) and replaced, so its slot is free
  within half a second. A running job whose heartbeat stops (its server or web process
  died) is queued again, at most ``MAX_ATTEMPTS`` times, then failed.

Which operations can be deferred, and how, each route module says (``DEFERRABLE``, a
mapping of operation ids to :class:`Deferrable`); the app gathers them.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import json
import logging
import os
import sqlite3
import threading
import time
import uuid
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
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
from service.runtime.metrics import observe_backends
from service.store import thread_connection

log = logging.getLogger("service")

STATES = ("queued", "running", "succeeded", "failed", "cancelled")
FINISHED = ("succeeded", "failed", "cancelled")
JOBS_SCHEMA = (
    "CREATE TABLE IF NOT EXISTS jobs (id TEXT PRIMARY KEY, owner TEXT NOT NULL, operation TEXT NOT NULL, "
    "body TEXT NOT NULL, state TEXT NOT NULL, created REAL NOT NULL, started REAL, finished REAL, "
    "expires REAL, attempts INTEGER NOT NULL DEFAULT 0, runner TEXT, heartbeat REAL, "
    "cancel INTEGER NOT NULL DEFAULT 0, status INTEGER, media_type TEXT, result BLOB, message TEXT, ran REAL, "
    "predicted REAL)",
    "CREATE INDEX IF NOT EXISTS jobs_state ON jobs (state, created)",
)
JOBS_COLUMNS_ADDED = ("ran REAL", "predicted REAL")
"""Columns added since the first jobs files (a file made before them gets them on open)."""
POLL_S = 0.25
"""How often a web process looks for queued jobs and for cancellations of its own."""
STALE_S = 10.0
"""A running job whose heartbeat is older than this has lost its process: queued again."""
MAX_ATTEMPTS = 3
"""Times a job is started before a lost one is failed."""
MAX_QUEUED_PER_CLIENT = 100
"""Jobs one client (API key, or everyone with keys off) may have queued at once."""


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


def _add_columns(conn: sqlite3.Connection) -> None:
    """Give a jobs file made before :data:`JOBS_COLUMNS_ADDED` those columns."""
    have = {row[1] for row in conn.execute("PRAGMA table_info(jobs)").fetchall()}
    for column in JOBS_COLUMNS_ADDED:
        if column.split()[0] not in have:
            conn.execute(f"ALTER TABLE jobs ADD COLUMN {column}")


class JobStore:
    """The jobs table in the SQLite file ``path`` (module docstring)."""

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self.path = Path(path)
        self._local = threading.local()

    def _conn(self) -> sqlite3.Connection:
        return thread_connection(self._local, self.path, JOBS_SCHEMA, check_same_thread=False, row_factory=sqlite3.Row,
                                 migrate=_add_columns)

    def submit(self, operation: str, body: dict[str, Any], owner: str) -> str:
        job_id = uuid.uuid4().hex
        self._conn().execute("INSERT INTO jobs (id, owner, operation, body, state, created) VALUES (?, ?, ?, ?, ?, ?)",
                             (job_id, owner, operation, json.dumps(body), "queued", time.time()))
        return job_id

    def get(self, job_id: str, owner: str | None = None) -> dict[str, Any] | None:
        """The job (None when unknown, or when ``owner`` is given and is not its owner)."""
        row = self._conn().execute("SELECT * FROM jobs WHERE id = ?", (job_id,)).fetchone()
        if row is None or (owner is not None and row["owner"] != owner):
            return None
        return dict(row)

    def list(self, owner: str | None, limit: int) -> list[dict[str, Any]]:
        sql = "SELECT * FROM jobs" + (" WHERE owner = ?" if owner is not None else "") + " ORDER BY created DESC LIMIT ?"
        args: tuple[Any, ...] = (owner, limit) if owner is not None else (limit,)
        return [dict(r) for r in self._conn().execute(sql, args).fetchall()]

    def cancel(self, job_id: str, ttl_s: float) -> None:
        """A queued job is cancelled at once (and expires ``ttl_s`` later); a running one is
        asked to stop. One transaction: a job requeued meanwhile is not missed."""
        now = time.time()
        conn = self._conn()
        conn.execute("BEGIN IMMEDIATE")
        try:
            conn.execute("UPDATE jobs SET state = 'cancelled', finished = ?, expires = ?, message = 'cancelled before "
                         "it started' WHERE id = ? AND state = 'queued'", (now, now + ttl_s, job_id))
            conn.execute("UPDATE jobs SET cancel = 1 WHERE id = ? AND state = 'running'", (job_id,))
            conn.execute("COMMIT")
        except BaseException:
            conn.execute("ROLLBACK")
            raise

    def queued_of(self, owner: str) -> int:
        row = self._conn().execute("SELECT COUNT(*) AS n FROM jobs WHERE owner = ? AND state = 'queued'",
                                   (owner,)).fetchone()
        return int(row["n"])

    def running_for(self, job_id: str, runner: str, predicted_s: float | None) -> None:
        """``runner``'s job has its slot and runs now, predicted to take ``predicted_s``."""
        self._conn().execute("UPDATE jobs SET ran = ?, predicted = ? WHERE id = ? AND state = 'running' AND runner = ?",
                             (time.time(), predicted_s, job_id, runner))

    def claim(self, runner: str) -> dict[str, Any] | None:
        """The oldest queued job, now running under ``runner`` (None when there is none)."""
        now = time.time()
        row = self._conn().execute(
            "UPDATE jobs SET state = 'running', runner = ?, started = ?, heartbeat = ?, attempts = attempts + 1 "
            "WHERE id = (SELECT id FROM jobs WHERE state = 'queued' ORDER BY created LIMIT 1) AND state = 'queued' "
            "RETURNING *", (runner, now, now)).fetchone()
        return None if row is None else dict(row)

    def beat(self, runner: str, job_ids: list[str]) -> set[str]:
        """Heartbeat of ``runner``'s running jobs; the ids among them whose cancellation was
        asked, or that are no longer its own (queued again and claimed elsewhere: it stops
        them too)."""
        if not job_ids:
            return set()
        marks = ",".join("?" * len(job_ids))
        conn = self._conn()
        conn.execute(f"UPDATE jobs SET heartbeat = ? WHERE id IN ({marks}) AND state = 'running' AND runner = ?",
                     (time.time(), *job_ids, runner))
        rows = conn.execute(f"SELECT id FROM jobs WHERE id IN ({marks}) AND (cancel = 1 OR state != 'running' OR "
                            "runner IS NOT ?)", (*job_ids, runner)).fetchall()
        return {r["id"] for r in rows}

    def finish(self, runner: str, job_id: str, state: str, ttl_s: float, reply: Reply | None, message: str) -> None:
        """The end of a job that ``runner`` ran (a job it lost to another is left alone)."""
        now = time.time()
        self._conn().execute(
            "UPDATE jobs SET state = ?, finished = ?, expires = ?, status = ?, media_type = ?, result = ?, "
            "message = ? WHERE id = ? AND state = 'running' AND runner = ?",
            (state, now, now + ttl_s, None if reply is None else reply.status,
             None if reply is None else reply.media_type, None if reply is None else reply.body, message, job_id,
             runner))

    def recover(self, ttl_s: float) -> int:
        """Queue again the running jobs whose process was lost (stale heartbeat), fail those
        started MAX_ATTEMPTS times; drop the finished jobs past their expiry. How many were
        queued again."""
        now = time.time()
        conn = self._conn()
        conn.execute("BEGIN IMMEDIATE")
        try:
            conn.execute("UPDATE jobs SET state = 'failed', finished = ?, expires = ?, message = ? WHERE "
                         "state = 'running' AND heartbeat < ? AND attempts >= ?",
                         (now, now + ttl_s, f"its process was lost {MAX_ATTEMPTS} times", now - STALE_S, MAX_ATTEMPTS))
            again = conn.execute("UPDATE jobs SET state = 'queued', runner = NULL, message = 'started again: its "
                                 "process was lost' WHERE state = 'running' AND heartbeat < ?",
                                 (now - STALE_S,)).rowcount
            conn.execute("DELETE FROM jobs WHERE expires IS NOT NULL AND expires < ?", (now,))
            conn.execute("COMMIT")
        except BaseException:
            conn.execute("ROLLBACK")
            raise
        return int(again)

    def counts(self) -> dict[str, int]:
        rows = self._conn().execute("SELECT state, COUNT(*) AS n FROM jobs GROUP BY state").fetchall()
        return {r["state"]: int(r["n"]) for r in rows}


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
    _loop_task: asyncio.Task[None] | None = None

    def start(self) -> None:
        """Start the loop on the running event loop (an app started again, as tests do,
        forgets what ran on an earlier loop)."""
        self.running.clear()
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
            except Exception:  # the loop must outlive a locked or broken file
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
        try:
            await anyio.to_thread.run_sync(self.store.finish, self.name, run.job_id, state, self.ttl_s, reply, message)
        except Exception:  # the job stays running, its heartbeat stops: it is run again
            log.exception("job %s: its end could not be written", run.job_id)
            return
        log.info("job %s %s: %s", run.job_id, state, message or "done")

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
