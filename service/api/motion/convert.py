"""Schema <-> problem <-> schema of ``POST /v1/cor/solve`` and ``POST
/v1/cor/tripod-statistics`` (no mechanics here).

:func:`motion_problem` builds the domain objects of :mod:`models` (``PushScene``,
``Support``, ``Footprint``) and a :class:`solver.motion.solve.MotionProblem`, checking the
service's size limits; :func:`solve_response` turns the
:class:`solver.motion.solve.MotionResult` into the response schema with plain floats and
no NaN/inf. Domain ``InvalidInput`` errors are re-located to the request field they
concern (e.g. ``["body", "supports", 3, "weights"]``). The same for the tripod statistics
with :class:`solver.motion.statistics.TripodStatisticsProblem`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from models.core.footprint import Footprint, area_centroid
from models.core.mpp import mason_sense
from models.core.scene import PushScene
from models.core.support import Support, SupportBatch
from service.api.motion.schemas import (
    BatchSummaryOut,
    CorColumnsOut,
    CorSolveRequest,
    CorSolveResponse,
    HistogramOut,
    ImpactOut,
    MotionColumnsOut,
    MotionOut,
    PressureSummaryOut,
    SupportIn,
    TripodStatisticsRequest,
    TripodStatisticsResponse,
)
from service.common.inputs import Loc, exactly_one, footprint_of, located
from service.common.numbers import listed
from service.common.scene import contact_warnings, disk_or_footprint, push_scene
from service.errors import FieldError
from service.limits import (
    MAX_BATCH,
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
from solver import (
    SOLVER_DEFAULT,
    BatchResult,
    ForwardResult,
    HistogramQuery,
    Impact,
    MotionProblem,
    MotionResult,
    TripodStatistics,
    TripodStatisticsProblem,
    UniformPressure,
)

PRESSURE_FIELDS = {"subdivisions": ("pressure", "resolution"), "rings": ("pressure", "resolution")}
"""Where an InvalidInput of the uniform-pressure discretisation is located in the request."""

# ---------------------------------------------------------------------------------------
# POST /v1/cor/solve
# ---------------------------------------------------------------------------------------


class RequestSupport:
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


@dataclass(frozen=True)
class MotionRequest:
    """A /v1/cor/solve request as a problem, with what the answer needs of the request:
    ``which`` input was given, the request's supports (their index maps), the pressure's
    cell count, a batch's ``layout`` ("rows" or "columns"; None for one motion)."""

    problem: MotionProblem
    which: str
    supports: tuple[RequestSupport, ...]
    n_cells: int | None
    layout: str | None = None


def _layout(req: CorSolveRequest, which: str, n: int) -> str | None:
    """The layout of a batch's answer (None for one motion), checked against its size."""
    if which not in ("supports", "batch"):
        if req.layout is not None:
            raise FieldError(("layout",), "applies to a batch only (`supports` or `batch`)")
        return None
    layout = req.layout or ("columns" if which == "batch" else "rows")
    if layout == "rows" and n > MAX_BATCH:
        raise FieldError(("layout",), f"'rows' answers at most {MAX_BATCH} motions and this batch has {n}: use 'columns'")
    return layout


def _batch_problem(req: CorSolveRequest, cm: np.ndarray) -> MotionRequest:
    """A columnar batch (``batch``): its arrays checked and shaped (B, k, 2), (B, k)."""
    if req.method != "newton":
        raise FieldError(("method",), f"is {req.method}: a columnar `batch` is solved by newton only")
    cols = req.batch
    k, n = cols.support_size, len(cols.x)
    for name in ("y", "weights"):
        if len(getattr(cols, name)) != n:
            raise FieldError(("batch", name), f"has {len(getattr(cols, name))} entries and x has {n}: one per point")
    if n % k:
        raise FieldError(("batch", "x"), f"has {n} entries, not a whole number of supports of support_size {k}")
    points = np.column_stack((np.asarray(cols.x, dtype=float), np.asarray(cols.y, dtype=float))).reshape(-1, k, 2)
    with located(("batch",)):
        supports = SupportBatch.create(points, np.asarray(cols.weights, dtype=float).reshape(-1, k), cm)
    reach = np.max(np.linalg.norm(points - cm, axis=2), axis=1)
    scene = push_scene(req, _disk_radius(req, cm, float(np.max(reach))), cm)
    if not float(np.linalg.norm(scene.contact_rel)) > 0.0 and not np.all(reach > 0.0):
        _require_length_scale(scene, 0.0, ("batch", "x"))
    problem = MotionProblem(scene, batch=supports, mu_c=float(req.mu_c), method="newton")
    return MotionRequest(problem, "batch", (), None, _layout(req, "batch", len(supports)))


