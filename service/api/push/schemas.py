"""Request and response schemas of the push endpoints: ``POST /v1/push/quasistatic``
(book 6.8) and the gross motions ``POST /v1/push/align`` (3.4, 4.3) and
``POST /v1/push/disk-encounter`` (4.4).

Is a push slow enough for the quasi-static results (chapters 3-4) to hold? Lengths are in
the client's unit L, times in seconds, speeds in L/s, g in L/s^2 (or named by
``length_unit``), angles in radians. Conventions as in :mod:`service.common.fields`:
strict finite numbers, unknown fields rejected, null counts as absent.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import ConfigDict, Field, field_validator
from pydantic_core import PydanticCustomError

from models.push.quasistatic import (
    BOOK_TRANSLATIONAL_ERROR_REL,
    GRAVITY_M_S2,
)
from service.common.fields import (
    Angle,
    MuC,
    MuCPositive,
    Point,
    Polygon,
    Strict,
    TimeLimit,
    exactly_one_of,
)
from service.common.quasistatic import Gravity, LengthUnit, QuasiStaticIn
from service.common.responses import ELAPSED_MS_DESCRIPTION, Out
from service.limits import (
    ALIGN_DEFAULT_N_NODES,
    DEFAULT_TIME_LIMIT_S,
    ENCOUNTER_DEFAULT_N_NODES,
    GROSS_DEFAULT_N_POINTS,
    GROSS_MAX_N_NODES,
    GROSS_MIN_LENGTH,
    GROSS_MIN_N_NODES,
    MAX_DISK_RADIUS,
    MAX_MU_C,
    MIN_N_POINTS,
    QS_MAX_ANGULAR_ERROR,
    QS_MAX_GRAVITY,
    QS_MAX_MU_S,
    QS_MAX_SPEED,
    QS_MIN_GRAVITY,
    QS_MIN_LENGTH,
    QS_MIN_MU_S,
    SKETCH_MAX_N_POINTS,
    TIME_LIMIT_CAP_TEXT,
)
from solver import ENCOUNTER_SKETCH_COST, SKETCH_COST

Length = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=QS_MIN_LENGTH, le=MAX_DISK_RADIUS)]

DEFAULT_ANGULAR_ERROR = math.radians(5.0)


class PushQuasistaticRequest(Strict):
    """A push at `speed` of a part on a table with friction `mu_s`: its characteristic
    speeds (6.8.1-6.8.3) and whether the quasi-static assumption holds. Give the part as
    `disk_radius` or `footprint`, and gravity as `g` or `length_unit` (exactly one of each)."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={
            **exactly_one_of(("disk_radius", "footprint"), ("g", "length_unit")),
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


class PartOut(Out):
    kind: Literal["disk", "polygon"] = Field(
        description="How the part was given: 'disk' (`disk_radius`, a uniform disk) or 'polygon' (`footprint`, a "
        "uniform lamina)."
    )
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


class ErrorSpeedOut(Out):
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
    formula: str = Field(
        description="The characteristic speed's formula as text, e.g. 'v^2 = 2 g mu_s X' (6.6) or 'v^2 = (8/3) mu_s a "
        "g theta' (6.3) for the disk."
    )


class QuasiStaticParameterOut(Out):
    characteristic_speed: float = Field(description="v_qs = sqrt(2 mu_s a g) (6.7), L/s.")
    ratio: float = Field(
        description="speed / v_qs, the quasi-static parameter. After release the part coasts "
        "ratio^2 a and turns at most ratio^2 rad."
    )
    equation: str = Field(
        description="The book's equation of the quasi-static parameter: '(6.7)'."
    )
    section: str = Field(
        description="The book's section of the quasi-static parameter: '6.8.3'."
    )
    formula: str = Field(
        description="The characteristic speed's formula as text: 'v^2 = 2 mu_s a g'."
    )


