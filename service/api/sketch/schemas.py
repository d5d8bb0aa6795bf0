"""Request and response schemas of ``POST /v1/cor/sketch``: the COR sketch with pusher
friction (book 4.1, :mod:`models.sketch.disk_sketch`).

Conventions as in :mod:`service.common.fields`: world frame (x right, y up), angles in radians
counter-clockwise, lengths in the client's unit, strict finite numbers, unknown fields
rejected, ``null`` counts as absent. "Up" and "down" are the book's (4.1.2): the
workpiece's contact point moving along +J p (the push direction p turned +90 degrees)
relative to the pusher is slipping *up*, along -J p slipping *down*; with the push drawn
along +x, up is +y.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import ConfigDict, Field, field_validator
from pydantic_core import PydanticCustomError

from models.sketch.disk_sketch import CONFIG_ORDER, IMPLIED_MODES, SKETCHES
from service.common.fields import (
    CONTACT_POINT_DESCRIPTION,
    EDGE_ANGLE_DESCRIPTION,
    ONE_SHAPE_OF,
    PUSH_DIRECTION_DESCRIPTION,
    Angle,
    LocusMethod,
    MuCPositive,
    Point,
    Polygon,
    Strict,
    TimeLimit,
    Vec2,
    exactly_one_of,
)
from service.common.responses import ELAPSED_MS_DESCRIPTION, Out
from service.limits import (
    DEFAULT_TIME_LIMIT_S,
    MAX_CERTIFIED_POINTS,
    MAX_DISK_RADIUS,
    MAX_MU_C,
    MIN_CERTIFIED_POINTS,
    MIN_N_POINTS,
    SKETCH_DEFAULT_N_POINTS,
    SKETCH_DEFAULT_RAYS,
    SKETCH_MAX_N_POINTS,
    SKETCH_MIN_LENGTH,
    TIME_LIMIT_CAP_TEXT,
)

FRICTIONLESS_HINT = (
    "Input should be greater than 0: the COR sketch needs pusher friction (a friction cone "
    "of half-angle atan(mu_c)); mu_c = 0 is a frictionless pusher, whose COR locus is "
    "POST /v1/cor/locus"
)

SketchDiskRadius = Annotated[
    float,
    Field(strict=True, allow_inf_nan=False, ge=SKETCH_MIN_LENGTH, le=MAX_DISK_RADIUS),
]


class CorSketchRequest(Strict):
    """A push of a workpiece by a pusher with friction mu_c > 0 (book 4.1): the workpiece
    as its bounding disk (``disk_radius``) or as a polygon (``footprint``, or its older
    name ``workpiece``) bounded by its circumscribing disk, exactly one of them."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={
            **exactly_one_of(ONE_SHAPE_OF),
            "examples": [
                {"disk_radius": 1.0, "contact_point": [-0.5, -0.3], "edge_angle": 1.5707963267948966,
                 "mu_c": 0.3},
            ],
        },
    )

    disk_radius: SketchDiskRadius | None = Field(
        default=None,
        description=f"Radius a of a disk about the centre of mass that bounds the workpiece (length, "
        f"in [{SKETCH_MIN_LENGTH:g}, {MAX_DISK_RADIUS:g}]). Give this, `footprint` or `workpiece`.",
    )
    footprint: Polygon | None = Field(
        default=None,
        description="The workpiece's outline as a simple polygon (either orientation). The sketch is "
        "that of its circumscribing disk (a = the largest distance from the centre of mass to a "
        "vertex, 3.1.8), whose loci contain the polygon's (7.5): `sketch_of` says "
        "`circumscribing_disk`. Its circumradius must be at least "
        f"{SKETCH_MIN_LENGTH:g}. Give this, `workpiece` or `disk_radius`.",
    )
    workpiece: Polygon | None = Field(
        default=None,
        description="Older name of `footprint` (as in /v1/cor/locus), same meaning.",
        json_schema_extra={"deprecated": True},
    )
    center_of_mass: Point | None = Field(
        default=None,
        description="Centre of mass [x, y]. Default: [0, 0] with `disk_radius`; the polygon's area "
        "centroid with `footprint` (an explicit one must lie in its convex hull).",
    )
    contact_point: Point = Field(description=CONTACT_POINT_DESCRIPTION)
    edge_angle: Angle = Field(description=EDGE_ANGLE_DESCRIPTION)
    push_direction: Angle = Field(default=0.0, description=PUSH_DIRECTION_DESCRIPTION)
    mu_c: MuCPositive = Field(
        description=f"Coefficient of friction between pusher and workpiece, in (0, {MAX_MU_C:g}]. "
        "The friction cone has half-angle nu = atan(mu_c) about the edge normal (4.1.1). 0 is "
        "refused: the frictionless locus is POST /v1/cor/locus."
    )
    n_points: Annotated[int, Field(strict=True, ge=MIN_N_POINTS, le=SKETCH_MAX_N_POINTS)] = Field(
        default=SKETCH_DEFAULT_N_POINTS,
        description=f"Boundary points of each elementary locus ({MIN_N_POINTS}..{SKETCH_MAX_N_POINTS}; "
        "odd counts are rounded up to even). The sticking locus is always swept with at least 1024.",
    )
    method: LocusMethod = Field(
        default="analytic",
        description="'analytic' (default): the disk's analytic loci and the book's sweep of the force "
        "over the cone for the sticking locus (4.1.4); a polygon is bounded by its circumscribing disk. "
        "'certified': every piece certified by the minimum-power engine: the sticking locus's ends by "
        "the exact feasibility problem (witness inside, dual certificate outside); with a footprint the "
        "sketch of the POLYGON ITSELF (its loci {COR}_(alpha+-nu) traced along `n_rays` rays with "
        "certified brackets), with a disk the analytic loci. Seconds, not milliseconds; see "
        "`certification`.",
    )
    n_rays: Annotated[int, Field(strict=True, ge=MIN_CERTIFIED_POINTS, le=MAX_CERTIFIED_POINTS)] = Field(
        default=SKETCH_DEFAULT_RAYS,
        description=f"Method 'certified' with a footprint: rays per traced locus, "
        f"{MIN_CERTIFIED_POINTS}..{MAX_CERTIFIED_POINTS} (~0.05-0.25 s each).",
    )
    time_limit_s: TimeLimit = Field(
        default=DEFAULT_TIME_LIMIT_S,
        description=f"Method 'certified': time budget in seconds, {TIME_LIMIT_CAP_TEXT}. What is not "
        "reached in time is left out and `certification` says so (`complete` false).",
    )

    @field_validator("mu_c")
    @classmethod
    def _positive_mu_c(cls, value: float) -> float:
        if not value > 0.0:
            raise PydanticCustomError("greater_than", FRICTIONLESS_HINT, {"gt": 0})
        return value