def motion_problem(req: CorSolveRequest) -> MotionRequest:
    """Check the service's limits and build the problem of ``req``."""
    which = exactly_one(req, ("support", "supports", "batch", "pressure"))
    if which == "batch":
        return _batch_problem(req, np.asarray(req.center_of_mass or (0.0, 0.0), dtype=float))
    layout = _layout(req, which, len(req.supports) if which == "supports" else 1)
    slow = req.method != "newton"
    max_points = MAX_SUPPORT_POINTS_SLOW if slow else MAX_SUPPORT_POINTS
    mu_c = float(req.mu_c)
    if which == "pressure":
        pr = req.pressure
        n = pr.resolution
        if pr.footprint is not None:
            footprint = footprint_of(pr.footprint, req.center_of_mass, ("pressure", "footprint"))
            cm = footprint.center_of_mass
            extent = footprint.circumradius
            n_cells = (len(footprint.vertices) - 2) * n * n
        else:
            footprint = None
            cm = np.asarray(req.center_of_mass if req.center_of_mass is not None else (0.0, 0.0), dtype=float)
            if req.disk_radius is None:
                raise FieldError(("disk_radius",), "is required for uniform pressure on the disk (or give pressure.footprint)")
            extent = 0.0
            n_cells = 6 * n * n
        if n_cells > max_points:
            raise FieldError(
                ("pressure", "resolution"),
                f"gives {n_cells} cells; method {req.method} accepts at most {max_points} points",
            )
        scene = push_scene(req, _disk_radius(req, cm, extent), cm)
        problem = MotionProblem(scene, pressure=UniformPressure(footprint, n), mu_c=mu_c, method=req.method)
        return MotionRequest(problem, which, (), n_cells)
    cm = np.asarray(req.center_of_mass if req.center_of_mass is not None else (0.0, 0.0), dtype=float)
    if which == "support":
        us = RequestSupport(req.support, cm, ("support",), max_points, req.method)
        scene = push_scene(req, _disk_radius(req, cm, us.extent), cm)
        _require_length_scale(scene, us.extent, ("support", "points"))
        problem = MotionProblem(scene, support=us.support, mu_c=mu_c, method=req.method)
        return MotionRequest(problem, which, (us,), None)
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
    users = tuple(RequestSupport(s, cm, ("supports", i), max_points, req.method) for i, s in enumerate(sups))
    scene = push_scene(req, _disk_radius(req, cm, max(u.extent for u in users)), cm)
    for i, u in enumerate(users):
        _require_length_scale(scene, u.extent, ("supports", i, "points"))
    problem = MotionProblem(scene, supports=tuple(u.support for u in users), mu_c=mu_c, method=req.method)
    return MotionRequest(problem, which, users, None, layout)


def motion_errors_located(mr: MotionRequest):
    """Where the solver's input errors go in the request: a pressure's discretisation at
    ``pressure.resolution``; a Newton batch's below ``supports``; the others at their own
    path (a member of a batch solved one by one at ``supports[i]``)."""
    if mr.which == "pressure":
        return located(rename=PRESSURE_FIELDS)
    if mr.which in ("supports", "batch") and mr.problem.method == "newton":
        return located((mr.which,), rename={"mu_c": ("mu_c",)})
    return located()


MASON_TRANSLATION = SOLVER_DEFAULT.translation_omega
"""The moment below which Mason's rules see a translation: the forward solver's own
translation tolerance (the problems are solved with SOLVER_DEFAULT), so that the two agree."""


