"""Who may call, and how often (a pure ASGI middleware, inside :mod:`service.runtime.context`).

With API keys configured (``PESHKIN_API_KEYS``) every request but the probes and the API's
own documents must carry one, as ``X-API-Key: <key>`` or ``Authorization: Bearer <key>``;
without, or with an unknown key, the answer is 401. A key is never logged: requests are
known by the key's id, the first 12 hex digits of its SHA-256 (``client`` in the access log,
and the owner of what the key's requests leave behind).

With a rate (``PESHKIN_RATE_LIMIT``, ``<requests>/<seconds>``) each key may make that many
requests in any window of that many seconds, counted over every web process of the server:
pyrate-limiter's sliding-window log in a SQLite file of the server's own (beside its solver
slots), a file lock serialising the processes' updates. Past the rate the answer is 429 with
``Retry-After`` (whole seconds until the oldest request of the window leaves it).

Operator keys (``PESHKIN_OPERATOR_KEYS``) are for the people who run the server: on a
deployment with keys, ``/metrics`` (every key's routes and jobs) answers only to an operator
key (401 without a known key, 403 to an API key), and ``/readyz`` shows its admission
counters and files only to one (``scope["state"]["operator"]``); anyone gets its status. An
operator key is an API key too. A deployment without keys is open to all.
"""

from __future__ import annotations

import hashlib
import hmac
import logging
import math
import os
import shutil
import tempfile
import threading

import anyio
from pyrate_limiter import Rate, RateItem, SQLiteBucket
from starlette.types import ASGIApp, Receive, Scope, Send

from service.errors import forbidden_response, rate_limited_response, unauthorized_response

PUBLIC_PATHS = frozenset({"/healthz", "/readyz", "/docs", "/redoc", "/openapi.json", "/docs/oauth2-redirect"})
"""Paths open without a key: the probes and the API's documents (they hold no data)."""

PUBLIC_PREFIXES = ("/static-offline-docs/",)
"""The documents' own scripts and styles (fastapi-offline)."""

log = logging.getLogger("service")

RATE_FILE = "rate-limits.sqlite3"

LEAK_EVERY = 256
"""Requests of a key between two removals of its entries that have left the window."""


def key_id(key: str) -> str:
    """The name a key is known by in logs and stores (never the key itself)."""
    return hashlib.sha256(key.encode()).hexdigest()[:12]


class ApiKeys:
    """The configured keys, compared in constant time through their SHA-256 digests."""

    def __init__(self, keys: tuple[str, ...]) -> None:
        self._digests = [(hashlib.sha256(k.encode()).digest(), key_id(k)) for k in keys]

    def __bool__(self) -> bool:
        return bool(self._digests)

    def identify(self, presented: str) -> str | None:
        """The id of the key ``presented``, or None when it is not one of them."""
        digest = hashlib.sha256(presented.encode()).digest()
        found = None
        for known, ident in self._digests:  # every digest compared: no early exit to time
            if hmac.compare_digest(digest, known):
                found = ident
        return found


def presented_key(scope: Scope) -> str | None:
    """The key a request carries (``X-API-Key``, else a bearer token), or None."""
    bearer = None
    for name, value in scope.get("headers", ()):
        if name == b"x-api-key":
            return value.decode("latin-1").strip()
        if name == b"authorization":
            scheme, _, token = value.decode("latin-1").strip().partition(" ")
            if scheme.lower() == "bearer" and token.strip():
                bearer = token.strip()
    return bearer


class KeyRates:
    """At most ``count`` requests per key in any ``seconds`` window, shared through the
    SQLite file in ``directory`` (the server's slot directory) by every process that opens
    it; without one, in a directory of its own, removed by :meth:`close` (module
    docstring)."""

    def __init__(self, count: int, seconds: float, directory: str | None) -> None:
        self.rate = Rate(count, max(1, round(1000 * seconds)))
        self._own = None if directory else tempfile.mkdtemp(prefix="peshkin-rates-")
        self.path = os.path.join(directory or self._own or "", RATE_FILE)
        self._buckets: dict[str, SQLiteBucket] = {}
        self._puts: dict[str, int] = {}
        self._lock = threading.Lock()  # one thread of this process at a time; the file lock for the others

    def _bucket(self, ident: str) -> SQLiteBucket:
        bucket = self._buckets.get(ident)
        if bucket is None:
            bucket = SQLiteBucket.init_from_file([self.rate], table=f"key_{ident}", db_path=self.path,
                                                 use_file_lock=True)
            self._buckets[ident] = bucket
        return bucket

    def admit(self, ident: str) -> float | None:
        """None when key ``ident`` may make a request now (it is counted), else the
        seconds until it may."""
        with self._lock:
            return self._admit(ident)

    def _admit(self, ident: str) -> float | None:
        bucket = self._bucket(ident)
        now = bucket.now()
        decision = bucket.put_decision(RateItem(ident, now))
        self._puts[ident] = self._puts.get(ident, 0) + 1
        if decision.failing_rate is None:
            if self._puts[ident] % LEAK_EVERY == 0:
                bucket.leak(now)
            return None
        bucket.leak(now)
        wait_ms = decision.retry_after_ms if decision.retry_after_ms is not None else self.rate.interval
        return max(wait_ms, 1) / 1000.0

    def close(self) -> None:
        for bucket in self._buckets.values():
            bucket.close()
        self._buckets.clear()
        if self._own:
            shutil.rmtree(self._own, ignore_errors=True)


def is_public(path: str) -> bool:
    return path in PUBLIC_PATHS or path.startswith(PUBLIC_PREFIXES)


OPERATOR_PATHS = frozenset({"/metrics"})
"""Paths only an operator key may read on a deployment with keys."""


class Access:
    """401 without a known key, 403 to a non-operator on an operator's path, 429 past the
    key's rate (module docstring); the key's id goes to ``scope["state"]["client"]``, and
    whether it is an operator's to ``scope["state"]["operator"]``."""

    def __init__(self, app: ASGIApp, keys: ApiKeys, rates: KeyRates | None, operators: ApiKeys | None = None) -> None:
        self.app = app
        self.keys = keys
        self.operators = operators if operators is not None else ApiKeys(())
        self.rates = rates

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        path = scope.get("path", "")
        presented = presented_key(scope)
        operator = None if presented is None else self.operators.identify(presented)
        state = scope.setdefault("state", {})
        state["operator"] = operator is not None or not (self.keys or self.operators)
        if path in OPERATOR_PATHS and (self.keys or self.operators):
            if operator is None:
                known = presented is not None and self.keys.identify(presented) is not None
                await (forbidden_response() if known else unauthorized_response(presented is not None))(
                    scope, receive, send)
                return
            state["client"] = operator
            await self.app(scope, receive, send)
            return
        if not self.keys or is_public(path):
            await self.app(scope, receive, send)
            return
        ident = operator if operator is not None else (None if presented is None else self.keys.identify(presented))
        if ident is None:
            await unauthorized_response(presented is not None)(scope, receive, send)
            return
        state["client"] = ident
        if self.rates is not None:
            try:
                wait_s = await anyio.to_thread.run_sync(self.rates.admit, ident)
            except Exception:  # a broken counts file must not refuse every request: counted as admitted
                log.exception("the rate limit could not be read; the request goes on")
                wait_s = None
            if wait_s is not None:
                await rate_limited_response(math.ceil(wait_s), self.rates.rate.limit,
                                            self.rates.rate.interval / 1000.0)(scope, receive, send)
                return
        await self.app(scope, receive, send)