# ---------------------------------------------------------------------------------------
# Responses
# ---------------------------------------------------------------------------------------


Configuration = Literal["pure_slipping", "same_sided_split", "opposite_sided_split", "wrapped"]
Mode = Literal["sticking", "slipping_up", "slipping_down"]
Implication = Literal[
    "must_slip_up", "stick_or_slip_up", "anything", "must_stick", "stick_or_slip_down", "must_slip_down"
]
SketchLetter = Literal["a", "b", "c", "d", "e", "f", "g", "h", "i"]
PolygonOut = list[Vec2]


class LineOut(Out):
    point: Vec2 = Field(description="A point of the line, world frame (the contact point).")
    direction: Vec2 = Field(description="Unit direction of the line, world frame.")


class ElementaryLocusOut(Out):
    """{COR}_(alpha +- nu): the frictionless COR locus of the disk for a force along one edge
    of the friction cone (4.1.3), drawn in outline in the book's figures."""

    label: Literal["alpha_plus_nu", "alpha_minus_nu"] = Field(
        description="'alpha_plus_nu': the cone edge n turned by +nu (CCW), the force of down-slipping; "
        "'alpha_minus_nu': n turned by -nu, the force of up-slipping."
    )
    force_direction: Vec2 = Field(
        description="Unit direction of that cone edge (the force on the part), world frame."
    )
    force_angle: float = Field(
        description="Angle of the force from the edge normal n, radians, CCW positive: +nu or -nu."
    )
    boundary: list[Vec2] | None = Field(
        description="The locus boundary, a closed counter-clockwise polygon in the world frame (first "
        "point not repeated); null when that force passes through the CM (a translation)."
    )
    tip: Vec2 | None = Field(
        description="The locus tip (its farthest point from the CM), world frame; null for a translation."
    )
    moment_sign: Literal[-1, 0, 1] = Field(
        description="Sign of the force's moment arm alpha_d . c: +1 turns the part clockwise, -1 "
        "counter-clockwise, 0 a translation."
    )
    configuration: Configuration = Field(
        description="Elementary configuration against the sticking line (4.1.5): 'pure_slipping' (misses "
        "it), 'same_sided_split' (crosses it, tip on the CM's side), 'opposite_sided_split' (crosses it, "
        "tip across), 'wrapped' (its sense of rotation is not the part's by Mason's rule, or a "
        "translation: it contributes nothing to the sketch)."
    )
    crosses_sticking_line: bool = Field(
        description="Whether the locus meets the sticking line (false when wrapped)."
    )
    tip_on_cm_side: bool | None = Field(
        description="Whether the tip lies on the CM's side of the sticking line; null when wrapped."
    )


