"""Request bodies: read once, refused at the first unknown field, and large ones never
decoded on the event loop.

Every route of :mod:`service.api` is a :class:`BodyRoute` (FastAPI's documented way to
customise how a route reads its request). Its body, JSON or (where the operation declares
it, :mod:`service.common.binary`) msgpack, is decoded by :func:`decode_object`: the
top-level object is walked key by key, each value decoded by the standard library's JSON
decoder or msgpack's unpacker, and a key the request model does not know is refused (422
``extra_forbidden``) *before its value is read*, so a body padded with an unknown field
costs nothing to refuse however large. FastAPI then validates the decoded object as usual
(every other error is pydantic's, at its field).

Decoding holds the interpreter's lock whatever thread does it (the JSON scanner and
msgpack are C code that never releases it), so a large body is never decoded in a web
process: a body over ``inline_bytes`` goes only to an operation that runs in a solver worker
and declared that it takes large bodies (:func:`large_bodies`); its route hands the raw
bytes on (:class:`RawBody`) and the worker decodes and validates them
(:func:`validated_in_worker`). The intake (:mod:`service.runtime.intake`) refuses, 413, a
body over the limit of its route (:func:`body_limits`), before it is read.
"""

from __future__ import annotations

import functools
import json
import re
from collections.abc import Awaitable, Callable, Coroutine
from dataclasses import dataclass
from typing import Any

import msgpack
from fastapi import Request
from fastapi.responses import JSONResponse, Response
from fastapi.routing import APIRoute
from pydantic import BaseModel, ValidationError

from service.common.binary import MSGPACK, MSGPACK_TYPES, media_type
from service.errors import UNPROCESSABLE, error_body, validation_error_body
from service.limits import MAX_COLUMN_POINTS

MAX_MAP_ITEMS = 256
"""Keys of one msgpack map (a request object has a few dozen fields at most)."""
REASON_CHARS = 200
"""Characters of a decoder's own message quoted in a 422."""

_SPACE = re.compile(r"[ \t\n\r]*")
_DECODER = json.JSONDecoder()


def _skip(text: str, i: int) -> int:
    """The index of the first character at or after ``i`` that is not JSON white space."""
    found = _SPACE.match(text, i)
    return i if found is None else found.end()


class BodyInvalid(Exception):
    """A body that cannot be read as the request object: answered 422 with ``item`` (one
    error in FastAPI's shape)."""

    def __init__(self, item: dict[str, Any]) -> None:
        super().__init__(item["msg"])
        self.item = item

    def response(self) -> JSONResponse:
        return JSONResponse({"detail": [self.item]}, status_code=UNPROCESSABLE)


def field_names(model: type[BaseModel]) -> frozenset[str]:
    """The top-level keys a body of ``model`` may have: each field's alias, and its name
    too when the model takes names."""
    by_name = bool(model.model_config.get("populate_by_name") or model.model_config.get("validate_by_name"))
    names: set[str] = set()
    for name, info in model.model_fields.items():
        names.add(info.alias or name)
        if by_name or not info.alias:
            names.add(name)
    return frozenset(names)


def _unknown(key: str) -> BodyInvalid:
    return BodyInvalid({"loc": ["body", key[:REASON_CHARS]], "msg": "Extra inputs are not permitted (the field is "
                        "not part of this request; its value was not read)", "type": "extra_forbidden"})


def _json_invalid(exc: json.JSONDecodeError) -> BodyInvalid:
    """FastAPI's own answer to a JSON syntax error."""
    return BodyInvalid({"loc": ["body", exc.pos], "msg": "JSON decode error", "type": "json_invalid",
                        "ctx": {"error": exc.msg}})


def _json_object(text: str, fields: frozenset[str] | None) -> Any:
    """The JSON document ``text``; when it is an object and ``fields`` is given, walked key
    by key, a key not in ``fields`` refused before its value is decoded. The same document
    and the same errors as ``json.loads`` otherwise (the last of repeated keys wins)."""
    i = _skip(text, 0)
    if fields is None or text[i:i + 1] != "{":
        return json.loads(text)
    out: dict[str, Any] = {}
    i = _skip(text, i + 1)
    if text[i:i + 1] == "}":
        i += 1
    else:
        while True:
            if text[i:i + 1] != '"':
                raise json.JSONDecodeError("Expecting property name enclosed in double quotes", text, i)
            key, i = json.decoder.scanstring(text, i + 1)  # type: ignore[attr-defined]
            i = _skip(text, i)
            if text[i:i + 1] != ":":
                raise json.JSONDecodeError("Expecting ':' delimiter", text, i)
            if key not in fields:
                raise _unknown(key)
            i = _skip(text, i + 1)
            out[key], i = _DECODER.raw_decode(text, i)
            i = _skip(text, i)
            if text[i:i + 1] == ",":
                i = _skip(text, i + 1)
                continue
            if text[i:i + 1] != "}":
                raise json.JSONDecodeError("Expecting ',' delimiter", text, i)
            i += 1
            break
    if _skip(text, i) != len(text):
        raise json.JSONDecodeError("Extra data", text, _skip(text, i))
    return out


