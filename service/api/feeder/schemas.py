"""Request and response schemas of ``POST /v1/feeder/map`` and ``POST /v1/feeder/simulate``
(book 5.1, 5.2, 6.4-6.6). Frames: the belt carries parts in -y; a fence's ``angle`` is its
angle from the x-axis in (-pi/2, pi/2) radians, positive when it hangs from the belt's
right side (the part slides down it to the left). Orientations are radians in [0, 2 pi);
a set of orientations is a list of closed arcs [start, width] counter-clockwise.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import ConfigDict, Field

from service.common.fields import OUTLINE_RULES, UNIQUE, Angle, MuC, Point, Strict, TimeLimit
from service.common.responses import ELAPSED_MS_DESCRIPTION, Out
from service.limits import (
    FEEDER_MAX_CATALOGUE_PARTS,
    FEEDER_MAX_DESIGN_DEPTH,
    FEEDER_MAX_FENCE_LENGTH_RADII,
    FEEDER_MAX_FENCES,
    FEEDER_MAX_PART_CONTACTS,
    FEEDER_MAX_RAYS_PER_AIM,
    FEEDER_MAX_RESOLUTION,
    FEEDER_MAX_STEPS,
    FEEDER_MAX_SUPPORT_POINTS,
    FEEDER_MAX_TRAJECTORY_POINTS,
    FEEDER_MAX_VALIDATION_PARTS,
    FEEDER_MAX_VERTICES,
    FEEDER_MAX_WORLD_RADII,
    FEEDER_PART_DEFAULT_TIME_LIMIT_S,
    MAX_WEIGHT,
    MIN_POLYGON_VERTICES,
    TIME_LIMIT_CAP_TEXT,
)

Arc = Annotated[list[float], Field(min_length=2, max_length=2, description="[start, width], radians.")]


class FeederPartIn(Strict):
    vertices: Annotated[list[Point], Field(min_length=MIN_POLYGON_VERTICES, max_length=FEEDER_MAX_VERTICES,
                                           json_schema_extra=UNIQUE)] = Field(
        description=f"The part's outline [[x, y], ...] in its own frame (only its convex hull meets a fence): "
                    f"{OUTLINE_RULES}.")
    center_of_mass: Point = Field(description="The centre of mass [x, y] in the same frame, inside the hull.")


class FeederFenceIn(Strict):
    angle: Angle = Field(description="Fence angle gamma from the x-axis, radians, in (-pi/2, pi/2), not 0.")
    mu_c: MuC | None = Field(default=None, description="Contact friction between part and fence.")
    mu_c_range: Annotated[list[MuC], Field(min_length=2, max_length=2)] | None = Field(
        default=None, description="An interval [low, high] of mu_c instead of one value (maps only).")
    reach: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0.0)] | None = Field(
        default=None, description="How far the fence extends beyond the part's first contact toward its free end "
                                  "(the least over where parts meet it; the part's units; maps only). Given, the map "
                                  f"reports the initial orientations for which it may be too short (book 1.8.6); at "
                                  f"most {FEEDER_MAX_FENCE_LENGTH_RADII:g} part radii.")


Fences = Annotated[list[FeederFenceIn], Field(min_length=1, max_length=FEEDER_MAX_FENCES)]


class FeederPartBoundIn(Strict):
    contacts: Annotated[int, Field(strict=True, ge=3, le=FEEDER_MAX_PART_CONTACTS)] = Field(
        default=5, description="Contact positions per edge and mu_c at which the part's locus is searched (more: "
                               "narrower bands, slower).")
    max_rays_per_aim: Annotated[int, Field(strict=True, ge=3, le=FEEDER_MAX_RAYS_PER_AIM)] = Field(
        default=8, description="Most certified rays of one climb along the exact locus from a dipod that bounds "
                               "the slip (a degree apart, while the slip rises).")


class FeederMapRequest(Strict):
    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={"examples": [{
            "part": {"vertices": [[0, 0], [3, 0], [3.5, 1.5], [1.5, 2.5], [-0.5, 1.2]], "center_of_mass": [1.4, 1.0]},
            "fences": [{"angle": 0.7, "mu_c": 0.25}, {"angle": -0.9, "mu_c_range": [0.1, 0.3]}],
            "resolution": 360,
        }]},
    )

    part: FeederPartIn
    fences: Fences = Field(description="The fences in the order the part meets them.")
    resolution: Annotated[int, Field(strict=True, ge=0, le=FEEDER_MAX_RESOLUTION)] = Field(
        default=0, description="Cells of the circle for the product's boolean matrix (0: none; 360: 1 degree).")
    bound: Literal["disk", "part"] = Field(
        default="disk",
        description="What bounds the turns off each fence's end (5.1): `disk`, the part's circumscribing disk "
                    "(analytic loci: milliseconds per fence); or `part`, the part's own COR loci as well (dipods on "
                    "its outline and certified rays of its exact locus: 4-18 s per fence on one core, bands a few "
                    "degrees narrower; docs/benchmarks.md). Ask for `part` only when the disk's bands are too wide. "
                    "The outline must then be a simple polygon.")
    part_bound: FeederPartBoundIn | None = Field(
        default=None, description="How finely the part's own loci are searched with `bound` `part` (null: 5 contacts, "
                                  "climbs of at most 8 rays).")
    time_limit_s: TimeLimit | None = Field(
        default=None, description=f"Seconds, {TIME_LIMIT_CAP_TEXT}. Without one: the cap with `bound` `disk`; with "
                                  f"`part` {FEEDER_PART_DEFAULT_TIME_LIMIT_S:g} s, or the cap if lower (a fence takes "
                                  "seconds to a minute).")

    @property
    def deadline_s(self) -> float | None:
        """The time limit the request runs under (None: the service's default)."""
        if self.time_limit_s is None and self.bound == "part":
            return FEEDER_PART_DEFAULT_TIME_LIMIT_S
        return self.time_limit_s


class FeederBandOut(Out):
    band: list[Arc] = Field(description="Final orientations B_j (5.2).")
    kernel: list[Arc] = Field(description="Initial orientations that end in the band, K_j (5.2).")


class FeederFenceBandOut(FeederBandOut):
    edge: int = Field(description="The hull edge that leaves the fence flush (index in the hull, CCW).")
    vertex: int = Field(description="The input vertex where that edge starts.")
    turn_least: float = Field(description="Extreme B: the least turn off the fence's end, radians (5.1).")
    turn_most: float = Field(description="Extreme A: the most turn, pi/2 - |gamma| (5.1).")
    contact_lost: bool = Field(description="Whether B ends with the end leaving the edge before A.")


class FeederPartBoundOut(Out):
    loci: int = Field(description="The part's own frictionless loci searched (per edge, mu_c and contact position).")
    dipods: int = Field(description="Dipods on the outline solved (witness CORs).")
    rays: int = Field(description="Rays of the exact loci traced toward the dipods that bound the slip.")
    rays_bracketed: int = Field(description="Those whose crossing was certified (inside and outside points).")
    solver_failures: int = Field(description="Traces a failed conic solve cut short (the disk bounded there).")
    seconds: float = Field(
        description="Seconds spent on the part's own bound for this fence."
    )


class FeederFenceMapOut(Out):
    angle: float = Field(
        description="Fence angle gamma from the x-axis, radians, in (-pi/2, pi/2); positive when it hangs from the "
        "belt's right side."
    )
    mu_c_range: list[float] = Field(
        description="[low, high] of the part-fence friction coefficient mapped (both equal to mu_c when one value was "
        "given)."
    )
    jams_possible: bool = Field(description="|tan gamma| <= the highest mu_c: a flush part may jam (6.4).")
    bands: list[FeederFenceBandOut] = Field(
        description="One band per hull edge that can come flush: final orientations B_j, their kernel K_j, the edge, "
        "and the least and most turn off the end (5.2)."
    )
    jam: list[Arc] = Field(description="Initial orientations that may jam on this fence.")
    reach: float | None = Field(description="The reach asked for (null: not checked).")
    unaligned: list[Arc] = Field(description="Initial orientations from which the reach may be too short for an edge to "
                                             "come flush: the map bounds nothing there (every final orientation may "
                                             "follow). Empty when no reach was given.")
    notes: list[str] = Field(
        description="Remarks on this fence: that a flush part may jam (6.4), or that the reach may be too short for "
        "some initial orientations (1.8.6)."
    )
    locus_evaluations: int = Field(
        description="Number of COR-locus evaluations spent integrating the turns off the fence's end, over all its "
        "bands."
    )
    part_bound: FeederPartBoundOut | None = Field(
        description="What the part's own bound cost on this fence (null with the disk bound).")


class FeederProductBandOut(FeederBandOut):
    code_set: list[int] = Field(description="The first fence's kernels whose union is this kernel (5.4, 5.5).")


class FeederProductOut(Out):
    bands: list[FeederProductBandOut] = Field(
        description="The bands of the whole sequence: final orientations, their kernel of initial orientations, and "
        "the first fence's kernels that make it up (5.4, 5.5)."
    )
    jam: list[Arc] = Field(
        description="Initial orientations from which the part may jam on some fence of the sequence, as a list of "
        "arcs [start, width], radians."
    )
    unaligned: list[Arc] = Field(description="Initial orientations that may meet a fence too short to align them.")


class FeederMatrixOut(Out):
    resolution: int = Field(
        description="Cells of the circle along each axis: the matrix has this many rows (final cells) and columns "
        "(initial cells)."
    )
    rows: list[str] = Field(description="Row f (final cell) as a string of 0/1 over the initial cells (5.1).")


class FeederMapResponse(Out):
    fences: list[FeederFenceMapOut] = Field(
        description="The map of each fence finished, in the order the part meets them (all of them unless the time "
        "limit cut the work short)."
    )
    product: FeederProductOut | None = Field(description="The map of the whole sequence (null unless every fence's map was made).")
    matrix: FeederMatrixOut | None = Field(
        description="The product's boolean matrix M[f, i] on `resolution` cells of the circle (5.1); null when "
        "`resolution` is 0 or not every map was made."
    )
    bound: str = Field(description="What bounded the turns off the end: `disk` (the part's circumscribing disk) or "
                                   "`part` (its own loci as well; the reach stays bounded by the disk).")
    status: str = Field(description="ok, or time_limit (the maps finished are returned).")
    complete: bool = Field(
        description="Whether every fence's map and the product were made; false when the time limit cut the work "
        "short (status 'time_limit')."
    )
    message: str = Field(
        description="The result in words: the maps and product made and how the turns were bounded, or how many maps "
        "were made before the time limit."
    )
    solve_time_ms: float = Field(
        description="Time the maps, their product and the matrix took in the solver, milliseconds."
    )
    elapsed_ms: float = Field(description=ELAPSED_MS_DESCRIPTION)


class FeederSupportIn(Strict):
    points: Annotated[list[Point], Field(min_length=1, max_length=FEEDER_MAX_SUPPORT_POINTS)] = Field(
        description="Support points in the part's frame; their weighted centroid must be the centre of mass.")
    weights: Annotated[list[Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0.0, le=MAX_WEIGHT)]],
                       Field(min_length=1, max_length=FEEDER_MAX_SUPPORT_POINTS)]


