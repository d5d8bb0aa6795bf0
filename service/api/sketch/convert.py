"""Schema <-> problem <-> schema of ``POST /v1/cor/sketch`` (no mechanics here).

The request becomes a ``PushScene`` exactly as for ``/v1/cor/locus``
(:func:`service.common.scene.prepare_push`: a disk, or a polygon bounded by its
circumscribing disk, with the same warnings) and a
:class:`solver.sketch.cor_sketch.SketchProblem`; :func:`sketch_response` turns the
:class:`solver.sketch.cor_sketch.SketchResult` into the response schema with plain floats and
no NaN/inf (with the certification report of method ``certified``).
"""

from __future__ import annotations

from models.sketch.disk_sketch import CorSketch, ElementaryLocus
from service.api.sketch.schemas import (
    CorSketchRequest,
    CorSketchResponse,
    ElementaryLocusOut,
    LineOut,
    SketchCertificationOut,
    StickingEndOut,
    StickingLocusOut,
    TipLineEstimateOut,
)
from service.common.numbers import listed
from service.common.scene import PreparedPush, prepare_push
from service.errors import FieldError
from service.limits import SKETCH_MIN_LENGTH
from solver import CertifiedSketch, LocusEnd, SketchProblem, SketchResult

IMPLICATION_TEXT = {
    "must_slip_up": "the part must slip up relative to the pusher",
    "must_slip_down": "the part must slip down relative to the pusher",
    "stick_or_slip_up": "the part must stick to the pusher or slip up",
    "stick_or_slip_down": "the part must stick to the pusher or slip down",
    "must_stick": "the part must stick to the pusher",
    "anything": "sticking and either slipping are possible, depending on the pressure distribution",
}
"""The implications of 4.1.6 in words."""


def sketch_problem(req: CorSketchRequest, with_tip_line: bool = False) -> tuple[PreparedPush, SketchProblem]:
    """The scene of the request, built and checked as for ``/v1/cor/locus``, and its sketch
    problem (``with_tip_line``: also the tip line, for the picture)."""
    prep = prepare_push(req)
    if prep.footprint is not None and not prep.scene.disk_radius >= SKETCH_MIN_LENGTH:
        raise FieldError(
            (prep.shape_field,),
            f"is too small: its circumradius {prep.scene.disk_radius:.6g} is below {SKETCH_MIN_LENGTH:g} "
            "(lengths squared would underflow)",
        )
    problem = SketchProblem(prep.scene, req.mu_c, footprint=prep.footprint, method=req.method,
                            n_points=req.n_points, n_rays=req.n_rays, with_tip_line=with_tip_line)
    return prep, problem


def _elementary(loc: ElementaryLocus, sigma: float, nu: float) -> ElementaryLocusOut:
    return ElementaryLocusOut(
        label=loc.label,
        force_direction=listed(loc.force),
        force_angle=sigma * nu,
        boundary=None if loc.boundary is None else listed(loc.boundary),
        tip=None if loc.tip is None else listed(loc.tip),
        moment_sign=int(loc.moment_sign),
        configuration=loc.configuration,
        crosses_sticking_line=bool(loc.crosses_sticking_line),
        tip_on_cm_side=None if loc.tip_on_cm_side is None else bool(loc.tip_on_cm_side),
    )


def is_translation(sk: CorSketch) -> bool:
    """Mason's rule (with the cone) gave no sense of rotation: no sketch."""
    return sk.sense == "none"


def sketch_of(prep: PreparedPush, certified: bool) -> str:
    if prep.footprint is None:
        return "disk"
    return "polygon" if certified else "circumscribing_disk"


def bounded_note(prep: PreparedPush, certified: CertifiedSketch | None) -> str:
    """What the message says first when a certified sketch is not whole: the sketch answered
    is the disk's analytic one, which bounds the polygon's (7.5; for a disk it is the sketch
    the certification checks), not a verdict drawn from the pieces finished."""
    if certified is None or certified.complete:
        return ""
    why = "the time limit cut it short" if certified.time_limited else "a piece is not certified"
    whose = "the polygon's" if prep.footprint is not None else "the"
    answered = ("its circumscribing disk's sketch, which bounds it (7.5), is answered" if prep.footprint is not None
                else "the analytic sketch is answered")
    return f"{whose} certified sketch is incomplete ({why}; see certification): {answered}: "


