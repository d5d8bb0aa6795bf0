"""Request and response schemas of ``POST /v1/push/quasistatic`` (book 6.8).

Is a push slow enough for the quasi-static results (chapters 3-4) to hold? Lengths are in
the client's unit L, times in seconds, speeds in L/s, g in L/s^2 (or named by
``length_unit``), angles in radians. Conventions as in :mod:`service.schemas`: strict
finite numbers, unknown fields rejected, null counts as absent.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field

from models.quasistatic import BOOK_TRANSLATIONAL_ERROR_REL, GRAVITY_M_S2, METRES_PER_UNIT
from service.limits import (
    MAX_DISK_RADIUS,
    QS_MAX_ANGULAR_ERROR,
    QS_MAX_GRAVITY,
    QS_MAX_MU_S,
    QS_MAX_SPEED,
    QS_MIN_GRAVITY,
    QS_MIN_LENGTH,
    QS_MIN_MU_S,
)
from service.schemas import Polygon

LengthUnit = Literal["m", "cm", "mm", "um", "in", "ft"]
assert set(LengthUnit.__args__) == set(METRES_PER_UNIT), "LengthUnit must list models.quasistatic.METRES_PER_UNIT"  # type: ignore[attr-defined]

Gravity = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=QS_MIN_GRAVITY, le=QS_MAX_GRAVITY)]
Length = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=QS_MIN_LENGTH, le=MAX_DISK_RADIUS)]

DEFAULT_ANGULAR_ERROR = math.radians(5.0)


class PushQuasistaticRequest(BaseModel):
    """A push at `speed` of a part on a table with friction `mu_s`: its characteristic
    speeds (6.8.1-6.8.3) and whether the quasi-static assumption holds. Give the part as
    `disk_radius` or `footprint`, and gravity as `g` or `length_unit` (exactly one of each)."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={
            "allOf": [
                {"oneOf": [
                    {"required": ["disk_radius"], "properties": {"disk_radius": {"type": "number"}}},
                    {"required": ["footprint"], "properties": {"footprint": {"type": "array"}}},
                ]},
                {"oneOf": [
                    {"required": ["g"], "properties": {"g": {"type": "number"}}},
                    {"required": ["length_unit"], "properties": {"length_unit": {"type": "string"}}},
                ]},
            ],
            "examples": [
                {"speed": 10.0, "mu_s": 0.25, "length_unit": "cm", "disk_radius": 3.5},
            ],
        },
    )

    speed: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0.0, le=QS_MAX_SPEED)] = Field(
        description=f"Relative speed v of pusher and part, length unit per second, [0, {QS_MAX_SPEED:g}]."
    )
    mu_s: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=QS_MIN_MU_S, le=QS_MAX_MU_S)] = Field(
        description=f"Coefficient of sliding friction between part and table, [{QS_MIN_MU_S:g}, {QS_MAX_MU_S:g}]."
    )
    g: Gravity | None = Field(
        default=None,
        description=f"Gravitational acceleration in the request's length unit per s^2, "
        f"[{QS_MIN_GRAVITY:g}, {QS_MAX_GRAVITY:g}] (981 for cm). Give this or `length_unit`.",
    )
    length_unit: LengthUnit | None = Field(
        default=None,
        description=f"The unit of every length and speed of the request; g = {GRAVITY_M_S2:g} m/s^2 "
        "converted to it. Give this or `g`.",
    )
    disk_radius: Length | None = Field(
        default=None,
        description=f"The part as a uniform disk of radius a, [{QS_MIN_LENGTH:g}, {MAX_DISK_RADIUS:g}] "
        "(the book's case). Give this or `footprint`.",
    )
    footprint: Polygon | None = Field(
        default=None,
        description="The part's outline, a simple polygon (either orientation): a uniform lamina "
        "whose CM is the area centroid; a = the largest CM-vertex distance. Give this or `disk_radius`.",
    )
    angular_error: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0.0, le=QS_MAX_ANGULAR_ERROR)] = Field(
        default=DEFAULT_ANGULAR_ERROR,
        description="Permissible angular error theta, radians, (0, 2 pi]. Default 5 degrees, the "
        "book's example (6.8.1).",
    )
    translational_error: Length | None = Field(
        default=None,
        description="Permissible displacement error X (length). Default a / 7, the book's example "
        f"(X = 0.5 cm for a = 3.5 cm, 6.8.2; {BOOK_TRANSLATIONAL_ERROR_REL:.6g} a).",
    )