class FeederSimFenceIn(Strict):
    angle: Angle = Field(description="Fence angle gamma, radians, in (-pi/2, pi/2), not 0.")
    mu_c: MuC = Field(description="Contact friction between part and fence.")
    end: Point | None = Field(
        default=None, description="Where the fence's free end E lies in the world frame (the belt runs in -y): give "
                                  "it, with `length`, for every fence or for none. Placed fences are met one after the "
                                  "other from the part's `start`, as on a belt (figure 1-9); otherwise each fence is "
                                  "met alone in its own frame.")
    length: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0.0)] | None = Field(
        default=None, description="A placed fence's length from E toward its root, along (cos angle, sin angle) "
                                  "times the sign of angle.")


class FeederSimulateRequest(Strict):
    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={"examples": [{
            "part": {"vertices": [[0, 0], [1, 0], [1, 1], [0, 1]], "center_of_mass": [0.5, 0.5]},
            "support": {"points": [[0.7, 0.6], [0.4, 0.65], [0.4, 0.25]], "weights": [1, 1, 1]},
            "fences": [{"angle": 0.7, "mu_c": 0.25}, {"angle": -0.8, "mu_c": 0.25}],
            "theta_initial": 0.3,
        }]},
    )

    part: FeederPartIn
    support: FeederSupportIn
    fences: Annotated[list[FeederSimFenceIn], Field(min_length=1, max_length=FEEDER_MAX_FENCES)]
    theta_initial: Angle = Field(description="The part's orientation before the first fence, radians.")
    fence_length: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0.0)] | None = Field(
        default=None, description=f"Length of every fence met alone (default 40 part radii; at most "
                                  f"{FEEDER_MAX_FENCE_LENGTH_RADII:g} radii); placed fences give their own.")
    start: Point | None = Field(
        default=None, description="With placed fences: the part's centre of mass at the start, world frame (default: "
                                  "just above the first fence, 0.7 of its length from its end). The first fence must "
                                  f"not pass through the part there; every point within {FEEDER_MAX_WORLD_RADII:g} "
                                  "part radii of the origin.")
    max_steps: Annotated[int, Field(strict=True, ge=1, le=FEEDER_MAX_STEPS)] = 20_000
    trajectory_points: Annotated[int, Field(strict=True, ge=0, le=FEEDER_MAX_TRAJECTORY_POINTS)] = Field(
        default=200, description="Trajectory samples returned per fence (evenly over the steps; 0: none).")
    check_map: bool = Field(default=True, description="Say whether each outcome lies in its fence's map.")
    time_limit_s: TimeLimit | None = None


