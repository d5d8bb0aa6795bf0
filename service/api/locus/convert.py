"""Schema <-> problem <-> schema for ``POST /v1/cor/locus`` and ``POST /v1/cor/membership``
(no mechanics here).

:func:`locus_problem` turns a validated request into a :class:`solver.locus.cor_locus.LocusProblem`
(the scene by :func:`service.common.scene.prepare_push`); :func:`locus_response` turns the
:class:`solver.locus.cor_locus.LocusResult` back into the response schema, with plain lists
of floats and no NaN/inf. The same for membership with
:class:`solver.locus.membership.MembershipProblem`.
"""

from __future__ import annotations

import math

from models.locus.cor_disk import OUTPUTS, DiskCorLocus
from service.api.locus.schemas import (
    BracketOut,
    CertifiedLocusOut,
    CorLocusRequest,
    CorLocusResponse,
    CurvaturesOut,
    DiskCrossingsOut,
    DualOut,
    MembershipRequest,
    MembershipResponse,
    PerimeterArcOut,
    RMinOut,
    TipLineOut,
    TipOut,
    WitnessOut,
)
from service.common.numbers import finite, finite_list, point_or_none
from service.common.scene import PreparedPush, disk_or_footprint, prepare_push
from solver import CertifiedDiskBoundary, LocusProblem, LocusResult, MembershipProblem, MembershipResult


def locus_problem(req: CorLocusRequest, all_outputs: bool = False) -> tuple[PreparedPush, LocusProblem]:
    """The scene of the request and its locus problem (``all_outputs``: every part of the
    analytic locus, for the picture)."""
    prep = prepare_push(req)
    outputs = tuple(dict.fromkeys([*req.outputs, *(OUTPUTS if all_outputs else ())]))
    problem = LocusProblem(prep.scene, prep.footprint, outputs, req.n_points, req.method, req.n_certified)
    return prep, problem


def translation_message(locus: DiskCorLocus) -> str:
    d = locus.translation_direction
    angle = math.atan2(float(d[1]), float(d[0]))
    return (
        f"pure translation along ({float(d[0]):.6g}, {float(d[1]):.6g}) "
        f"(direction {angle:.6g} rad): the line of force passes through the centre of mass; "
        "the COR is at infinity"
    )


def locus_response(prep: PreparedPush, result: LocusResult, time_limit_s: float, elapsed_ms: float) -> CorLocusResponse:
    """The response schema for ``result``; raises ``NonFiniteResult`` rather than letting a
    NaN or infinity through."""
    scene = prep.scene
    locus = result.analytic
    tip = None
    if locus.tip is not None:
        tip = TipOut(
            point=finite_list(locus.tip.point, "tip.point"),
            distance=finite(locus.tip.distance, "tip.distance"),
            distance_book=finite(locus.tip.distance_book, "tip.distance_book"),
            on_disk=bool(locus.tip.on_disk),
        )
    tip_line = None
    if locus.tip_line is not None:
        tip_line = TipLineOut(
            point=finite_list(locus.tip_line.point, "tip_line.point"),
            direction=finite_list(locus.tip_line.direction, "tip_line.direction"),
            distance=finite(locus.tip_line.distance, "tip_line.distance"),
        )
    r_min = None
    if locus.r_min is not None:
        r_min = RMinOut(point=finite_list(locus.r_min.point, "r_min.point"), distance=finite(locus.r_min.distance, "r_min.distance"))
    curvatures = None
    if locus.curvatures is not None:
        c = locus.curvatures
        curvatures = CurvaturesOut(
            tip_radius=finite(c.tip_radius, "curvatures.tip_radius"),
            tip_radius_book_printed=finite(c.tip_radius_book_printed, "curvatures.tip_radius_book_printed"),
            r_min_radius=finite(c.r_min_radius, "curvatures.r_min_radius"),
        )
    crossings = None
    if locus.disk_crossings is not None:
        dc = locus.disk_crossings
        crossings = DiskCrossingsOut(
            cos_eta=finite(dc.cos_eta, "disk_crossings.cos_eta"),
            points=finite_list(dc.points, "disk_crossings.points"),
            arcs=[
                PerimeterArcOut(
                    start_angle=finite(arc.start_angle, "disk_crossings.arcs.start_angle"),
                    end_angle=finite(arc.end_angle, "disk_crossings.arcs.end_angle"),
                    start=finite_list(arc.start, "disk_crossings.arcs.start"),
                    end=finite_list(arc.end, "disk_crossings.arcs.end"),
                )
                for arc in dc.arcs
            ],
        )
    boundary = None if locus.boundary is None else finite_list(locus.boundary, "boundary")
    residual = None if locus.boundary_residual is None else finite(locus.boundary_residual, "boundary_residual")
    return CorLocusResponse(
        kind=locus.kind,
        sense=locus.sense,
        message=translation_message(locus) if locus.kind == "translation" else None,
        disk_radius=finite(scene.disk_radius, "disk_radius"),
        center_of_mass=finite_list(scene.center_of_mass, "center_of_mass"),
        moment_arm=finite(locus.moment_arm, "moment_arm"),
        relative_moment_arm=finite(locus.relative_moment_arm, "relative_moment_arm"),
        book_alpha=finite(locus.book_alpha, "book_alpha"),
        axis=finite_list(locus.axis, "axis"),
        translation_direction=finite_list(locus.translation_direction, "translation_direction"),
        r_tip=None if tip is None else tip.distance,
        tip=tip,
        tip_line=tip_line,
        r_min=r_min,
        curvatures=curvatures,
        disk_crossings=crossings,
        boundary=boundary,
        boundary_residual=residual,
        boundary_iterations=locus.boundary_iterations,
        contact_distance_to_outline=(
            None if prep.contact_distance_to_outline is None
            else finite(prep.contact_distance_to_outline, "contact_distance_to_outline")
        ),
        warnings=[*prep.warnings, *result.notes],
        method=result.problem.method,
        locus_of="disk" if prep.footprint is None else "circumscribing_disk",
        certified=None if result.certified is None else certified_out(result, time_limit_s),
        elapsed_ms=elapsed_ms,
    )