def _no_extension(code: int, data: bytes) -> Any:
    raise ValueError(f"extension type {code} is not a JSON value")


def _msgpack_invalid(exc: Exception) -> BodyInvalid:
    detail = f": {str(exc)[:REASON_CHARS]}" if str(exc) else ""
    return BodyInvalid({"loc": ["body"], "msg": f"is not a msgpack document of JSON values ({type(exc).__name__}"
                        f"{detail})", "type": "msgpack_invalid"})


def _msgpack_object(raw: bytes, fields: frozenset[str] | None, max_items: int) -> Any:
    """The msgpack document ``raw``; a map walked key by key like :func:`_json_object`.
    Arrays longer than ``max_items`` and extension types are refused while decoding."""
    limits = {"raw": False, "ext_hook": _no_extension, "max_array_len": max_items, "max_map_len": MAX_MAP_ITEMS,
              "max_buffer_size": max(len(raw), 1)}
    try:
        unpacker = msgpack.Unpacker(**limits)
        unpacker.feed(raw)
        try:
            n = unpacker.read_map_header() if fields is not None else None
        except msgpack.UnpackValueError:  # not a map: the document as it is
            n = None
        if n is None:
            return msgpack.unpackb(raw, **{k: v for k, v in limits.items() if k != "max_buffer_size"})
        out: dict[str, Any] = {}
        for _ in range(n):
            key = unpacker.unpack()
            if not isinstance(key, str):
                raise ValueError(f"an object's keys must be strings, got {type(key).__name__}")
            if fields is not None and key not in fields:
                raise _unknown(key)
            out[key] = unpacker.unpack()
        if unpacker.tell() != len(raw):
            raise msgpack.ExtraData(out, raw[unpacker.tell():])
        return out
    except BodyInvalid:
        raise
    except Exception as exc:  # any undecodable body is the client's error
        raise _msgpack_invalid(exc) from None


def decode_object(raw: bytes, media: str, fields: frozenset[str] | None, max_items: int) -> Any:
    """The document of body ``raw`` of media type ``media`` (JSON unless msgpack), an
    object's unknown keys refused before their values are read (:class:`BodyInvalid`)."""
    if media in MSGPACK_TYPES:
        return _msgpack_object(raw, fields, max_items)
    try:
        text = raw.decode(json.detect_encoding(raw), "surrogatepass")
    except UnicodeDecodeError as exc:
        raise BodyInvalid(error_body(["body"], f"the body is not valid JSON: {exc.reason}", "json_invalid")
                          ["detail"][0]) from None
    try:
        return _json_object(text, fields)
    except json.JSONDecodeError as exc:
        raise _json_invalid(exc) from None
    except RecursionError:
        raise BodyInvalid(error_body(["body"], "the body is nested too deeply", "json_invalid")["detail"][0]) from None


@dataclass(frozen=True)
class RawBody:
    """A body too large to decode in a web process: its bytes and media type, decoded
    where the job runs (:func:`validated_in_worker`)."""

    data: bytes
    media: str


def validated_in_worker(job: Callable[..., Any], model: type[BaseModel], body: RawBody, *rest: Any) -> Any:
    """``job(request, *rest)`` of the request ``model`` decoded and validated from ``body``
    (in a solver worker); an invalid body answered 422 as FastAPI would have."""
    try:
        req = model.model_validate(decode_object(body.data, body.media, field_names(model), MAX_COLUMN_POINTS))
    except BodyInvalid as exc:
        return exc.response()
    except ValidationError as exc:
        errors = [{**e, "loc": ("body", *e["loc"])} for e in exc.errors(include_url=False)]
        return JSONResponse(validation_error_body(errors), status_code=UNPROCESSABLE)
    return job(req, *rest)


def in_worker(job: Callable[..., Any], model: type[BaseModel]) -> Callable[..., Any]:
    """``job`` taking a :class:`RawBody` instead of its request (picklable, for a worker)."""
    return functools.partial(validated_in_worker, job, model)


