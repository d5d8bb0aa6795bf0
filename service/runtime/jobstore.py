"""The jobs table (``POST /v1/jobs``): a SQLite file shared by the web processes of a server
and kept across its restarts (the standard library's ``sqlite3``, one connection per process
and thread, WAL, a busy timeout; every change one statement or one immediate transaction).

States: ``queued`` → ``running`` → ``succeeded`` | ``failed`` | ``cancelled``. A job's answer
is the operation's own: its status code and JSON body, kept until ``expires``.

What the file may hold is capped: the whole file (``max_bytes``: SQLite's page limit, so a
full cap behaves as a full disk), each answer (``max_answer_bytes``: a larger one fails the
job, saying so) and everything one client's jobs keep (``max_client_bytes``: bodies and
answers; a submission past it is refused with the cap named). Every failure of the file is a
:class:`service.store.StorageFault` (full, read-only, broken, unavailable), raised to the
caller and recorded in :attr:`JobStore.health` (logged once per change, shown by the
readiness probe); a transaction that fails is rolled back only if SQLite left it open (a full
disk rolls it back itself), so the real error is the one reported.
"""

from __future__ import annotations

import contextlib
import json
import os
import sqlite3
import threading
import time
import uuid
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any, TypeVar

from service.store import StorageFault, StorageHealth, thread_connection

STATES = ("queued", "running", "succeeded", "failed", "cancelled")
FINISHED = ("succeeded", "failed", "cancelled")
JOBS_SCHEMA = (
    "CREATE TABLE IF NOT EXISTS jobs (id TEXT PRIMARY KEY, owner TEXT NOT NULL, operation TEXT NOT NULL, "
    "body TEXT NOT NULL, state TEXT NOT NULL, created REAL NOT NULL, started REAL, finished REAL, "
    "expires REAL, attempts INTEGER NOT NULL DEFAULT 0, runner TEXT, heartbeat REAL, "
    "cancel INTEGER NOT NULL DEFAULT 0, status INTEGER, media_type TEXT, result BLOB, message TEXT, ran REAL, "
    "predicted REAL)",
    "CREATE INDEX IF NOT EXISTS jobs_state ON jobs (state, created)",
    "CREATE INDEX IF NOT EXISTS jobs_owner ON jobs (owner)",
)
JOBS_COLUMNS_ADDED = ("ran REAL", "predicted REAL")
"""Columns added since the first jobs files (a file made before them gets them on open)."""
STALE_S = 10.0
"""A running job whose heartbeat is older than this has lost its process: queued again."""
MAX_ATTEMPTS = 3
"""Times a job is started before a lost one is failed."""
MAX_QUEUED_PER_CLIENT = 100
"""Jobs one client (API key, or everyone with keys off) may have queued at once."""

T = TypeVar("T")


def _add_columns(conn: sqlite3.Connection) -> None:
    """Give a jobs file made before :data:`JOBS_COLUMNS_ADDED` those columns."""
    have = {row[1] for row in conn.execute("PRAGMA table_info(jobs)").fetchall()}
    for column in JOBS_COLUMNS_ADDED:
        if column.split()[0] not in have:
            conn.execute(f"ALTER TABLE jobs ADD COLUMN {column}")


class OverQuota(Exception):
    """A submission that would take a client's jobs past what they may keep."""

    def __init__(self, kept: int, adding: int, cap: int) -> None:
        super().__init__(f"your jobs keep {kept} bytes (bodies and answers) and this one adds {adding}, past the "
                         f"{cap} bytes one client's jobs may keep (PESHKIN_JOB_MAX_CLIENT_BYTES); delete finished "
                         "jobs (DELETE /v1/jobs/<id>) or wait for them to expire")
        self.kept, self.adding, self.cap = kept, adding, cap