def _sense_of(omega: float, translation: bool) -> str:
    return "none" if translation else ("ccw" if omega > 0.0 else "cw")


def motion_out(scene: PushScene, res: ForwardResult, mu_c: float, cor_on_support: int | None) -> MotionOut:
    mason = mason_sense(scene.contact_rel, scene.normal, scene.push_hat, mu_c, MASON_TRANSLATION)
    return MotionOut(
        status=res.status,
        method=res.method,
        mode=res.mode,
        kind="translation" if res.cor is None else "rotation",
        cor=None if res.cor is None else listed(res.cor),
        velocity_cm=listed(res.velocity_cm),
        rotation_per_push=res.omega,
        slip_per_push=res.slip,
        sense=res.sense,
        mason_sense=mason,
        mason_agrees=mason == res.sense,
        power=res.power,
        contact_force=listed(res.contact_force),
        kkt_residual=res.kkt_residual,
        gap=res.gap,
        cor_on_support=cor_on_support,
        iterations=int(res.iterations),
        solve_time_ms=res.solve_time_s * 1e3,
        raw_twist_error=None if res.raw_twist_error is None else res.raw_twist_error,
    )


def batch_motion_out(scene: PushScene, br: BatchResult, j: int, mu_c: float, cor_on_support: int | None) -> MotionOut:
    """Row ``j`` of a Newton batch (the batch has no per-motion time)."""
    cor = br.cor[j]
    translation = not bool(np.all(np.isfinite(cor)))
    omega = float(br.omega[j])
    v = br.velocity_cm[j]
    sense = _sense_of(omega, translation)
    mason = mason_sense(scene.contact_rel, scene.normal, scene.push_hat, mu_c, MASON_TRANSLATION)
    return MotionOut(
        status="optimal" if bool(br.converged[j]) else "not_converged",
        method="newton",
        mode=BatchResult.MODES[int(br.mode[j])],
        kind="translation" if translation else "rotation",
        cor=None if translation else listed(cor),
        velocity_cm=listed(v),
        rotation_per_push=omega,
        slip_per_push=br.slip[j],
        sense=sense,
        mason_sense=mason,
        mason_agrees=mason == sense,
        power=br.power[j],
        contact_force=listed(br.contact_force[j]),
        kkt_residual=br.kkt_residual[j],
        gap=br.gap[j],
        cor_on_support=cor_on_support,
        iterations=int(br.iterations[j]),
        solve_time_ms=None,
    )


def _impact_out(impact: Impact | None) -> ImpactOut | None:
    if impact is None:
        return None
    return ImpactOut(
        cor=None if impact.cor is None else listed(impact.cor),
        distance=None if impact.distance is None else impact.distance,
        radius_of_gyration=impact.radius_of_gyration,
        source=impact.source,
    )


def _original(mr: MotionRequest, i: int, j: int | None) -> int | None:
    """The request's index of point ``j`` of support ``i`` (a columnar batch keeps its points)."""
    if mr.which == "batch":
        return None if j is None or j < 0 else int(j)
    return mr.supports[i].original(j)


def batch_motion_rows(mr: MotionRequest, result: MotionResult, mu_c: float) -> list[MotionOut]:
    """A batch's motions, one object each, in request order."""
    scene = mr.problem.scene
    out: list[MotionOut | None] = [None] * result.n_motions
    if result.motions is not None:
        for i, res in enumerate(result.motions):
            out[i] = motion_out(scene, res, mu_c, _original(mr, i, res.cor_on_support))
    else:
        for group in result.groups:
            br = group.result
            for j, i in enumerate(group.indices):
                out[i] = batch_motion_out(scene, br, j, mu_c, _original(mr, i, int(br.cor_on_support[j])))
    return out


def _nullable(values: np.ndarray) -> list[float | None]:
    """Floats with NaN (undefined: a translation's COR) as None."""
    return [None if v != v else v for v in values.tolist()]