class StickingLocusOut(Out):
    """The sticking locus (4.1.4): the segment of the sticking line that holds every
    sticking COR, by the book's sweep of the force over the cone (refined at the ends)."""

    t_low: float = Field(
        description="Signed distance (length) of its lower end from the contact along J p (the sticking "
        "line's direction)."
    )
    t_high: float = Field(description="Signed distance of its upper end, t_high >= t_low.")
    low: Vec2 = Field(description="Lower end point, contact + t_low J p, world frame.")
    high: Vec2 = Field(description="Upper end point, world frame.")
    phi_low: float | None = Field(
        description="Force angle from the edge normal (rad, CCW, in [-nu, nu]) whose locus reaches the lower "
        "end; null for method 'certified' (the exact ends come with a pressure distribution, not an angle)."
    )
    phi_high: float | None = Field(description="Force angle whose locus reaches the upper end (null: certified).")


class TipLineEstimateOut(Out):
    """The book's approximation of the sticking locus's far end (4.1.4): where the tip line
    (3.3.11.1, perpendicular to c at a^2/|c| beyond the CM) meets the sticking line."""

    point: Vec2 = Field(description="The intersection, world frame.")
    t: float = Field(description="Its signed distance from the contact along J p (length).")
    error: float | None = Field(
        description="Distance (length) from the estimate to the nearer end of the swept sticking locus; "
        "null when the sticking locus is empty."
    )


class StickingEndOut(Out):
    status: str = Field(
        description="'bracketed' (certified inside and outside points `width` apart), 'wide' (as bracketed, "
        "wider than asked), 'contact' (runs up to the contact point), 'search_limit' (still feasible at "
        "the search cap: possibly unbounded), 'undecided' (time limit or an undecidable query)."
    )
    position: float = Field(description="Midpoint of the bracket, signed distance from the contact along J p.")
    feasible_position: float | None = Field(description="The certified inside end of the bracket (t).")
    infeasible_position: float | None = Field(description="The certified outside end of the bracket (t).")
    width: float = Field(description="Bracket width (length).")
    certified: bool = Field(description="Both ends of the bracket carry their certificate.")


class SketchCertificationOut(Out):
    """How the pieces of a 'certified' sketch were certified, and whether all were."""

    complete: bool = Field(description="Every traced ray and both sticking ends certified, nothing cut by the time limit.")
    time_limited: bool = Field(description="The time limit left something out.")
    message: str = Field(description="What is missing, or 'every piece certified'.")
    sticking_status: Literal["found", "empty", "incomplete"] | None = Field(
        description="The exact sticking locus: 'found', 'empty' (no sticking COR), 'incomplete'; null for a translation."
    )
    sticking_lower: StickingEndOut | None = Field(
        description="The exact sticking locus's lower end (smallest t along J p) with its certified bracket; null for "
        "a translation or when no sticking locus was found."
    )
    sticking_upper: StickingEndOut | None = Field(
        description="The exact sticking locus's upper end (largest t along J p) with its certified bracket; null for "
        "a translation or when no sticking locus was found."
    )
    sticking_multiple_intervals: bool = Field(
        description="The exact locus has gaps; `sticking` is then the hull of its intervals."
    )
    n_rays: int | None = Field(description="Rays per traced locus (polygon); null for a disk (analytic loci).")
    plus_certified_rays: int | None = Field(description="Rays of {COR}_(alpha+nu) certified; null when not traced.")
    minus_certified_rays: int | None = Field(description="Rays of {COR}_(alpha-nu) certified; null when not traced.")
    solve_time_s: float = Field(
        description="Time the certification took in the solver, seconds."
    )


