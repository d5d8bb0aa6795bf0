"""The service's store of expensive results (the r* rows of spiral localization, 4.5.3):
a local SQLite file, so that a restart, a retry or another worker process does not pay for
them again, and a table cut by a time limit is kept and extended by the next request.

The standard library's ``sqlite3`` (no extra dependency; the access is two statements):
every process and thread opens its own connection on first use (a connection is never
shared), WAL mode so readers never wait for the writer, a busy timeout for concurrent
writers. The file holds ``(namespace, key) -> JSON`` with a schema version; at most
``max_rows`` rows (the least recently written are dropped first). A file that cannot be
opened, read or written is logged once and the service goes on without it (a store is an
optimisation, never a reason to fail a request), trying it again later unless it is not a
database; the readiness probe says its state (:class:`StorageHealth`, shared with the jobs
file, service.runtime.jobstore).
"""

from __future__ import annotations

import errno
import json
import logging
import os
import sqlite3
import threading
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

log = logging.getLogger("service")

SCHEMA_VERSION = 1
BUSY_TIMEOUT_S = 5.0
"""How long a writer waits for another process's write to finish."""
WAL_RETRY_S = 0.01
"""The pause between tries of switching a file to WAL: SQLite answers "database is locked"
at once, without its busy timeout, to a connection that switches while another does (two
processes opening a new file together: about one opening in four lost its store)."""
_BUSY = {"SQLITE_BUSY", "SQLITE_BUSY_RECOVERY", "SQLITE_BUSY_SNAPSHOT", "SQLITE_LOCKED", "SQLITE_LOCKED_SHAREDCACHE"}
DEFAULT_MAX_ROWS = 200_000
"""About 40 MB of r* rows (a table is ~60 rows)."""

RESULTS_SCHEMA = (
    "CREATE TABLE IF NOT EXISTS results (namespace TEXT NOT NULL, key TEXT NOT NULL, "
    "value TEXT NOT NULL, schema INTEGER NOT NULL, PRIMARY KEY (namespace, key))",
)


FAULT_KINDS = ("full", "read_only", "broken", "unavailable")
"""What can be wrong with a file of the service: its disk (or its own size cap) is full;
it or its directory is read-only; it is not a SQLite database (or is corrupt); anything
else (its directory is missing, the file is locked too long, an I/O error)."""

_FULL = {"SQLITE_FULL"}
_READ_ONLY = {"SQLITE_READONLY", "SQLITE_READONLY_DBMOVED", "SQLITE_READONLY_DIRECTORY", "SQLITE_PERM", "SQLITE_AUTH"}
_BROKEN = {"SQLITE_NOTADB", "SQLITE_CORRUPT"}


class StorageFault(Exception):
    """A SQLite file of the service cannot be used now: ``kind`` (one of FAULT_KINDS),
    its ``path`` and the ``reason`` in words (the library's own message)."""

    def __init__(self, path: Path, kind: str, reason: str) -> None:
        super().__init__(f"{path}: {reason}")
        self.path, self.kind, self.reason = path, kind, reason

    @property
    def words(self) -> str:
        return {"full": "full", "read_only": "read-only", "broken": "not a usable database",
                "unavailable": "unavailable"}[self.kind]

    @classmethod
    def of(cls, path: Path, exc: BaseException) -> StorageFault:
        """The fault ``exc`` (a ``sqlite3.Error`` or an ``OSError``) says the file has."""
        name = str(getattr(exc, "sqlite_errorname", "") or "")
        errno_ = getattr(exc, "errno", None)
        text = str(exc) or type(exc).__name__
        if name in _FULL or errno_ in (errno.ENOSPC, errno.EDQUOT, errno.EFBIG) or "disk is full" in text:
            kind = "full"
        elif name in _READ_ONLY or errno_ in (errno.EROFS, errno.EACCES, errno.EPERM) or "readonly" in text:
            kind = "read_only"
        elif name in _BROKEN or "not a database" in text or "malformed" in text:
            kind = "broken"
        else:
            kind = "unavailable"
        return cls(path, kind, text)


class StorageHealth:
    """The state of one file of the service (``what`` it holds, at ``path``; what the service
    does ``meanwhile``, for the log): None while it works, else its last
    :class:`StorageFault`. Logged once per change (a fault, another fault, usable again),
    never once per failed attempt."""

    def __init__(self, what: str, path: Path, meanwhile: str) -> None:
        self.what, self.path, self.meanwhile = what, path, meanwhile
        self.fault: StorageFault | None = None
        self._lock = threading.Lock()

    def record(self, fault: StorageFault | None) -> None:
        with self._lock:
            old, self.fault = self.fault, fault
        if fault is not None and (old is None or (old.kind, old.reason) != (fault.kind, fault.reason)):
            log.warning("the %s file %s cannot be used (%s): %s; %s", self.what, self.path, fault.kind, fault.reason,
                        self.meanwhile)
        elif fault is None and old is not None:
            log.warning("the %s file %s is usable again", self.what, self.path)

    def state(self) -> dict[str, str]:
        """For the readiness probe: ``{"name", "path", "state" ("ok" or the fault's kind), "reason"}``."""
        fault = self.fault
        return {"name": self.what, "path": str(self.path), "state": "ok" if fault is None else fault.kind,
                "reason": "" if fault is None else fault.reason}


