"""Every request's id, its line in the access log and its metrics (a pure ASGI middleware,
the outermost one).

* The id is the client's ``X-Request-ID`` when it is a sane token (1-128 characters of
  letters, digits and ``-_.:@/+=``), else a new one (32 hex digits); it is sent back in
  the ``X-Request-ID`` header, put in the body of every error answer (``request_id``,
  beside ``detail``) and carried by every log record of the request
  (:data:`service.runtime.logs.REQUEST_ID`).
* When the answer is complete: ``peshkin_http_requests_total`` and
  ``peshkin_http_request_duration_seconds`` (:mod:`service.runtime.metrics`), this web
  process's queue gauges, and one record in the access log (route template, method,
  status, duration, the model that answered, the API key's id, the request id).
"""

from __future__ import annotations

import json
import logging
import re
import time
import uuid

from starlette.types import ASGIApp, Message, Receive, Scope, Send

from service.runtime.admission import Gate, RunQueue
from service.runtime.logs import ACCESS, REQUEST_ID
from service.runtime.metrics import observe_request, observe_work

HEADER = b"x-request-id"
TOKEN = re.compile(r"[A-Za-z0-9\-_.:@/+=]{1,128}")
"""What a client's request id may be (anything else is replaced by a new id)."""

UNKNOWN_ROUTE = "other"
"""The route label of a path the service does not have (keeps the metrics' labels few)."""

access_log = logging.getLogger(ACCESS)


def request_id_of(scope: Scope) -> str:
    """The client's sane ``X-Request-ID``, else a new id."""
    for name, value in scope.get("headers", ()):
        if name == HEADER:
            text = value.decode("latin-1").strip()
            if TOKEN.fullmatch(text):
                return text
            break
    return uuid.uuid4().hex


def with_request_id(body: bytes, request_id: str) -> bytes:
    """A JSON error body with ``request_id`` added (other bodies as they are)."""
    try:
        doc = json.loads(body)
    except ValueError:
        return body
    if not isinstance(doc, dict):
        return body
    doc["request_id"] = request_id
    return json.dumps(doc, separators=(",", ":"), allow_nan=False).encode()


class RequestContext:
    """The request id, the access log and the request metrics (module docstring);
    ``expensive``: the web process's expensive work (its queue gauges); ``access_log``:
    whether to write the access log."""

    def __init__(self, app: ASGIApp, expensive: Gate | RunQueue, log_requests: bool = True) -> None:
        self.app = app
        self.expensive = expensive
        self.log_requests = log_requests

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        t0 = time.perf_counter()
        rid = request_id_of(scope)
        token = REQUEST_ID.set(rid)
        state = scope.setdefault("state", {})
        state["request_id"] = rid
        status = 500
        held: Message | None = None  # an error's start, held until its body is rewritten
        chunks: list[bytes] = []

        async def send_with_id(message: Message) -> None:
            nonlocal status, held
            if message["type"] == "http.response.start":
                status = int(message["status"])
                headers = [(k, v) for k, v in message.get("headers", []) if k != HEADER] + [(HEADER, rid.encode())]
                message = {**message, "headers": headers}
                if status >= 400 and (b"content-type", b"application/json") in headers:
                    held = message
                    return
            elif message["type"] == "http.response.body" and held is not None:
                chunks.append(message.get("body", b""))
                if message.get("more_body", False):
                    return
                body = with_request_id(b"".join(chunks), rid)
                headers = [(k, v) for k, v in held["headers"] if k != b"content-length"]
                await send({**held, "headers": [*headers, (b"content-length", str(len(body)).encode())]})
                held = None
                message = {"type": "http.response.body", "body": body}
            await send(message)

        try:
            await self.app(scope, receive, send_with_id)
        finally:
            REQUEST_ID.reset(token)
            self._record(scope, status, time.perf_counter() - t0, rid)

    def _record(self, scope: Scope, status: int, seconds: float, rid: str) -> None:
        route = scope.get("route")
        template = getattr(route, "path", None) or UNKNOWN_ROUTE
        method = scope.get("method", "")
        observe_request(template, method, status, seconds)
        observe_work(self.expensive)
        if self.log_requests:
            state = scope.get("state", {})
            access_log.info(
                "%s %s %d %.1f ms", method, scope.get("path", ""), status, 1e3 * seconds,
                extra={"request_id": rid, "method": method, "route": template, "status": status,
                       "duration_ms": round(1e3 * seconds, 3), "model": state.get("model"),
                       "client": state.get("client")},
            )