class ThresholdsOut(Out):
    quasi_static_max_ratio: float = Field(description="ratio at or below which the verdict is quasi_static.")
    inertial_min_ratio: float = Field(description="ratio at or above which the verdict is inertial.")


class PushQuasistaticResponse(Out):
    verdict: Literal["quasi_static", "transitional", "inertial"] = Field(
        description="On the quasi-static parameter: quasi_static (ratio <= 0.3: coasting <= 9 % of a and "
        "<= 0.09 rad), transitional, or inertial (ratio >= 1: inertia as large as friction, 6.8.3; "
        "the impact limit of 7.4 is the better model as it grows)."
    )
    message: str = Field(
        description="The verdict in words, with the ratio speed / v_qs and how far the part slides and turns after "
        "release at this speed."
    )
    speed: float = Field(
        description="Relative speed v of pusher and part, as given, in the request's length unit per second."
    )
    mu_s: float = Field(
        description="Coefficient of sliding friction between part and table, as given."
    )
    g: float = Field(description="g used, length unit / s^2.")
    g_source: Literal["g", "length_unit"] = Field(description="Whether g was given or derived from `length_unit`.")
    length_unit: LengthUnit | None = Field(
        description="The request's `length_unit` ('m', 'cm', 'mm', 'um', 'in' or 'ft'); null when `g` was given "
        "instead."
    )
    part: PartOut = Field(
        description="The part's moments: kind, radius a, radius of gyration, mean distance from the CM, spin factor, "
        "and the polygon's CM (request's length unit)."
    )
    angular: ErrorSpeedOut = Field(description="6.8.1, (6.3): the angular-error speed.")
    translational: ErrorSpeedOut = Field(description="6.8.2, (6.6): the translational-error speed.")
    quasi_static: QuasiStaticParameterOut = Field(description="6.8.3, (6.7): the quasi-static parameter.")
    thresholds: ThresholdsOut = Field(
        description="The ratio limits of the verdict: quasi_static_max_ratio (0.3) and inertial_min_ratio (1)."
    )
    reference: str = Field(description="Where the formulas come from.")
    elapsed_ms: float = Field(
        description="Milliseconds from the request's arrival until its answer was assembled (computed in the web "
        "process, no solver worker)."
    )


# =======================================================================================
# Gross motions (book 3.4, 4.2-4.4): POST /v1/push/align and POST /v1/push/disk-encounter
# =======================================================================================

GrossMethod = Literal["closed_form", "exact", "both"]
NNodes = Annotated[int, Field(strict=True, ge=GROSS_MIN_N_NODES, le=GROSS_MAX_N_NODES)]
SketchPoints = Annotated[int, Field(strict=True, ge=MIN_N_POINTS, le=SKETCH_MAX_N_POINTS)]
GrossLength = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=GROSS_MIN_LENGTH, le=MAX_DISK_RADIUS)]

METHOD_DESCRIPTION = (
    "`closed_form`: the book's closed forms only (fast); `exact`: the bounds integrated over the "
    "exact COR sketch (costs about (n_nodes + n_nodes // 2) sketches per bound); "
    "`both` (default): both and their difference."
)
N_NODES_DESCRIPTION = (
    f"Gauss-Legendre nodes of an exact bound, {GROSS_MIN_N_NODES}..{GROSS_MAX_N_NODES}; the rule with "
    "n_nodes // 2 nodes gives the quadrature error estimate."
)
N_POINTS_DESCRIPTION = (
    f"Boundary points of each elementary locus of the exact sketches, {MIN_N_POINTS}..{SKETCH_MAX_N_POINTS}."
)
TIME_LIMIT_DESCRIPTION = (
    f"Time budget in seconds, {TIME_LIMIT_CAP_TEXT}. A request whose exact bounds are predicted to "
    f"take longer ({SKETCH_COST.fixed_s:g} s + {SKETCH_COST.per_point_s:g} s x n_points per sketch for an "
    f"alignment, {ENCOUNTER_SKETCH_COST.fixed_s:g} s + {ENCOUNTER_SKETCH_COST.per_point_s:g} s x n_points for a "
    "disk encounter) "
    "is refused (422 at time_limit_s) before any work; between exact bounds the time spent is checked "
    "again."
)