def certified_out(result: LocusResult, time_limit_s: float) -> CertifiedLocusOut:
    """The certified brackets of ``result`` (method certified, not a translation)."""
    res = result.certified
    if isinstance(res, CertifiedDiskBoundary):
        pairs = res.pairs
        return CertifiedLocusOut(
            region="disk",
            n_requested=result.n_requested,
            n_done=result.n_done,
            n_certified=res.n_certified,
            complete=res.complete,
            boundary=[finite_list(p.point, "certified.boundary") for p in pairs],
            brackets=[
                BracketOut(
                    point=finite_list(p.point, "certified.point"),
                    inner=finite_list(p.inner.cor, "certified.inner"),
                    outer=finite_list(p.outer.cor, "certified.outer"),
                    inner_status=p.inner.status,
                    outer_status=p.outer.status,
                    verdict=p.verdict,
                )
                for p in pairs
            ],
            bracket_width=finite(2.0 * res.delta, "certified.bracket_width"),
            wrong=list(res.wrong),
            undecided=list(res.undecided),
            multi_crossing=[],
            centre=None,
            time_limit_s=time_limit_s,
            solve_time_ms=res.solve_time_s * 1e3,
        )
    rays = list(res.rays)
    brackets = []
    for ray in rays:
        ok = math.isfinite(ray.t_in) and math.isfinite(ray.t_out) and ray.inner is not None
        brackets.append(BracketOut(
            point=point_or_none(ray.point),
            inner=point_or_none(ray.inner.cor) if ok else None,
            outer=point_or_none(ray.outer.cor) if ok else None,
            inner_status=ray.inner.status if ray.inner is not None else None,
            outer_status=ray.outer.status if ray.outer is not None else None,
            verdict=ray.verdict,
            crossings=int(ray.crossings),
        ))
    return CertifiedLocusOut(
        region="polygon",
        n_requested=result.n_requested,
        n_done=result.n_done,
        n_certified=sum(r.verdict == "bracketed" for r in rays),
        complete=result.complete,
        boundary=[point_or_none(r.point) for r in rays],
        brackets=brackets,
        bracket_width=finite(res.width, "certified.bracket_width"),
        wrong=[],
        undecided=[i for i, r in enumerate(rays) if r.verdict != "bracketed"],
        multi_crossing=[i for i, r in enumerate(rays) if r.crossings > 1],
        centre=finite_list(res.centre, "certified.centre"),
        time_limit_s=time_limit_s,
        solve_time_ms=res.solve_time_s * 1e3,
    )


# ---------------------------------------------------------------------------------------
# POST /v1/cor/membership
# ---------------------------------------------------------------------------------------


def membership_problem(req: MembershipRequest) -> MembershipProblem:
    scene, footprint = disk_or_footprint(req)
    return MembershipProblem(scene, req.cor, footprint)


def membership_response(req: MembershipRequest, problem: MembershipProblem, res: MembershipResult,
                        elapsed_ms: float) -> MembershipResponse:
    scene = problem.scene
    witness = dual = None
    if res.status == "inside":
        witness = WitnessOut(
            points=finite_list(res.witness_points, "witness.points"),
            weights=finite_list(res.witness_weights, "witness.weights"),
            point_mass_at_cor=finite(res.point_mass_at_cor, "witness.point_mass_at_cor"),
            point_mass_subgradient=finite_list(res.point_mass_subgradient, "witness.point_mass_subgradient"),
            residual=finite(res.witness_residual, "witness.residual"),
            forward_cor_error=(
                None if res.witness_forward_cor_error is None
                else finite(res.witness_forward_cor_error, "witness.forward_cor_error")
            ),
        )
    if res.dual is not None and res.status != "inside":
        dual = DualOut(
            vector=finite_list(res.dual, "dual.vector"),
            lower_bound=None if res.dual_lower_bound is None else finite(res.dual_lower_bound, "dual.lower_bound"),
            margin=None if res.dual_margin is None else finite(res.dual_margin, "dual.margin"),
            lower_bound_method=res.lower_bound_method,
        )
    return MembershipResponse(
        status=res.status,
        certificate_kind=res.certificate_kind,
        cor=finite_list(res.cor, "cor"),
        cor_query=[float(x) for x in req.cor],
        in_footprint=bool(res.in_footprint),
        witness=witness,
        dual=dual,
        residual=finite(res.witness_residual, "residual") if math.isfinite(res.witness_residual) else None,
        length_scale=finite(res.length_scale, "length_scale"),
        disk_radius=finite(scene.disk_radius, "disk_radius"),
        center_of_mass=finite_list(scene.center_of_mass, "center_of_mass"),
        iterations=int(res.iterations),
        n_columns=int(res.n_columns),
        bnb_intervals=int(res.bnb_intervals),
        message=res.message,
        time_limit_s=float(req.time_limit_s),
        solve_time_ms=res.solve_time_s * 1e3,
        elapsed_ms=elapsed_ms,
    )

