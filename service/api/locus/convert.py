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
    LocusTipLineOut,
    MembershipRequest,
    MembershipResponse,
    PerimeterArcOut,
    RMinOut,
    TipOut,
    WitnessOut,
)
from service.common.numbers import listed, point_or_none
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
            point=listed(locus.tip.point),
            distance=locus.tip.distance,
            distance_book=locus.tip.distance_book,
            on_disk=bool(locus.tip.on_disk),
        )
    tip_line = None
    if locus.tip_line is not None:
        tip_line = LocusTipLineOut(
            point=listed(locus.tip_line.point),
            direction=listed(locus.tip_line.direction),
            distance=locus.tip_line.distance,
        )
    r_min = None
    if locus.r_min is not None:
        r_min = RMinOut(point=listed(locus.r_min.point), distance=locus.r_min.distance)
    curvatures = None
    if locus.curvatures is not None:
        c = locus.curvatures
        curvatures = CurvaturesOut(
            tip_radius=c.tip_radius,
            tip_radius_book_printed=c.tip_radius_book_printed,
            r_min_radius=c.r_min_radius,
        )
    crossings = None
    if locus.disk_crossings is not None:
        dc = locus.disk_crossings
        crossings = DiskCrossingsOut(
            cos_eta=dc.cos_eta,
            points=listed(dc.points),
            arcs=[
                PerimeterArcOut(
                    start_angle=arc.start_angle,
                    end_angle=arc.end_angle,
                    start=listed(arc.start),
                    end=listed(arc.end),
                )
                for arc in dc.arcs
            ],
        )
    boundary = None if locus.boundary is None else listed(locus.boundary)
    residual = None if locus.boundary_residual is None else locus.boundary_residual
    return CorLocusResponse(
        kind=locus.kind,
        sense=locus.sense,
        message=translation_message(locus) if locus.kind == "translation" else None,
        disk_radius=scene.disk_radius,
        center_of_mass=listed(scene.center_of_mass),
        moment_arm=locus.moment_arm,
        relative_moment_arm=locus.relative_moment_arm,
        book_alpha=locus.book_alpha,
        axis=listed(locus.axis),
        translation_direction=listed(locus.translation_direction),
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
            else prep.contact_distance_to_outline
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
            boundary=[listed(p.point) for p in pairs],
            brackets=[
                BracketOut(
                    point=listed(p.point),
                    inner=listed(p.inner.cor),
                    outer=listed(p.outer.cor),
                    inner_status=p.inner.status,
                    outer_status=p.outer.status,
                    verdict=p.verdict,
                )
                for p in pairs
            ],
            bracket_width=2.0 * res.delta,
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
        bracket_width=res.width,
        wrong=[],
        undecided=[i for i, r in enumerate(rays) if r.verdict != "bracketed"],
        multi_crossing=[i for i, r in enumerate(rays) if r.crossings > 1],
        centre=listed(res.centre),
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
            points=listed(res.witness_points),
            weights=listed(res.witness_weights),
            point_mass_at_cor=res.point_mass_at_cor,
            point_mass_subgradient=listed(res.point_mass_subgradient),
            residual=res.witness_residual,
            forward_cor_error=(
                None if res.witness_forward_cor_error is None
                else res.witness_forward_cor_error
            ),
        )
    if res.dual is not None and res.status != "inside":
        dual = DualOut(
            vector=listed(res.dual),
            lower_bound=None if res.dual_lower_bound is None else res.dual_lower_bound,
            margin=None if res.dual_margin is None else res.dual_margin,
            lower_bound_method=res.lower_bound_method,
        )
    return MembershipResponse(
        status=res.status,
        certificate_kind=res.certificate_kind,
        cor=listed(res.cor),
        cor_query=[float(x) for x in req.cor],
        in_footprint=bool(res.in_footprint),
        witness=witness,
        dual=dual,
        residual=res.witness_residual if math.isfinite(res.witness_residual) else None,
        length_scale=res.length_scale,
        disk_radius=scene.disk_radius,
        center_of_mass=listed(scene.center_of_mass),
        iterations=int(res.iterations),
        n_columns=int(res.n_columns),
        bnb_intervals=int(res.bnb_intervals),
        message=res.message,
        time_limit_s=float(req.time_limit_s),
        solve_time_ms=res.solve_time_s * 1e3,
        elapsed_ms=elapsed_ms,
    )

