"""Error handling: every input problem is an HTTP 422 in FastAPI's validation-error shape,
a time limit that runs out is an HTTP 504 saying what was reached, and nothing is a 500.

    {"detail": [{"loc": ["body", "<field>"], "msg": "<reason>", "type": "<type>"}]}

* a body that cannot be decoded at all (FastAPI's HTTP 400 "error parsing the body",
  e.g. bytes that are not UTF-8): ``loc`` ["body"], type ``json_invalid``, like a JSON
  syntax error;
* request validation (pydantic): FastAPI's own errors, with non-finite numbers in the
  echoed ``input``/``ctx`` turned into strings so the body stays valid JSON;
* ``models.core.errors.InvalidInput(field, reason)``: ``loc`` ["body", field], type
  ``value_error``;
* :class:`FieldError` (an ``InvalidInput`` located inside a nested field, e.g. the
  weights of the third support of a batch): ``loc`` ["body", *path], type ``value_error``;
* ``solver.core.errors.TimeLimitReached`` (the request's budget ran out before the answer
  was complete): HTTP **504**, :class:`service.common.responses.TimeLimitResponse`:
  ``loc`` ["body", "time_limit_s"], type ``time_limit``, the place reached (``reached``)
  and, when a route converted it (:func:`time_limited`), the partial result;
* any other ``solver.core.errors.SolverError`` (an optimisation back end failed or ended
  with an unusable status): ``loc`` ["body"], type ``solver_error``;
* any other ``models.core.errors.ModelError`` (e.g. a boundary solve that missed its
  tolerance): ``loc`` ["body"], type ``model_error``;
* :class:`NonFiniteResult`, or an answer's part refusing a number that is not finite
  (:class:`service.common.responses.Out`, pydantic's ``finite_number``): the input is
  valid but so extreme that a result overflowed; ``loc`` ["body"], type ``numeric_range``.
  Python's own ``ArithmeticError`` (a float division by zero or an overflow deep in a
  computation on such inputs) is answered the same way, and logged with its traceback.

Anything else is a bug: HTTP 500 with a short JSON body (type ``internal_error``); the
traceback goes to the ``service`` log only, never to the client. The routes must never
let it happen.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from typing import Any

from fastapi import FastAPI, Request
from fastapi.exception_handlers import http_exception_handler
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from pydantic import ValidationError
from starlette.exceptions import HTTPException as StarletteHTTPException

from models.core.errors import InvalidInput, ModelError
from service.limits import ECHO_MAX_CHARS, ECHO_MAX_DEPTH, ECHO_MAX_ERRORS, ECHO_MAX_ITEMS
from service.settings import Settings
from solver import SolverError, TimeLimitReached

log = logging.getLogger("service")

UNPROCESSABLE = 422
GATEWAY_TIMEOUT = 504


class NonFiniteResult(Exception):
    """A computed quantity is NaN or infinite (inputs at the edge of float range)."""

    def __init__(self, what: str) -> None:
        super().__init__(what)
        self.what = what


class FieldError(Exception):
    """An input problem at a nested place of the request: ``loc`` is the path below
    ``where`` ("body" or "query"), e.g. ("supports", 2, "weights"); ``reason`` what is wrong."""

    def __init__(self, loc: tuple[str | int, ...], reason: str, where: str = "body", kind: str = "value_error") -> None:
        super().__init__(f"{'.'.join(map(str, loc))}: {reason}")
        self.loc = tuple(loc)
        self.reason = reason
        self.where = where
        self.kind = kind


class BodyTooLarge(Exception):
    """The request's body is longer than the service reads (HTTP 413)."""

    def __init__(self, limit_bytes: int, path: str = "") -> None:
        where = f" for {path}" if path else ""
        super().__init__(f"the body is longer than {limit_bytes} bytes, the most this service reads{where}")
        self.limit_bytes = limit_bytes


PAYLOAD_TOO_LARGE = 413


def too_large_response(exc: BodyTooLarge) -> JSONResponse:
    """The 413 of a body over the limit (the rest of it is not read: the connection closes)."""
    return JSONResponse(status_code=PAYLOAD_TOO_LARGE, content=error_body(["body"], str(exc), "body_too_large"),
                        headers={"connection": "close"})