def sketch_message(prep: PreparedPush, sk: CorSketch, certified: bool = False) -> str:
    of = {"disk": "", "circumscribing_disk": " of the polygon's circumscribing disk", "polygon": " of the polygon"}[
        sketch_of(prep, certified)]
    if is_translation(sk):
        if not any(prep.scene.contact_rel):
            return (
                "the contact is at the centre of mass: every pusher force passes through it and the "
                "part translates (the COR is at infinity); there is no sketch"
            )
        return (
            "Mason's rule gives no sense of rotation (1.6.2): the line of pushing passes through the "
            "centre of mass inside the friction cone, so for every pressure distribution the part "
            "translates along the push with the contact sticking (the COR is at infinity); there is "
            "no sketch"
        )
    configs = f"{{COR}}_(alpha+nu) {sk.plus.configuration}, {{COR}}_(alpha-nu) {sk.minus.configuration}"
    if sk.sketch is None:
        return (
            f"the COR sketch{of} matches none of the nine sketches of figure 4-6 ({configs}; e.g. a "
            "friction-cone edge pointing back against the push, which the book never draws); "
            f"allowed modes, from the non-empty loci: {', '.join(sk.allowed_modes) or 'none'}"
        )
    mirror = ", mirrored" if sk.mirrored else ""
    where = {"disk": "", "circumscribing_disk": " (the polygon's circumscribing disk)", "polygon": " (the polygon itself)"}[
        sketch_of(prep, certified)]
    return f"sketch {sk.sketch} of figure 4-6{mirror}{where}: {IMPLICATION_TEXT[sk.implication]} ({configs})"


def _end(end: LocusEnd | None) -> StickingEndOut | None:
    if end is None:
        return None
    return StickingEndOut(
        status=end.status, position=end.position,
        feasible_position=None if end.feasible_position is None else end.feasible_position,
        infeasible_position=(None if end.infeasible_position is None
                             else end.infeasible_position),
        width=end.width, certified=bool(end.certified),
    )


def certification_out(cs: CertifiedSketch) -> SketchCertificationOut:
    st = cs.sticking
    polygon = cs.footprint is not None
    return SketchCertificationOut(
        complete=cs.complete, time_limited=cs.time_limited, message=cs.message,
        sticking_status=None if st is None else st.status,
        sticking_lower=None if st is None else _end(st.lower),
        sticking_upper=None if st is None else _end(st.upper),
        sticking_multiple_intervals=bool(st is not None and st.multiple_intervals),
        n_rays=cs.n_rays if polygon else None,
        plus_certified_rays=None if cs.plus_trace is None else int(cs.plus_trace.n_certified),
        minus_certified_rays=None if cs.minus_trace is None else int(cs.minus_trace.n_certified),
        solve_time_s=cs.solve_time_s,
    )


def sketch_response(prep: PreparedPush, result: SketchResult, elapsed_ms: float) -> CorSketchResponse:
    """The response schema for ``result`` (with the certification report of a certified
    sketch); raises ``NonFiniteResult`` rather than letting a NaN or infinity through."""
    scene = prep.scene
    sk = result.sketch
    certified = result.certified
    whole = certified is not None and not result.bounded  # the polygon's own sketch was answered
    sticking = None
    if sk.sticking is not None:
        s = sk.sticking
        sticking = StickingLocusOut(
            t_low=s.t_low,
            t_high=s.t_high,
            low=listed(s.low),
            high=listed(s.high),
            phi_low=None if s.phi_low is None else s.phi_low,
            phi_high=None if s.phi_high is None else s.phi_high,
        )
    tip_line = None
    if sk.tip_line_t is not None:
        tip_line = TipLineEstimateOut(
            point=listed(sk.tip_line_low),
            t=sk.tip_line_t,
            error=None if sk.tip_line_error is None else sk.tip_line_error,
        )
    return CorSketchResponse(
        kind="translation" if is_translation(sk) else "sketch",
        message=bounded_note(prep, certified) + sketch_message(prep, sk, whole),
        mu_c=sk.mu_c,
        nu=sk.nu,
        sense=sk.sense,
        disk_radius=scene.disk_radius,
        center_of_mass=listed(scene.center_of_mass),
        sketch_of=sketch_of(prep, whole),
        method="analytic" if certified is None else "certified",
        certification=None if certified is None else certification_out(certified),
        sticking_line=LineOut(
            point=listed(sk.sticking_line_point),
            direction=listed(sk.sticking_line_direction),
        ),
        edge_normal_direction=listed(sk.edge_normal_direction),
        plus=_elementary(sk.plus, 1.0, sk.nu),
        minus=_elementary(sk.minus, -1.0, sk.nu),
        down_slipping=[listed(p) for p in sk.down_slipping],
        up_slipping=[listed(p) for p in sk.up_slipping],
        sticking=sticking,
        tip_line_estimate=tip_line,
        sketch=sk.sketch,
        mirrored=bool(sk.mirrored),
        implication=sk.implication,
        allowed_modes=list(sk.allowed_modes),
        n_points=result.problem.n_points,
        contact_distance_to_outline=(
            None if prep.contact_distance_to_outline is None
            else prep.contact_distance_to_outline
        ),
        warnings=list(prep.warnings),
        elapsed_ms=elapsed_ms,
    )
