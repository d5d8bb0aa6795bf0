"""Request and response schemas of the HTTP API (pydantic v2).

All geometry is in the world frame: right-handed, x right, y up; angles in radians,
counter-clockwise positive; lengths in any unit the client uses consistently (the answer
comes back in the same unit). Limits are the constants of :mod:`service.limits`.

Numbers are validated strictly: JSON ``true``/``false`` and strings are not numbers,
NaN/Infinity (which Python's JSON parser accepts) are rejected, integers are accepted
where a float is expected, and unknown fields are rejected.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator

from models.locus.cor_disk import OUTPUTS
from service.limits import (
    DEFAULT_CERTIFIED_POINTS,
    DEFAULT_N_POINTS,
    DEFAULT_TIME_LIMIT_S,
    MAX_CERTIFIED_POINTS,
    MAX_TIME_LIMIT_S,
    MIN_CERTIFIED_POINTS,
    MAX_ABS_ANGLE,
    MAX_ABS_COORDINATE,
    MAX_DISK_RADIUS,
    MAX_N_POINTS,
    MAX_POLYGON_VERTICES,
    MIN_N_POINTS,
    MIN_POLYGON_VERTICES,
)

# ---------------------------------------------------------------------------------------
# Scalar and point types of requests
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
Polygon = Annotated[
    list[Point],
    Field(min_length=MIN_POLYGON_VERTICES, max_length=MAX_POLYGON_VERTICES),
]

OutputName = Literal["tip", "tip_line", "r_min", "curvatures", "disk_crossings", "boundary"]
OUTPUT_NAMES: tuple[str, ...] = OutputName.__args__  # type: ignore[attr-defined]
assert set(OUTPUT_NAMES) == set(OUTPUTS), "OutputName must list models.locus.cor_disk.OUTPUTS"

ResponseFormat = Literal["json", "svg"]
LocusMethod = Literal["analytic", "certified"]


ONE_SHAPE_OF = [
    {"required": ["disk_radius"], "properties": {"disk_radius": {"type": "number"}}},
    {"required": ["workpiece"], "properties": {"workpiece": {"type": "array"}}},
    {"required": ["footprint"], "properties": {"footprint": {"type": "array"}}},
]
"""JSON-schema: exactly one of disk_radius / workpiece / footprint (null counts as absent)."""


class CorLocusRequest(BaseModel):
    """One push of a sliding workpiece by a frictionless pusher (book 3.1.9).

    Give the workpiece as its bounding disk (``disk_radius``) or as a polygon
    (``footprint``, or its older name ``workpiece``), exactly one of them.
    """

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={
            "oneOf": ONE_SHAPE_OF,
            "examples": [
                {"disk_radius": 1.0, "contact_point": [-0.5, -0.3], "edge_angle": 1.5707963267948966},
            ],
        },
    )

    disk_radius: DiskRadius | None = Field(
        default=None,
        description=(
            "Radius a of a disk about the centre of mass that bounds the workpiece "
            f"(length, in (0, {MAX_DISK_RADIUS:g}]). Give this or `workpiece`."
        ),
    )
    workpiece: Polygon | None = Field(
        default=None,
        description=(
            "The workpiece's outline as a simple polygon, vertices [x, y] in order (either "
            f"orientation), {MIN_POLYGON_VERTICES}..{MAX_POLYGON_VERTICES} vertices. "
            "The disk radius a used is the largest distance from the centre of mass to a "
            "vertex. Give this, `footprint` or `disk_radius`. Older name of `footprint`, "
            "with the same meaning."
        ),
        json_schema_extra={"deprecated": True},
    )
    footprint: Polygon | None = Field(
        default=None,
        description=(
            "The workpiece's outline as a simple polygon (either orientation, "
            f"{MIN_POLYGON_VERTICES}..{MAX_POLYGON_VERTICES} vertices) whose locus is wanted. "
            "Method 'analytic' bounds it by its circumscribing disk (a = the largest distance "
            "from the centre of mass to a vertex, 3.1.8): the answer is that disk's locus, "
            "which contains the polygon's (7.5). Method 'certified' also traces the polygon's "
            "exact locus. Give this, `workpiece` or `disk_radius`."
        ),
    )
    center_of_mass: Point | None = Field(
        default=None,
        description=(
            "Centre of mass [x, y]. Default: [0, 0] with `disk_radius`; the polygon's "
            "area centroid with `workpiece` (an explicit one must lie in its convex hull)."
        ),
    )
    contact_point: Point = Field(description="Where the pusher touches the workpiece, [x, y].")
    edge_angle: Angle = Field(
        description="Direction of the pushed edge (the fence face) through the contact, radians."
    )
    push_direction: Angle = Field(
        default=0.0,
        description="Direction in which the pusher advances, radians (0 = +x). Must not be "
        "parallel to the edge.",
    )
    n_points: NPoints = Field(
        default=DEFAULT_N_POINTS,
        description=f"Number of boundary points ({MIN_N_POINTS}..{MAX_N_POINTS}; odd counts "
        "are rounded up to even because the locus is mirror symmetric).",
    )
    outputs: Annotated[list[OutputName], Field(max_length=len(OUTPUT_NAMES))] = Field(
        default_factory=lambda: list(OUTPUT_NAMES),
        description="Parts of the locus to compute, each at most once (default: all). "
        "Parts not asked for come back as null.",
        json_schema_extra={"uniqueItems": True, "default": list(OUTPUT_NAMES)},
    )

    method: LocusMethod = Field(
        default="analytic",
        description="'analytic' (default): the closed forms of the disk locus (3.3). 'certified': "
        "also certified brackets of the boundary by minimum-power membership queries: for the disk "
        "at each analytic boundary point (a check of the closed forms), for a footprint polygon "
        "along rays from an inside point (its exact locus). JSON only.",
    )
    n_certified: Annotated[int, Field(strict=True, ge=MIN_CERTIFIED_POINTS, le=MAX_CERTIFIED_POINTS)] = Field(
        default=DEFAULT_CERTIFIED_POINTS,
        description=f"Method 'certified': boundary points (disk) or rays (polygon), "
        f"{MIN_CERTIFIED_POINTS}..{MAX_CERTIFIED_POINTS}.",
    )
    time_limit_s: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0.0, le=MAX_TIME_LIMIT_S)] = Field(
        default=DEFAULT_TIME_LIMIT_S,
        description=f"Method 'certified': time budget in seconds, (0, {MAX_TIME_LIMIT_S:g}]. Points "
        "or rays not reached in time are reported as not done.",
    )

    @field_validator("outputs")
    @classmethod
    def _unique_outputs(cls, value: list[str]) -> list[str]:
        if len(set(value)) != len(value):
            raise ValueError("must not repeat an output")
        return value


# ---------------------------------------------------------------------------------------
# Responses
# ---------------------------------------------------------------------------------------

Vec2 = Annotated[list[float], Field(min_length=2, max_length=2)]


class _Out(BaseModel):
    model_config = ConfigDict(extra="forbid")


class TipOut(_Out):
    point: Vec2 = Field(description="The tip of the locus: its farthest point from the CM, on the axis.")
    distance: float = Field(description="r_tip: distance of the tip from the CM (3.37; a when the tip is on the disk).")
    distance_book: float = Field(description="a^2 / |alpha . c|, equation (3.37) as printed.")
    on_disk: bool = Field(description="True when |alpha . c| >= a: the tip lies on the disk perimeter.")


class TipLineOut(_Out):
    point: Vec2 = Field(description="Foot of the tip line: the point at distance a^2/|c| from the CM, opposite the contact.")
    direction: Vec2 = Field(description="Unit direction of the tip line (perpendicular to c).")
    distance: float = Field(description="a^2 / |c|: distance of the tip line from the CM.")


class RMinOut(_Out):
    point: Vec2 = Field(description="Nearest point of the locus boundary to the CM.")
    distance: float = Field(description="r_min = a |alpha . c| / (2a + |alpha . c|), equation (3.31).")


class CurvaturesOut(_Out):
    tip_radius: float = Field(description="Radius of curvature of the boundary at the tip (corrected 3.38).")
    tip_radius_book_printed: float = Field(description="(3.38) exactly as printed in the book.")
    r_min_radius: float = Field(description="Radius of curvature at r_min, equation (3.33).")


class PerimeterArcOut(_Out):
    start_angle: float = Field(description="Polar angle about the CM where the arc starts (rad); runs CCW.")
    end_angle: float = Field(description="Polar angle about the CM where the arc ends (rad).")
    start: Vec2
    end: Vec2


class DiskCrossingsOut(_Out):
    cos_eta: float = Field(description="cos(eta) where the inner boundary meets the disk, equation (3.32).")
    points: Annotated[list[Vec2], Field(min_length=2, max_length=2)] = Field(
        description="The two points where the inner boundary (3.30) meets the disk."
    )
    arcs: list[PerimeterArcOut] = Field(
        description="Stretches of the disk perimeter that belong to the boundary (none when |alpha . c| < a/sqrt 2)."
    )


class BracketOut(_Out):
    """One certified bracket: `inner` proven inside the locus (a witness support), `outer`
    proven outside (a dual with a positive branch-and-bound margin)."""

    point: Vec2 | None = Field(
        description="Disk: the analytic boundary point checked. Polygon: the bracket's midpoint on "
        "the ray (null unless bracketed)."
    )
    inner: Vec2 | None = Field(description="The inner end of the bracket (null when the ray could not be bracketed).")
    outer: Vec2 | None = Field(description="The outer end.")
    inner_status: Literal["inside", "outside", "undecided"] | None
    outer_status: Literal["inside", "outside", "undecided"] | None
    verdict: Literal["bracketed", "both_inside", "both_outside", "reversed", "undecided"] = Field(
        description="'bracketed': the true boundary crosses [inner, outer]. 'both_inside' / "
        "'both_outside' / 'reversed' at a disk point: the analytic boundary is wrong there."
    )
    crossings: int | None = Field(
        default=None,
        description="Polygon: inside-to-outside changes seen by the uncertified scan along the ray "
        "(more than 1: the locus is not star-shaped from the centre there).",
    )


class CertifiedLocusOut(_Out):
    """Certified brackets of the COR locus boundary (method 'certified')."""

    region: Literal["disk", "polygon"]
    n_requested: int = Field(description="Boundary points (disk) or rays (polygon) asked for.")
    n_done: int = Field(description="Of them examined before the time limit.")
    n_certified: int = Field(description="Of them bracketed.")
    complete: bool = Field(description="Whether all were examined (false: the time limit was reached).")
    boundary: list[Vec2 | None] = Field(
        description="Disk: the analytic boundary points examined, CCW from the tip. Polygon: the "
        "certified boundary points, CCW by ray angle (null where a ray was not bracketed)."
    )
    brackets: list[BracketOut]
    bracket_width: float = Field(description="Distance between the two ends of a bracket (length).")
    wrong: list[int] = Field(description="Disk: indices where the analytic boundary is proven wrong.")
    undecided: list[int] = Field(description="Indices not bracketed (undecided ends, or rays that failed).")
    multi_crossing: list[int] = Field(description="Polygon: rays with more than one crossing in the scan.")
    centre: Vec2 | None = Field(description="Polygon: the certified inside point the rays start from.")
    time_limit_s: float
    solve_time_ms: float


class CorLocusResponse(_Out):
    """The locus of centres of rotation (COR) of the pushed workpiece, world frame."""

    kind: Literal["bounded", "translation"] = Field(
        description="'bounded', or 'translation' when the line of force passes through the CM: "
        "the workpiece translates and the COR is at infinity."
    )
    sense: Literal["cw", "ccw", "none"] = Field(description="Sense of rotation of the workpiece.")
    message: str | None = Field(description="Human-readable note (set for pure translation).")
    disk_radius: float = Field(description="Disk radius a actually used.")
    center_of_mass: Vec2 = Field(description="Centre of mass actually used.")
    moment_arm: float = Field(description="|alpha . c|: distance from the CM to the line of force.")
    relative_moment_arm: float = Field(description="|alpha . c| / a, the only shape parameter of the locus.")
    book_alpha: float = Field(description="The book's alpha: angle from the push direction to the edge vector, in (0, pi).")
    axis: Vec2 = Field(description="Unit vector from the CM towards the tip (the locus' symmetry axis).")
    translation_direction: Vec2 = Field(description="Unit direction of a pure translation (the edge normal, into the part).")
    r_tip: float | None = Field(description="Distance of the tip from the CM; null for translation or when `tip` was not asked for.")
    tip: TipOut | None
    tip_line: TipLineOut | None
    r_min: RMinOut | None
    curvatures: CurvaturesOut | None
    disk_crossings: DiskCrossingsOut | None
    boundary: list[Vec2] | None = Field(
        description="Closed boundary polygon of the locus, counter-clockwise, starting at the tip; "
        "the first point is not repeated."
    )
    boundary_residual: float | None = Field(description="Largest relative residual of the boundary equations.")
    boundary_iterations: int | None = Field(description="Iterations of the outer-boundary root solve.")
    contact_distance_to_outline: float | None = Field(
        description="With `workpiece`: distance from the contact point to the polygon outline."
    )
    warnings: list[str] = Field(description="Non-fatal remarks about the input.")
    method: LocusMethod = Field(default="analytic", description="The method asked for.")
    locus_of: Literal["disk", "circumscribing_disk"] = Field(
        default="disk",
        description="What the analytic fields describe: the given disk, or the circumscribing disk "
        "of the polygon (an outer bound of the polygon's locus, 7.5).",
    )
    certified: CertifiedLocusOut | None = Field(
        default=None, description="Method 'certified': the certified brackets (null for a translation)."
    )
    elapsed_ms: float = Field(description="Time spent computing, milliseconds.")


class HealthResponse(_Out):
    status: Literal["ok"]
    version: str


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


class ErrorResponse(BaseModel):
    detail: list[ErrorItem]
