"""The intake of every HTTP request (a pure ASGI middleware, before the body is read): it
notes when the request arrived (its deadline starts then, service.runtime.deadline) and
admits it through the web process's gate of requests in flight, or answers 503 with
``Retry-After`` at once. The probes (``/healthz``, ``/readyz``) are never refused."""

from __future__ import annotations

import json
import time

from starlette.types import ASGIApp, Receive, Scope, Send

from service.errors import error_body
from service.runtime.admission import Gate, Refused
from service.runtime.deadline import ARRIVAL_KEY

PROBES = frozenset({"/healthz", "/readyz"})


def busy_response_parts(exc: Refused) -> tuple[bytes, list[tuple[bytes, bytes]]]:
    """The body and headers of the 503 of a full gate."""
    body = json.dumps(error_body([], str(exc), "busy")).encode()
    headers = [(b"content-type", b"application/json"), (b"content-length", str(len(body)).encode()),
               (b"retry-after", str(exc.retry_after_s).encode())]
    return body, headers


class Intake:
    """Stamps the arrival and admits through ``gate`` (``retry_after_s`` on a 503)."""

    def __init__(self, app: ASGIApp, gate: Gate, retry_after_s: int) -> None:
        self.app = app
        self.gate = gate
        self.retry_after_s = retry_after_s

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        scope.setdefault("state", {})[ARRIVAL_KEY] = time.monotonic()
        if scope.get("path") in PROBES:
            await self.app(scope, receive, send)
            return
        if not self.gate.try_enter():
            body, headers = busy_response_parts(Refused(self.gate.name, self.retry_after_s))
            await send({"type": "http.response.start", "status": 503, "headers": headers})
            await send({"type": "http.response.body", "body": body})
            return
        try:
            await self.app(scope, receive, send)
        finally:
            self.gate.leave()
