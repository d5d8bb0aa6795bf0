"""Schema <-> problem <-> schema of ``POST /v1/scenes/analyze`` (no mechanics here).

:func:`scene_problem` builds a :class:`solver.scenes.problem.SceneProblem` from the
request, checking the service's limits (errors located at the request's fields);
:func:`analyze_response` turns the analysis into the response, each answer with the part of
its result the question asked for.
"""

from __future__ import annotations

import math

import numpy as np

from models.feeder.fence import feeder_part
from service.api.scenes.schemas import (
    FencesAnswerOut,
    LocusAnswerOut,
    ModesAnswerOut,
    PushAnswerOut,
    QuasiStaticAnswerOut,
    QuestionIn,
    SceneAnalyzeRequest,
    SceneAnalyzeResponse,
    SceneAnswerOut,
    TriedOut,
)
from service.common.inputs import located
from service.common.numbers import design_margin, listed
from service.common.quasistatic import quasi_static_query
from service.common.scene import contact_warnings, disk_or_footprint
from service.errors import FieldError
from service.limits import CONTACT_ON_OUTLINE_REL, FEEDER_MAX_CANDIDATES, GROSS_MIN_LENGTH
from solver import Answer, Question, SceneAnalysis, SceneProblem, angle_count

DEFAULT_ANGLES = (math.radians(10.0), math.radians(80.0), math.radians(5.0))
"""Candidate fences of the feeder questions by default: 10..80 degrees in 5 degree steps."""


def _question(q: QuestionIn, k: int) -> Question:
    lo, hi, step = DEFAULT_ANGLES if q.angles is None else (q.angles.min, q.angles.max, q.angles.step)
    if hi < lo:
        raise FieldError(("questions", k, "angles", "max"), "must be at least angles.min")
    count = 2 * angle_count(lo, hi, step)
    if count > FEEDER_MAX_CANDIDATES:
        raise FieldError(("questions", k, "angles", "step"),
                         f"gives {count:g} candidate fences; at most {FEEDER_MAX_CANDIDATES} (both sides together)")
    return Question(q.ask, q.accuracy, n_points=q.n_points, n_rays=q.n_rays, angle_min=lo, angle_max=hi,
                    angle_step=step, max_depth=q.max_depth, alternate=q.alternate, validation_parts=q.validation_parts,
                    seed=q.seed)


def scene_problem(req: SceneAnalyzeRequest) -> tuple[SceneProblem, list[str]]:
    """The problem of ``req`` and the remarks on its scene."""
    scene, footprint = disk_or_footprint(req)
    if req.mu_c is not None and req.mu_c_range is not None:
        raise FieldError(("mu_c_range",), "give mu_c or mu_c_range, not both")
    mu = (req.mu_c or 0.0, req.mu_c or 0.0) if req.mu_c_range is None else (req.mu_c_range[0], req.mu_c_range[1])
    if not mu[0] <= mu[1]:
        raise FieldError(("mu_c_range",), "must be [low, high] with low <= high")
    if scene.disk_radius < GROSS_MIN_LENGTH:
        raise FieldError(("footprint" if footprint is not None else "disk_radius",),
                         f"is too small: the part's radius {scene.disk_radius:.3g} is below {GROSS_MIN_LENGTH:g}")
    questions = tuple(_question(q, k) for k, q in enumerate(req.questions))
    if footprint is not None and any(q.ask in ("aligning_fence", "feeder_design") for q in questions):
        with located(rename={"workpiece": ("footprint",), "center_of_mass": ("center_of_mass",)}):
            feeder_part(footprint.vertices, footprint.center_of_mass)  # the feeder's own checks, up front
    with located():
        problem = SceneProblem(scene, footprint, (float(mu[0]), float(mu[1])), quasi_static_query(req.quasi_static),
                               questions)
    warnings = contact_warnings(scene)
    if footprint is not None:
        distance = footprint.distance_to_outline(scene.contact_point)
        if distance > CONTACT_ON_OUTLINE_REL * scene.disk_radius:
            warnings.append(f"contact_point is {distance:.6g} away from the part's outline: the pusher is not touching "
                            "it there")
    return problem, warnings