class FeederEventOut(Out):
    push: float = Field(description="Belt travel so far in this fence's run.")
    kind: str = Field(
        description="Kind of event: 'contact', 'vertex', 'end', 'flush', 'left', 'missed', 'jam', 'stalled', "
        "'time_limit' or 'overlap'."
    )
    detail: str = Field(
        description="The event in words, e.g. 'first contact', 'edge 2 flush on the face, sliding', or the "
        "orientation at which the part left."
    )


class FeederFenceRunOut(Out):
    status: str = Field(description="left, missed (never touched the fence), jammed, step_limit, stalled (a contact the simulator cannot advance), overlap (the fence passes through the part where the run starts: fences too close) or time_limit.")
    flushed: bool = Field(description="Whether an edge came flush on the fence; the maps assume it does (a fence too "
                                      "short for the part to finish turning lets it leave still turning).")
    theta_initial: float = Field(
        description="The part's orientation when its run on this fence starts, radians (the previous fence's final "
        "orientation, or `theta_initial`)."
    )
    theta_final: float | None = Field(
        description="The part's orientation when it left the fence, radians; null unless the status is 'left' or "
        "'missed'."
    )
    in_map: bool | None = Field(description="Whether the outcome lies in the fence's map (null: not checked or not finished).")
    events: list[FeederEventOut] = Field(
        description="What happened on the fence, in order: contacts, vertex, end and flush contacts, and how the run "
        "ended, each with the belt travel at which it occurred."
    )
    trajectory: list[list[float]] = Field(description="[push, x, y, theta] of the centre of mass: in the world frame for placed fences, else in the fence's frame (its free end at the origin).")
    steps: int = Field(
        description="Number of steps the simulation took on this fence (moves of the part, drift onto the fence "
        "included)."
    )
    forward_solves: int = Field(
        description="Number of forward minimum-power solves of the part's motion during this run."
    )