def _positive_mu(value: float) -> float:
    if not value > 0.0:
        raise PydanticCustomError(
            "greater_than",
            "Input should be greater than 0: the disk encounter needs pusher friction (with mu_c = 0 "
            "the force passes through the disk's centre: it translates, never turns, and the "
            "encounter lasts a ln(tan(pi/4)/tan(beta/2)))",
            {"gt": 0},
        )
    return value


class PushAlignRequest(Strict):
    """A fence pushing a polygonal part until an edge lies flush (book 3.4, 4.3). The fence
    is the line with direction `fence_angle`; it advances along `push_direction` and meets
    the footprint (turned by `orientation` about its CM) from behind."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={
            "examples": [
                {"footprint": [[-1, -1], [1, -1], [1, 1], [-1, 1]], "orientation": 0.5235987755982988,
                 "fence_angle": 1.5707963267948966, "push_direction": 0.0, "mu_c": 0.25},
            ],
        },
    )

    footprint: Polygon = Field(
        description="The part's outline, a simple polygon (either orientation), world frame. Bounds "
        "are those of its circumscribing disk about the CM (a = the largest CM-vertex distance, 3.1.8); "
        f"a must be at least {GROSS_MIN_LENGTH:g}."
    )
    center_of_mass: Point | None = Field(
        default=None,
        description="Centre of mass [x, y]; default the area centroid (an explicit one must lie in the "
        "footprint's convex hull).",
    )
    orientation: Angle = Field(
        default=0.0, description="The footprint is turned by this angle (radians, CCW) about its CM."
    )
    fence_angle: Angle = Field(
        description="Direction of the fence face, radians (theta and theta + pi are the same fence)."
    )
    push_direction: Angle = Field(
        default=0.0, description="Direction in which the fence advances, radians; not parallel to the fence."
    )
    mu_c: MuC = Field(
        default=0.0,
        description=f"Friction coefficient between fence and part, [0, {MAX_MU_C:g}]. 0: the frictionless "
        "fence of 3.4, (3.41); > 0: 4.3.",
    )
    method: GrossMethod = Field(default="both", description=METHOD_DESCRIPTION)
    n_nodes: NNodes = Field(default=ALIGN_DEFAULT_N_NODES, description=N_NODES_DESCRIPTION)
    n_points: SketchPoints = Field(default=GROSS_DEFAULT_N_POINTS, description=N_POINTS_DESCRIPTION)
    time_limit_s: TimeLimit = Field(default=DEFAULT_TIME_LIMIT_S, description=TIME_LIMIT_DESCRIPTION)
    quasi_static: QuasiStaticIn | None = Field(
        default=None,
        description="Optional: the fence's speed and the table's friction; the answer then says whether "
        "the speed is quasi-static for this part (6.8).",
    )


class PushDiskEncounterRequest(Strict):
    """A point pusher moving in a straight line pushes a disk aside (book 4.4, figure
    4-10). Give the collision parameter `beta_initial` or the `offset` of the pusher's line
    from grazing (4.24), exactly one."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={
            **exactly_one_of(("beta_initial", "offset")),
            "examples": [{"disk_radius": 1.0, "beta_initial": 0.7853981633974483, "mu_c": 0.5}],
        },
    )

    disk_radius: GrossLength = Field(description=f"Radius a of the disk, [{GROSS_MIN_LENGTH:g}, {MAX_DISK_RADIUS:g}].")
    beta_initial: Annotated[
        float,
        Field(strict=True, allow_inf_nan=False,
              json_schema_extra={"exclusiveMinimum": 0, "exclusiveMaximum": 1.5707963267948966}),
    ] | None = Field(
        default=None,
        description="Collision parameter at first contact, radians, 0 < beta < pi/2: the pusher's line is "
        "a sin(beta) from the disk's centre. Give this or `offset`.",
    )
    offset: GrossLength | None = Field(
        default=None,
        description="How far inside the grazing line the pusher's line passes, d = a (1 - sin beta) (4.24); "
        "0 < d < a. Give this or `beta_initial`.",
    )
    mu_c: MuCPositive = Field(
        description=f"Friction coefficient between pusher and disk, (0, {MAX_MU_C:g}] (the COR sketch needs "
        "friction)."
    )
    method: GrossMethod = Field(default="both", description=METHOD_DESCRIPTION)
    n_nodes: NNodes = Field(default=ENCOUNTER_DEFAULT_N_NODES, description=N_NODES_DESCRIPTION)
    n_points: SketchPoints = Field(default=GROSS_DEFAULT_N_POINTS, description=N_POINTS_DESCRIPTION)
    time_limit_s: TimeLimit = Field(default=DEFAULT_TIME_LIMIT_S, description=TIME_LIMIT_DESCRIPTION)
    quasi_static: QuasiStaticIn | None = Field(
        default=None,
        description="Optional: the pusher's speed and the table's friction; the answer then says whether "
        "the speed is quasi-static for this disk (6.8).",
    )

    @field_validator("beta_initial")
    @classmethod
    def _beta_range(cls, value: float | None) -> float | None:
        if value is not None and not 0.0 < value < 0.5 * math.pi:
            raise PydanticCustomError(
                "beta_range",
                "Input should lie strictly between 0 (a head-on push through the centre) and pi/2 "
                "(grazing): the collision parameter of 4.4",
                {},
            )
        return value

    @field_validator("mu_c")
    @classmethod
    def _positive_mu_c(cls, value: float) -> float:
        return _positive_mu(value)


