"""Schema <-> problem <-> schema of the push endpoints (no mechanics here).

``POST /v1/push/quasistatic``: the request becomes a
:class:`models.push.quasistatic.ShapeMoments` (disk or polygon footprint) and a g (given,
or 9.81 m/s^2 in the named length unit) for the closed forms of
:func:`models.push.quasistatic.assess`; the answer goes back as plain finite floats.
Domain ``InvalidInput`` errors name the request's own fields (speed, mu_s, g,
disk_radius, angular_error, translational_error); the polygon's are located at
``footprint``.

``POST /v1/push/align`` and ``POST /v1/push/disk-encounter``: the request becomes a
:class:`solver.push.align.AlignProblem` / :class:`solver.push.disk_encounter.DiskEncounterProblem`
(with the optional quasi-static check); the result goes back with the request's vertex
indices, the notes and the references. The solver refuses (422 at ``time_limit_s``) what
its cost model predicts to exceed the time limit; a time limit reached on the way is a
504 with the stages done (:func:`align_partial`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from models.push import fence_geometry as fg
from models.push import quasistatic as qs
from service.api.push.schemas import (
    BoundOut,
    ErrorSpeedOut,
    FenceBoundOut,
    FenceEdgeOut,
    FenceGeometryOut,
    FencePieceOut,
    FenceSlipOut,
    FenceStageOut,
    PartOut,
    PushAlignRequest,
    PushAlignResponse,
    PushDiskEncounterRequest,
    PushDiskEncounterResponse,
    PushQuasistaticRequest,
    PushQuasistaticResponse,
    QuasiStaticCheckOut,
    QuasiStaticParameterOut,
    SketchIOut,
    ThresholdsOut,
)
from service.common.inputs import exactly_one, footprint_of
from service.common.numbers import listed
from service.common.quasistatic import QuasiStaticIn, quasi_static_query
from service.errors import FieldError
from service.limits import GROSS_MIN_LENGTH
from solver import (
    ENCOUNTER_SKETCH_COST,
    SKETCH_COST,
    AlignProblem,
    AlignResult,
    AlignStage,
    Bound,
    DiskEncounterProblem,
    DiskEncounterResult,
    Slip,
    below_line_of_motion,
)

REFERENCE = (
    "M. A. Peshkin, Robotic Manipulation Strategies (1990), section 6.8 (characteristic speed "
    "for quasi-static motion), equations (6.1)-(6.7); section 7.4 (non-quasi-static speeds)"
)


def _error_speed(cs: qs.CharacteristicSpeed) -> ErrorSpeedOut:
    return ErrorSpeedOut(
        characteristic_speed=cs.characteristic_speed,
        ratio=cs.ratio,
        permissible_error=cs.permissible_error,
        error_at_speed=cs.error_at_speed,
        within_tolerance=cs.within_tolerance,
        equation=cs.equation,
        section=cs.section,
        formula=cs.formula,
    )



def _quasi_static_parameter(res: qs.QuasiStaticAssessment) -> QuasiStaticParameterOut:
    """(6.7): the characteristic speed of the quasi-static parameter and the ratio to it."""
    return QuasiStaticParameterOut(
        characteristic_speed=res.quasi_static.characteristic_speed,
        ratio=res.quasi_static.ratio,
        equation=res.quasi_static.equation,
        section=res.quasi_static.section,
        formula=res.quasi_static.formula,
    )

def _message(res: qs.QuasiStaticAssessment, unit: str | None) -> str:
    r = res.quasi_static.ratio
    t = res.thresholds
    coast = (
        f"after release the part slides about {res.translational.error_at_speed:.3g}{' ' + unit if unit else ''} "
        f"or turns about {res.angular.error_at_speed:.3g} rad"
    )
    if res.verdict == "quasi_static":
        return (
            f"quasi-static: speed / v_qs = {r:.3g} <= {t.quasi_static_max_ratio:g} (6.7); {coast}, "
            "so friction dominates inertia and the quasi-static results (chapters 3-4) apply"
        )
    if res.verdict == "transitional":
        return (
            f"transitional: speed / v_qs = {r:.3g} is between {t.quasi_static_max_ratio:g} and "
            f"{t.inertial_min_ratio:g}; {coast}: inertia is no longer negligible, treat the "
            "quasi-static predictions as approximate"
        )
    return (
        f"inertial: speed / v_qs = {r:.3g} >= {t.inertial_min_ratio:g}: inertia is as large as "
        f"friction or larger (6.8.3); {coast}. The quasi-static COR loci do not apply; as the "
        "ratio grows the impact limit (7.4, (7.1); `impact` of /v1/cor/solve) is the better model"
    )


@dataclass(frozen=True)
class QuasistaticInputs:
    """What ``models.push.quasistatic.assess`` needs of a /v1/push/quasistatic request,
    and what the answer repeats: where g came from, the polygon's centre of mass."""

    part: qs.ShapeMoments
    g: float
    g_source: str
    center_of_mass: list[float] | None