def _point_or_none(point: np.ndarray) -> list[float] | None:
    return listed(point) if bool(np.all(np.isfinite(point))) else None


def _locus(result, model: str | None) -> LocusAnswerOut:
    """The certified boundary points (one per ray) of a certified answer, else the analytic
    boundary (the disk's: a bound for a polygon)."""
    an, cert = result.analytic, result.certified
    if cert is not None and model == "certified":
        boundary = [_point_or_none(pt) for pt in cert.boundary]
    else:
        boundary = [] if an.boundary is None else listed(an.boundary)
    return LocusAnswerOut(kind=an.kind, tip=None if an.tip is None else listed(an.tip.point),
                          r_min=None if an.r_min is None else an.r_min.distance, boundary=boundary)


def _modes(verdict) -> ModesAnswerOut:
    letter = None if verdict.sketch is None else verdict.sketch.sketch.sketch
    return ModesAnswerOut(verdict=verdict.verdict, modes=list(verdict.modes), sketch=letter)


def _push(result, problem: SceneProblem) -> PushAnswerOut:
    def best(bound) -> float | None:
        return bound.exact if bound.exact is not None else bound.closed_form

    slip = result.slip
    index = problem.footprint.input_index
    return PushAnswerOut(longest=best(result.longest), shortest=best(result.shortest),
                         longest_closed_form=result.longest.closed_form,
                         slip_most=None if slip is None else max(abs(slip.most_positive), abs(slip.most_negative)),
                         final_edge=[index(k) for k in result.alignment.final_edge])


def _fences(result, one_fence: bool) -> FencesAnswerOut:
    design = result.design
    angles = None if design is None else [float(result.maps[f].fence.angle) for f in design.fences]
    margin = None if design is None else design_margin(design.margin)
    v = result.validation
    if one_fence and angles is not None and len(angles) != 1:
        angles = margin = v = None  # the fewest fences are more than one: no single fence orients the part
    return FencesAnswerOut(fence_angles=angles, fewest_proven=0 if result.search is None else result.search.depth_proven,
                           margin=margin,
                           simulated_parts=0 if v is None else v.parts, simulated_in_band=0 if v is None else v.in_band)


def answer_out(a: Answer, problem: SceneProblem) -> SceneAnswerOut:
    payload: dict = {"locus": None, "modes": None, "push": None, "quasi_static": None, "fences": None}
    r, ask = a.result, a.question.ask
    if r is not None:
        if ask == "cor_locus":
            payload["locus"] = _locus(r, a.model)
        elif ask == "stick_or_slip":
            payload["modes"] = _modes(r)
        elif ask == "push_to_align":
            payload["push"] = _push(r, problem)
        elif ask == "quasi_static":
            payload["quasi_static"] = QuasiStaticAnswerOut(verdict=r.verdict, ratio=r.quasi_static.ratio,
                                                           characteristic_speed=r.quasi_static.characteristic_speed)
        else:
            payload["fences"] = _fences(r, ask == "aligning_fence")
    return SceneAnswerOut(
        ask=ask, accuracy_asked=a.question.accuracy, status=a.status, model=a.model, accuracy=a.accuracy,
        error_bound=a.error_bound, error_meaning=a.error_meaning, cost_ms=a.cost_s * 1e3, reused_from=a.reused_from,
        tried=[TriedOut(model=t.model, cost_ms=t.cost_s * 1e3, why_not=t.why_not) for t in a.tried], note=a.note,
        **payload)


def analyze_response(analysis: SceneAnalysis, warnings: list[str], elapsed_ms: float) -> SceneAnalyzeResponse:
    problem = analysis.problem
    scene = problem.scene
    return SceneAnalyzeResponse(
        status=analysis.status, part="disk" if problem.is_disk else "polygon", disk_radius=scene.disk_radius,
        center_of_mass=listed(scene.center_of_mass), answers=[answer_out(a, problem) for a in analysis.answers],
        warnings=warnings, solve_time_ms=analysis.solve_time_s * 1e3, elapsed_ms=elapsed_ms)
