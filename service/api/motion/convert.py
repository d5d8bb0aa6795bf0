"""Schema <-> domain conversions of the minimum-power endpoints (no mechanics here).

Each ``*_response`` function takes a validated request, builds the domain objects of
:mod:`models` (``PushScene``, ``Support``, ``Footprint``), calls one function of
:mod:`solver`, and turns its result into the response schema with plain floats and no
NaN/inf. Domain ``InvalidInput`` errors are re-located to the request field they concern
(e.g. ``["body", "supports", 3, "weights"]``) with :func:`located`.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterator
from contextlib import contextmanager

import numpy as np

from models import particle
from models.errors import InvalidInput
from models.footprint import Footprint, area_centroid
from models.inertia import (
    disk_radius_of_gyration,
    impact_cor,
    impact_cor_distance,
    polygon_radius_of_gyration,
    support_radius_of_gyration,
)
from models.mpp import mason_sense
from models.scene import PushScene
from models.support import Support
from service.convert import _f, _v
from service.errors import FieldError, NonFiniteResult
from service.limits import (
    AGREEMENT_REL,
    CONTACT_IN_DISK_REL,
    MAX_BATCH_POINTS,
    MAX_BATCH_SLOW,
    MAX_SUPPORT_POINTS,
    MAX_SUPPORT_POINTS_SLOW,
    MAX_TRIPOD_CORS,
    MIN_FOOTPRINT_FILL,
    SAMPLING_MIN_SIZE,
    SAMPLING_MIN_SIZE_REL,
    SUPPORT_IN_DISK_REL,
)
from service.schemas_mpp import (
    BatchSummaryOut,
    CorSolveRequest,
    CorSolveResponse,
    DualOut,
    HistogramOut,
    ImpactOut,
    MembershipRequest,
    MembershipResponse,
    MotionOut,
    ParticleRequest,
    ParticleResponse,
    PressureSummaryOut,
    SupportIn,
    TripodStatisticsRequest,
    TripodStatisticsResponse,
    WitnessOut,
)
from solver.core.budget import Budget
from solver.motion.forward import BatchResult, ForwardResult, solve_forward, solve_forward_batch
from solver.locus.membership import membership
from solver.motion.particle import solve_particle
from solver.motion.statistics import sticking_line_histogram, tripod_sample, uniform_pressure_cor

Loc = tuple[str | int, ...]


@contextmanager
def located(prefix: Loc = (), rename: dict[str, Loc] | None = None) -> Iterator[None]:
    """Re-raise a domain ``InvalidInput(field, reason)`` as a :class:`FieldError` at
    ``rename[field]`` or, by default, at ``prefix + (field,)``."""
    try:
        yield
    except InvalidInput as exc:
        loc = (rename or {}).get(exc.field, (*prefix, exc.field))
        raise FieldError(loc, exc.reason) from exc


def exactly_one(req, names: tuple[str, ...]) -> str:
    """The one field of ``names`` that is given (not null); FieldError otherwise."""
    given = [name for name in names if getattr(req, name) is not None]
    listing = ", ".join(names[:-1]) + f" or {names[-1]}"
    if not given:
        raise FieldError((names[0],), f"give exactly one of {listing}")
    if len(given) > 1:
        raise FieldError((given[1],), f"give exactly one of {listing}, not both {given[0]} and {given[1]}")
    return given[0]


def footprint_of(vertices, center_of_mass, field: Loc) -> Footprint:
    """``Footprint.create`` with its errors located at ``field`` (it calls the polygon
    "workpiece")."""
    with located(rename={"workpiece": field, "vertices": field}):
        return Footprint.create(vertices, center_of_mass)


def contact_warnings(scene: PushScene) -> list[str]:
    c_norm = float(np.linalg.norm(scene.contact_rel))
    a = scene.disk_radius
    if c_norm > (1.0 + CONTACT_IN_DISK_REL) * a:
        return [
            f"contact_point is {c_norm:.6g} from the centre of mass, outside the disk of radius "
            f"a = {a:.6g} that should bound the workpiece"
        ]
    return []


# ---------------------------------------------------------------------------------------
# POST /v1/cor/solve
# ---------------------------------------------------------------------------------------


class _UserSupport:
    """A request support as a domain ``Support`` plus the map from the support's points
    (coincident points merged, zero weights dropped) back to the request's indices."""

    def __init__(self, sin: SupportIn, center_of_mass, loc: Loc, max_points: int, method: str):
        k = len(sin.points)
        if k > max_points:
            raise FieldError(
                (*loc, "points"),
                f"has {k} points; method {method} accepts at most {max_points} per support",
            )
        with located(loc):
            self.support = Support.create(sin.points, sin.weights, center_of_mass)
        pts = np.asarray(sin.points, dtype=float)
        kept = np.nonzero(np.asarray(sin.weights, dtype=float) > 0.0)[0]
        if np.array_equal(self.support.points, pts[kept]):
            self.index = kept
        else:  # coincident points were merged (or a tiny weight vanished on normalising)
            first: dict[tuple[float, float], int] = {}
            for i in kept[::-1]:
                first[(pts[i, 0], pts[i, 1])] = int(i)
            self.index = np.array([first[(w[0], w[1])] for w in self.support.points], dtype=int)
        self.extent = float(np.max(np.linalg.norm(self.support.points - self.support.center_of_mass, axis=1)))

    def original(self, j: int | None) -> int | None:
        return None if j is None or j < 0 else int(self.index[j])


