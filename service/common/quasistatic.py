"""The push's speed and the table of a request: is it slow enough for the quasi-static
results to hold (book 6.8)? Shared by the gross motions (``/v1/push/align``,
``/v1/push/disk-encounter``) and the scenes (``/v1/scenes/analyze``)."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import ConfigDict, Field

from models.push import quasistatic as qs
from models.push.quasistatic import GRAVITY_M_S2, METRES_PER_UNIT
from service.common.fields import Strict, exactly_one_of
from service.errors import FieldError
from service.limits import QS_MAX_GRAVITY, QS_MAX_MU_S, QS_MAX_SPEED, QS_MIN_GRAVITY, QS_MIN_MU_S
from solver import QuasiStaticQuery

LengthUnit = Literal["m", "cm", "mm", "um", "in", "ft"]
assert set(LengthUnit.__args__) == set(METRES_PER_UNIT), "LengthUnit must list models.push.quasistatic.METRES_PER_UNIT"  # type: ignore[attr-defined]

Gravity = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=QS_MIN_GRAVITY, le=QS_MAX_GRAVITY)]


class QuasiStaticIn(Strict):
    """The push speed and the table's friction: is the gross motion slow enough for the
    quasi-static bounds to hold (book 6.8; as POST /v1/push/quasistatic)? Give gravity as
    `g` or `length_unit` (exactly one)."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={
            **exactly_one_of(("g", "length_unit")),
        },
    )

    speed: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0.0, le=QS_MAX_SPEED)] = Field(
        description=f"Speed of the pusher, length unit per second, [0, {QS_MAX_SPEED:g}]."
    )
    mu_s: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=QS_MIN_MU_S, le=QS_MAX_MU_S)] = Field(
        description=f"Friction coefficient between part and table, [{QS_MIN_MU_S:g}, {QS_MAX_MU_S:g}]."
    )
    g: Gravity | None = Field(default=None, description="Gravity in the request's length unit per s^2.")
    length_unit: LengthUnit | None = Field(
        default=None, description=f"The request's length unit; g = {GRAVITY_M_S2:g} m/s^2 converted to it."
    )


def quasi_static_query(qin: QuasiStaticIn | None, loc: tuple = ("quasi_static",)) -> QuasiStaticQuery | None:
    """The quasi-static check of a request (None when no speed was given); errors at ``loc``."""
    if qin is None:
        return None
    given = [name for name in ("g", "length_unit") if getattr(qin, name) is not None]
    if len(given) != 1:
        where = "g" if not given else given[1]
        raise FieldError((*loc, where), "give exactly one of g or length_unit")
    g = qin.g if given[0] == "g" else qs.gravity(qin.length_unit)
    return QuasiStaticQuery(qin.speed, qin.mu_s, g)
