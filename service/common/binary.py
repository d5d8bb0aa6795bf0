"""msgpack bodies of the batch routes: the same documents as JSON, in a binary encoding.

A request whose ``Content-Type`` is ``application/msgpack`` is decoded like a JSON one
(:mod:`service.common.bodies`) into the document it encodes, so validation, limits and
error locations are those of JSON. An answer is msgpack when the client's ``Accept``
prefers it (:func:`wants_msgpack`); the worker then encodes the answer itself
(:func:`in_msgpack`). Errors are always JSON. Only the operations that declare the encoding
in their OpenAPI entry (:func:`msgpack_openapi`) take it.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import msgpack
from fastapi import Request
from fastapi.responses import Response
from pydantic import BaseModel

MSGPACK = "application/msgpack"
MSGPACK_TYPES = frozenset({MSGPACK, "application/x-msgpack"})
"""Media types read as msgpack (the registered one and the older ``x-`` name)."""



def msgpack_openapi(schema: str, response: str) -> dict[str, Any]:
    """The OpenAPI entries of an operation that takes and answers msgpack too: its request
    body and its 200 under ``application/msgpack`` with the JSON schemas ``schema`` and
    ``response``."""
    return {
        "requestBody": {"content": {MSGPACK: {"schema": {"$ref": f"#/components/schemas/{schema}"}}}},
        "responses": {"200": {"content": {MSGPACK: {"schema": {"$ref": f"#/components/schemas/{response}"}}}}},
    }


def media_type(value: str) -> str:
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