def quasistatic_inputs(req: PushQuasistaticRequest) -> QuasistaticInputs:
    shape = exactly_one(req, ("disk_radius", "footprint"))
    g_source = exactly_one(req, ("g", "length_unit"))
    g = req.g if g_source == "g" else qs.gravity(req.length_unit)
    if shape == "disk_radius":
        return QuasistaticInputs(qs.ShapeMoments.disk(req.disk_radius), g, g_source, None)
    fp = footprint_of(req.footprint, None, ("footprint",))
    return QuasistaticInputs(qs.ShapeMoments.polygon(fp), g, g_source, listed(fp.center_of_mass))


def quasistatic_response(req: PushQuasistaticRequest, inputs: QuasistaticInputs, res: qs.QuasiStaticAssessment,
                         elapsed_ms: float) -> PushQuasistaticResponse:
    part, g_source, cm = inputs.part, inputs.g_source, inputs.center_of_mass
    spin_factor = part.spin_factor
    return PushQuasistaticResponse(
        verdict=res.verdict,
        message=_message(res, req.length_unit),
        speed=res.speed,
        mu_s=res.mu_s,
        g=res.g,
        g_source=g_source,
        length_unit=req.length_unit,
        part=PartOut(
            kind=part.kind,
            radius=part.radius,
            radius_of_gyration=part.radius_of_gyration,
            mean_distance=part.mean_distance,
            spin_factor=spin_factor,
            center_of_mass=cm,
        ),
        angular=_error_speed(res.angular),
        translational=_error_speed(res.translational),
        quasi_static=_quasi_static_parameter(res),
        thresholds=ThresholdsOut(
            quasi_static_max_ratio=res.thresholds.quasi_static_max_ratio,
            inertial_min_ratio=res.thresholds.inertial_min_ratio,
        ),
        reference=REFERENCE,
        elapsed_ms=elapsed_ms,
    )


# =======================================================================================
# Gross motions: POST /v1/push/align (3.4, 4.3) and POST /v1/push/disk-encounter (4.4)
# =======================================================================================

GROSS_REFERENCE = (
    "M. A. Peshkin, Robotic Manipulation Strategies (1990): 3.4 (aligning a workpiece with a fence, "
    "(3.39)-(3.41)), 4.2 (from instantaneous to gross motion), 4.3 (the fence with contact friction, "
    "(4.2)-(4.8)), 4.4 (a disk pushed aside, (4.9)-(4.24)); 3.1.8 (the circumscribing disk); 6.8 "
    "(quasi-static speeds). The closed forms re-derived, with the corrections to the printed text, "
    "in the service's docs/mechanics.md (gross motion)"
)

ALIGN_NOTE = (
    "The bounds are those of the circumscribing disk's COR sketch (book 3.1.8): every pressure "
    "distribution on the disk of radius a about the CM, which includes every distribution on the "
    "footprint, so the part's true push lies between the shortest and the longest exact push (up to "
    "their quadrature error and the sampling of the loci, n_points). The "
    "book's closed forms take the tips of {COR}_(alpha+-nu) and the tip line instead of the exact "
    "slowest CORs: they are approximations, not bounds (the exact longest push exceeds them by up to a "
    "few per cent at large mu_c, docs/mechanics.md). With mu_c = 0 the closed forms are exact (the "
    "tip of {COR}_alpha is the slowest COR and r_min the fastest). A stage ends when its edge is flush; "
    "the part stops when the frictionless line of force through the CM meets that edge."
)