def _disk_radius(req: CorSolveRequest, cm: np.ndarray, extent: float) -> float:
    """The explicit disk_radius (checked against the support's extent) or the default: the
    largest distance of a support point or of the contact from the CM."""
    if req.disk_radius is not None:
        if req.disk_radius < (1.0 - SUPPORT_IN_DISK_REL) * extent:
            raise FieldError(
                ("disk_radius",),
                f"is smaller than the support: a support point is {extent:.6g} from the centre of "
                "mass, outside the disk (omit disk_radius to use that distance)",
            )
        return float(req.disk_radius)
    a = max(extent, float(np.linalg.norm(np.asarray(req.contact_point, dtype=float) - cm)))
    if not (a > 0.0 and math.isfinite(a)):
        raise FieldError(
            ("disk_radius",),
            "cannot be derived: every support point and the contact are at the centre of mass; give it",
        )
    return a


def _require_length_scale(scene: PushScene, extent: float, loc: Loc) -> None:
    """The forward solver measures lengths in units of the farthest support point or
    contact from the CM; when all of them are at the CM there is no such unit."""
    if not max(extent, float(np.linalg.norm(scene.contact_rel))) > 0.0:
        raise FieldError(
            loc,
            "are all at the centre of mass, and so is the contact: the motion is undefined "
            "(move the contact or spread the support)",
        )


def _scene(req, disk_radius: float, cm) -> PushScene:
    with located():
        return PushScene.create(disk_radius, req.contact_point, req.edge_angle, req.push_direction, cm)


def _sense_of(omega: float, translation: bool) -> str:
    return "none" if translation else ("ccw" if omega > 0.0 else "cw")


def motion_out(scene: PushScene, res: ForwardResult, mu_c: float, cor_on_support: int | None) -> MotionOut:
    mason = mason_sense(scene.contact_rel, scene.normal, scene.push_hat, mu_c)
    return MotionOut(
        status=res.status,
        method=res.method,
        mode=res.mode,
        kind="translation" if res.cor is None else "rotation",
        cor=None if res.cor is None else _v(res.cor, "cor"),
        velocity_cm=_v(res.velocity_cm, "velocity_cm"),
        rotation_per_push=_f(res.omega, "rotation_per_push"),
        slip_per_push=_f(res.slip, "slip_per_push"),
        sense=res.sense,
        mason_sense=mason,
        mason_agrees=mason == res.sense,
        power=_f(res.power, "power"),
        contact_force=_v(res.contact_force, "contact_force"),
        kkt_residual=_f(res.kkt_residual, "kkt_residual"),
        gap=_f(res.gap, "gap"),
        cor_on_support=cor_on_support,
        iterations=int(res.iterations),
        solve_time_ms=res.solve_time_s * 1e3,
        raw_twist_error=None if res.raw_twist_error is None else _f(res.raw_twist_error, "raw_twist_error"),
    )