def motion_columns(mr: MotionRequest, result: MotionResult, mu_c: float) -> MotionColumnsOut:
    """A batch's motions as columns, in request order: Newton groups scattered back to their
    supports' places, motions solved one by one stacked."""
    n = result.n_motions
    vec = {name: np.full((n, 2), np.nan) for name in ("cor", "velocity_cm", "contact_force")}
    num = {name: np.full(n, np.nan) for name in ("omega", "slip", "power", "kkt_residual", "gap")}
    text = {name: np.empty(n, dtype=object) for name in ("status", "mode", "sense")}
    iterations, on = np.zeros(n, dtype=int), np.full(n, -1)
    if result.groups is not None:
        for group in result.groups:
            br, i = group.result, np.asarray(group.indices, dtype=int)
            for name in (*vec, *num):
                (vec if name in vec else num)[name][i] = getattr(br, name)
            iterations[i], on[i] = br.iterations, br.cor_on_support
            text["status"][i] = np.where(br.converged, "optimal", "not_converged")
            text["mode"][i] = np.asarray(BatchResult.MODES, dtype=object)[br.mode]
        translation = ~np.all(np.isfinite(vec["cor"]), axis=1)
        text["sense"] = np.where(translation, "none", np.where(num["omega"] > 0.0, "ccw", "cw")).astype(object)
    else:
        for i, res in enumerate(result.motions):
            for name in (*vec, *num):
                value = getattr(res, name)
                (vec if name in vec else num)[name][i] = np.nan if value is None else value
            iterations[i], on[i] = res.iterations, -1 if res.cor_on_support is None else res.cor_on_support
            text["status"][i], text["mode"][i], text["sense"][i] = res.status, res.mode, res.sense
    scene = mr.problem.scene
    return MotionColumnsOut(
        status=text["status"].tolist(), mode=text["mode"].tolist(),
        cor_x=_nullable(vec["cor"][:, 0]), cor_y=_nullable(vec["cor"][:, 1]),
        velocity_cm_x=vec["velocity_cm"][:, 0].tolist(), velocity_cm_y=vec["velocity_cm"][:, 1].tolist(),
        rotation_per_push=num["omega"].tolist(), slip_per_push=num["slip"].tolist(),
        sense=text["sense"].tolist(),
        mason_sense=mason_sense(scene.contact_rel, scene.normal, scene.push_hat, mu_c, MASON_TRANSLATION),
        power=num["power"].tolist(),
        contact_force_x=vec["contact_force"][:, 0].tolist(), contact_force_y=vec["contact_force"][:, 1].tolist(),
        kkt_residual=num["kkt_residual"].tolist(), gap=_nullable(num["gap"]),
        cor_on_support=[_original(mr, i, j) for i, j in enumerate(on.tolist())],
        iterations=iterations.tolist(),
    )


def _batch_summary(mr: MotionRequest, result: MotionResult, statuses: list[str], cors: list) -> BatchSummaryOut:
    if mr.which == "batch":
        sizes = [mr.problem.batch.points.shape[1]]
    else:
        sizes = sorted({len(u.support.points) for u in mr.supports})
    return BatchSummaryOut(
        n=len(statuses),
        converged=sum(status == "optimal" for status in statuses),
        translations=sum(c is None for c in cors),
        fallbacks=sum(int(g.result.fallbacks) for g in result.groups or ()),
        support_sizes=sizes,
    )