# --- responses ----------------------------------------------------------------------------


class QuasiStaticCheckOut(Out):
    """Whether the given speed is within the quasi-static limit of 6.8 for this part (the
    verdict of POST /v1/push/quasistatic)."""

    within_quasi_static: bool = Field(description="verdict == quasi_static: the bounds of this answer apply.")
    verdict: Literal["quasi_static", "transitional", "inertial"] = Field(
        description="On the ratio speed / v_qs (6.7) against the service's thresholds (`thresholds` of the "
        "quasi-static answer; 0.3 and 1): 'quasi_static', 'transitional', or 'inertial' (inertia as large as friction)."
    )
    message: str = Field(
        description="The verdict in words, with the ratio speed / v_qs and how far the part slides and turns after "
        "release at this speed."
    )
    speed: float = Field(
        description="Speed of the pusher, as given in `quasi_static.speed`, in the request's length unit per second."
    )
    mu_s: float = Field(
        description="Friction coefficient between part and table, as given in `quasi_static.mu_s`."
    )
    g: float = Field(
        description="Gravitational acceleration used, in the request's length unit per s^2."
    )
    g_source: Literal["g", "length_unit"] = Field(
        description="Where g came from: 'g' (given) or 'length_unit' (9.81 m/s^2 converted to the named unit)."
    )
    length_unit: LengthUnit | None = Field(
        description="The `quasi_static.length_unit` ('m', 'cm', 'mm', 'um', 'in' or 'ft'); null when `g` was given "
        "instead."
    )
    quasi_static: QuasiStaticParameterOut = Field(description="6.8.3, (6.7): speed / v_qs.")
    angular: ErrorSpeedOut = Field(description="6.8.1, (6.3): for the book's 5-degree angular error.")
    translational: ErrorSpeedOut = Field(description="6.8.2, (6.6): for the book's X = a/7.")