def thread_connection(local: threading.local, path: Path, schema: Sequence[str], check_same_thread: bool = True,
                      row_factory: Any = None,
                      migrate: Callable[[sqlite3.Connection], None] | None = None) -> sqlite3.Connection:
    """This thread's connection (kept in ``local``) to the SQLite file ``path`` in WAL mode,
    made on its first use in this process (a forked child makes its own) with ``schema``
    (``CREATE ... IF NOT EXISTS`` statements) applied, then ``migrate``. Errors are the
    caller's."""
    conn: sqlite3.Connection | None = getattr(local, "conn", None)
    if conn is not None and getattr(local, "pid", None) == os.getpid():
        return conn
    path.parent.mkdir(parents=True, exist_ok=True)
    conn = sqlite3.connect(path, timeout=BUSY_TIMEOUT_S, isolation_level=None, check_same_thread=check_same_thread)
    conn.row_factory = row_factory
    _to_wal(conn)
    for statement in schema:
        conn.execute(statement)
    if migrate is not None:
        migrate(conn)
    local.conn, local.pid = conn, os.getpid()
    return conn


def _to_wal(conn: sqlite3.Connection) -> None:
    """Switch the file to WAL, trying again while another connection holds it (for at most
    the busy timeout; see WAL_RETRY_S)."""
    give_up = time.monotonic() + BUSY_TIMEOUT_S
    while True:
        try:
            conn.execute("PRAGMA journal_mode=WAL")
            return
        except sqlite3.OperationalError as exc:
            if getattr(exc, "sqlite_errorname", "") not in _BUSY or time.monotonic() > give_up:
                raise
        time.sleep(WAL_RETRY_S)


RETRY_S = 30.0
"""How long a store that failed (its disk full, say) is left alone before it is tried again;
a file that is not a database is not tried again."""


class SqliteStore:
    """:class:`solver.ResultStore` on the SQLite file ``path``: a store is an optimisation, so
    a file that fails is logged once (:class:`StorageHealth`) and the service goes on
    without it; it is tried again :data:`RETRY_S` later, unless it is not a database."""

    def __init__(self, path: str | os.PathLike[str], max_rows: int = DEFAULT_MAX_ROWS) -> None:
        self.path = Path(path)
        self.max_rows = max_rows
        self._local = threading.local()
        self.health = StorageHealth("result store", self.path, "the service goes on without it")
        self._retry_at = 0.0

    def _connection(self) -> sqlite3.Connection | None:
        fault = self.health.fault
        if fault is not None and (fault.kind == "broken" or time.monotonic() < self._retry_at):
            return None
        try:
            return thread_connection(self._local, self.path, RESULTS_SCHEMA)
        except (sqlite3.Error, OSError) as exc:
            self._failed(exc)
            return None

    def _failed(self, exc: BaseException) -> None:
        self.health.record(StorageFault.of(self.path, exc))
        self._retry_at = time.monotonic() + RETRY_S
        self._local = threading.local()  # connections made again when it is tried again

    def check(self) -> None:
        """Open the file and read and write it once (at start: a garbage file is reported
        then, not at its first use)."""
        conn = self._connection()
        if conn is None:
            return
        try:
            conn.execute("BEGIN IMMEDIATE")
            conn.execute("SELECT COUNT(*) FROM results").fetchone()
            conn.execute("ROLLBACK")
        except (sqlite3.Error, OSError) as exc:
            self._failed(exc)
            return
        self.health.record(None)

    def get(self, namespace: str, key: str) -> dict[str, Any] | None:
        conn = self._connection()
        if conn is None:
            return None
        try:
            row = conn.execute("SELECT value FROM results WHERE namespace = ? AND key = ? AND schema = ?",
                               (namespace, key, SCHEMA_VERSION)).fetchone()
            value = None if row is None else json.loads(row[0])
        except sqlite3.Error as exc:
            self._failed(exc)
            return None
        except ValueError:  # a row that is not JSON: as if it were not kept
            return None
        self.health.record(None)
        return value if isinstance(value, dict) else None

    def put(self, namespace: str, key: str, value: dict[str, Any]) -> None:
        conn = self._connection()
        if conn is None:
            return
        try:
            text = json.dumps(value, allow_nan=False)
        except ValueError:  # a non-finite number: not kept
            return
        try:
            conn.execute("INSERT OR REPLACE INTO results (namespace, key, value, schema) VALUES (?, ?, ?, ?)",
                         (namespace, key, text, SCHEMA_VERSION))
            conn.execute("DELETE FROM results WHERE rowid <= (SELECT MAX(rowid) FROM results) - ?", (self.max_rows,))
        except sqlite3.Error as exc:
            self._failed(exc)
            return
        self.health.record(None)

    def count(self) -> int:
        conn = self._connection()
        if conn is None:
            return 0
        return int(conn.execute("SELECT COUNT(*) FROM results").fetchone()[0])


_PROCESS_STORE: dict[str, SqliteStore | None] = {}
_PROCESS_STORE_LOCK = threading.Lock()


def result_store() -> SqliteStore | None:
    """This process's store at PESHKIN_STORE_PATH ("" for none), made on first use."""
    from service.settings import Settings

    path = Settings.from_env().store_path
    with _PROCESS_STORE_LOCK:
        if path not in _PROCESS_STORE:
            _PROCESS_STORE[path] = SqliteStore(path) if path else None
        return _PROCESS_STORE[path]