class FeederSimulateResponse(Out):
    runs: list[FeederFenceRunOut] = Field(
        description="One run per fence the part met (or passed, on a belt), in order; the simulation stops at the "
        "first fence the part does not leave."
    )
    theta_final: float | None = Field(
        description="The part's orientation after the last fence, radians; null unless it left (or passed) every "
        "fence."
    )
    status: str = Field(
        description="The last run's status: 'left', 'missed', 'jammed', 'step_limit', 'stalled', 'overlap' or "
        "'time_limit'."
    )
    complete: bool = Field(
        description="Whether every run finished (left, missed or jammed) and the part either passed every fence or "
        "jammed; false when cut by a limit, stalled or overlapping."
    )
    message: str = Field(
        description="The result in words: that the part left all fences (and how many it passed untouched), or where "
        "and why it stopped."
    )
    solve_time_ms: float = Field(
        description="Time the simulation took in the solver, milliseconds."
    )
    elapsed_ms: float = Field(description=ELAPSED_MS_DESCRIPTION)




class FeederAnglesIn(Strict):
    min: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0.0, lt=1.5707963267948966)] = Field(
        description="Smallest |angle| of a candidate fence, radians.")
    max: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0.0, lt=1.5707963267948966)] = Field(
        description="Largest |angle|, radians (at least min).")
    step: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0.0)] = Field(
        description="Step between candidate angles, radians; both sides of the belt are tried.")


Length = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0.0)]


class FeederBeltIn(Strict):
    width: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0.0)] = Field(
        description="Belt width, in the part's units (more than the part's diameter plus the clearance).")
    clearance: Length | None = Field(default=None, description="Extra gap at a fence's free end beyond the part's "
                                                               "diameter (default a tenth of the part's radius).")
    spacing: Length | None = Field(default=None, description="Along the belt from a fence's free end to the next "
                                                             "fence's root (default the part's diameter).")
    entry_x: Annotated[float, Field(strict=True, allow_inf_nan=False)] | None = Field(
        default=None, description="Lane of the arriving parts' centre of mass, x across the belt, in the part's "
                                  "units (default: beside the right side, the clearance from it; the first fence "
                                  "then hangs from the right).")
    entry_spread: Length | None = Field(default=None, description="Half width of the entry lane, in the part's "
                                                                  "units: parts arrive with their centre of mass "
                                                                  "anywhere within it of entry_x (default half the "
                                                                  "part's radius).")


Radians = Annotated[float, Field(strict=True, allow_inf_nan=False)]