class BoundOut(Out):
    """One bound on a gross motion: exact (from the exact COR sketch), closed form (the
    book's), and exact - closed_form. A field is null when the method did not compute it or
    the book has no closed form for it."""

    exact: float | None = Field(description="From the exact COR sketch (length or radians).")
    quadrature_error: float | None = Field(
        description="|rule(n_nodes) - rule(n_nodes // 2)| of the exact bound; 0 when it is itself a closed form."
    )
    closed_form: float | None = Field(description="The book's closed form.")
    equation: str | None = Field(description="Which closed form.")
    difference: float | None = Field(description="exact - closed_form.")


class FencePieceOut(Out):
    beta_start: float = Field(
        description="beta where the stretch begins, radians (the book's fence frame, after the reflection when "
        "mirrored)."
    )
    beta_end: float = Field(
        description="beta where the stretch ends, radians (the book's fence frame, after the reflection when "
        "mirrored)."
    )
    regime: Literal["frictionless", "sticking", "slipping_down", "slipping_up"] = Field(
        description="Slowest COR of the stretch: the tip of {COR}_alpha (3.41); B, the lower end of the "
        "sticking locus (4.7)-(4.8); the tip of {COR}_(alpha+nu) or {COR}_(alpha-nu) ((4.6), corrected)."
    )
    push: float = Field(description="The closed form's push over the stretch (length).")
    equation: str = Field(
        description="The closed form of the stretch's regime: '(3.41)', '(4.8)', or '(4.6) corrected, tip of "
        "{COR}_(alpha+nu)' / '{COR}_(alpha-nu)'."
    )


class FenceBoundOut(BoundOut):
    pieces: list[FencePieceOut] | None = Field(
        default=None, description="The closed form's stretches of constant regime (longest push only)."
    )
    transitions: list[float] | None = Field(
        default=None, description="beta where the regime changes, (4.4) (longest push only)."
    )
    exact_sources: list[str] | None = Field(
        default=None, description="The loci in which the exact extreme CORs lie along the way (sticking, "
        "slipping_up, slipping_down)."
    )
    exact_time_s: float | None = Field(default=None, description="Time of the exact bound, seconds.")


class FenceSlipOut(Out):
    """How far the fence face slips past the contact vertex while the part turns (4.3),
    from the exact COR sketch (the book has no closed form). Positive along `direction`."""

    most_positive: float = Field(description="The largest slip along `direction` any pressure distribution allows (length).")
    most_negative: float = Field(description="The smallest (most negative) slip along `direction` (length).")
    quadrature_error_positive: float = Field(description="Quadrature error estimate of most_positive.")
    quadrature_error_negative: float = Field(description="Quadrature error estimate of most_negative.")
    direction: list[float] = Field(
        description="World unit vector along the fence face: slip of the fence relative to the part's contact "
        "vertex (the vertex moves the other way relative to the fence)."
    )
    exact_time_s: float | None = Field(default=None, description="Time of the exact slip bounds, seconds.")


class FenceStageOut(Out):
    contact_vertex_index: int = Field(description="The vertex the part turns about (index into `footprint`).")
    flush_edge_vertex_indices: list[int] = Field(description="[contact, other end] of the hull edge that comes flush.")
    flush_edge_is_polygon_edge: bool = Field(description="False: the edge bridges a concavity of the footprint.")
    flush_edge_stable: bool = Field(
        description="The frictionless line of force through the CM meets the flush edge: the part stops here."
    )
    contact_distance: float = Field(description="c: distance of the contact vertex from the CM (length).")
    contact_fence_frame: list[float] = Field(description="c (-cos beta_initial, sin beta_initial), the book's fence frame.")
    beta_initial: float = Field(description="Angle between the line of motion and the line from the contact to the CM (rad).")
    beta_final: float = Field(description="pi - alpha - vertex_edge_angle: beta when the edge is flush (rad).")
    vertex_edge_angle: float = Field(description="psi: from the ray to the CM clockwise to the flush edge (rad).")
    rotation: float = Field(description="beta_final - beta_initial: the angle the part turns (rad).")
    orientation_initial: float = Field(description="The part's world orientation at the start of the stage (rad).")
    orientation_final: float = Field(
        description="The part's world orientation at the end of the stage, when its edge is flush, radians (CCW)."
    )
    longest_push: FenceBoundOut = Field(description="Longest push of the fence over the stage (length).")
    shortest_push: FenceBoundOut = Field(description="Shortest push over the stage (length).")
    slip: FenceSlipOut | None = Field(
        default=None, description="Slip of the fence along the part over the stage (method exact or both)."
    )


