"""Request fields shared by several resources (pydantic v2).

All geometry is in the world frame: right-handed, x right, y up; angles in radians,
counter-clockwise positive; lengths in any unit the client uses consistently (the answer
comes back in the same unit). Limits are the constants of :mod:`service.limits`.

Numbers are validated strictly: JSON ``true``/``false`` and strings are not numbers,
NaN/Infinity (which Python's JSON parser accepts) are rejected, integers are accepted
where a float is expected, and unknown fields are rejected (:class:`Strict`).
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field

from service.limits import (
    MAX_ABS_ANGLE,
    MAX_ABS_COORDINATE,
    MAX_DISK_RADIUS,
    MAX_MU_C,
    MAX_N_POINTS,
    MAX_POLYGON_VERTICES,
    MIN_N_POINTS,
    MIN_POLYGON_VERTICES,
    TIME_LIMIT_HARD_MAX_S,
)


class Strict(BaseModel):
    """A request or response part that rejects unknown fields."""

    model_config = ConfigDict(extra="forbid")


# ---------------------------------------------------------------------------------------
# Scalars and points
# ---------------------------------------------------------------------------------------

Coordinate = Annotated[
    float,
    Field(strict=True, allow_inf_nan=False, ge=-MAX_ABS_COORDINATE, le=MAX_ABS_COORDINATE),
]
Point = Annotated[
    list[Coordinate],
    Field(min_length=2, max_length=2, description="A point [x, y] in the world frame."),
]
Angle = Annotated[
    float,
    Field(strict=True, allow_inf_nan=False, ge=-MAX_ABS_ANGLE, le=MAX_ABS_ANGLE),
]
DiskRadius = Annotated[
    float,
    Field(strict=True, allow_inf_nan=False, gt=0.0, le=MAX_DISK_RADIUS),
]
NPoints = Annotated[int, Field(strict=True, ge=MIN_N_POINTS, le=MAX_N_POINTS)]
OUTLINE_RULES = ("a simple polygon: no vertex repeated (uniqueItems), no two edges crossing or touching, not all "
                 "collinear, and its extent within about 1e-154..1e154 (its squared lengths must not underflow); "
                 "either orientation")
"""What every outline of a request must be (models.core.footprint.Footprint.create checks it,
with the true reason in a 422, the same for every route)."""
UNIQUE = {"uniqueItems": True}
Polygon = Annotated[
    list[Point],
    Field(min_length=MIN_POLYGON_VERTICES, max_length=MAX_POLYGON_VERTICES, json_schema_extra=UNIQUE),
]
MuC = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0.0, le=MAX_MU_C)]
MuCPositive = Annotated[
    float,
    Field(strict=True, allow_inf_nan=False, le=MAX_MU_C, json_schema_extra={"exclusiveMinimum": 0}),
]
"""mu_c > 0 (pushes with a friction cone); the route's validator gives the reason."""
TimeLimit = Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0.0, le=TIME_LIMIT_HARD_MAX_S)]
"""A time limit in seconds: the schema takes up to the hard maximum; the runner refuses what
exceeds the deployment's cap (service.runtime.jobs.Runner.deadline)."""
Vec2 = Annotated[list[float], Field(min_length=2, max_length=2)]
"""A point or vector [x, y] of a response."""

ResponseFormat = Literal["json", "svg"]
LocusMethod = Literal["analytic", "certified"]

# ---------------------------------------------------------------------------------------
# The push (book 3.1.9)
# ---------------------------------------------------------------------------------------

CONTACT_POINT_DESCRIPTION = "Where the pusher touches the workpiece, [x, y]."
EDGE_ANGLE_DESCRIPTION = "Direction of the pushed edge (the fence face) through the contact, radians."
PUSH_DIRECTION_DESCRIPTION = (
    "Direction in which the pusher advances, radians (0 = +x). Must not be parallel to the edge."
)

EXACTLY_ONE_OF = "x-exactly-one-of"
"""The OpenAPI extension listing groups of fields of which a request gives exactly one
(null counts as absent); the service answers 422 otherwise. Written as an extension, not as
JSON Schema's ``oneOf`` of partial objects, which client generators cannot turn into a
model (openapi-python-client dropped every such request and its operation)."""


def exactly_one_of(*groups: tuple[str, ...]) -> dict[str, list[list[str]]]:
    """The schema extension saying that of each group of fields exactly one is given."""
    return {EXACTLY_ONE_OF: [list(g) for g in groups]}


ONE_SHAPE_OF = ("disk_radius", "workpiece", "footprint")
"""Exactly one of disk_radius / workpiece / footprint."""

DISK_OR_FOOTPRINT = ("disk_radius", "footprint")
"""Exactly one of disk_radius / footprint."""


class PushIn(Strict):
    """The push (book 3.1.9), as in ``/v1/cor/locus``."""

    contact_point: Point = Field(description=CONTACT_POINT_DESCRIPTION)
    edge_angle: Angle = Field(description=EDGE_ANGLE_DESCRIPTION)
    push_direction: Angle = Field(default=0.0, description=PUSH_DIRECTION_DESCRIPTION)
