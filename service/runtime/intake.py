"""The intake of every HTTP request (a pure ASGI middleware, before the body is read): it
notes when the request arrived (its deadline starts then, service.runtime.deadline),
refuses a body longer than its route's limit (413: at once when ``Content-Length`` says
so, else as soon as the streamed bytes pass it, without reading further; the limits:
service.common.bodies.body_limits), and admits the request
through the web process's gate of requests in flight, or answers 503 with ``Retry-After``
at once. The probes (``/healthz``, ``/readyz``) and the metrics' scrape are never refused. It is also the one
catch-all: an exception nothing else answered becomes a JSON 500 here, sent as a normal
answer, so the connection stays usable (Starlette's own last resort re-raises into the
server, which then drops the connection)."""

from __future__ import annotations

import logging
import time

from starlette.types import ASGIApp, Message, Receive, Scope, Send

from service.errors import BodyTooLarge, busy_response, response_for, too_large_response
from service.runtime.admission import Gate
from service.runtime.deadline import ARRIVAL_KEY

PROBES = frozenset({"/healthz", "/readyz", "/metrics"})
log = logging.getLogger("service")


def _content_length(scope: Scope) -> int | None:
    for name, value in scope.get("headers", ()):
        if name == b"content-length":
            try:
                return int(value)
            except ValueError:
                return None
    return None


class Intake:
    """Stamps the arrival, limits the body to its path's entry of ``body_limits`` (else
    ``default_body_bytes``) and admits through ``gate`` (``retry_after_s`` on a 503)."""

    def __init__(self, app: ASGIApp, gate: Gate, retry_after_s: int, body_limits: dict[str, int],
                 default_body_bytes: int) -> None:
        self.app = app
        self.gate = gate
        self.retry_after_s = retry_after_s
        self.body_limits = body_limits
        self.default_body_bytes = default_body_bytes

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        scope.setdefault("state", {})[ARRIVAL_KEY] = time.monotonic()
        if scope.get("path") in PROBES:
            await self.app(scope, receive, send)
            return
        path = scope.get("path", "")
        limit = self.body_limits.get(path, self.default_body_bytes)
        length = _content_length(scope)
        if length is not None and length > limit:
            await too_large_response(BodyTooLarge(limit, path))(scope, receive, send)
            return
        if not self.gate.try_enter():
            await busy_response(self.gate.name, self.retry_after_s)(scope, receive, send)
            return
        seen = 0

        async def limited_receive() -> Message:
            nonlocal seen
            message = await receive()
            if message["type"] == "http.request":
                seen += len(message.get("body", b""))
                if seen > limit:
                    raise BodyTooLarge(limit, path)  # answered 413 by service.errors
            return message

        started = False

        async def tracked_send(message: Message) -> None:
            nonlocal started
            started = started or message["type"] == "http.response.start"
            await send(message)

        try:
            await self.app(scope, limited_receive, tracked_send)
        except Exception as exc:
            if started:
                log.exception("unexpected error on %s %s", scope.get("method"), scope.get("path"))
                raise  # half an answer is out: the server must close the connection
            await response_for(exc, f"{scope.get('method')} {scope.get('path')}")(scope, receive, send)
        finally:
            self.gate.leave()