ENCOUNTER_NOTE = (
    "The disk of 4.4 is the book's exact case (no circumscribing approximation). (4.16) takes the "
    "intersection of the tip line with the sticking line as the lower end of the sticking locus: it "
    "neglects the dip of that end below the tip line (too low) and overestimates in sketch i (too "
    "high), 4.4.1.2; the exact bounds take the ends from the exact sketch. (4.18) is re-derived as "
    "pi/2 - beta_initial (the OCR prints a pi/(2 - beta_initial)), an exact upper bound."
)


STAGE_FIELDS = {
    "beta_initial": ("orientation",),
    "beta_final": ("orientation",),
    "cor_of_beta": ("orientation",),
    "alpha": ("fence_angle",),
    "disk_radius": ("footprint",),
    "contact_distance": ("footprint",),
}
"""Where an InvalidInput of a stage's bound (named in the fence frame) is located in the
request."""

QUASI_STATIC_FIELDS = {name: ("quasi_static", name) for name in ("speed", "mu_s", "g", "angular_error",
                                                                 "translational_error")}
"""Where an InvalidInput of the quasi-static check is located in the request."""

ALIGN_FIELDS = {**STAGE_FIELDS, **QUASI_STATIC_FIELDS}
"""Where the alignment's InvalidInput errors are located in the request."""

ENCOUNTER_FIELDS = QUASI_STATIC_FIELDS
"""Where the encounter's InvalidInput errors are located in the request."""

QUADRATURE_WARN_REL = 0.01
"""The message warns when an exact bound's quadrature error estimate exceeds this fraction."""



def quasi_static_out(qin: QuasiStaticIn | None, res: qs.QuasiStaticAssessment | None) -> QuasiStaticCheckOut | None:
    """The verdict of 6.8 for the pusher's speed (as POST /v1/push/quasistatic, with the
    book's permissible errors), or None when no speed was given."""
    if qin is None or res is None:
        return None
    return QuasiStaticCheckOut(
        within_quasi_static=res.verdict == "quasi_static",
        verdict=res.verdict,
        message=_message(res, qin.length_unit),
        speed=res.speed,
        mu_s=res.mu_s,
        g=res.g,
        g_source="g" if qin.g is not None else "length_unit",
        length_unit=qin.length_unit,
        quasi_static=_quasi_static_parameter(res),
        angular=_error_speed(res.angular),
        translational=_error_speed(res.translational),
    )


def _bound_out(b: Bound) -> BoundOut:
    return BoundOut(
        exact=b.exact,
        quadrature_error=b.quadrature_error,
        closed_form=b.closed_form,
        equation=b.equation,
        difference=b.difference,
    )


def _fence_bound_out(b: Bound) -> FenceBoundOut:
    return FenceBoundOut(
        **_bound_out(b).model_dump(),
        pieces=None if b.pieces is None else [
            FencePieceOut(beta_start=p.beta_start, beta_end=p.beta_end, regime=p.regime,
                          push=p.push, equation=p.equation) for p in b.pieces],
        transitions=None if b.transitions is None else list(b.transitions),
        exact_sources=None if b.exact_sources is None else list(b.exact_sources),
        exact_time_s=b.exact_time_s,
    )


def _slip_out(slip: Slip | None) -> FenceSlipOut | None:
    if slip is None:
        return None
    return FenceSlipOut(
        most_positive=slip.most_positive,
        most_negative=slip.most_negative,
        quadrature_error_positive=slip.quadrature_error_positive,
        quadrature_error_negative=slip.quadrature_error_negative,
        direction=list(slip.direction), exact_time_s=slip.exact_time_s,
    )


def _stage_out(s: AlignStage, index) -> FenceStageOut:
    st = s.stage
    return FenceStageOut(
        contact_vertex_index=index(st.contact_index),
        flush_edge_vertex_indices=[index(st.contact_index), index(st.flush_index)],
        flush_edge_is_polygon_edge=st.flush_is_polygon_edge,
        flush_edge_stable=st.flush_edge_stable,
        contact_distance=st.contact_distance,
        contact_fence_frame=listed(st.contact_fence_frame),
        beta_initial=st.beta_initial, beta_final=st.beta_final, vertex_edge_angle=st.vertex_edge_angle,
        rotation=st.rotation, orientation_initial=st.orientation_initial, orientation_final=st.orientation_final,
        longest_push=_fence_bound_out(s.longest),
        shortest_push=_fence_bound_out(s.shortest),
        slip=_slip_out(s.slip),
    )