def batch_motion_out(scene: PushScene, br: BatchResult, j: int, mu_c: float, cor_on_support: int | None) -> MotionOut:
    """Row ``j`` of a Newton batch (the batch has no per-motion time)."""
    cor = br.cor[j]
    translation = not bool(np.all(np.isfinite(cor)))
    omega = float(br.omega[j])
    v = br.velocity_cm[j]
    sense = _sense_of(omega, translation)
    mason = mason_sense(scene.contact_rel, scene.normal, scene.push_hat, mu_c)
    return MotionOut(
        status="optimal" if bool(br.converged[j]) else "not_converged",
        method="newton",
        mode=BatchResult.MODES[int(br.mode[j])],
        kind="translation" if translation else "rotation",
        cor=None if translation else _v(cor, "cor"),
        velocity_cm=_v(v, "velocity_cm"),
        rotation_per_push=_f(omega, "rotation_per_push"),
        slip_per_push=_f(br.slip[j], "slip_per_push"),
        sense=sense,
        mason_sense=mason,
        mason_agrees=mason == sense,
        power=_f(br.power[j], "power"),
        contact_force=_v(br.contact_force[j], "contact_force"),
        kkt_residual=_f(br.kkt_residual[j], "kkt_residual"),
        gap=_f(br.gap[j], "gap"),
        cor_on_support=cor_on_support,
        iterations=int(br.iterations[j]),
        solve_time_ms=None,
    )


def _impact(scene: PushScene, rho: float, source: str) -> ImpactOut | None:
    """(7.1) with the radius of gyration ``rho``; rho may exceed a by rounding only (a is
    at least the support's extent), so it is capped at a. None when rho = 0 (all the mass
    at the CM: no rotational inertia, (7.1) is undefined)."""
    if not rho > 0.0:
        return None
    rho = min(rho, scene.disk_radius)
    with located():
        point = impact_cor(scene, rho)
        dist = impact_cor_distance(scene, rho)
    return ImpactOut(
        cor=None if point is None else _v(point, "impact.cor"),
        distance=None if dist is None else _f(dist, "impact.distance"),
        radius_of_gyration=_f(rho, "impact.radius_of_gyration"),
        source=source,
    )


