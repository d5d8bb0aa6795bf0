"""Request and response schemas of ``POST /v1/cor/locus`` (the COR locus, book 3.3) and
``POST /v1/cor/membership`` ("can r be a COR?", with a certificate, 3.3.2-3.3.13).

Conventions are those of :mod:`service.common.fields`: world frame, radians, lengths in
any consistent unit, strict finite numbers, unknown fields rejected.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import ConfigDict, Field, field_validator

from models.locus.cor_disk import OUTPUTS
from service.common.fields import (
    CONTACT_POINT_DESCRIPTION,
    DISK_OR_FOOTPRINT,
    EDGE_ANGLE_DESCRIPTION,
    ONE_SHAPE_OF,
    PUSH_DIRECTION_DESCRIPTION,
    Angle,
    DiskRadius,
    LocusMethod,
    NPoints,
    Point,
    Polygon,
    PushIn,
    Strict,
    TimeLimit,
    Vec2,
    exactly_one_of,
)
from service.common.responses import ELAPSED_MS_DESCRIPTION, Out
from service.limits import (
    DEFAULT_CERTIFIED_POINTS,
    DEFAULT_N_POINTS,
    DEFAULT_TIME_LIMIT_S,
    MAX_CERTIFIED_POINTS,
    MAX_DISK_RADIUS,
    MAX_N_POINTS,
    MAX_POLYGON_VERTICES,
    MIN_CERTIFIED_POINTS,
    MIN_N_POINTS,
    MIN_POLYGON_VERTICES,
    TIME_LIMIT_CAP_TEXT,
)

OutputName = Literal["tip", "tip_line", "r_min", "curvatures", "disk_crossings", "boundary"]
OUTPUT_NAMES: tuple[str, ...] = OutputName.__args__  # type: ignore[attr-defined]
assert set(OUTPUT_NAMES) == set(OUTPUTS), "OutputName must list models.locus.cor_disk.OUTPUTS"



class CorLocusRequest(Strict):
    """One push of a sliding workpiece by a frictionless pusher (book 3.1.9).

    Give the workpiece as its bounding disk (``disk_radius``) or as a polygon
    (``footprint``, or its older name ``workpiece``), exactly one of them.
    """

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={
            **exactly_one_of(ONE_SHAPE_OF),
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
    contact_point: Point = Field(description=CONTACT_POINT_DESCRIPTION)
    edge_angle: Angle = Field(description=EDGE_ANGLE_DESCRIPTION)
    push_direction: Angle = Field(default=0.0, description=PUSH_DIRECTION_DESCRIPTION)
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
    time_limit_s: TimeLimit = Field(
        default=DEFAULT_TIME_LIMIT_S,
        description=f"Method 'certified': time budget in seconds, {TIME_LIMIT_CAP_TEXT}. Points "
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


class TipOut(Out):
    point: Vec2 = Field(description="The tip of the locus: its farthest point from the CM, on the axis.")
    distance: float = Field(description="r_tip: distance of the tip from the CM (3.37; a when the tip is on the disk).")
    distance_book: float = Field(description="a^2 / |alpha . c|, equation (3.37) as printed.")
    on_disk: bool = Field(description="True when |alpha . c| >= a: the tip lies on the disk perimeter.")


class LocusTipLineOut(Out):
    """The tip line of the locus (3.3.11.1)."""

    point: Vec2 = Field(description="Foot of the tip line: the point at distance a^2/|c| from the CM, opposite the "
                        "contact (world frame).")
    direction: Vec2 = Field(description="Unit direction of the tip line (perpendicular to c, world frame).")
    distance: float = Field(description="a^2 / |c|: distance of the tip line from the CM (the request's length unit).")


class RMinOut(Out):
    point: Vec2 = Field(description="Nearest point of the locus boundary to the CM.")
    distance: float = Field(description="r_min = a |alpha . c| / (2a + |alpha . c|), equation (3.31).")


class CurvaturesOut(Out):
    tip_radius: float = Field(description="Radius of curvature of the boundary at the tip (corrected 3.38).")
    tip_radius_book_printed: float = Field(description="(3.38) exactly as printed in the book.")
    r_min_radius: float = Field(description="Radius of curvature at r_min, equation (3.33).")


class PerimeterArcOut(Out):
    start_angle: float = Field(description="Polar angle about the CM where the arc starts (rad); runs CCW.")
    end_angle: float = Field(description="Polar angle about the CM where the arc ends (rad).")
    start: Vec2 = Field(
        description="The point [x, y] where the arc starts on the disk perimeter (at `start_angle`), world frame."
    )
    end: Vec2 = Field(
        description="The point [x, y] where the arc ends on the disk perimeter (at `end_angle`), world frame."
    )


class DiskCrossingsOut(Out):
    cos_eta: float = Field(description="cos(eta) where the inner boundary meets the disk, equation (3.32).")
    points: Annotated[list[Vec2], Field(min_length=2, max_length=2)] = Field(
        description="The two points where the inner boundary (3.30) meets the disk."
    )
    arcs: list[PerimeterArcOut] = Field(
        description="Stretches of the disk perimeter that belong to the boundary (none when |alpha . c| < a/sqrt 2)."
    )


class BracketOut(Out):
    """One certified bracket: `inner` proven inside the locus (a witness support), `outer`
    proven outside (a dual with a positive branch-and-bound margin)."""

    point: Vec2 | None = Field(
        description="Disk: the analytic boundary point checked. Polygon: the bracket's midpoint on "
        "the ray (null unless bracketed)."
    )
    inner: Vec2 | None = Field(description="The inner end of the bracket (null when the ray could not be bracketed).")
    outer: Vec2 | None = Field(description="The outer end.")
    inner_status: Literal["inside", "outside", "undecided"] | None = Field(
        description="Membership status of the inner end: 'inside', 'outside' or 'undecided'; null when a polygon ray "
        "had no inner query."
    )
    outer_status: Literal["inside", "outside", "undecided"] | None = Field(
        description="Membership status of the outer end: 'inside', 'outside' or 'undecided'; null when a polygon ray "
        "had no outer query."
    )
    verdict: Literal["bracketed", "both_inside", "both_outside", "reversed", "undecided"] = Field(
        description="'bracketed': the true boundary crosses [inner, outer]. 'both_inside' / "
        "'both_outside' / 'reversed' at a disk point: the analytic boundary is wrong there."
    )
    crossings: int | None = Field(
        default=None,
        description="Polygon: inside-to-outside changes seen by the uncertified scan along the ray "
        "(more than 1: the locus is not star-shaped from the centre there).",
    )


class CertifiedLocusOut(Out):
    """Certified brackets of the COR locus boundary (method 'certified')."""

    region: Literal["disk", "polygon"] = Field(
        description="What was certified: 'disk' (the analytic boundary of the disk, checked point by point) or "
        "'polygon' (the exact locus of the footprint, traced along rays)."
    )
    n_requested: int = Field(description="Boundary points (disk) or rays (polygon) asked for.")
    n_done: int = Field(description="Of them examined before the time limit.")
    n_certified: int = Field(description="Of them bracketed.")
    complete: bool = Field(description="Whether all were examined (false: the time limit was reached).")
    boundary: list[Vec2 | None] = Field(
        description="Disk: the analytic boundary points examined, CCW from the tip. Polygon: the "
        "certified boundary points, CCW by ray angle (null where a ray was not bracketed)."
    )
    brackets: list[BracketOut] = Field(
        description="One certified bracket per boundary point examined (disk) or per ray traced (polygon), in the "
        "order of `boundary`."
    )
    bracket_width: float = Field(description="Distance between the two ends of a bracket (length).")
    wrong: list[int] = Field(description="Disk: indices where the analytic boundary is proven wrong.")
    undecided: list[int] = Field(description="Indices not bracketed (undecided ends, or rays that failed).")
    multi_crossing: list[int] = Field(description="Polygon: rays with more than one crossing in the scan.")
    centre: Vec2 | None = Field(description="Polygon: the certified inside point the rays start from.")
    time_limit_s: float = Field(
        description="The request's time limit (its `time_limit_s` or the route's default), seconds."
    )
    solve_time_ms: float = Field(
        description="Time the certification took in the solver, milliseconds."
    )


class CorLocusResponse(Out):
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
    tip: TipOut | None = Field(
        description="The tip, the farthest COR from the CM (3.37): {point, distance, distance_book, on_disk}; null "
        "for a translation or when `tip` was not asked for."
    )
    tip_line: LocusTipLineOut | None = Field(
        description="The line of tips over all edge angles (3.3.11.1): {point, direction, distance}, world frame; "
        "null when not asked for or when the contact is at the CM."
    )
    r_min: RMinOut | None = Field(
        description="The boundary point nearest the CM (3.31): {point, distance}; null for a translation or when "
        "`r_min` was not asked for."
    )
    curvatures: CurvaturesOut | None = Field(
        description="Radii of curvature of the boundary at the tip (3.38 corrected and as printed) and at r_min "
        "(3.33), length; null for a translation or when not asked for."
    )
    disk_crossings: DiskCrossingsOut | None = Field(
        description="Where the boundary meets the disk (3.32): {cos_eta, points, arcs}; null for a translation or "
        "when `disk_crossings` was not asked for."
    )
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
    from_store: bool = Field(
        default=False,
        description="Method 'certified': the answer was computed before for the same request (all but "
        "time_limit_s) and kept in the service's result store; only complete answers are kept.",
    )
    elapsed_ms: float = Field(description=ELAPSED_MS_DESCRIPTION)



# ---------------------------------------------------------------------------------------
# POST /v1/cor/membership
# ---------------------------------------------------------------------------------------


class MembershipRequest(PushIn):
    """Can `cor` be the centre of rotation of this push, for some pressure distribution
    on the disk (or `footprint`)? Frictionless pusher (book 3.3.2-3.3.13)."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={
            **exactly_one_of(DISK_OR_FOOTPRINT),
            "examples": [
                {"disk_radius": 1.0, "contact_point": [-0.5, -0.3], "edge_angle": 1.5707963267948966,
                 "cor": [0.0, 3.0]},
            ],
        },
    )

    disk_radius: DiskRadius | None = Field(
        default=None,
        description="Radius a of the disk about the CM on which the pressure may lie. Give this "
        "or `footprint`.",
    )
    footprint: Polygon | None = Field(
        default=None,
        description="The workpiece's outline (simple polygon, either orientation): the pressure "
        "may lie anywhere on it. Give this or `disk_radius`.",
    )
    center_of_mass: Point | None = Field(
        default=None,
        description="Centre of mass. Default: [0, 0] with `disk_radius`, the area centroid with "
        "`footprint` (an explicit one must lie in its convex hull).",
    )
    cor: Point = Field(description="The candidate centre of rotation r, [x, y].")
    time_limit_s: TimeLimit = Field(
        default=DEFAULT_TIME_LIMIT_S,
        description=f"Time budget of the search, seconds, {TIME_LIMIT_CAP_TEXT}. When it "
        "runs out the answer is 'undecided'.",
    )