class FeederGoalIn(Strict):
    """What the next station accepts: give either ``accepted`` or ``edge``."""

    accepted: list[Annotated[list[Radians], Field(min_length=2, max_length=2)]] | None = Field(
        default=None, min_length=1, description="Accepted final orientations as intervals [start, end], radians, "
                                                "start in [0, 2 pi), end after start by less than 2 pi (an interval "
                                                "may run past 2 pi).")
    edge: Annotated[int, Field(strict=True, ge=0)] | None = Field(
        default=None, description="Accept the part with this edge of the outline (from vertex edge to vertex "
                                  "edge + 1, in the order given) along the belt's motion against a guide.")
    side: Literal["right", "left", "either"] = Field(
        default="either", description="With edge: the guide it lies against, on the belt's right (+x) or left side, "
                                      "or either (the part half a turn round).")
    tolerance: Radians = Field(default=0.6981, description="With edge: how far from exactly along the guide, radians "
                                                           "(default 40 degrees). A band is accepted only when it lies "
                                                           "within the goal, and bands after a fence are some 13 to 40 "
                                                           "degrees wide: a tolerance below half a band's width "
                                                           "accepts none.")


class FeederGateIn(Strict):
    """Allow a reject gate after the fences (book 7.1): it measures one feature of the
    silhouette and returns the parts it rejects to the start."""

    features: list[Literal["across", "along"]] = Field(
        default=["across", "along"], min_length=1,
        description="Features the gate may measure: the silhouette's extent across the belt (x) or along it (y).")
    margin: Length | None = Field(default=None, description="Least distance, in the part's units, from the threshold "
                                                            "to every band's range of the feature (default 0.005 of "
                                                            "the part's radius).")
    min_yield: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0.0, le=1.0)] = Field(
        default=0.25, description="Least guaranteed yield per pass a gate design must have.")
    max_depth: Annotated[int, Field(strict=True, ge=1, le=FEEDER_MAX_DESIGN_DEPTH)] = Field(
        default=4, description="The most fences before the gate (at most max_depth): the gate search prunes less "
                               "than the fences-only one and grows about twofold per fence.")


class FeederDesignSettingsIn(Strict):
    """What a design is searched with, whatever the part (5.3-5.4)."""

    angles: FeederAnglesIn
    mu_c: MuC | None = Field(default=None, description="Contact friction between part and fences.")
    mu_c_range: Annotated[list[MuC], Field(min_length=2, max_length=2)] | None = Field(
        default=None, description="An interval [low, high] of mu_c instead: the design must work for all of it.")
    max_depth: Annotated[int, Field(strict=True, ge=1, le=FEEDER_MAX_DESIGN_DEPTH)] = Field(
        default=8, description="The most fences a design may have.")
    alternate: bool | None = Field(default=None, description="Consecutive fences on opposite sides of the belt. "
                                   "Default: true without a belt (the book's parts feeder, 5.3), false on a belt "
                                   "(alternating sides rules out designs that exist for asymmetric parts, "
                                   "docs/mechanics.md).")
    prove_with_cp_sat: bool = Field(default=False, description="Prove the least number of fences again with CP-SAT.")
    validation_parts: Annotated[int, Field(strict=True, ge=0, le=FEEDER_MAX_VALIDATION_PARTS)] = Field(
        default=0, description="Simulated parts (random support, orientation, mu_c) run through the design.")
    seed: Annotated[int, Field(strict=True, ge=0, le=2**63 - 1)] = 0


class FeederDesignRequest(FeederDesignSettingsIn):
    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={"examples": [{
            "part": {"vertices": [[0, 0], [3, 0], [3.5, 1.5], [1.5, 2.5], [-0.5, 1.2]], "center_of_mass": [1.4, 1.0]},
            "angles": {"min": 0.349, "max": 1.222, "step": 0.0873},
            "mu_c": 0.25, "alternate": False, "validation_parts": 20,
        }]},
    )

    part: FeederPartIn
    belt: FeederBeltIn | None = Field(default=None, description="Search the design as placed on this belt (book "
                                                                "1.8.6, figure 1-9): each fence's side, angle, free "
                                                                "end and reach inside the search.")
    goal: FeederGoalIn | None = Field(default=None, description="With a belt: the final orientations accepted "
                                                                "(default: one band per symmetry class, 5.3.1).")
    gate: FeederGateIn | None = Field(default=None, description="With a belt: allow a reject gate when no design of "
                                                                "fences alone reaches min_yield up to max_depth. Left "
                                                                "out on a belt: a gate with these defaults is allowed; "
                                                                "null: fences only.")
    min_yield: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0.0, le=1.0)] = Field(
        default=0.995, description="With a belt: least guaranteed yield per pass of a design of fences alone.")
    time_limit_s: TimeLimit | None = None


