"""Request and response schemas of ``POST /v1/scenes/analyze``: one pushing scene, the
questions asked of it and, per answer, the model that answered, the accuracy it reached,
its error bound and its cost (:mod:`solver.scenes`).

Conventions are those of :mod:`service.common.fields`: world frame, radians, lengths in any
consistent unit, strict finite numbers, unknown fields rejected.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import ConfigDict, Field, StrictBool

from service.common.fields import (
    DISK_OR_FOOTPRINT,
    DiskRadius,
    MuC,
    Point,
    Polygon,
    PushIn,
    Strict,
    TimeLimit,
    Vec2,
    exactly_one_of,
)
from service.common.quasistatic import QuasiStaticIn
from service.common.responses import ELAPSED_MS_DESCRIPTION, Out
from service.limits import (
    FEEDER_MAX_DESIGN_DEPTH,
    FEEDER_MAX_VALIDATION_PARTS,
    MAX_CERTIFIED_POINTS,
    MIN_CERTIFIED_POINTS,
    MIN_N_POINTS,
    SCENE_DEFAULT_TIME_LIMIT_S,
    SCENE_MAX_QUESTIONS,
    SKETCH_MAX_N_POINTS,
    TIME_LIMIT_CAP_TEXT,
)

Ask = Literal["cor_locus", "stick_or_slip", "push_to_align", "quasi_static", "aligning_fence", "feeder_design"]
Accuracy = Literal["estimate", "bound", "exact"]
ACCURACY_DESCRIPTION = (
    "The accuracy needed: 'estimate' (the cheapest answer, its error possibly unknown), 'bound' (guaranteed for "
    "every pressure distribution the part allows, conservative) or 'exact' (the part's own answer, certified). The "
    "service answers with the cheapest model that reaches it, or says which it reached."
)
HalfTurnAngle = Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0.0, lt=1.5707963267948966)]


class CandidateAnglesIn(Strict):
    """The candidate fences of the feeder questions: |angle| from `min` to `max` in steps of
    `step`, on both sides of the belt (as `/v1/feeder/design`)."""

    min: HalfTurnAngle = Field(description="Smallest |angle| of a candidate fence, radians.")
    max: HalfTurnAngle = Field(description="Largest |angle|, radians (at least min).")
    step: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0.0)] = Field(
        description="Step between candidate angles, radians.")


class QuestionIn(Strict):
    """One question about the scene and the accuracy it needs."""

    ask: Ask = Field(
        description="'cor_locus': where can the COR be (3.3); 'stick_or_slip': will the pusher stick or slip (4.1); "
        "'push_to_align': how far must the fence (the scene's edge, advancing along its push) push the polygon to "
        "align it, and how far does it slip (3.4, 4.3); 'quasi_static': is the push slow enough (6.8; needs "
        "`quasi_static`); 'aligning_fence': which single fence on a belt orients the polygon, if any; "
        "'feeder_design': the fewest fences that orient it (5.3-5.4)."
    )
    accuracy: Accuracy = Field(default="bound", description=ACCURACY_DESCRIPTION)
    n_points: Annotated[int, Field(strict=True, ge=MIN_N_POINTS, le=SKETCH_MAX_N_POINTS)] = Field(
        default=256, description="Boundary points of an analytic locus or sketch.")
    n_rays: Annotated[int, Field(strict=True, ge=MIN_CERTIFIED_POINTS, le=MAX_CERTIFIED_POINTS)] = Field(
        default=16, description="Rays of a certified locus or sketch of a polygon (more: finer, dearer).")
    angles: CandidateAnglesIn | None = Field(
        default=None, description="Candidate fences of the feeder questions. Default 10..80 degrees in 5 degree steps.")
    max_depth: Annotated[int, Field(strict=True, ge=1, le=FEEDER_MAX_DESIGN_DEPTH)] = Field(
        default=6, description="The most fences of a design ('feeder_design').")
    alternate: StrictBool = Field(default=True, description="Whether consecutive fences of a design alternate sides "
                                  "of the belt (a single fence has no other).")
    validation_parts: Annotated[int, Field(strict=True, ge=0, le=FEEDER_MAX_VALIDATION_PARTS)] | None = Field(
        default=None,
        description="Simulated parts that check a design. Default: 100 when 'exact' is asked for, else 0.")
    seed: Annotated[int, Field(strict=True, ge=0, le=2**63 - 1)] = Field(
        default=0, description="Seed of the simulated parts.")


class SceneAnalyzeRequest(PushIn):
    """One scene and the questions asked of it: exactly one of `disk_radius` (a disk part)
    or `footprint` (a polygon part)."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={
            **exactly_one_of(DISK_OR_FOOTPRINT, ("mu_c", "mu_c_range")),
            "examples": [{
                "footprint": [[0, 0], [3, 0], [3.5, 1.5], [1.5, 2.5], [-0.5, 1.2]],
                "contact_point": [1.0, 0.0], "edge_angle": 0.3, "push_direction": 1.5707963267948966,
                "mu_c": 0.25, "quasi_static": {"speed": 0.05, "mu_s": 0.3, "length_unit": "m"},
                "questions": [{"ask": "cor_locus"}, {"ask": "stick_or_slip", "accuracy": "exact"},
                              {"ask": "push_to_align"}, {"ask": "quasi_static"}, {"ask": "aligning_fence"},
                              {"ask": "feeder_design", "alternate": False, "max_depth": 10}],
            }],
        },
    )

    disk_radius: DiskRadius | None = Field(default=None, description="A disk part of this radius about the CM.")
    footprint: Polygon | None = Field(
        default=None, description="Or a polygon part's outline, world frame (its circumscribing disk about the CM "
        "bounds it, 3.1.8).")
    center_of_mass: Point | None = Field(
        default=None, description="Centre of mass. Default [0, 0] for a disk, the area centroid for a polygon.")
    mu_c: MuC | None = Field(default=None, description="Pusher-part friction coefficient. Default 0 (frictionless).")
    mu_c_range: Annotated[list[MuC], Field(min_length=2, max_length=2)] | None = Field(
        default=None, description="Or an interval [low, high] of mu_c (the feeder questions only).")
    quasi_static: QuasiStaticIn | None = Field(
        default=None, description="The push's speed and the table's friction (and gravity): needed by 'quasi_static', "
        "and then also checked by 'push_to_align'.")
    questions: Annotated[list[QuestionIn], Field(min_length=1, max_length=SCENE_MAX_QUESTIONS)] = Field(
        description=f"The questions, 1..{SCENE_MAX_QUESTIONS}; answered in this order in `answers`.")
    time_limit_s: TimeLimit = Field(
        default=SCENE_DEFAULT_TIME_LIMIT_S,
        description=f"Seconds for the whole analysis, {TIME_LIMIT_CAP_TEXT}. Questions reached with no time left are "
        "'not_run'; one whose model runs out of time is 'time_limited' with what it completed.")