class FenceEdgeOut(Out):
    vertex_indices: list[int] = Field(description="Indices into `footprint` of the edge's ends.")
    points: list[list[float]] = Field(description="The ends in the world frame, in the initial orientation.")


class FenceGeometryOut(Out):
    disk_radius: float = Field(description="a: the footprint's circumradius about the CM (3.1.8).")
    center_of_mass: list[float] = Field(
        description="The part's centre of mass [x, y], world frame (the footprint's area centroid unless given)."
    )
    alpha: float = Field(
        description="The book's alpha in the fence frame (after the reflection when `mirrored`): the angle "
        "from the push direction to the fence face, in (0, pi)."
    )
    alpha_unmirrored: float = Field(description="alpha before the reflection.")
    fence_normal: list[float] = Field(description="Unit normal of the fence into the part (n . p > 0), world.")
    sense: Literal["cw", "ccw", "none"] = Field(description="The part's sense of turning in the world frame.")
    mirrored: bool = Field(
        description="The part turns counter-clockwise: the problem was reflected across the line of motion "
        "through the CM (y -> -y in the fence frame, alpha -> pi - alpha) onto the book's clockwise case; "
        "lengths and angles turned are unchanged."
    )
    first_contact: FenceEdgeOut = Field(description="The vertex the fence touches first (one index and point).")
    already_flush: bool = Field(description="An edge is flush and stable at first contact: zero push.")
    initial_flush_edge: list[int] | None = Field(description="An edge flush at first contact (stable or not).")
    final_edge: FenceEdgeOut = Field(description="The edge flush with the fence at the end.")
    total_rotation: float = Field(description="Sum of the stages' turns (rad).")
    final_orientation: float = Field(description="The part's world orientation at the end (rad).")
    below_line_of_motion: bool = Field(
        description="Some stage starts with beta_initial <= 0 (an oblique fence): answered only for mu_c = 0."
    )


class ExactBoundsRun(Out):
    """How the exact bounds of a gross-motion answer were computed (the end of both answers)."""

    reference: str = Field(
        description="The book's sections and equations the answer rests on, as text."
    )
    n_nodes: int = Field(
        description="Gauss-Legendre nodes of each exact bound, as asked."
    )
    n_points: int = Field(
        description="Boundary points of each elementary locus of the exact sketches, as asked."
    )
    time_limit_s: float = Field(
        description="The request's time limit (its `time_limit_s` or the route's default), seconds."
    )
    predicted_time_s: float = Field(
        description="The cost model's prediction for the exact bounds, seconds (0 for method closed_form); a request "
        "predicted over its time limit is refused."
    )
    elapsed_ms: float = Field(description=ELAPSED_MS_DESCRIPTION)