class FeederPlacedFenceOut(Out):
    angle: float = Field(description="Fence angle gamma, radians.")
    side: str = Field(description="The side of the belt it hangs from: right (gamma > 0) or left.")
    root: list[float] = Field(description="[x, y] where it hangs from the belt's side, in the part's units: x across "
                                          "the belt, y against the belt's motion (the belt runs in -y), the first root "
                                          "at y = 0.")
    end: list[float] = Field(description="[x, y] of its free end, in the part's units.")
    length: float = Field(description="From root to free end, in the part's units.")
    reach: float = Field(description="Along the fence from the part's least favourable first contact to the free "
                                     "end, in the part's units.")
    reach_needed: float = Field(description="The reach the orientations arriving at it need to come flush (1.8.6, "
                                            "bounded with the circumscribing disk), plus a slack of a quarter of the "
                                            "part's radius, in the part's units.")
    binding: list[str] = Field(description="What keeps this fence from being shorter: reach (it needs its reach), "
                                           "width (the gap at its free end), jam (a shallower candidate would jam).")


class FeederGateOut(Out):
    feature: str = Field(description="across (the silhouette's extent across the belt, x) or along (along it, y).")
    rule: str = Field(description="at_most or at_least: the gate accepts a part whose feature is at most (at least) "
                                  "the threshold.")
    threshold: float = Field(description="In the part's units.")
    margin: float = Field(description="Least distance from the threshold to any band's range of the feature, in the "
                                      "part's units.")
    y: float = Field(description="Where it stands along the belt (world y, part's units): spacing after the last "
                                 "fence's free end.")


class FeederLayoutOut(Out):
    belt_width: float = Field(description="In the part's units.")
    gap: float = Field(description="Free width left at each fence's end for the part to pass, in the part's units.")
    entry_x: float = Field(description="The entry lane's centre (x of the centre of mass), in the part's units.")
    entry_spread: float = Field(description="The entry lane's half width, in the part's units.")
    belt_length: float = Field(description="From the first root to the last free end (to the gate, with one), along "
                                           "the belt, in the part's units: the shortest for this design and width.")
    fences: list[FeederPlacedFenceOut] = Field(
        description="The placed fences in the order the part meets them: angle, side, root, free end, length, reach, "
        "reach needed, and what binds their length."
    )
    gate: FeederGateOut | None = Field(description="The reject gate (null: fences only).")


class FeederDesignFenceOut(Out):
    angle: float = Field(description="Fence angle gamma, radians.")
    side: str = Field(description="The side of the belt it hangs from: right (gamma > 0) or left.")


class FeederDesignOut(Out):
    fences: list[FeederDesignFenceOut] = Field(description="In the order the part meets them.")
    final_band: list[Arc] = Field(description="The orientations the part may leave the last fence in.")
    final_edges: list[int] = Field(description="The hull edges flush on the last fence (one, or one per symmetry).")
    margin: float = Field(description="Radians every band edge may move without the design failing (1.8.6).")
    accepted_band: list[Arc] | None = Field(default=None, description="On a belt: the orientations accepted (all of "
                                                                      "final_band without a gate).")
    accepted_edges: list[int] | None = Field(default=None, description="On a belt: the hull edges of the accepted "
                                                                       "bands.")
    guaranteed_yield: float | None = Field(default=None, description="On a belt: the share of initial orientations "
                                                                     "every outcome of which is accepted, from the "
                                                                     "maps (per pass), at each mu_c sample of an "
                                                                     "interval; slivers are counted by their own "
                                                                     "measure (docs/mechanics.md).")
    expected_passes: float | None = Field(default=None, description="On a belt: at most 1 / guaranteed_yield passes "
                                                                    "a part on average (rejected parts start again).")
    lost: float | None = Field(default=None, description="On a belt: radians of initial orientations the first "
                                                         "fence's reach may leave unaligned (counted as lost).")
    slivers: float | None = Field(default=None, description="On a belt: radians of arriving orientations later "
                                                            "fences may leave unaligned (within a sliver of a "
                                                            "balance), counted against the yield.")


class FeederCpSatOut(Out):
    depth_proven: int = Field(description="Every design depth up to this proven impossible.")
    statuses: list[str] = Field(description="CP-SAT's status per depth tried, from 1.")
    complete: bool = Field(
        description="Whether CP-SAT decided every depth it tried; false when a depth's solve ran out of time (the "
        "depths after it were not tried)."
    )
    solve_time_ms: float = Field(
        description="Time the CP-SAT proof took, milliseconds."
    )


