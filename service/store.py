"""The service's store of expensive results (the r* rows of spiral localization, 4.5.3):
a local SQLite file, so that a restart, a retry or another worker process does not pay for
them again, and a table cut by a time limit is kept and extended by the next request.

The standard library's ``sqlite3`` (no extra dependency; the access is two statements):
every process and thread opens its own connection on first use (a connection is never
shared), WAL mode so readers never wait for the writer, a busy timeout for concurrent
writers. The file holds ``(namespace, key) -> JSON`` with a schema version; at most
``max_rows`` rows (the least recently written are dropped first). A file that cannot be
opened, read or written is logged once and the service goes on without it: a store is an
optimisation, never a reason to fail a request.
"""

from __future__ import annotations

import json
import logging
import os
import sqlite3
import threading
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

log = logging.getLogger("service")

SCHEMA_VERSION = 1
BUSY_TIMEOUT_S = 5.0
"""How long a writer waits for another process's write to finish."""
DEFAULT_MAX_ROWS = 200_000
"""About 40 MB of r* rows (a table is ~60 rows)."""

RESULTS_SCHEMA = (
    "CREATE TABLE IF NOT EXISTS results (namespace TEXT NOT NULL, key TEXT NOT NULL, "
    "value TEXT NOT NULL, schema INTEGER NOT NULL, PRIMARY KEY (namespace, key))",
)


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
    conn.execute("PRAGMA journal_mode=WAL")
    for statement in schema:
        conn.execute(statement)
    if migrate is not None:
        migrate(conn)
    local.conn, local.pid = conn, os.getpid()
    return conn


class SqliteStore:
    """:class:`solver.ResultStore` on the SQLite file ``path``."""

    def __init__(self, path: str | os.PathLike[str], max_rows: int = DEFAULT_MAX_ROWS) -> None:
        self.path = Path(path)
        self.max_rows = max_rows
        self._local = threading.local()
        self._failed = False

    def _connection(self) -> sqlite3.Connection | None:
        if self._failed:
            return None
        try:
            return thread_connection(self._local, self.path, RESULTS_SCHEMA)
        except (sqlite3.Error, OSError) as exc:
            self._give_up("open", exc)
            return None

    def _give_up(self, what: str, exc: BaseException) -> None:
        if not self._failed:
            log.warning("result store %s: cannot %s it (%s); going on without it", self.path, what, exc)
        self._failed = True

    def get(self, namespace: str, key: str) -> dict[str, Any] | None:
        conn = self._connection()
        if conn is None:
            return None
        try:
            row = conn.execute("SELECT value FROM results WHERE namespace = ? AND key = ? AND schema = ?",
                               (namespace, key, SCHEMA_VERSION)).fetchone()
            value = None if row is None else json.loads(row[0])
        except (sqlite3.Error, ValueError) as exc:
            self._give_up("read", exc)
            return None
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
            self._give_up("write", exc)

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