def solve_response(req: CorSolveRequest) -> CorSolveResponse:
    t_start = time.perf_counter()
    which = exactly_one(req, ("support", "supports", "pressure"))
    slow = req.method != "newton"
    max_points = MAX_SUPPORT_POINTS_SLOW if slow else MAX_SUPPORT_POINTS
    mu_c = float(req.mu_c)
    motion = impact = motions = batch = pressure = None
    notes: list[str] = []

    if which == "pressure":
        pr = req.pressure
        n = pr.resolution
        if pr.footprint is not None:
            footprint = footprint_of(pr.footprint, req.center_of_mass, ("pressure", "footprint"))
            cm = footprint.center_of_mass
            extent = footprint.circumradius
            n_cells = (len(footprint.vertices) - 2) * n * n
            region = "polygon"
        else:
            footprint = None
            cm = np.asarray(req.center_of_mass if req.center_of_mass is not None else (0.0, 0.0), dtype=float)
            if req.disk_radius is None:
                raise FieldError(("disk_radius",), "is required for uniform pressure on the disk (or give pressure.footprint)")
            extent = 0.0
            n_cells = 6 * n * n
            region = "disk"
        if n_cells > max_points:
            raise FieldError(
                ("pressure", "resolution"),
                f"gives {n_cells} cells; method {req.method} accepts at most {max_points} points",
            )
        scene = _scene(req, _disk_radius(req, cm, extent), cm)
        with located(rename={"subdivisions": ("pressure", "resolution"), "rings": ("pressure", "resolution")}):
            res = uniform_pressure_cor(scene, footprint, resolution=n, mu_c=mu_c, method=req.method)
        motion = motion_out(scene, res, mu_c, res.cor_on_support)
        if footprint is None:
            impact = _impact(scene, disk_radius_of_gyration(scene.disk_radius), "uniform_disk")
        else:
            impact = _impact(scene, polygon_radius_of_gyration(footprint), "uniform_polygon")
        pressure = PressureSummaryOut(kind=pr.kind, region=region, resolution=n, n_cells=n_cells)
        solve_s = res.solve_time_s

    elif which == "support":
        cm = np.asarray(req.center_of_mass if req.center_of_mass is not None else (0.0, 0.0), dtype=float)
        us = _UserSupport(req.support, cm, ("support",), max_points, req.method)
        scene = _scene(req, _disk_radius(req, cm, us.extent), cm)
        _require_length_scale(scene, us.extent, ("support", "points"))
        with located(rename={"support": ("support",)}):
            res = solve_forward(scene, us.support, mu_c=mu_c, method=req.method)
        motion = motion_out(scene, res, mu_c, us.original(res.cor_on_support))
        rho = support_radius_of_gyration(us.support.points, us.support.weights)
        impact = _impact(scene, rho, "support")
        if impact is None:
            notes.append("impact is null: the whole support is at the centre of mass (radius of gyration 0)")
        solve_s = res.solve_time_s

    else:
        cm = np.asarray(req.center_of_mass if req.center_of_mass is not None else (0.0, 0.0), dtype=float)
        sups = req.supports
        if slow and len(sups) > MAX_BATCH_SLOW:
            raise FieldError(
                ("supports",),
                f"has {len(sups)} supports; method {req.method} accepts at most {MAX_BATCH_SLOW} "
                "(use method newton for large batches)",
            )
        total = sum(len(s.points) for s in sups)
        if total > MAX_BATCH_POINTS:
            raise FieldError(("supports",), f"has {total} points in all, more than {MAX_BATCH_POINTS}")
        users = [_UserSupport(s, cm, ("supports", i), max_points, req.method) for i, s in enumerate(sups)]
        scene = _scene(req, _disk_radius(req, cm, max(u.extent for u in users)), cm)
        for i, u in enumerate(users):
            _require_length_scale(scene, u.extent, ("supports", i, "points"))
        out: list[MotionOut | None] = [None] * len(users)
        fallbacks = 0
        solve_s = 0.0
        if slow:
            for i, u in enumerate(users):
                with located(rename={"support": ("supports", i)}):
                    res = solve_forward(scene, u.support, mu_c=mu_c, method=req.method)
                out[i] = motion_out(scene, res, mu_c, u.original(res.cor_on_support))
                solve_s += res.solve_time_s
        else:
            groups: dict[int, list[int]] = {}
            for i, u in enumerate(users):
                groups.setdefault(len(u.support.points), []).append(i)
            for idx in groups.values():
                pts = np.stack([users[i].support.points for i in idx])
                wts = np.stack([users[i].support.weights for i in idx])
                with located(("supports",), rename={"mu_c": ("mu_c",)}):
                    br = solve_forward_batch(scene, pts, wts, mu_c=mu_c, check_centroid=False)
                fallbacks += int(br.fallbacks)
                solve_s += br.solve_time_s
                for j, i in enumerate(idx):
                    out[i] = batch_motion_out(scene, br, j, mu_c, users[i].original(int(br.cor_on_support[j])))
        motions = out
        batch = BatchSummaryOut(
            n=len(out),
            converged=sum(m.status == "optimal" for m in out),
            translations=sum(m.kind == "translation" for m in out),
            fallbacks=fallbacks,
            support_sizes=sorted({len(u.support.points) for u in users}),
        )

    all_motions = motions if motions is not None else [motion]
    bad = sum(m.status != "optimal" for m in all_motions)
    if bad:
        notes.append(
            f"{bad} of {len(all_motions)} motions are not optimal (status not_converged or inconsistent): "
            "see their kkt_residual; another method may do better"
        )
    return CorSolveResponse(
        input=which,
        disk_radius=_f(scene.disk_radius, "disk_radius"),
        center_of_mass=_v(scene.center_of_mass, "center_of_mass"),
        mu_c=mu_c,
        method=req.method,
        motion=motion,
        impact=impact,
        motions=motions,
        batch=batch,
        pressure=pressure,
        warnings=contact_warnings(scene) + notes,
        solve_time_ms=solve_s * 1e3,
        elapsed_ms=(time.perf_counter() - t_start) * 1e3,
    )


# ---------------------------------------------------------------------------------------
# POST /v1/mpp/particle
# ---------------------------------------------------------------------------------------


