"""Error bodies and the documented ``responses`` of the routes.

Every input problem is HTTP 422 (:class:`ErrorResponse`, FastAPI's validation-error
shape); a time limit that runs out before the answer is complete is HTTP 504
(:class:`TimeLimitResponse`: the same ``detail`` plus where it got to and what it had
finished). :mod:`service.errors` builds both.
"""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ConfigDict, Field

SVG_MEDIA_TYPE = "image/svg+xml"


class Out(BaseModel):
    """The base of every part of every answer, where its rules are declared once: unknown
    fields are refused, and every number is finite. A NaN or an infinity that an extreme
    input made of a result is refused when the answer is built (pydantic's
    ``finite_number``) and answered 422 ``numeric_range`` naming the quantity
    (:func:`service.errors.response_for`): converters copy values, they do not check them.
    ``tests/service/test_responses.py`` checks that every answer's parts are ``Out``."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)


class ErrorItem(BaseModel):
    """One problem with the request, in FastAPI's validation-error shape."""

    loc: list[str | int] = Field(
        description='Where the problem is, e.g. ["body", "disk_radius"] or ["query", "format"].'
    )
    msg: str = Field(description="What is wrong and, where possible, how to fix it.")
    type: str = Field(
        description="Kind of error: pydantic's error types for schema violations, 'value_error' for "
        "inputs the mechanics reject, 'model_error' / 'numeric_range' for computations that fail."
    )
    input: Any = Field(default=None, description="The offending input, when known (schema violations).")
    ctx: dict[str, Any] | None = Field(default=None, description="Extra context of a schema violation.")


ELAPSED_MS_DESCRIPTION = ("Milliseconds from the request's arrival until its answer was assembled (any wait for a "
                          "solver worker included).")

REQUEST_ID_FIELD = ("The request's id (its X-Request-ID header, given or made): quote it when reporting a "
                    "problem; the service's log carries it.")


class ErrorResponse(BaseModel):
    detail: list[ErrorItem] = Field(description="What was wrong, one item per problem.")
    request_id: str | None = Field(default=None, description=REQUEST_ID_FIELD)


class TimeLimitResponse(BaseModel):
    """The time limit ran out before the answer was complete (HTTP 504)."""

    detail: list[ErrorItem] = Field(
        description='One item: loc ["body", "time_limit_s"], type "time_limit", msg: where the time ran out '
        "and how to ask for less."
    )
    reached: str = Field(description="What was about to start when the time ran out.")
    time_limit_s: float | None = Field(description="The time limit, seconds.")
    elapsed_s: float = Field(description="Seconds spent when it ran out.")
    partial: dict[str, Any] | None = Field(
        description="What was completed before, in the shape of the answer's own parts (e.g. POST "
        "/v1/push/align: {\"stages\": [...]}, the stages done); null when nothing was."
    )
    request_id: str | None = Field(default=None, description=REQUEST_ID_FIELD)


INVALID_INPUT = {422: {"model": ErrorResponse, "description": "Invalid input: the body names the field and the reason."}}
"""The ``responses`` entry of every route."""

TIME_LIMIT = {
    504: {
        "model": TimeLimitResponse,
        "description": "The time limit ran out before the answer was complete: where it got to, and what it "
        "had finished.",
    },
}
"""The ``responses`` entry of the routes whose computation may stop at its time limit."""

BUSY = {
    503: {
        "model": ErrorResponse,
        "description": "The service is busy: the request's admission gate is full (type \"busy\"). Nothing was "
        "computed; retry after the `Retry-After` header's seconds.",
        "headers": {"Retry-After": {"description": "Seconds to wait before retrying.", "schema": {"type": "integer"}}},
    },
}
"""The ``responses`` entry of every route behind an admission gate (service.runtime)."""

IN_WORKER = {**INVALID_INPUT, **TIME_LIMIT, **BUSY}
"""The ``responses`` entry of a route whose job runs in a solver worker under its deadline."""


def json_or_svg(description: str) -> dict:
    """The 200 entry of a route that answers JSON or, with ``format=svg``, a picture."""
    return {200: {"description": description, "content": {SVG_MEDIA_TYPE: {"schema": {"type": "string"}}}}}