class JobStore:
    """The jobs table in the SQLite file ``path`` (module docstring)."""

    def __init__(self, path: str | os.PathLike[str], max_bytes: int | None = None,
                 max_answer_bytes: int | None = None, max_client_bytes: int | None = None) -> None:
        self.path = Path(path)
        self.max_bytes = max_bytes
        self.max_answer_bytes = max_answer_bytes
        self.max_client_bytes = max_client_bytes
        self.health = StorageHealth("jobs", self.path, "jobs wait, and submissions are refused, until it works")
        self._local = threading.local()

    def _conn(self) -> sqlite3.Connection:
        conn = thread_connection(self._local, self.path, JOBS_SCHEMA, check_same_thread=False,
                                 row_factory=sqlite3.Row, migrate=_add_columns)
        if self.max_bytes is not None and not getattr(self._local, "capped", False):
            page = int(conn.execute("PRAGMA page_size").fetchone()[0])
            conn.execute(f"PRAGMA max_page_count = {max(self.max_bytes // page, 1)}")
            self._local.capped = True
        return conn

    def _guarded(self, work: Callable[[sqlite3.Connection], T]) -> T:
        """``work`` on this thread's connection; a failure of the file becomes a
        :class:`StorageFault` (recorded, then raised), success clears a fault."""
        try:
            out = work(self._conn())
        except (sqlite3.Error, OSError) as exc:
            fault = StorageFault.of(self.path, exc)
            self.health.record(fault)
            if fault.kind != "full":
                self._local = threading.local()  # a connection made again next time
            raise fault from exc
        self.health.record(None)
        return out

    @staticmethod
    @contextlib.contextmanager
    def _transaction(conn: sqlite3.Connection) -> Iterator[None]:
        conn.execute("BEGIN IMMEDIATE")
        try:
            yield
            conn.execute("COMMIT")
        except BaseException:
            if conn.in_transaction:  # a full disk has rolled it back already
                conn.execute("ROLLBACK")
            raise

    def check(self) -> None:
        """Open the file and take its write lock once (at start: a file that is not a
        database, or a read-only place, is reported then). Raises :class:`StorageFault`."""
        def probe(conn: sqlite3.Connection) -> None:
            with self._transaction(conn):
                conn.execute("SELECT COUNT(*) FROM jobs").fetchone()

        self._guarded(probe)

    def submit(self, operation: str, body: dict[str, Any], owner: str) -> str:
        """A new queued job (its id); :class:`OverQuota` past the client's cap."""
        job_id, text = uuid.uuid4().hex, json.dumps(body)

        def insert(conn: sqlite3.Connection) -> None:
            with self._transaction(conn):
                if self.max_client_bytes is not None:
                    kept = int(conn.execute("SELECT COALESCE(SUM(LENGTH(body) + COALESCE(LENGTH(result), 0)), 0) "
                                            "FROM jobs WHERE owner = ?", (owner,)).fetchone()[0])
                    if kept + len(text) > self.max_client_bytes:
                        raise OverQuota(kept, len(text), self.max_client_bytes)
                conn.execute("INSERT INTO jobs (id, owner, operation, body, state, created) VALUES (?, ?, ?, ?, ?, ?)",
                             (job_id, owner, operation, text, "queued", time.time()))

        self._guarded(insert)
        return job_id

    def get(self, job_id: str, owner: str | None = None) -> dict[str, Any] | None:
        """The job (None when unknown, or when ``owner`` is given and is not its owner)."""
        row = self._guarded(lambda conn: conn.execute("SELECT * FROM jobs WHERE id = ?", (job_id,)).fetchone())
        if row is None or (owner is not None and row["owner"] != owner):
            return None
        return dict(row)

    def list(self, owner: str | None, limit: int) -> list[dict[str, Any]]:
        """The jobs of ``owner`` (everyone's: None), newest first, without their answers."""
        columns = "id, owner, operation, state, created, started, finished, expires, attempts, message, status, " \
                  "media_type, ran, predicted, NULL AS result"
        sql = f"SELECT {columns} FROM jobs" + (" WHERE owner = ?" if owner is not None else "") + \
            " ORDER BY created DESC LIMIT ?"
        args: tuple[Any, ...] = (owner, limit) if owner is not None else (limit,)
        return [dict(r) for r in self._guarded(lambda conn: conn.execute(sql, args).fetchall())]

    def cancel(self, job_id: str, ttl_s: float) -> None:
        """A queued job is cancelled at once (and expires ``ttl_s`` later); a running one is
        asked to stop. One transaction: a job requeued meanwhile is not missed."""
        now = time.time()

        def cancel(conn: sqlite3.Connection) -> None:
            with self._transaction(conn):
                conn.execute("UPDATE jobs SET state = 'cancelled', finished = ?, expires = ?, message = 'cancelled "
                             "before it started' WHERE id = ? AND state = 'queued'", (now, now + ttl_s, job_id))
                conn.execute("UPDATE jobs SET cancel = 1 WHERE id = ? AND state = 'running'", (job_id,))

        self._guarded(cancel)

    def remove(self, job_id: str) -> bool:
        """Forget an ended job and its answer (what it kept no longer counts for its client)."""
        placeholders = ",".join("?" * len(FINISHED))
        return bool(self._guarded(lambda conn: conn.execute(
            f"DELETE FROM jobs WHERE id = ? AND state IN ({placeholders})", (job_id, *FINISHED)).rowcount))

    def queued_of(self, owner: str) -> int:
        row = self._guarded(lambda conn: conn.execute(
            "SELECT COUNT(*) AS n FROM jobs WHERE owner = ? AND state = 'queued'", (owner,)).fetchone())
        return int(row["n"])

    def running_for(self, job_id: str, runner: str, predicted_s: float | None) -> None:
        """``runner``'s job has its slot and runs now, predicted to take ``predicted_s``."""
        self._guarded(lambda conn: conn.execute(
            "UPDATE jobs SET ran = ?, predicted = ? WHERE id = ? AND state = 'running' AND runner = ?",
            (time.time(), predicted_s, job_id, runner)))

    def claim(self, runner: str) -> dict[str, Any] | None:
        """The oldest queued job, now running under ``runner`` (None when there is none)."""
        now = time.time()
        row = self._guarded(lambda conn: conn.execute(
            "UPDATE jobs SET state = 'running', runner = ?, started = ?, heartbeat = ?, attempts = attempts + 1, "
            "ran = NULL, predicted = NULL WHERE id = (SELECT id FROM jobs WHERE state = 'queued' ORDER BY created "
            "LIMIT 1) AND state = 'queued' RETURNING *", (runner, now, now)).fetchone())
        return None if row is None else dict(row)

    def beat(self, runner: str, job_ids: list[str]) -> set[str]:
        """Heartbeat of ``runner``'s running jobs (one queued again while its runner was cut
        off from the file, and not claimed by another since, is running again); the ids
        among them whose cancellation was asked, or that are no longer its own (claimed
        elsewhere: it stops them too)."""
        if not job_ids:
            return set()
        marks = ",".join("?" * len(job_ids))

        def beat(conn: sqlite3.Connection) -> set[str]:
            conn.execute(f"UPDATE jobs SET heartbeat = ?, state = 'running' WHERE id IN ({marks}) AND runner = ? "
                         "AND state IN ('running', 'queued')", (time.time(), *job_ids, runner))
            rows = conn.execute(f"SELECT id FROM jobs WHERE id IN ({marks}) AND (cancel = 1 OR state != 'running' OR "
                                "runner IS NOT ?)", (*job_ids, runner)).fetchall()
            return {r["id"] for r in rows}

        return self._guarded(beat)

    def finish(self, runner: str, job_id: str, state: str, ttl_s: float, status: int | None,
               media_type: str | None, body: bytes | None, message: str) -> None:
        """The end of a job that ``runner`` ran: written while the job is still its own,
        running or queued again after its heartbeat went stale (a job claimed by another
        runner since is left alone). An answer over the cap per answer is not kept: the job
        fails, saying so."""
        if body is not None and self.max_answer_bytes is not None and len(body) > self.max_answer_bytes:
            message = (f"its answer ({status}, {len(body)} bytes) is over the {self.max_answer_bytes} bytes a job's "
                       "answer may keep (PESHKIN_JOB_MAX_ANSWER_BYTES) and was not kept: ask for less, or call the "
                       "operation's route")
            state, status, media_type, body = "failed", None, None, None
        now = time.time()
        self._guarded(lambda conn: conn.execute(
            "UPDATE jobs SET state = ?, finished = ?, expires = ?, status = ?, media_type = ?, result = ?, "
            "message = ? WHERE id = ? AND state IN ('running', 'queued') AND runner = ?",
            (state, now, now + ttl_s, status, media_type, body, message, job_id, runner)))

    def recover(self, ttl_s: float) -> int:
        """Queue again the running jobs whose process was lost (stale heartbeat), fail those
        started MAX_ATTEMPTS times; drop the finished jobs past their expiry. How many were
        queued again."""
        now = time.time()

        def recover(conn: sqlite3.Connection) -> int:
            with self._transaction(conn):
                conn.execute("UPDATE jobs SET state = 'failed', finished = ?, expires = ?, message = ? WHERE "
                             "state = 'running' AND heartbeat < ? AND attempts >= ?",
                             (now, now + ttl_s, f"its process was lost {MAX_ATTEMPTS} times", now - STALE_S,
                              MAX_ATTEMPTS))
                # the runner is kept: if it was only cut off from the file, its end still lands (finish)
                again = conn.execute("UPDATE jobs SET state = 'queued', message = 'started again: its process was "
                                     "lost' WHERE state = 'running' AND heartbeat < ?", (now - STALE_S,)).rowcount
                conn.execute("DELETE FROM jobs WHERE expires IS NOT NULL AND expires < ?", (now,))
            return int(again)

        return self._guarded(recover)

    def counts(self) -> dict[str, int]:
        rows = self._guarded(lambda conn: conn.execute("SELECT state, COUNT(*) AS n FROM jobs GROUP BY state")
                             .fetchall())
        return {r["state"]: int(r["n"]) for r in rows}
