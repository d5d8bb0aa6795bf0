"""Request and response schemas of ``POST /v1/cor/solve`` (the motion for a known
pressure distribution) and ``POST /v1/cor/tripod-statistics`` (figures 3-5 and 7-2).

Conventions are those of :mod:`service.common.fields`: world frame, radians, lengths in
any consistent unit, strict finite numbers, unknown fields rejected. Forces and powers of
the pushed workpiece are divided by mu_s times its weight (dimensionless); motions are per
unit advance of the pusher.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import ConfigDict, Field, StrictBool

from service.common.fields import (
    DISK_OR_FOOTPRINT,
    Coordinate,
    DiskRadius,
    MuC,
    Point,
    PushIn,
    Strict,
    Vec2,
    exactly_one_of,
)
from service.common.responses import ELAPSED_MS_DESCRIPTION, Out
from service.limits import (
    DEFAULT_PRESSURE_RESOLUTION,
    MAX_BATCH,
    MAX_BATCH_POINTS,
    MAX_BATCH_SLOW,
    MAX_COLUMN_POINTS,
    MAX_HISTOGRAM_BINS,
    MAX_MU_C,
    MAX_PRESSURE_FOOTPRINT_VERTICES,
    MAX_PRESSURE_RESOLUTION,
    MAX_SUPPORT_POINTS,
    MAX_SUPPORT_POINTS_SLOW,
    MAX_TRIPOD_CORS,
    MAX_TRIPODS,
    MAX_WEIGHT,
)

# ---------------------------------------------------------------------------------------
# Request building blocks
# ---------------------------------------------------------------------------------------

Weight = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0.0, le=MAX_WEIGHT)]
PositiveWeight = Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0.0, le=MAX_WEIGHT)]
ForwardMethod = Literal["newton", "cvxpy", "casadi"]


class SupportIn(Strict):
    """A discrete pressure distribution: point masses on which the workpiece rests (3.1.5)."""

    points: Annotated[list[Point], Field(min_length=1, max_length=MAX_SUPPORT_POINTS)] = Field(
        description=f"Support points [x, y], world frame; 1..{MAX_SUPPORT_POINTS} with method "
        f"newton, at most {MAX_SUPPORT_POINTS_SLOW} with cvxpy / casadi."
    )
    weights: Annotated[list[Weight], Field(min_length=1, max_length=MAX_SUPPORT_POINTS)] = Field(
        description=f"One weight >= 0 (at most {MAX_WEIGHT:g}) per point, not all zero; they are "
        "normalised to sum 1. Their weighted centroid must be the centre of mass."
    )


Column = Annotated[list[Coordinate], Field(min_length=1, max_length=MAX_COLUMN_POINTS)]
Layout = Literal["rows", "columns"]


class SupportColumnsIn(Strict):
    """A batch of supports of one size as columns: flat arrays, support after support
    (the points of support j are entries j*k .. j*k+k-1)."""

    support_size: Annotated[int, Field(strict=True, ge=1, le=MAX_SUPPORT_POINTS)] = Field(
        description="k, the number of points of every support (3 for tripods)."
    )
    x: Column = Field(description=f"x of every point, world frame (length); B*k entries, at most {MAX_COLUMN_POINTS}.")
    y: Column = Field(description="y of every point, world frame (length); as many entries as `x`.")
    weights: Annotated[list[PositiveWeight], Field(min_length=1, max_length=MAX_COLUMN_POINTS)] = Field(
        description=f"Weight of every point, > 0 (at most {MAX_WEIGHT:g}); normalised to sum 1 per support, "
        "whose weighted centroid must be the centre of mass. Points of a support must be distinct."
    )


class PressureIn(Strict):
    """A modelled pressure distribution (figure 7-1)."""

    kind: Literal["uniform"] = Field(description="Only 'uniform' pressure for now.")
    footprint: Annotated[
        list[Point] | None,
        Field(min_length=3, max_length=MAX_PRESSURE_FOOTPRINT_VERTICES),
    ] = Field(
        default=None,
        description="The pressed region as a simple polygon (either orientation, "
        f"3..{MAX_PRESSURE_FOOTPRINT_VERTICES} vertices); its area centroid is the centre of "
        "mass. Omitted or null: the disk of radius `disk_radius` about the centre of mass.",
    )
    resolution: Annotated[int, Field(strict=True, ge=1, le=MAX_PRESSURE_RESOLUTION)] = Field(
        default=DEFAULT_PRESSURE_RESOLUTION,
        description="Rings of the disk discretisation (6 n^2 annular-sector cells) or "
        "subdivisions of each triangle of the polygon (n^2 cells per triangle). The cell count "
        f"is limited to {MAX_SUPPORT_POINTS} (newton) or {MAX_SUPPORT_POINTS_SLOW} (cvxpy, casadi).",
    )


class CorSolveRequest(PushIn):
    """The motion of a pushed workpiece for a known pressure distribution (book 3.2-3.3.3,
    4.1): exactly one of `support`, `supports` (a batch), `batch` (a batch as columns) or
    `pressure`."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={
            **exactly_one_of(("support", "supports", "batch", "pressure")),
            "examples": [
                {
                    "contact_point": [-0.5, -0.3],
                    "edge_angle": 1.5707963267948966,
                    "support": {"points": [[0.6, 0.0], [-0.3, 0.5], [-0.3, -0.5]], "weights": [1, 1, 1]},
                },
            ],
        },
    )

    center_of_mass: Point | None = Field(
        default=None,
        description="Centre of mass [x, y]. Default: [0, 0]; with `pressure.footprint` the "
        "polygon's area centroid (an explicit one must equal it).",
    )
    disk_radius: DiskRadius | None = Field(
        default=None,
        description="Radius a of a disk about the CM bounding the workpiece (length). Default: the "
        "largest distance of a support point (or footprint vertex) or of the contact from the "
        "CM. Required for uniform pressure on the disk. An explicit one must not be smaller "
        "than the support's extent.",
    )
    mu_c: MuC = Field(
        default=0.0,
        description=f"Coefficient of friction between pusher and workpiece, 0..{MAX_MU_C:g} (4.1). "
        "0: frictionless pusher.",
    )
    method: ForwardMethod = Field(
        default="newton",
        description="Back end: 'newton' (exact batched Newton, default), 'cvxpy' (Clarabel "
        "cone programme, polished), 'casadi' (IPOPT on the dual).",
    )
    support: SupportIn | None = Field(default=None, description="One support: one motion.")
    supports: Annotated[list[SupportIn] | None, Field(min_length=1, max_length=MAX_BATCH)] = Field(
        default=None,
        description=f"A batch of supports: 1..{MAX_BATCH} with newton (at most {MAX_BATCH_POINTS} "
        f"points in all), at most {MAX_BATCH_SLOW} with cvxpy / casadi.",
    )
    batch: SupportColumnsIn | None = Field(
        default=None,
        description="A batch of supports of one size as columns (method newton): the fast way to send many "
        f"supports, up to {MAX_COLUMN_POINTS} points in all.",
    )
    pressure: PressureIn | None = Field(default=None, description="A modelled pressure distribution.")
    layout: Layout | None = Field(
        default=None,
        description="How a batch's motions are returned: 'rows' (`motions`, one object each; at most "
        f"{MAX_BATCH} supports) or 'columns' (`columns`, one array per quantity). Default: 'columns' for "
        "`batch`, 'rows' for `supports`. Not for a single support or a pressure.",
    )