def solve_response(req: CorSolveRequest, mr: MotionRequest, result: MotionResult, elapsed_ms: float) -> CorSolveResponse:
    scene = mr.problem.scene
    mu_c = float(req.mu_c)
    motion = motions = columns = batch = pressure = None
    notes: list[str] = []
    if mr.which == "pressure":
        motion = motion_out(scene, result.motion, mu_c, result.motion.cor_on_support)
        pr = req.pressure
        pressure = PressureSummaryOut(kind=pr.kind, region="disk" if pr.footprint is None else "polygon",
                                      resolution=pr.resolution, n_cells=mr.n_cells)
    elif mr.which == "support":
        us = mr.supports[0]
        motion = motion_out(scene, result.motion, mu_c, us.original(result.motion.cor_on_support))
        if result.impact is None:
            notes.append("impact is null: the whole support is at the centre of mass (radius of gyration 0)")
    elif mr.layout == "columns":
        columns = motion_columns(mr, result, mu_c)
        batch = _batch_summary(mr, result, columns.status, columns.cor_x)
    else:
        motions = batch_motion_rows(mr, result, mu_c)
        batch = _batch_summary(mr, result, [m.status for m in motions], [m.cor for m in motions])
    statuses = columns.status if columns is not None else [m.status for m in (motions or [motion])]
    bad = sum(status != "optimal" for status in statuses)
    if bad:
        notes.append(
            f"{bad} of {len(statuses)} motions are not optimal (status not_converged or inconsistent): "
            "see their kkt_residual; another method may do better"
        )
    return CorSolveResponse(
        input=mr.which,
        disk_radius=scene.disk_radius,
        center_of_mass=listed(scene.center_of_mass),
        mu_c=mu_c,
        method=req.method,
        motion=motion,
        impact=None if mr.which in ("supports", "batch") else _impact_out(result.impact),
        motions=motions,
        columns=columns,
        batch=batch,
        pressure=pressure,
        warnings=contact_warnings(scene) + notes,
        solve_time_ms=result.solve_time_s * 1e3,
        elapsed_ms=elapsed_ms,
    )


# ---------------------------------------------------------------------------------------
# POST /v1/cor/tripod-statistics
# ---------------------------------------------------------------------------------------


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


def tripod_problem(req: TripodStatisticsRequest) -> TripodStatisticsProblem:
    """Check the service's limits and build the problem of ``req``."""
    if req.include_cors and req.layout == "rows" and req.n_tripods > MAX_TRIPOD_CORS:
        raise FieldError(
            ("include_cors",),
            f"the CORs of at most {MAX_TRIPOD_CORS} tripods are returned as rows; set layout 'columns' "
            "(or include_cors false) for larger samples",
        )
    scene, footprint = disk_or_footprint(req)
    _check_samplable(scene, footprint, req.center_of_mass is not None)
    histogram = None
    if req.histogram:
        span = None if req.span is None else (req.span[0], req.span[1])
        histogram = HistogramQuery(mu_c=req.histogram_mu_c, bins=req.bins, span=span)
    return TripodStatisticsProblem(scene, req.n_tripods, req.seed, mu_c=req.mu_c, footprint=footprint,
                                   histogram=histogram)


def tripod_statistics_response(req: TripodStatisticsRequest, stats: TripodStatistics,
                               elapsed_ms: float) -> TripodStatisticsResponse:
    scene = stats.problem.scene
    b = stats.sample.batch
    ok = np.all(np.isfinite(b.cor), axis=1)
    cors = cor_columns = None
    if req.include_cors and req.layout == "rows":
        cors = [(listed(c) if good else None) for c, good in zip(b.cor, ok)]
    elif req.include_cors:
        cor_columns = CorColumnsOut(x=_nullable(np.where(ok, b.cor[:, 0], np.nan)),
                                    y=_nullable(np.where(ok, b.cor[:, 1], np.nan)))
    modes = {name: int(np.sum(b.mode == i)) for i, name in enumerate(BatchResult.MODES)}
    hist = None
    if stats.histogram is not None:
        h = stats.histogram
        hist = HistogramOut(
            edges=listed(h.edges),
            counts=[int(c) for c in h.counts],
            sticking_fraction=h.sticking_fraction,
            outside_range=int(h.outside_range),
            mu_c=float(req.histogram_mu_c),
            solve_time_ms=h.solve_time_s * 1e3,
        )
    return TripodStatisticsResponse(
        status=stats.status,
        max_kkt_residual=np.max(b.kkt_residual),
        n_tripods=req.n_tripods,
        seed=req.seed,
        disk_radius=scene.disk_radius,
        center_of_mass=listed(scene.center_of_mass),
        mu_c=float(req.mu_c),
        cors=cors,
        cor_columns=cor_columns,
        converged=int(np.sum(b.converged)),
        translations=int(np.sum(~ok)),
        fallbacks=int(b.fallbacks),
        mode_counts=modes,
        histogram=hist,
        solve_time_ms=stats.solve_time_s * 1e3,
        elapsed_ms=elapsed_ms,
    )