class WitnessOut(Out):
    points: list[Vec2] = Field(description="Support points (world frame) on the outline of the footprint.")
    weights: list[float] = Field(description="Their weights; with `point_mass_at_cor` they sum to 1.")
    point_mass_at_cor: float = Field(description="Weight of a point mass at the COR itself.")
    point_mass_subgradient: Vec2 = Field(
        description="z with |z| <= point_mass_at_cor: the point mass contributes -s z / L to (3.8) "
        "(the subgradient of |w - r| at w = r, times the mass)."
    )
    residual: float = Field(description="L1 residual of the membership equations (3.8) (dimensionless).")
    forward_cor_error: float | None = Field(
        description="|COR of this support by the forward solver - cor| / L: the re-verification."
    )


class DualOut(Out):
    vector: Annotated[list[float], Field(min_length=5, max_length=5)] = Field(
        description="Separating functional y on the columns G(w) = (1, w/L, g_r(w)/L) of (3.8) "
        "(world-aligned CM frame, lengths / L; |y_0| <= 1, |y_w|, |y_g| <= sqrt 2)."
    )
    lower_bound: float | None = Field(description="Lower bound m_F of y . G over the footprint.")
    margin: float | None = Field(description="m_F - y . b: > 0 proves the candidate outside.")
    lower_bound_method: str | None = Field(
        description="'branch_and_bound' (sound over the continuous outline) or 'grid' (not a certificate)."
    )