async def _body_too_large(request: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, BodyTooLarge)
    return too_large_response(exc)


class TimeLimitAnswer(Exception):
    """A :class:`TimeLimitReached` with what the route made of its partial result
    (``partial``: a JSON-able dict, or None) and a hint on how to ask for less (``hint``)."""

    def __init__(self, reached: TimeLimitReached, partial: dict[str, Any] | None, hint: str) -> None:
        super().__init__(str(reached))
        self.reached = reached
        self.partial = partial
        self.hint = hint


DEFAULT_TIME_LIMIT_HINT = "ask for less work"


def limit_advice(limit_s: float | None) -> str:
    """What to do for the whole answer besides asking for less: a longer time limit while
    the deployment's cap allows one, else a job (POST /v1/jobs, up to the jobs' cap)."""
    settings = Settings.from_env()
    cap, jobs = settings.max_time_limit_s, settings.job_max_time_s
    if limit_s is None or limit_s < cap:
        return f"raise time_limit_s (up to {cap:g} s on this deployment), or submit it as a job (POST /v1/jobs, " \
               f"up to {jobs:g} s)"
    return f"{cap:g} s is this deployment's cap: submit it as a job (POST /v1/jobs, up to {jobs:g} s)"


@contextmanager
def time_limited(
    convert: Callable[[Any], dict[str, Any] | None] | None = None, hint: str = DEFAULT_TIME_LIMIT_HINT,
) -> Iterator[None]:
    """Around a solver call: a :class:`TimeLimitReached` is answered 504 with ``convert``
    of its partial result (when it carries one) and ``hint`` in the message."""
    try:
        yield
    except TimeLimitReached as exc:
        partial = None if (convert is None or exc.partial is None) else convert(exc.partial)
        raise TimeLimitAnswer(exc, partial, hint) from exc


def nothing_computed(before: str, limit_s: float | None, elapsed_s: float,
                     partial: dict[str, Any] | None = None) -> TimeLimitAnswer:
    """The 504 of an answer its time limit cut before any of what was asked was computed
    (``before``: what was about to start): such an answer is not a success (issue 25).
    ``partial``: what there is besides (e.g. the analytic locus of a certified one)."""
    return TimeLimitAnswer(TimeLimitReached(before, limit_s, elapsed_s, partial), partial, DEFAULT_TIME_LIMIT_HINT)


def error_body(loc: list[str | int], msg: str, type_: str) -> dict[str, Any]:
    return {"detail": [{"loc": loc, "msg": msg, "type": type_}]}


def json_safe(value: Any) -> Any:
    """Replace non-finite floats (which JSON cannot carry) by their names, recursively."""
    if isinstance(value, float):
        return value if math.isfinite(value) else repr(value)  # 'nan', 'inf', '-inf'
    if isinstance(value, dict):
        return {str(k): json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_safe(v) for v in value]
    if value is None or isinstance(value, (str, int, bool)):
        return value
    return str(value)