def particle_response(req: ParticleRequest) -> ParticleResponse:
    t_start = time.perf_counter()
    try:
        with located():
            sol = solve_particle(req.v_x, req.mg, req.eta, req.n)
        kkt = abs(float(particle.power_derivative(sol.mpp_v_y_numeric, sol.scene))) / sol.scene.mg
        newton_res = float(particle.force_balance_residual(sol.newton_v_y, sol.scene))
    except (OverflowError, ZeroDivisionError, FloatingPointError) as exc:
        raise NonFiniteResult(f"the particle answer ({type(exc).__name__})") from exc
    agree = abs(sol.relative_disagreement) <= AGREEMENT_REL
    if agree:
        message = (
            "Newton's law and the minimum power principle agree"
            + (" (n = 0, Coulomb friction: book 2.5.2)" if sol.scene.n == 0.0 else "")
        )
    else:
        message = (
            f"the minimum power principle gives v_y = {sol.mpp_v_y:.6g}, Newton's law {sol.newton_v_y:.6g}: "
            f"they differ by {100.0 * sol.relative_disagreement:.4g} % because the dissipative force is "
            f"not Coulomb friction (n = {sol.scene.n:g} > 0); the principle holds only for n = 0 (book 2.5)"
        )
    return ParticleResponse(
        newton_v_y=_f(sol.newton_v_y, "newton_v_y"),
        mpp_v_y=_f(sol.mpp_v_y, "mpp_v_y"),
        mpp_v_y_numeric=_f(sol.mpp_v_y_numeric, "mpp_v_y_numeric"),
        relative_disagreement=_f(sol.relative_disagreement, "relative_disagreement"),
        agree=agree,
        numeric_error=_f(sol.numeric_error, "numeric_error"),
        kkt_residual=_f(kkt, "kkt_residual"),
        newton_residual=_f(newton_res, "newton_residual"),
        power_newton=_f(sol.power_newton, "power_newton"),
        power_mpp=_f(sol.power_mpp, "power_mpp"),
        status=sol.status,
        iterations=int(sol.iterations),
        message=message,
        solve_time_ms=sol.solve_time_s * 1e3,
        elapsed_ms=(time.perf_counter() - t_start) * 1e3,
    )


# ---------------------------------------------------------------------------------------
# POST /v1/cor/tripod-statistics
# ---------------------------------------------------------------------------------------


def _disk_or_footprint(req, footprint_limit_field: str = "footprint") -> tuple[PushScene, Footprint | None]:
    """Scene and footprint of a request with exactly one of disk_radius / footprint."""
    exactly_one(req, ("disk_radius", "footprint"))
    footprint = None
    if req.footprint is not None:
        footprint = footprint_of(req.footprint, req.center_of_mass, (footprint_limit_field,))
        radius, cm = footprint.circumradius, footprint.center_of_mass
    else:
        radius = req.disk_radius
        cm = req.center_of_mass if req.center_of_mass is not None else (0.0, 0.0)
    return _scene(req, radius, cm), footprint


def _check_samplable(scene: PushScene, footprint: Footprint | None, explicit_cm: bool) -> None:
    """Refuse what the tripod sampler (rejection sampling of balanced tripods, 3.3.3) cannot
    finish in reasonable time: a region below the float resolution of its coordinates, a
    sliver filling little of its bounding box, a centre of mass near the hull (almost no
    triangle contains it)."""
    size = scene.disk_radius
    field = "disk_radius" if footprint is None else "footprint"
    if size < SAMPLING_MIN_SIZE or size < SAMPLING_MIN_SIZE_REL * float(np.max(np.abs(scene.center_of_mass))):
        raise FieldError(
            (field,),
            f"is too small to sample: its size {size:.3g} must be at least {SAMPLING_MIN_SIZE:g} and "
            f"{SAMPLING_MIN_SIZE_REL:g} times the distance of the centre of mass from the origin",
        )
    if footprint is None:
        return
    if explicit_cm:
        centroid = area_centroid(footprint.vertices)
        if np.linalg.norm(centroid - footprint.center_of_mass) > SUPPORT_IN_DISK_REL * footprint.circumradius:
            raise FieldError(
                ("center_of_mass",),
                "must be the footprint's area centroid (or omitted) for tripod statistics: with the "
                "CM near the hull almost no random triangle contains it and sampling would not end",
            )
    box = np.ptp(footprint.vertices, axis=0)
    fill = footprint.area / float(box[0] * box[1])
    if fill < MIN_FOOTPRINT_FILL:
        raise FieldError(
            ("footprint",),
            f"fills {fill:.3g} of its bounding box, less than {MIN_FOOTPRINT_FILL:g}: tripods are "
            "drawn by rejection from the box and would take too long (rotate the polygon to "
            "align it with the axes, or use a fuller shape)",
        )