class TripodStatisticsRequest(PushIn):
    """Random balanced tripods (3.3.3) on the disk or a footprint, their CORs (figure 3-5) and,
    with `histogram`, where the sticking CORs fall on the sticking line (figure 7-2)."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={
            **exactly_one_of(DISK_OR_FOOTPRINT),
            "examples": [
                {"disk_radius": 1.0, "contact_point": [-0.5, -0.3], "edge_angle": 1.5707963267948966,
                 "n_tripods": 1000, "seed": 7},
            ],
        },
    )

    disk_radius: DiskRadius | None = Field(default=None, description="Disk about the CM the tripods are drawn in.")
    footprint: Annotated[
        list[Point] | None,
        Field(min_length=3, max_length=MAX_PRESSURE_FOOTPRINT_VERTICES),
    ] = Field(default=None, description="Or a polygon the tripods are drawn in (its area centroid is the CM).")
    center_of_mass: Point | None = Field(default=None, description="Centre of mass (default [0, 0] or the area centroid).")
    n_tripods: Annotated[int, Field(strict=True, ge=1, le=MAX_TRIPODS)] = Field(
        description=f"Number of tripods, 1..{MAX_TRIPODS}."
    )
    seed: Annotated[int, Field(strict=True, ge=0, le=2**63 - 1)] = Field(
        description="Seed of the random generator: the same request gives the same answer."
    )
    mu_c: MuC = Field(default=0.0, description="Pusher friction for the COR sample (figure 3-5 uses 0).")
    histogram: StrictBool = Field(
        default=False,
        description="Also the sticking-line histogram of figure 7-2 (solved again with "
        "`histogram_mu_c`).",
    )
    histogram_mu_c: MuC = Field(default=MAX_MU_C, description="mu_c of the histogram (7.7: a large one).")
    bins: Annotated[int, Field(strict=True, ge=1, le=MAX_HISTOGRAM_BINS)] = Field(
        default=50, description="Histogram bins."
    )
    span: Annotated[list[Annotated[float, Field(strict=True, allow_inf_nan=False, ge=-1e9, le=1e9)]] | None,
                    Field(min_length=2, max_length=2)] = Field(
        default=None,
        description="[lo, hi] of the histogram, signed distance from the contact along the push "
        "direction turned +90 degrees (length). Default: the 1st..99th percentile.",
    )
    include_cors: StrictBool = Field(default=True, description="Return the CORs themselves (n_tripods points).")
    layout: Layout = Field(
        default="rows",
        description=f"How the CORs are returned: 'rows' (`cors`, [x, y] or null each; at most {MAX_TRIPOD_CORS} "
        f"tripods) or 'columns' (`cor_columns`, {{x, y}}; up to {MAX_TRIPODS}).",
    )


# ---------------------------------------------------------------------------------------
# Responses
# ---------------------------------------------------------------------------------------


Sense = Literal["cw", "ccw", "none"]


class MotionOut(Out):
    """The motion of the workpiece per unit advance of the pusher, world frame."""

    status: Literal["optimal", "not_converged", "inconsistent"] = Field(
        description="'optimal' when the KKT residual is within tolerance and the friction mode's "
        "own assumptions hold; 'inconsistent' when the mode's assumptions fail; else 'not_converged'."
    )
    method: str = Field(description="Back end that produced the answer.")
    mode: Literal["frictionless", "sticking", "slipping_up", "slipping_down"] = Field(
        description="Contact mode (4.1): 'frictionless' for mu_c = 0."
    )
    kind: Literal["rotation", "translation"] = Field(description="'translation' when the COR is at infinity.")
    cor: Vec2 | None = Field(description="Centre of rotation [x, y]; null for a translation.")
    velocity_cm: Vec2 = Field(description="Velocity of the CM per unit push (dimensionless).")
    rotation_per_push: float = Field(description="omega: rotation per unit push, rad per length, CCW positive (3.3).")
    slip_per_push: float = Field(
        description="Slip of the pusher along the edge per unit push, positive along the book's "
        "alpha (the normal turned +90 degrees) (3.2)."
    )
    sense: Sense = Field(description="Sense of rotation of the solved motion.")
    mason_sense: Sense = Field(description="Sense by Mason's rules (1.6.2), from the push alone.")
    mason_agrees: bool = Field(description="Whether `sense` equals `mason_sense`.")
    power: float = Field(description="Frictional power per unit push / (mu_s W) (3.6).")
    contact_force: Vec2 = Field(description="Force of the pusher on the workpiece / (mu_s W), world vector.")
    kkt_residual: float = Field(description="Dimensionless KKT residual of the minimum-power problem.")
    gap: float | None = Field(
        description="power - work rate of the contact force on the part (0 at the optimum)."
    )
    cor_on_support: int | None = Field(
        description="Index (into the request's points) of the support point the COR sits on, if any. "
        "For `pressure`: index of the discretisation cell."
    )
    iterations: int | None = Field(description="Newton iterations (0 for a COR found on a support point), or IPOPT's for method casadi.")
    solve_time_ms: float | None = Field(description="Solver time of this motion, ms; null in newton batches.")
    raw_twist_error: float | None = Field(
        default=None,
        description="cvxpy: distance (normalised units) between Clarabel's own answer and the polished one.",
    )


class ImpactOut(Out):
    """The impact-limit COR (7.1) of a body with the support's mass distribution."""

    cor: Vec2 | None = Field(description="COR of the impulsive motion; null for a pure translation.")
    distance: float | None = Field(description="rho^2 / |alpha . c|: its distance from the CM.")
    radius_of_gyration: float = Field(description="rho about the CM (length).")
    source: Literal["support", "uniform_disk", "uniform_polygon"] = Field(
        description="Whose radius of gyration: the point masses of the support, or the uniform lamina."
    )