class TriedOut(Out):
    model: str = Field(description="A cheaper model tried first.")
    cost_ms: float = Field(description="What it cost, milliseconds (0 when reused).")
    why_not: str = Field(description="Why its answer did not reach the accuracy asked for.")


class LocusAnswerOut(Out):
    """Where the COR can be: the boundary of the locus (3.3)."""

    kind: str = Field(description="'bounded' (the COR can be anywhere in a bounded region) or 'translation' (the push translates the part: no COR).")
    tip: Vec2 | None = Field(description="The locus's tip (3.37), world frame; of the disk's locus.")
    r_min: float | None = Field(description="Distance of the locus's nearest point from the CM (3.31), of the disk's.")
    boundary: list[Vec2 | None] = Field(
        description="Boundary points, world frame: the analytic boundary, or for a certified polygon one per ray "
        "(null: the ray was not certified).")


class ModesAnswerOut(Out):
    """Which contact modes the pusher can be in (4.1)."""

    verdict: Literal["sticks", "slips", "either"] = Field(
        description="'sticks' (sticking for every pressure distribution), 'slips' (never sticking) or 'either'.")
    modes: list[str] = Field(description="The modes possible: sticking, slipping_up, slipping_down, frictionless.")
    sketch: str | None = Field(description="Which of the nine sketches of figure 4-6 (null: none, or mu_c = 0).")