class CorSketchResponse(Out):
    """The COR sketch (book 4.1): every COR consistent with the force that produces it, for
    every pressure distribution on the disk, world frame."""

    kind: Literal["sketch", "translation"] = Field(
        description="'sketch', or 'translation' when Mason's rule gives no sense of rotation: the line "
        "of pushing passes through the CM inside the friction cone (or the contact is at the CM); the "
        "part does not rotate, the COR is at infinity, and there is no sketch (no letter, no finite "
        "loci; see `message`)."
    )
    message: str = Field(description="The sketch and what it implies, in words.")
    mu_c: float = Field(description="Pusher friction coefficient used.")
    nu: float = Field(description="Half-angle of the friction cone, atan(mu_c), radians (4.1).")
    sense: Literal["cw", "ccw", "none"] = Field(
        description="Sense of rotation of the part by Mason's rule with the friction cone (1.6.2); "
        "'none' for kind 'translation'."
    )
    disk_radius: float = Field(
        description="Disk radius a used (the polygon's circumradius with a footprint)."
    )
    center_of_mass: Vec2 = Field(description="Centre of mass used, world frame.")
    sketch_of: Literal["disk", "circumscribing_disk", "polygon"] = Field(
        description="What the sketch describes: the given disk, the circumscribing disk of the polygon "
        "(its loci contain the polygon's, 7.5), or the polygon itself (method 'certified')."
    )
    method: LocusMethod = Field(description="The method asked for.")
    certification: SketchCertificationOut | None = Field(
        description="Method 'certified': how each piece was certified; null for 'analytic'."
    )
    sticking_line: LineOut = Field(
        description="Through the contact, direction J p (the push direction turned +90 degrees): CORs on "
        "it make the part move with the pusher at the contact (4.1.2.1). Positions t along it are "
        "measured from the contact in this direction."
    )
    edge_normal_direction: Vec2 = Field(
        description="Unit edge normal n at the contact, into the part (n . p > 0): the centre of the "
        "friction cone. The edge normal line is the line through the contact along it (figure 4-2)."
    )
    plus: ElementaryLocusOut = Field(description="{COR}_(alpha+nu), the locus of the down-slipping force.")
    minus: ElementaryLocusOut = Field(description="{COR}_(alpha-nu), the locus of the up-slipping force.")
    down_slipping: list[PolygonOut] = Field(
        description="The down-slipping locus (4.1.3): the part of {COR}_(alpha+nu) whose CORs move the "
        "part's contact along -J p relative to the pusher, as closed world-frame polygons (empty: none)."
    )
    up_slipping: list[PolygonOut] = Field(
        description="The up-slipping locus: the part of {COR}_(alpha-nu) moving the contact along +J p."
    )
    sticking: StickingLocusOut | None = Field(description="The sticking locus; null when no COR can stick.")
    tip_line_estimate: TipLineEstimateOut | None = Field(
        description="The tip-line estimate of the sticking locus's far end; null when the tip line is "
        "parallel to the sticking line or the contact is at the CM."
    )
    sketch: SketchLetter | None = Field(
        description="Which of the nine sketches of figure 4-6 this is (the letter of its canonical, "
        "unmirrored image); null when the loci match none of the nine."
    )
    mirrored: bool = Field(
        description="Whether the sketch is the mirror image of the book's figure (4.1.6): the roles of "
        "{COR}_(alpha+nu) and {COR}_(alpha-nu), and of up and down, are swapped."
    )
    implication: Implication | None = Field(
        description="What the sketch implies for the contact, already mirrored when `mirrored` (4.1.6); "
        "null with no letter."
    )
    allowed_modes: list[Mode] = Field(
        description="The contact modes whose loci are non-empty: 'sticking', 'slipping_up', "
        "'slipping_down' (for a translation: empty, there is no finite COR)."
    )
    n_points: int = Field(description="Boundary points per elementary locus asked for.")
    contact_distance_to_outline: float | None = Field(
        description="With a polygon: distance from the contact to its outline (length); else null."
    )
    warnings: list[str] = Field(description="Non-fatal remarks about the input.")
    elapsed_ms: float = Field(description=ELAPSED_MS_DESCRIPTION)


def _check_modes() -> None:
    """The literals above must list the model's names."""
    assert set(CONFIG_ORDER) == set(Configuration.__args__)  # type: ignore[attr-defined]
    assert set(IMPLIED_MODES) == set(Implication.__args__)  # type: ignore[attr-defined]
    assert set(SKETCHES.values()) == set(SketchLetter.__args__)  # type: ignore[attr-defined]
    assert {m for ms in IMPLIED_MODES.values() for m in ms} == set(Mode.__args__)  # type: ignore[attr-defined]


_check_modes()
