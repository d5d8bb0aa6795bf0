"""msgpack bodies of the batch routes: the same documents as JSON, in a binary encoding.

A request whose ``Content-Type`` is ``application/msgpack`` is decoded by
:class:`MsgpackBodies` (a pure ASGI middleware, inside the intake's body limit) and handed
on as the JSON document it encodes, so validation, limits and error locations are those of
JSON. An answer is msgpack when the client's ``Accept`` prefers it (:func:`wants_msgpack`);
the worker then encodes the answer itself (:func:`in_msgpack`). Errors are always JSON.
Only the operations that declare the encoding in their OpenAPI entry (:func:`msgpack_openapi`)
take it: their paths are given to the middleware by the app.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import msgpack
import pydantic_core
from fastapi import Request
from fastapi.responses import JSONResponse, Response
from pydantic import BaseModel
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from service.errors import UNPROCESSABLE, error_body

MSGPACK = "application/msgpack"
MSGPACK_TYPES = frozenset({MSGPACK, "application/x-msgpack"})
"""Media types read as msgpack (the registered one and the older ``x-`` name)."""

MAX_MAP_ITEMS = 256
"""Keys of one msgpack map (a request object has a few dozen fields at most)."""
REASON_CHARS = 200
"""Characters of the decoder's own message quoted in a 422."""


def msgpack_openapi(schema: str, response: str) -> dict[str, Any]:
    """The OpenAPI entries of an operation that takes and answers msgpack too: its request
    body and its 200 under ``application/msgpack`` with the JSON schemas ``schema`` and
    ``response``."""
    return {
        "requestBody": {"content": {MSGPACK: {"schema": {"$ref": f"#/components/schemas/{schema}"}}}},
        "responses": {"200": {"content": {MSGPACK: {"schema": {"$ref": f"#/components/schemas/{response}"}}}}},
    }


def msgpack_paths(routers: list[Any]) -> frozenset[str]:
    """The paths of the operations of ``routers`` that declared msgpack bodies."""
    return frozenset(
        route.path for router in routers for route in router.routes
        if MSGPACK in ((getattr(route, "openapi_extra", None) or {}).get("requestBody", {}).get("content", {}))
    )


def _media_type(value: str) -> str:
    return value.split(";", 1)[0].strip().lower()


def wants_msgpack(request: Request) -> bool:
    """Whether the ``Accept`` header prefers msgpack to JSON (by quality, then order)."""
    best: tuple[float, int, bool] | None = None
    for order, part in enumerate(request.headers.get("accept", "").split(",")):
        media, *params = [p.strip() for p in part.split(";")]
        media = media.lower()
        q = 1.0
        for param in params:
            if param.replace(" ", "").startswith("q="):
                try:
                    q = float(param.split("=", 1)[1])
                except ValueError:
                    q = 0.0
        if q <= 0.0 or media not in (*MSGPACK_TYPES, "application/json", "application/*", "*/*"):
            continue
        rank = (q, -order, media in MSGPACK_TYPES)
        if best is None or rank[:2] > best[:2]:
            best = rank
    return best is not None and best[2]


def in_msgpack(job: Callable[..., Any], *args: Any) -> Any:
    """Run ``job(*args)`` (in a worker) and answer its model as msgpack; an error answer as
    it is."""
    answer = job(*args)
    if not isinstance(answer, BaseModel):
        return answer
    body = msgpack.packb(answer.model_dump(by_alias=True), use_bin_type=True)
    return Response(content=body, media_type=MSGPACK)


class MsgpackBodies:
    """Hands a msgpack request body on to ``paths`` as JSON (module docstring); anything
    else passes untouched. An array longer than ``max_items`` (the longest the schemas
    allow) is refused while decoding, before it becomes Python objects."""

    def __init__(self, app: ASGIApp, paths: frozenset[str], max_items: int) -> None:
        self.app = app
        self.paths = paths
        self.max_items = max_items

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http" or scope.get("path") not in self.paths or not self._is_msgpack(scope):
            await self.app(scope, receive, send)
            return
        chunks = []
        while True:
            message = await receive()
            if message["type"] != "http.request":  # the client went away: the app learns it
                await self.app(scope, _replay([message], receive), send)
                return
            chunks.append(message.get("body", b""))
            if not message.get("more_body", False):
                break
        try:
            body = pydantic_core.to_json(msgpack.unpackb(b"".join(chunks), raw=False, ext_hook=_no_extension,
                                                         max_array_len=self.max_items, max_map_len=MAX_MAP_ITEMS))
        except Exception as exc:  # any undecodable body is the client's error
            detail = f": {str(exc)[:REASON_CHARS]}" if str(exc) else ""
            reason = f"is not a msgpack document of JSON values ({type(exc).__name__}{detail})"
            await JSONResponse(error_body(["body"], reason, "msgpack_invalid"), status_code=UNPROCESSABLE)(
                scope, receive, send)
            return
        headers = [(k, v) for k, v in scope["headers"] if k not in (b"content-type", b"content-length")]
        headers += [(b"content-type", b"application/json"), (b"content-length", str(len(body)).encode())]
        scope["headers"] = headers  # in place: what the router notes in the scope (the route) reaches the log
        await self.app(scope, _replay([{"type": "http.request", "body": body}], receive), send)

    @staticmethod
    def _is_msgpack(scope: Scope) -> bool:
        for name, value in scope.get("headers", ()):
            if name == b"content-type":
                return _media_type(value.decode("latin-1")) in MSGPACK_TYPES
        return False


def _no_extension(code: int, data: bytes) -> Any:
    raise ValueError(f"extension type {code} is not a JSON value")


def _replay(messages: list[Message], then: Receive) -> Receive:
    """A receive that gives ``messages``, then the server's own (which waits for a disconnect)."""
    pending = list(messages)

    async def receive() -> Message:
        if pending:
            return pending.pop(0)
        return await then()

    return receive