class BatchSummaryOut(Out):
    n: int = Field(description="Supports solved.")
    converged: int = Field(description="Of them with status 'optimal'.")
    translations: int = Field(description="Of them translating (cor null).")
    fallbacks: int = Field(description="Newton solves re-done by the conic solver.")
    support_sizes: list[int] = Field(description="Distinct support sizes (after merging coincident points).")


class PressureSummaryOut(Out):
    kind: Literal["uniform"] = Field(
        description="Kind of pressure distribution: always 'uniform'."
    )
    region: Literal["disk", "polygon"] = Field(
        description="Where the pressure lies: 'disk' (no `pressure.footprint`: the disk of radius `disk_radius`) or "
        "'polygon' (the footprint)."
    )
    resolution: int = Field(
        description="The request's `pressure.resolution`: rings of the disk (6 n^2 cells) or subdivisions of each "
        "triangle of the polygon (n^2 cells per triangle)."
    )
    n_cells: int = Field(description="Cells of the discretisation (point masses solved).")


Float = float | None


class MotionColumnsOut(Out):
    """The motions of a batch as columns: entry j of every array is support j (the fields of
    a motion, per unit advance of the pusher, world frame)."""

    status: list[Literal["optimal", "not_converged", "inconsistent"]] = Field(
        description="As a motion's `status`: 'optimal', 'not_converged' or 'inconsistent'."
    )
    mode: list[Literal["frictionless", "sticking", "slipping_up", "slipping_down"]] = Field(
        description="Contact mode (4.1): 'frictionless' for mu_c = 0."
    )
    cor_x: list[Float] = Field(description="x of the centre of rotation; null for a translation.")
    cor_y: list[Float] = Field(description="y of the centre of rotation; null for a translation.")
    velocity_cm_x: list[float] = Field(description="x of the CM's velocity per unit push (dimensionless).")
    velocity_cm_y: list[float] = Field(description="y of the CM's velocity per unit push (dimensionless).")
    rotation_per_push: list[float] = Field(description="omega: rotation per unit push, rad per length, CCW positive (3.3).")
    slip_per_push: list[float] = Field(
        description="Slip of the pusher along the edge per unit push, positive along the normal turned +90 degrees (3.2)."
    )
    sense: list[Sense] = Field(description="Sense of rotation of each motion.")
    mason_sense: Sense = Field(description="Sense by Mason's rules (1.6.2), from the push alone: one for the batch.")
    power: list[float] = Field(description="Frictional power per unit push / (mu_s W) (3.6).")
    contact_force_x: list[float] = Field(description="x of the pusher's force on the workpiece / (mu_s W).")
    contact_force_y: list[float] = Field(description="y of the pusher's force on the workpiece / (mu_s W).")
    kkt_residual: list[float] = Field(description="Dimensionless KKT residual of each minimum-power problem.")
    gap: list[Float] = Field(description="power - work rate of the contact force on the part (0 at the optimum).")
    cor_on_support: list[int | None] = Field(
        description="Index within its support of the point the COR sits on (into the request's points of that "
        "support), or null."
    )
    iterations: list[int] = Field(description="Newton iterations of each motion (0 for a COR found on a support point).")