BodyReader = Callable[[], Awaitable[RawBody]]
"""Reads a request's body when awaited (a large one is read only if its handler needs it)."""
LargeHandler = Callable[[Request, BodyReader], Awaitable[Response]]
LARGE_BODY_ATTRIBUTE = "large_body_handler"


def large_bodies(handler: LargeHandler) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """Decorate a route's endpoint (below its ``@router.post``): its bodies may be as long
    as the service reads, and one over the inline limit is answered by ``handler`` with a
    reader of the raw bytes (it may refuse before reading them, and must hand them to a
    solver worker, :func:`in_worker`)."""

    def mark(endpoint: Callable[..., Any]) -> Callable[..., Any]:
        setattr(endpoint, LARGE_BODY_ATTRIBUTE, handler)
        return endpoint

    return mark


def is_json(media: str) -> bool:
    """Whether FastAPI reads a body of ``media`` as JSON."""
    return media == "application/json" or (media.startswith("application/") and media.endswith("+json"))


class DecodedRequest(Request):
    """The request with its body already decoded (``document``): FastAPI reads it as JSON."""

    def __init__(self, request: Request, raw: bytes, document: Any) -> None:
        scope = dict(request.scope)
        scope["headers"] = [(k, v) for k, v in request.scope["headers"] if k != b"content-type"]
        scope["headers"].append((b"content-type", b"application/json"))
        super().__init__(scope, request.receive)
        self.raw, self.document = raw, document

    async def body(self) -> bytes:
        return self.raw

    async def json(self) -> Any:
        return self.document


INLINE_STATE = "inline_body_bytes"
"""The app's state attribute holding the longest body decoded in a web process (its
settings' ``inline_body_bytes``; :data:`DEFAULT_INLINE_BYTES` when the app sets none)."""
DEFAULT_INLINE_BYTES = 2 * 1024 * 1024


def _declared_length(request: Request) -> int | None:
    try:
        return int(request.headers["content-length"])
    except (KeyError, ValueError):
        return None


class BodyRoute(APIRoute):
    """A route whose body is read by :func:`decode_object` (module docstring); large bodies
    of an operation marked by :func:`large_bodies` go to its handler undecoded."""

    def get_route_handler(self) -> Callable[[Request], Coroutine[Any, Any, Response]]:
        handler = super().get_route_handler()
        model = self.body_field.field_info.annotation if self.body_field is not None else None
        if not (isinstance(model, type) and issubclass(model, BaseModel)):
            return handler
        fields = field_names(model)
        takes_msgpack = MSGPACK in ((self.openapi_extra or {}).get("requestBody", {}).get("content", {}))
        large: LargeHandler | None = getattr(self.endpoint, LARGE_BODY_ATTRIBUTE, None)

        async def decoded(request: Request) -> Response:
            media = media_type(request.headers.get("content-type", ""))
            if not (is_json(media) or (media in MSGPACK_TYPES and takes_msgpack)):
                return await handler(request)  # not a body it reads: FastAPI's own 422
            inline = getattr(request.app.state, INLINE_STATE, DEFAULT_INLINE_BYTES)
            declared = _declared_length(request)
            if large is not None and declared is not None and declared > inline:

                async def read() -> RawBody:
                    return RawBody(await request.body(), media)

                return await large(request, read)
            raw = await request.body()
            if not raw:
                return await handler(request)
            if large is not None and len(raw) > inline:  # a long body sent without its length

                async def read_already() -> RawBody:
                    return RawBody(raw, media)

                return await large(request, read_already)
            try:
                document = decode_object(raw, media, fields, MAX_COLUMN_POINTS)
            except BodyInvalid as exc:
                return exc.response()
            return await handler(DecodedRequest(request, raw, document))

        return decoded


def body_limits(routers: list[Any], inline_bytes: int, max_bytes: int) -> dict[str, int]:
    """The longest body of each path of ``routers``: ``max_bytes`` where an operation takes
    large bodies (:func:`large_bodies`), ``inline_bytes`` elsewhere."""
    limits: dict[str, int] = {}
    for router in routers:
        for route in router.routes:
            large = getattr(getattr(route, "endpoint", None), LARGE_BODY_ATTRIBUTE, None) is not None
            path = getattr(route, "path", "")
            limits[path] = max(limits.get(path, 0), max_bytes if large else min(inline_bytes, max_bytes))
    return limits