class MembershipResponse(Out):
    status: Literal["inside", "outside", "undecided"] = Field(
        description="The decision: 'inside' (r is a COR), 'outside' (it is not), or 'undecided' (time limit or "
        "iteration caps reached, or r within the tolerances of the boundary)."
    )
    certificate_kind: Literal["witness", "dual", "none"] = Field(
        description="The certificate given: 'witness' (inside: a support), 'dual' (outside: a separating functional "
        "with a sound lower bound), or 'none'."
    )
    cor: Vec2 = Field(description="The point decided: the query, or moved onto the outline when within 1e-9 L of it.")
    cor_query: Vec2 = Field(description="The query as given.")
    in_footprint: bool = Field(description="Whether the COR lies in the closed footprint (a point mass there is allowed).")
    witness: WitnessOut | None = Field(description="For 'inside': a support whose COR is `cor`.")
    dual: DualOut | None = Field(description="For 'outside' (and 'undecided'): the separating functional.")
    residual: float | None = Field(
        description="L1 residual of the membership equations for the best support found (0 up to "
        "rounding for 'inside'; for 'outside' an upper bound of the distance to feasibility); null "
        "when no round ran (time limit)."
    )
    length_scale: float = Field(description="L: the disk radius or the polygon's circumradius.")
    disk_radius: float = Field(
        description="Disk radius a used: the request's `disk_radius`, or the footprint's circumradius about the CM "
        "(request's length unit)."
    )
    center_of_mass: Vec2 = Field(
        description="Centre of mass used, [x, y] in the world frame ([0, 0] with a disk, the footprint's area "
        "centroid, unless given)."
    )
    iterations: int = Field(description="Column-generation rounds.")
    n_columns: int = Field(
        description="Columns (support points on the outline) in the last restricted master problem of the column "
        "generation."
    )
    bnb_intervals: int = Field(description="Branch-and-bound intervals examined.")
    message: str = Field(
        description="The solver's summary of the decision, e.g. that the witness satisfies (3.8) or that the time "
        "limit was reached."
    )
    time_limit_s: float = Field(
        description="The request's time limit (its `time_limit_s` or the route's default), seconds."
    )
    solve_time_ms: float = Field(
        description="Time the membership decision took in the solver, milliseconds."
    )
    elapsed_ms: float = Field(description=ELAPSED_MS_DESCRIPTION)