def align_problem(req: PushAlignRequest) -> AlignProblem:
    fp = footprint_of(req.footprint, req.center_of_mass, ("footprint",))
    if not fp.circumradius >= GROSS_MIN_LENGTH:
        raise FieldError(
            ("footprint",),
            f"is too small: its circumradius {fp.circumradius:.6g} is below {GROSS_MIN_LENGTH:g} "
            "(lengths squared would underflow)",
        )
    return AlignProblem(fp, req.orientation, req.fence_angle, req.push_direction, mu_c=req.mu_c, method=req.method,
                        n_nodes=req.n_nodes, n_points=req.n_points, quasi_static=quasi_static_query(req.quasi_static),
                        cost=SKETCH_COST)


def align_partial(problem: AlignProblem):
    """The converter of the stages done when the time limit runs out (the 504's ``partial``)."""
    index = problem.footprint.input_index

    def convert(stages: tuple[AlignStage, ...]) -> dict:
        return {"stages": [_stage_out(s, index).model_dump() for s in stages]}

    return convert


def _align_message(al: fg.FenceAlignment, stages: list[FenceStageOut], longest: BoundOut, index) -> str:
    if al.already_flush:
        i, j = (index(k) for k in al.final_edge)
        return (f"edge [{i}, {j}] is already flush with the fence and the line of force through the CM meets it: "
                "the part does not turn (zero push)")
    first = stages[0]
    i, j = al.final_edge
    text = (
        f"the fence touches vertex {first.contact_vertex_index} first; the part turns "
        f"{'clockwise' if al.sense == 'cw' else 'counter-clockwise'} by {al.total_rotation:.6g} rad in "
        f"{len(stages)} stage{'s' if len(stages) > 1 else ''} until edge [{index(i)}, {index(j)}] is flush"
    )
    if al.mirrored:
        text += " (reflected onto the book's clockwise case)"
    bits = []
    if longest.closed_form is not None:
        bits.append(f"closed form {longest.closed_form:.6g}")
    if longest.exact is not None:
        bits.append(f"exact {longest.exact:.6g}")
    if bits:
        text += "; longest push: " + ", ".join(bits)
    return text + _quadrature_warning([longest])


def _quadrature_warning(bounds: list[BoundOut]) -> str:
    """A remark when an exact bound's error estimate exceeds QUADRATURE_WARN_REL of it (an
    integrand with a near-singularity, e.g. (4.8) or (4.16) as beta_initial -> 0)."""
    worst = max(
        ((b.quadrature_error / abs(b.exact)) for b in bounds
         if b.exact is not None and b.quadrature_error is not None and b.exact != 0.0),
        default=0.0,
    )
    if worst <= QUADRATURE_WARN_REL:
        return ""
    return (f"; warning: an exact bound's quadrature error estimate is {100 * worst:.3g} % of it "
            "(the integrand has a kink or varies fast, e.g. near beta = 0): raise n_nodes")


def align_response(req: PushAlignRequest, result: AlignResult, elapsed_ms: float) -> PushAlignResponse:
    al = result.alignment
    index = result.problem.footprint.input_index
    stages = [_stage_out(s, index) for s in result.stages]
    longest = _bound_out(result.longest)
    shortest = _bound_out(result.shortest)

    def edge(ids):
        return FenceEdgeOut(vertex_indices=[index(k) for k in ids],
                            points=[listed(al.initial_vertices[k]) for k in ids])

    geometry = FenceGeometryOut(
        disk_radius=al.disk_radius,
        center_of_mass=listed(al.center_of_mass),
        alpha=al.alpha, alpha_unmirrored=al.alpha_unmirrored,
        fence_normal=listed(al.fence_normal),
        sense=al.sense, mirrored=al.mirrored,
        first_contact=edge((al.first_contact_index,)),
        already_flush=al.already_flush,
        initial_flush_edge=None if al.initial_flush_edge is None else [index(k) for k in al.initial_flush_edge],
        final_edge=edge(al.final_edge),
        total_rotation=al.total_rotation, final_orientation=al.final_orientation,
        below_line_of_motion=below_line_of_motion(al),
    )
    return PushAlignResponse(
        message=_align_message(al, stages, longest, index),
        method=req.method, mu_c=req.mu_c, nu=math.atan(req.mu_c),
        geometry=geometry, stages=stages, longest_push=longest, shortest_push=shortest,
        slip=_slip_out(result.slip),
        quasi_static=quasi_static_out(req.quasi_static, result.quasi_static),
        note=ALIGN_NOTE, reference=GROSS_REFERENCE,
        n_nodes=req.n_nodes, n_points=req.n_points, time_limit_s=req.time_limit_s,
        predicted_time_s=result.predicted_time_s, elapsed_ms=elapsed_ms,
    )