class FeederValidationOut(Out):
    parts: int = Field(
        description="Number of simulated parts run through the design (the request's `validation_parts`), `cut` of "
                    "them stopped by the time limit."
    )
    cut: int = Field(default=0, description="Parts the time limit stopped before they ended: no outcome, not in any "
                                            "count or share below (the design's answer is then `time_limit`).")
    in_band: int = Field(description="Parts that ended in the promised band.")
    outside: int = Field(description="Parts that came flush on every fence and ended elsewhere (a failure).")
    unflushed: int = Field(description="Parts that left some fence without an edge flush (too short a fence): a "
                                       "failure (with a gate, see unflushed_gated).")
    unfinished: int = Field(description="Parts that jammed, stalled, met two fences at once or ran out of steps.")
    missed: int = Field(description="Parts that passed some placed fence untouched (on a belt only; a failure).")
    rejected: int = Field(default=0, description="On a belt with a gate: parts the gate returned to the start.")
    unflushed_gated: int = Field(default=0, description="On a belt with a gate: parts that left a fence still turning "
                                                        "and were then judged by the gate (counted in in_band, outside "
                                                        "or rejected; without a gate they count in unflushed).")
    yield_per_pass: float | None = Field(default=None, description="On a belt: the share of the parts accepted in an "
                                                                   "accepted band.")
    succeeded: float | None = Field(default=None, description="On a belt: the share of the parts that ended as "
                                                              "promised (accepted in band, or rejected by the gate); "
                                                              "every failure counts against it.")
    on_belt: bool = Field(description="The parts met the placed fences of `layout` one after the other, entering in "
                                      "its lane; otherwise each fence alone in its own frame.")
    off_belt: int = Field(description="On a belt: parts whose outline crossed a side of the belt somewhere (side walls "
                                      "are not simulated).")
    rate: float | None = Field(description="in_band / (in_band + outside).")


class FeederPushPlanOut(Out):
    pushes: int | None = Field(description="Pushes of the shortest plan (null: none up to max_depth).")
    alphas: list[float] | None = Field(description="Turns of the push direction between pushes, radians.")
    tolerance: float | None = Field(description="How far each turn may err, radians (null: no turn needed).")
    solve_time_ms: float = Field(
        description="Time the push-plan baseline search took, milliseconds (it may take a tenth of the time that "
        "remained)."
    )
    complete: bool = Field(description="False: the baseline was cut at its share of the time limit (a tenth of "
                                        "what remained), before it found a plan or proved none exists up to "
                                        "max_depth; `pushes` is then null and says nothing.")


class FeederRelaxedOut(Out):
    setting: Literal["alternate", "gate"] = Field(description="The setting lifted: alternate (the same search with "
                                                  "sides free) or gate (with a reject gate allowed, its defaults).")
    searched: bool = Field(description="False: the time limit was reached before this search.")
    fences: int | None = Field(description="Fences of the design it found (null: none, or not searched).")
    gated: bool | None = Field(description="On a belt: whether that design ends with a reject gate.")
    guaranteed_yield: float | None = Field(description="On a belt: that design's guaranteed yield per pass.")


class FeederDesignResponse(Out):
    design: FeederDesignOut | None = Field(
        description="The design found: fences in order with angle and side, final band and edges, margin, and on a "
        "belt its yield; null when none was found."
    )
    depth_proven: int = Field(description="No design has this many fences or fewer (complete depths only).")
    exhausted: bool = Field(description="No design exists with these candidate fences at any depth.")
    fences_only_exhausted: bool | None = Field(default=None, description="On a belt with a gate allowed, when no "
                                                                         "design of fences alone was found (the gate "
                                                                         "search then ran): whether none exists at "
                                                                         "any depth (false: none up to max_depth).")
    relaxed: list[FeederRelaxedOut] = Field(default_factory=list, description="When no design was found: what the "
                                            "same search finds with each restricting setting lifted alone (sides "
                                            "alternating, no gate), so the answer says which one ruled a design out.")
    candidates: int = Field(description="Candidate fences whose maps were made.")
    nodes: int = Field(
        description="Search nodes made: states (a fence and the set of orientations the part may have after it) kept "
        "by the breadth-first search."
    )
    pruned: int = Field(
        description="Search nodes dropped because their orientation set contains one already reached at no greater "
        "depth with no smaller margin."
    )
    cp_sat: FeederCpSatOut | None = Field(
        description="CP-SAT's proof that no shorter design exists: depth proven, status per depth, time; null unless "
        "`prove_with_cp_sat` (without a belt)."
    )
    validation: FeederValidationOut | None = Field(
        description="Simulated parts (random tripod, orientation and mu_c) run through the design, by outcome; null "
        "unless `validation_parts` > 0 and a design was found."
    )
    layout: FeederLayoutOut | None = Field(description="The design on the belt asked for (null: no belt or no design).")
    push_plan_baseline: FeederPushPlanOut | None = Field(
        description="For comparison: the shortest sensorless plan of a frictionless single pusher for the same part "
                    "(Goldberg 1993), no belt, no friction.")
    timings_ms: dict[str, float] = Field(
        description="Milliseconds per phase that ran: push_plan, maps, reach_profiles, search, cp_sat, layout, "
        "validation."
    )
    status: str = Field(description="ok, or time_limit (what was finished is returned).")
    complete: bool = Field(
        description="Whether the design computation finished; false when the time limit cut it short (status "
        "'time_limit')."
    )
    message: str = Field(
        description="The result in words: the design's fence count and yield with the nodes searched, that none "
        "exists, or how far it got before the time limit."
    )
    solve_time_ms: float = Field(
        description="Time the design computation took in the solver (baseline, maps, search, proof, layout, "
        "validation), milliseconds."
    )
    elapsed_ms: float = Field(description=ELAPSED_MS_DESCRIPTION)