def tripod_statistics_response(req: TripodStatisticsRequest) -> TripodStatisticsResponse:
    t_start = time.perf_counter()
    if req.include_cors and req.n_tripods > MAX_TRIPOD_CORS:
        raise FieldError(
            ("include_cors",),
            f"the CORs of at most {MAX_TRIPOD_CORS} tripods are returned; set include_cors false "
            "for larger samples",
        )
    scene, footprint = _disk_or_footprint(req)
    _check_samplable(scene, footprint, req.center_of_mass is not None)
    with located():
        sample = tripod_sample(scene, req.n_tripods, req.seed, mu_c=req.mu_c, footprint=footprint)
    b = sample.batch
    finite = np.all(np.isfinite(b.cor), axis=1)
    cors = None
    if req.include_cors:
        cors = [(_v(c, "cors") if ok else None) for c, ok in zip(b.cor, finite)]
    modes = {name: int(np.sum(b.mode == i)) for i, name in enumerate(BatchResult.MODES)}
    hist = None
    solve_s = b.solve_time_s
    if req.histogram:
        span = None if req.span is None else (req.span[0], req.span[1])
        with located():
            h = sticking_line_histogram(
                scene, req.n_tripods, req.seed, mu_c=req.histogram_mu_c, bins=req.bins, span=span,
                footprint=footprint,
            )
        hist = HistogramOut(
            edges=_v(h.edges, "histogram.edges"),
            counts=[int(c) for c in h.counts],
            sticking_fraction=_f(h.sticking_fraction, "histogram.sticking_fraction"),
            outside_range=int(h.outside_range),
            mu_c=float(req.histogram_mu_c),
            solve_time_ms=h.solve_time_s * 1e3,
        )
        solve_s += h.solve_time_s
    return TripodStatisticsResponse(
        status="optimal" if bool(np.all(b.converged)) else "not_converged",
        max_kkt_residual=_f(np.max(b.kkt_residual), "max_kkt_residual"),
        n_tripods=req.n_tripods,
        seed=req.seed,
        disk_radius=_f(scene.disk_radius, "disk_radius"),
        center_of_mass=_v(scene.center_of_mass, "center_of_mass"),
        mu_c=float(req.mu_c),
        cors=cors,
        converged=int(np.sum(b.converged)),
        translations=int(np.sum(~finite)),
        fallbacks=int(b.fallbacks),
        mode_counts=modes,
        histogram=hist,
        solve_time_ms=solve_s * 1e3,
        elapsed_ms=(time.perf_counter() - t_start) * 1e3,
    )


# ---------------------------------------------------------------------------------------
# POST /v1/cor/membership
# ---------------------------------------------------------------------------------------


def membership_response(req: MembershipRequest) -> MembershipResponse:
    t_start = time.perf_counter()
    scene, footprint = _disk_or_footprint(req)
    with located():
        res = membership(scene, req.cor, footprint, budget=Budget.of(req.time_limit_s))
    witness = dual = None
    if res.status == "inside":
        witness = WitnessOut(
            points=_v(res.witness_points, "witness.points"),
            weights=_v(res.witness_weights, "witness.weights"),
            point_mass_at_cor=_f(res.point_mass_at_cor, "witness.point_mass_at_cor"),
            point_mass_subgradient=_v(res.point_mass_subgradient, "witness.point_mass_subgradient"),
            residual=_f(res.witness_residual, "witness.residual"),
            forward_cor_error=(
                None if res.witness_forward_cor_error is None
                else _f(res.witness_forward_cor_error, "witness.forward_cor_error")
            ),
        )
    if res.dual is not None and res.status != "inside":
        dual = DualOut(
            vector=_v(res.dual, "dual.vector"),
            lower_bound=None if res.dual_lower_bound is None else _f(res.dual_lower_bound, "dual.lower_bound"),
            margin=None if res.dual_margin is None else _f(res.dual_margin, "dual.margin"),
            lower_bound_method=res.lower_bound_method,
        )
    return MembershipResponse(
        status=res.status,
        certificate_kind=res.certificate_kind,
        cor=_v(res.cor, "cor"),
        cor_query=[float(x) for x in req.cor],
        in_footprint=bool(res.in_footprint),
        witness=witness,
        dual=dual,
        residual=_f(res.witness_residual, "residual") if math.isfinite(res.witness_residual) else None,
        length_scale=_f(res.length_scale, "length_scale"),
        disk_radius=_f(scene.disk_radius, "disk_radius"),
        center_of_mass=_v(scene.center_of_mass, "center_of_mass"),
        iterations=int(res.iterations),
        n_columns=int(res.n_columns),
        bnb_intervals=int(res.bnb_intervals),
        message=res.message,
        time_limit_s=float(req.time_limit_s),
        solve_time_ms=res.solve_time_s * 1e3,
        elapsed_ms=(time.perf_counter() - t_start) * 1e3,
    )