class CorSolveResponse(Out):
    """Motions for known pressure distributions."""

    input: Literal["support", "supports", "batch", "pressure"] = Field(description="Which of the four inputs was given.")
    disk_radius: float = Field(description="Disk radius a used (length).")
    center_of_mass: Vec2 = Field(description="Centre of mass used.")
    mu_c: float = Field(
        description="Pusher-workpiece friction coefficient used (the request's `mu_c`; 0: frictionless pusher)."
    )
    method: str = Field(
        description="Back end asked for: 'newton', 'cvxpy' or 'casadi' (each motion's `method` says which produced "
        "it)."
    )
    motion: MotionOut | None = Field(description="The motion (`support`, `pressure`); null for a batch.")
    impact: ImpactOut | None = Field(description="Impact-limit COR (7.1) (`support`, `pressure`); null for a batch.")
    motions: list[MotionOut] | None = Field(description="One motion per support, in order (a batch with layout 'rows').")
    columns: MotionColumnsOut | None = Field(
        default=None, description="The motions as columns, in order (a batch with layout 'columns')."
    )
    batch: BatchSummaryOut | None = Field(description="Counts of a batch (`supports` or `batch`).")
    pressure: PressureSummaryOut | None = Field(description="The discretisation (`pressure`).")
    warnings: list[str] = Field(
        description="Non-fatal remarks: the contact outside the disk, motions that are not optimal, an impact that is "
        "null because all the mass is at the CM."
    )
    solve_time_ms: float = Field(description="Time in the solver, ms.")
    elapsed_ms: float = Field(description=ELAPSED_MS_DESCRIPTION)