class FeederCataloguePartIn(FeederPartIn):
    name: Annotated[str, Field(max_length=200)] | None = Field(default=None, description="The part's name, echoed back.")


class FeederCatalogueRequest(Strict):
    """A catalogue of parts and one design request for all of them: each part's design and
    its validation, in parallel on Ray (a local Ray, or the cluster at PESHKIN_RAY_ADDRESS)."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={"examples": [{
            "parts": [{"name": "pentagon", "vertices": [[0, 0], [3, 0], [3.5, 1.5], [1.5, 2.5], [-0.5, 1.2]],
                       "center_of_mass": [1.4, 1.0]},
                      {"name": "plate", "vertices": [[0, 0], [2.5, 0], [2.5, 1], [0, 1]],
                       "center_of_mass": [1.25, 0.5]}],
            "design": {"angles": {"min": 0.1745, "max": 1.3963, "step": 0.0873}, "mu_c": 0.25, "alternate": False,
                       "validation_parts": 10},
        }]},
    )

    parts: Annotated[list[FeederCataloguePartIn], Field(min_length=1, max_length=FEEDER_MAX_CATALOGUE_PARTS)] = Field(
        description=f"The parts, 1..{FEEDER_MAX_CATALOGUE_PARTS}, each as `part` of /v1/feeder/design.")
    design: FeederDesignSettingsIn = Field(description="The design request applied to every part (as "
                                                       "/v1/feeder/design, without a belt).")
    time_limit_s: TimeLimit | None = Field(default=None, description="Seconds for the whole catalogue; parts whose "
                                                                     "design is not finished by then are "
                                                                     "'not_finished'. Default: the cap.")


class FeederCatalogueItemOut(Out):
    name: str | None = Field(description="The part's name as given.")
    status: Literal["ok", "time_limit", "not_finished"] = Field(
        description="'ok': its design search ended; 'time_limit': it ran out of time (what it reached is given); "
        "'not_finished': no answer by the catalogue's deadline.")
    fences: list[FeederDesignFenceOut] | None = Field(description="The design's fences in order; null: none found "
                                                                  "(or not finished).")
    depth_proven: int | None = Field(description="No design has fewer fences than this + 1.")
    margin: float | None = Field(description="The design's margin, radians (1.8.6).")
    validation_parts: int = Field(description="Simulated parts run through the design to their end (parts the "
                                  "time limit stopped are not counted).")
    validation_in_band: int = Field(description="Of them, those that ended in the design's final band.")
    solve_time_ms: float | None = Field(description="This part's design time, milliseconds.")


class FeederCatalogueResponse(Out):
    status: Literal["complete", "time_limit"] = Field(description="'complete' when every part's search ended.")
    designs: list[FeederCatalogueItemOut] = Field(description="One per part, in the request's order.")
    finished: int = Field(description="Parts whose design is given.")
    backend: Literal["ray", "in_process"] = Field(description="Where the designs ran: on Ray, or one after the other.")
    cpus: int = Field(description="CPUs the designs had (Ray's cluster, or 1).")
    nodes: int = Field(description="Machines of the Ray cluster (1 in process).")
    solve_time_ms: float = Field(description="Time of the whole catalogue, milliseconds.")
    elapsed_ms: float = Field(description=ELAPSED_MS_DESCRIPTION)