def echo(value: Any, depth: int = 0) -> Any:
    """What a 422 says back of the client's own input: scalars as they are (non-finite
    floats by name, strings cut at ECHO_MAX_CHARS), small arrays and objects down to
    ECHO_MAX_DEPTH levels, anything larger by its size only ("a list of 5000000 items").
    Bounded in size and in recursion whatever the client sent."""
    if isinstance(value, float):
        return value if math.isfinite(value) else repr(value)
    if value is None or isinstance(value, (bool, int)):
        return value
    if isinstance(value, str):
        return value if len(value) <= ECHO_MAX_CHARS else value[:ECHO_MAX_CHARS] + f"... ({len(value)} characters)"
    if isinstance(value, dict):
        if depth >= ECHO_MAX_DEPTH or len(value) > ECHO_MAX_ITEMS:
            return f"an object of {len(value)} fields"
        return {str(k)[:ECHO_MAX_CHARS]: echo(v, depth + 1) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        if depth >= ECHO_MAX_DEPTH or len(value) > ECHO_MAX_ITEMS:
            return f"a list of {len(value)} items"
        return [echo(v, depth + 1) for v in value]
    return echo(str(value), depth)


def validation_error_body(errors: Sequence[Any]) -> dict[str, Any]:
    """The 422 body of request-validation ``errors`` (pydantic's, located): at most
    ECHO_MAX_ERRORS of them, what they echo of the input bounded (:func:`echo`)."""
    items = []
    for err in errors[:ECHO_MAX_ERRORS]:
        items.append({k: (echo(v) if k in ("input", "ctx") else json_safe(v))
                      for k, v in err.items() if k in ("loc", "msg", "type", "input", "ctx")})
    return {"detail": items}


async def _request_validation(request: Request, exc: RequestValidationError) -> JSONResponse:
    return JSONResponse(status_code=UNPROCESSABLE, content=validation_error_body(exc.errors()))


async def _http_exception(request: Request, exc: StarletteHTTPException):
    if isinstance(exc.__cause__, BodyTooLarge):  # FastAPI wraps what stopped the body's read
        return await _body_too_large(request, exc.__cause__)
    if exc.status_code == 400:  # FastAPI could not read the body (e.g. not UTF-8)
        return JSONResponse(
            status_code=UNPROCESSABLE,
            content=error_body(["body"], f"the body is not valid JSON: {exc.detail}", "json_invalid"),
        )
    return await http_exception_handler(request, exc)


def _invalid_input(exc: InvalidInput, where: str) -> JSONResponse:
    return JSONResponse(
        status_code=UNPROCESSABLE,
        content=error_body(["body", exc.field], exc.reason, "value_error"),
    )


def _field_error(exc: FieldError, where: str) -> JSONResponse:
    return JSONResponse(
        status_code=UNPROCESSABLE,
        content=error_body([exc.where, *exc.loc], exc.reason, exc.kind),
    )


def _solver_error(exc: SolverError, where: str) -> JSONResponse:
    log.warning("solver error on %s: %s", where, exc)
    return JSONResponse(
        status_code=UNPROCESSABLE,
        content=error_body(
            ["body"],
            f"the optimisation failed: {exc}. Try another method, or a smaller or better "
            "conditioned problem",
            "solver_error",
        ),
    )


def time_limit_body(exc: TimeLimitReached, partial: dict[str, Any] | None, hint: str) -> dict[str, Any]:
    """The 504 body (:class:`service.common.responses.TimeLimitResponse`)."""
    limit = "no time limit" if exc.limit_s is None else f"time_limit_s = {exc.limit_s:g} s"
    msg = f"ran out after {exc.elapsed_s:.3g} s ({limit}) before {exc.where}: {hint}; or {limit_advice(exc.limit_s)}"
    body = error_body(["body", "time_limit_s"], msg, "time_limit")
    body.update(reached=exc.where, time_limit_s=exc.limit_s, elapsed_s=exc.elapsed_s, partial=json_safe(partial))
    return body


def _time_limit(exc: TimeLimitReached, where: str) -> JSONResponse:
    log.info("time limit on %s: %s", where, exc)
    return JSONResponse(status_code=GATEWAY_TIMEOUT, content=time_limit_body(exc, None, DEFAULT_TIME_LIMIT_HINT))


def _time_limit_answer(exc: TimeLimitAnswer, where: str) -> JSONResponse:
    log.info("time limit on %s: %s", where, exc)
    return JSONResponse(status_code=GATEWAY_TIMEOUT, content=time_limit_body(exc.reached, exc.partial, exc.hint))


def _model_error(exc: ModelError, where: str) -> JSONResponse:
    log.warning("model error on %s: %s", where, exc)
    return JSONResponse(
        status_code=UNPROCESSABLE,
        content=error_body(["body"], f"{type(exc).__name__}: {exc}", "model_error"),
    )


def _non_finite(exc: NonFiniteResult, where: str) -> JSONResponse:
    return JSONResponse(
        status_code=UNPROCESSABLE,
        content=error_body(
            ["body"],
            f"the result is out of floating-point range ({exc.what} is not finite); "
            "use less extreme sizes (e.g. a disk radius closer to the scene's size)",
            "numeric_range",
        ),
    )


def _answer_not_built(exc: ValidationError, where: str) -> JSONResponse:
    """An answer's part refused a value (service.common.responses.Out): a number that is not
    finite is a result out of floating-point range; anything else is a bug."""
    errors = exc.errors(include_url=False, include_context=False, include_input=False)
    if errors and all(e["type"] == "finite_number" for e in errors):
        first = ".".join(str(part) for part in errors[0]["loc"])
        return _non_finite(NonFiniteResult(f"{exc.title}.{first}"), where)
    return _unexpected(exc, where)


def _arithmetic(exc: ArithmeticError, where: str) -> JSONResponse:
    log.warning("arithmetic error on %s", where, exc_info=exc)
    return _non_finite(NonFiniteResult(f"a computation ({type(exc).__name__})"), where)


def _unexpected(exc: Exception, where: str) -> JSONResponse:
    log.error("unexpected error on %s", where, exc_info=exc)
    return JSONResponse(
        status_code=500,
        content=error_body([], f"internal error ({type(exc).__name__}); this is a bug", "internal_error"),
    )


_ANSWERS: tuple[tuple[type[Exception], Callable[[Any, str], JSONResponse]], ...] = (
    (TimeLimitAnswer, _time_limit_answer),
    (TimeLimitReached, _time_limit),
    (FieldError, _field_error),
    (InvalidInput, _invalid_input),
    (SolverError, _solver_error),
    (ModelError, _model_error),
    (NonFiniteResult, _non_finite),
    (ValidationError, _answer_not_built),
    (ArithmeticError, _arithmetic),
)
"""The answer to each error a computation may raise, most specific first."""


BUSY = 503


def busy_response(gate: str, retry_after_s: int, reason: str = "") -> JSONResponse:
    """The 503 of a request refused by an admission gate (service.runtime): nothing was
    computed. ``reason``: why, when more is known than a full gate."""
    why = f" ({reason})" if reason else ""
    return JSONResponse(
        status_code=BUSY,
        content=error_body([], f"the service is busy with {gate} work{why}; retry after {retry_after_s} s", "busy"),
        headers={"Retry-After": str(retry_after_s)},
    )


UNAUTHORIZED = 401
TOO_MANY_REQUESTS = 429


def unauthorized_response(key_given: bool) -> JSONResponse:
    """The 401 of a request without a known API key (service.runtime.access)."""
    msg = ("the API key is not known" if key_given else
           "an API key is needed: send it as X-API-Key: <key> or Authorization: Bearer <key>")
    return JSONResponse(status_code=UNAUTHORIZED, content=error_body(["header", "x-api-key"], msg, "unauthorized"),
                        headers={"WWW-Authenticate": 'Bearer realm="peshkin"'})


FORBIDDEN = 403


def forbidden_response() -> JSONResponse:
    """The 403 of an API key on a path for operators only (service.runtime.access)."""
    return JSONResponse(status_code=FORBIDDEN, content=error_body(
        ["header", "x-api-key"], "this path is for the server's operators: it needs an operator key "
        "(PESHKIN_OPERATOR_KEYS)", "forbidden"))


def rate_limited_response(retry_after_s: int, count: int, seconds: float) -> JSONResponse:
    """The 429 of a key past its rate (service.runtime.access): nothing was computed."""
    return JSONResponse(
        status_code=TOO_MANY_REQUESTS,
        content=error_body([], f"this API key's rate of {count} requests per {seconds:g} s is used up; retry after "
                               f"{retry_after_s} s", "rate_limited"),
        headers={"Retry-After": str(retry_after_s)},
    )


def response_for(exc: Exception, where: str) -> JSONResponse:
    """The HTTP answer to ``exc`` raised while computing the answer to ``where`` ("POST
    /v1/..."): the same in the web process and in a solver worker (service.runtime)."""
    for kind, answer in _ANSWERS:
        if isinstance(exc, kind):
            return answer(exc, where)
    return _unexpected(exc, where)


async def _computation_error(request: Request, exc: Exception) -> JSONResponse:
    return response_for(exc, f"{request.method} {request.url.path}")


def install(app: FastAPI) -> None:
    """Register the handlers on ``app``."""
    app.add_exception_handler(StarletteHTTPException, _http_exception)
    app.add_exception_handler(BodyTooLarge, _body_too_large)
    app.add_exception_handler(RequestValidationError, _request_validation)
    # anything else is answered by the intake's catch-all (service.runtime.intake), which
    # sends response_for's 500 as a normal answer
    for kind, _ in _ANSWERS:
        app.add_exception_handler(kind, _computation_error)