class PushAnswerOut(Out):
    """How far the fence pushes the part until it is aligned, and how far it slips (3.4, 4.3)."""

    longest: float | None = Field(description="The longest push to align (length): exact bound, else closed form.")
    shortest: float | None = Field(description="The shortest push to align (length): exact bound, else closed form.")
    longest_closed_form: float | None = Field(description="The book's closed form of the longest push (3.41, 4.3).")
    slip_most: float | None = Field(
        description="The most the fence slips along its face while the part turns (length; exact bounds only).")
    final_edge: list[int] = Field(description="Indices of the outline's edge that ends flush with the fence.")


class QuasiStaticAnswerOut(Out):
    verdict: str = Field(description="'quasi_static', 'transitional' or 'inertial' (6.8).")
    ratio: float = Field(description="v / v_qs: the push speed over the quasi-static characteristic speed.")
    characteristic_speed: float = Field(description="v_qs, length unit per second (6.8).")


class FencesAnswerOut(Out):
    """A feeder design, or the one aligning fence (5.3-5.4)."""

    fence_angles: list[float] | None = Field(
        description="The design's fence angles in order, radians (null: no design found); for 'aligning_fence' one "
        "angle, or null when no single fence orients the part.")
    fewest_proven: int = Field(description="No design has fewer fences than this + 1 (searched completely).")
    margin: float | None = Field(description="The design's margin, radians (1.8.6).")
    simulated_parts: int = Field(description="Simulated parts that ran through the design (0: not checked).")
    simulated_in_band: int = Field(description="Of them, those that ended in the design's final orientations.")


class SceneAnswerOut(Out):
    """The answer to one question."""

    ask: Ask = Field(description="The question.")
    accuracy_asked: Accuracy = Field(description="The accuracy asked for.")
    status: Literal["answered", "time_limited", "not_run"] = Field(
        description="'answered'; 'time_limited': its model ran out of time (what it completed is given, if "
        "anything); 'not_run': no time was left for it.")
    model: str | None = Field(
        description="The model that answered: 'closed_form', 'disk_bound' (the circumscribing disk's answer), "
        "'certified', 'exact_bounds', 'design_search' or 'design_search+simulation'.")
    accuracy: Accuracy | None = Field(description="The accuracy reached (null when not answered).")
    error_bound: float | None = Field(description="The answer's error bound (null: none known); see error_meaning.")
    error_meaning: str = Field(description="What error_bound measures, its unit, and what it does not cover.")
    cost_ms: float = Field(description="This answer's own computing time, milliseconds (0 when it reused another's).")
    reused_from: int | None = Field(description="Index of the answer whose computation this one reused (null: none).")
    tried: list[TriedOut] = Field(description="Cheaper models tried first and why they were not enough.")
    note: str = Field(description="Remarks: what the model could not reach, what was not certified.")
    locus: LocusAnswerOut | None = Field(description="'cor_locus': the locus.")
    modes: ModesAnswerOut | None = Field(description="'stick_or_slip': the contact modes.")
    push: PushAnswerOut | None = Field(description="'push_to_align': the push.")
    quasi_static: QuasiStaticAnswerOut | None = Field(description="'quasi_static': the verdict.")
    fences: FencesAnswerOut | None = Field(description="'aligning_fence', 'feeder_design': the fences.")


class SceneAnalyzeResponse(Out):
    status: Literal["complete", "incomplete"] = Field(description="'complete' when every question was answered.")
    part: Literal["disk", "polygon"] = Field(description="The part: a disk or a polygon.")
    disk_radius: float = Field(description="The disk's radius, or the polygon's circumscribing radius about the CM.")
    center_of_mass: Vec2 = Field(description="Centre of mass used, world frame.")
    answers: list[SceneAnswerOut] = Field(description="One answer per question, in the request's order.")
    warnings: list[str] = Field(description="Remarks on the scene (e.g. the contact off the outline).")
    solve_time_ms: float = Field(description="Time of all the answers' computations, milliseconds.")
    elapsed_ms: float = Field(description=ELAPSED_MS_DESCRIPTION)