class HistogramOut(Out):
    edges: list[float] = Field(description="Bin edges: signed distance from the contact along J p (length).")
    counts: list[int] = Field(
        description="Number of sticking CORs in each bin between consecutive `edges` (one count per bin)."
    )
    sticking_fraction: float = Field(description="Fraction of tripods that stick.")
    outside_range: int = Field(description="Sticking CORs outside [edges[0], edges[-1]].")
    mu_c: float = Field(
        description="Pusher friction with which the tripods were solved again for the histogram (the request's "
        "`histogram_mu_c`)."
    )
    solve_time_ms: float = Field(
        description="Time to draw and solve the histogram's tripods and bin them, milliseconds."
    )


class CorColumnsOut(Out):
    """CORs as columns: entry j is tripod j; null in both for a translation."""

    x: list[Float] = Field(description="x of each COR, world frame (length).")
    y: list[Float] = Field(description="y of each COR, world frame (length).")


class TripodStatisticsResponse(Out):
    status: Literal["optimal", "not_converged"] = Field(
        description="'optimal' when every tripod's solve converged (KKT residual within tolerance)."
    )
    max_kkt_residual: float = Field(description="Largest KKT residual over the sample (dimensionless).")
    n_tripods: int = Field(
        description="Number of random tripods drawn and solved (the request's `n_tripods`)."
    )
    seed: int = Field(
        description="Seed of the random generator (the request's `seed`): the same request gives the same answer."
    )
    disk_radius: float = Field(
        description="Disk radius a used: the request's `disk_radius`, or the footprint's circumradius about the CM "
        "(request's length unit)."
    )
    center_of_mass: Vec2 = Field(
        description="Centre of mass used, [x, y] in the world frame ([0, 0] or the footprint's area centroid unless "
        "given)."
    )
    mu_c: float = Field(
        description="Pusher friction coefficient of the COR sample (the request's `mu_c`; figure 3-5 uses 0)."
    )
    cors: list[Vec2 | None] | None = Field(description="CORs of the tripods (null entries: translations), layout 'rows'.")
    cor_columns: CorColumnsOut | None = Field(default=None, description="CORs of the tripods, layout 'columns'.")
    converged: int = Field(
        description="Number of tripods whose solve converged (KKT residual within tolerance and the contact mode "
        "consistent)."
    )
    translations: int = Field(
        description="Number of tripods whose motion is a translation (the COR at infinity; their entries in `cors`, "
        "when returned, are null)."
    )
    fallbacks: int = Field(
        description="Number of tripods whose Newton solve failed and was re-done by the conic solver."
    )
    mode_counts: dict[str, int] = Field(description="Tripods per contact mode.")
    histogram: HistogramOut | None = Field(
        description="The sticking-line histogram of figure 7-2: {edges, counts, sticking_fraction, outside_range, "
        "mu_c, solve_time_ms}; null unless `histogram` was asked for."
    )
    solve_time_ms: float = Field(
        description="Time the solver took for the tripod batch, plus the histogram's second sample when asked for, "
        "milliseconds."
    )
    elapsed_ms: float = Field(description=ELAPSED_MS_DESCRIPTION)