class PushAlignResponse(ExactBoundsRun):
    message: str = Field(
        description="What happens, in words: the first contact vertex, the sense and angle turned, the flush edge, "
        "the longest push; warns of a large quadrature error."
    )
    method: GrossMethod = Field(
        description="The method asked for: 'closed_form', 'exact' or 'both'."
    )
    mu_c: float = Field(
        description="Friction coefficient between fence and part, as given (0: the frictionless fence of 3.4)."
    )
    nu: float = Field(description="atan(mu_c), half-angle of the friction cone (rad).")
    geometry: FenceGeometryOut = Field(
        description="The alignment's geometry: a, CM, the book's alpha, fence normal, sense, reflection, first "
        "contact, flush edges, total rotation, final orientation."
    )
    stages: list[FenceStageOut] = Field(
        description="The turns until a stable edge is flush: the first is the book's problem; more follow "
        "when a flush edge is not stable (the CM's foot is off it). Empty when nothing turns."
    )
    longest_push: BoundOut = Field(description="Sum over the stages: the longest push the fence may need (length).")
    shortest_push: BoundOut = Field(description="Sum over the stages: the shortest push that can align the part.")
    slip: FenceSlipOut | None = Field(
        description="Sum over the stages of the slip bounds (every stage slides along the same fence face); null "
        "for method closed_form. exact_time_s is the total."
    )
    quasi_static: QuasiStaticCheckOut | None = Field(
        description="Whether the fence's speed is quasi-static for this part as a uniform lamina (6.8); null unless "
        "`quasi_static` was given."
    )
    note: str = Field(
        description="Fixed text on what the bounds mean: circumscribing-disk bounds (3.1.8), closed forms as "
        "approximations, when a stage ends and the part stops."
    )


class SketchIOut(Out):
    onset_beta: float = Field(description="atan(2 mu_c): for beta above it the COR sketch is of type i (4.17).")
    at_start: bool = Field(description="The sketch is of type i already at beta_initial.")
    occurs: bool = Field(
        description="Sketch i occurs somewhere in [beta_initial, pi/2) (always for finite mu_c: 4.4.1.2)."
    )
    note: str = Field(
        description="Sketch i in words: tan beta > 2 mu_c (4.17), (4.16) then overestimates, and where it begins (or "
        "that the whole encounter is in it)."
    )


class PushDiskEncounterResponse(ExactBoundsRun):
    message: str = Field(
        description="The encounter in words: a, beta, offset, mu_c, the greatest length, the greatest rotation pi/2 - "
        "beta, where sketch i begins; warns of a large quadrature error."
    )
    method: GrossMethod = Field(
        description="The method asked for: 'closed_form', 'exact' or 'both'."
    )
    disk_radius: float = Field(
        description="Radius a of the disk, as given (request's length unit)."
    )
    beta_initial: float = Field(
        description="Collision parameter at first contact, radians: as given, or derived from `offset` by (4.24)."
    )
    beta_final: float = Field(description="pi/2: the disk is left tangent to the pusher's path.")
    offset: float = Field(description="d = a (1 - sin beta_initial) (4.24).")
    beta_source: Literal["beta_initial", "offset"] = Field(
        description="Which request field gave the collision parameter: 'beta_initial' or 'offset'."
    )
    mu_c: float = Field(
        description="Friction coefficient between pusher and disk, as given."
    )
    nu: float = Field(
        description="atan(mu_c), half-angle of the friction cone, radians."
    )
    length_greatest: BoundOut = Field(description="Greatest length of the encounter; closed form (4.16).")
    length_least: BoundOut = Field(description="Least length of the encounter (no closed form, 4.4.1.3).")
    length_frictionless: float = Field(
        description="For comparison: the length with mu_c = 0 (the disk translates), half of (4.16)."
    )
    rotation_greatest: BoundOut = Field(description="Greatest rotation of the disk (rad); (4.18) = pi/2 - beta_initial.")
    rotation_least: BoundOut = Field(description="Least rotation of the disk (rad; 4.4.2.2, numerical only).")
    sketch_i: SketchIOut = Field(
        description="Where the COR sketch is of type i (tan beta > 2 mu_c, 4.17): onset_beta, at_start, occurs and a "
        "note."
    )
    quasi_static: QuasiStaticCheckOut | None = Field(
        description="Whether the pusher's speed is quasi-static for this disk (6.8); null unless `quasi_static` was "
        "given."
    )
    note: str = Field(
        description="Fixed text on the bounds: the disk is the book's exact case, where (4.16) errs, and (4.18) "
        "re-derived as pi/2 - beta_initial."
    )