class _Out(BaseModel):
    model_config = ConfigDict(extra="forbid")


class PartOut(_Out):
    kind: Literal["disk", "polygon"]
    radius: float = Field(description="a: the disk's radius or the polygon's circumradius about the CM (length).")
    radius_of_gyration: float = Field(description="rho, polar, about the CM (length): a / sqrt 2 for the disk.")
    mean_distance: float = Field(
        description="rbar = mean |x - CM| over the part (length): 2a/3 for the disk. The friction "
        "torque of a spin about the CM under uniform pressure is mu_s M g rbar."
    )
    spin_factor: float = Field(
        description="2 rbar a / rho^2 (>= 2): v_theta^2 = spin_factor mu_s g a theta; 8/3 for the disk (6.3)."
    )
    center_of_mass: list[float] | None = Field(description="The polygon's CM (area centroid); null for the disk.")


class ErrorSpeedOut(_Out):
    """A characteristic speed for a permissible error, and the push measured against it."""

    characteristic_speed: float = Field(description="The speed at which the part coasts exactly the permissible error (L/s).")
    ratio: float = Field(description="speed / characteristic_speed.")
    permissible_error: float = Field(description="theta (rad) or X (length).")
    error_at_speed: float = Field(
        description="What the part coasts after release at `speed`, same unit: permissible_error x ratio^2."
    )
    within_tolerance: bool = Field(description="ratio <= 1: the coasting stays within the permissible error.")
    equation: str = Field(description="The book's equation.")
    section: str = Field(description="The book's section.")
    formula: str


class QuasiStaticParameterOut(_Out):
    characteristic_speed: float = Field(description="v_qs = sqrt(2 mu_s a g) (6.7), L/s.")
    ratio: float = Field(
        description="speed / v_qs, the quasi-static parameter. After release the part coasts "
        "ratio^2 a and turns at most ratio^2 rad."
    )
    equation: str
    section: str
    formula: str


class ThresholdsOut(_Out):
    quasi_static_max_ratio: float = Field(description="ratio at or below which the verdict is quasi_static.")
    inertial_min_ratio: float = Field(description="ratio at or above which the verdict is inertial.")


class PushQuasistaticResponse(_Out):
    verdict: Literal["quasi_static", "transitional", "inertial"] = Field(
        description="On the quasi-static parameter: quasi_static (ratio <= 0.3: coasting <= 9 % of a and "
        "<= 0.09 rad), transitional, or inertial (ratio >= 1: inertia as large as friction, 6.8.3; "
        "the impact limit of 7.4 is the better model as it grows)."
    )
    message: str
    speed: float
    mu_s: float
    g: float = Field(description="g used, length unit / s^2.")
    g_source: Literal["g", "length_unit"] = Field(description="Whether g was given or derived from `length_unit`.")
    length_unit: LengthUnit | None
    part: PartOut
    angular: ErrorSpeedOut = Field(description="6.8.1, (6.3): the angular-error speed.")
    translational: ErrorSpeedOut = Field(description="6.8.2, (6.6): the translational-error speed.")
    quasi_static: QuasiStaticParameterOut = Field(description="6.8.3, (6.7): the quasi-static parameter.")
    thresholds: ThresholdsOut
    reference: str = Field(description="Where the formulas come from.")
    elapsed_ms: float