def encounter_problem(req: PushDiskEncounterRequest) -> DiskEncounterProblem:
    source = exactly_one(req, ("beta_initial", "offset"))
    return DiskEncounterProblem(
        req.disk_radius, req.mu_c, beta_initial=req.beta_initial if source == "beta_initial" else None,
        offset=req.offset if source == "offset" else None, method=req.method, n_nodes=req.n_nodes,
        n_points=req.n_points, quasi_static=quasi_static_query(req.quasi_static), cost=ENCOUNTER_SKETCH_COST,
    )


def encounter_response(req: PushDiskEncounterRequest, result: DiskEncounterResult,
                       elapsed_ms: float) -> PushDiskEncounterResponse:
    a, mu, beta, onset = req.disk_radius, req.mu_c, result.beta_initial, result.sketch_i_onset
    at_start = result.sketch_i_at_start
    sketch_i = SketchIOut(
        onset_beta=onset, at_start=at_start, occurs=onset < 0.5 * math.pi,
        note=(
            "tan beta > 2 mu_c (4.17): the tip of {COR}_(alpha+nu) lies left of the sticking line, the lower "
            "end of the sticking locus is no longer near the tip line, and (4.16) overestimates; "
            + ("the whole encounter is in sketch i" if at_start else
               f"sketch i begins at beta = {onset:.6g} rad, before the disk is left at pi/2 (4.4.1.2)")
        ),
    )
    length_max = _bound_out(result.length_max)
    message = (
        f"a disk of radius {a:.6g} met at beta = {beta:.6g} rad (offset {result.offset:.6g}) with mu_c = {mu:.6g}: "
        + (f"the encounter lasts at most {length_max.exact:.6g} (exact)" if length_max.exact is not None else
           f"the encounter lasts at most {length_max.closed_form:.6g} by (4.16)")
        + f"; the disk turns at most pi/2 - beta = {0.5 * math.pi - beta:.6g} rad; sketch i "
        + ("from the start" if at_start else f"from beta = {onset:.6g}")
    )
    length_min = _bound_out(result.length_min)
    rotation_max = _bound_out(result.rotation_max)
    rotation_min = _bound_out(result.rotation_min)
    message += _quadrature_warning([length_max, length_min, rotation_max, rotation_min])
    return PushDiskEncounterResponse(
        message=message, method=req.method, disk_radius=a, beta_initial=beta, beta_final=0.5 * math.pi,
        offset=result.offset, beta_source=result.beta_source, mu_c=mu, nu=math.atan(mu),
        length_greatest=length_max,
        length_least=length_min,
        length_frictionless=result.length_frictionless,
        rotation_greatest=rotation_max,
        rotation_least=rotation_min,
        sketch_i=sketch_i,
        quasi_static=quasi_static_out(req.quasi_static, result.quasi_static),
        note=ENCOUNTER_NOTE, reference=GROSS_REFERENCE,
        n_nodes=req.n_nodes, n_points=req.n_points, time_limit_s=req.time_limit_s,
        predicted_time_s=result.predicted_time_s, elapsed_ms=elapsed_ms,
    )


def encounter_partial(req: PushDiskEncounterRequest):
    """The converter of the closed forms computed when the time limit runs out (the 504's
    ``partial``: the answer with the exact bounds null)."""

    def convert(result: DiskEncounterResult) -> dict:
        return encounter_response(req, result, result.solve_time_s * 1e3).model_dump()

    return convert
