"""Schema <-> domain conversions for the COR-locus endpoint (no mechanics here).

:func:`prepare` turns a validated request into the domain objects of :mod:`models`
(``Footprint``, ``PushScene``); :func:`locus_response` turns a ``DiskCorLocus`` back into
the response schema, with plain lists of floats and no NaN/inf.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from models.locus.cor_disk import DiskCorLocus
from models.errors import InvalidInput
from models.footprint import Footprint
from models.scene import PushScene
from service.errors import NonFiniteResult
from service.limits import CONTACT_IN_DISK_REL, CONTACT_ON_OUTLINE_REL
from service.schemas import (
    CertifiedLocusOut,
    CorLocusRequest,
    CorLocusResponse,
    CurvaturesOut,
    DiskCrossingsOut,
    PerimeterArcOut,
    RMinOut,
    TipLineOut,
    TipOut,
)


SHAPE_FIELDS = ("disk_radius", "workpiece", "footprint")
"""The ways of giving the workpiece's shape, exactly one per request."""


@dataclass(frozen=True)
class PreparedPush:
    """A request as domain objects, plus what the service remarks about it."""

    scene: PushScene
    footprint: Footprint | None
    outputs: tuple[str, ...]
    n_points: int
    contact_distance_to_outline: float | None
    warnings: tuple[str, ...]


def prepare(req: CorLocusRequest, extra_outputs: tuple[str, ...] = ()) -> PreparedPush:
    """Build the scene. Raises ``InvalidInput`` (-> 422) for inconsistent input."""
    given = [name for name in SHAPE_FIELDS if getattr(req, name) is not None]
    if not given:
        raise InvalidInput("disk_radius", "give either disk_radius or footprint (or workpiece): exactly one of them")
    if len(given) > 1:
        raise InvalidInput(given[1], f"give exactly one of disk_radius, workpiece and footprint, not both {given[0]} and {given[1]}")
    footprint = None
    polygon_field = given[0] if given[0] != "disk_radius" else None
    if polygon_field is not None:
        try:
            footprint = Footprint.create(getattr(req, polygon_field), req.center_of_mass)
        except InvalidInput as exc:
            if exc.field == "workpiece":  # Footprint.create's name for the polygon
                raise InvalidInput(polygon_field, exc.reason) from exc
            raise
        radius = footprint.circumradius
        cm = footprint.center_of_mass
    else:
        radius = req.disk_radius
        cm = req.center_of_mass if req.center_of_mass is not None else (0.0, 0.0)
    scene = PushScene.create(radius, req.contact_point, req.edge_angle, req.push_direction, cm)

    warnings: list[str] = []
    outline_distance = None
    a = scene.disk_radius
    if footprint is not None:
        outline_distance = footprint.distance_to_outline(scene.contact_point)
        if outline_distance > CONTACT_ON_OUTLINE_REL * a:
            warnings.append(
                f"contact_point is {outline_distance:.6g} away from the workpiece outline "
                f"(tolerance {CONTACT_ON_OUTLINE_REL:g} * a): the pusher is not touching the "
                "workpiece there"
            )
    c_norm = float(np.linalg.norm(scene.contact_rel))
    if c_norm > (1.0 + CONTACT_IN_DISK_REL) * a:
        warnings.append(
            f"contact_point is {c_norm:.6g} from the centre of mass, outside the disk of radius "
            f"a = {a:.6g} that should bound the workpiece"
        )
    outputs = tuple(dict.fromkeys([*req.outputs, *extra_outputs]))
    return PreparedPush(
        scene=scene,
        footprint=footprint,
        outputs=outputs,
        n_points=req.n_points,
        contact_distance_to_outline=outline_distance,
        warnings=tuple(warnings),
    )


def _f(value, what: str) -> float:
    x = float(value)
    if not math.isfinite(x):
        raise NonFiniteResult(what)
    return x


def _v(value, what: str) -> list[float]:
    arr = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(arr)):
        raise NonFiniteResult(what)
    return arr.tolist()


def translation_message(locus: DiskCorLocus) -> str:
    d = locus.translation_direction
    angle = math.atan2(float(d[1]), float(d[0]))
    return (
        f"pure translation along ({float(d[0]):.6g}, {float(d[1]):.6g}) "
        f"(direction {angle:.6g} rad): the line of force passes through the centre of mass; "
        "the COR is at infinity"
    )


def locus_response(
    prep: PreparedPush,
    locus: DiskCorLocus,
    elapsed_ms: float,
    method: str = "analytic",
    certified: CertifiedLocusOut | None = None,
) -> CorLocusResponse:
    """The response schema for ``locus``; raises :class:`NonFiniteResult` rather than
    letting a NaN or infinity through."""
    scene = prep.scene
    tip = None
    if locus.tip is not None:
        tip = TipOut(
            point=_v(locus.tip.point, "tip.point"),
            distance=_f(locus.tip.distance, "tip.distance"),
            distance_book=_f(locus.tip.distance_book, "tip.distance_book"),
            on_disk=bool(locus.tip.on_disk),
        )
    tip_line = None
    if locus.tip_line is not None:
        tip_line = TipLineOut(
            point=_v(locus.tip_line.point, "tip_line.point"),
            direction=_v(locus.tip_line.direction, "tip_line.direction"),
            distance=_f(locus.tip_line.distance, "tip_line.distance"),
        )
    r_min = None
    if locus.r_min is not None:
        r_min = RMinOut(point=_v(locus.r_min.point, "r_min.point"), distance=_f(locus.r_min.distance, "r_min.distance"))
    curvatures = None
    if locus.curvatures is not None:
        c = locus.curvatures
        curvatures = CurvaturesOut(
            tip_radius=_f(c.tip_radius, "curvatures.tip_radius"),
            tip_radius_book_printed=_f(c.tip_radius_book_printed, "curvatures.tip_radius_book_printed"),
            r_min_radius=_f(c.r_min_radius, "curvatures.r_min_radius"),
        )
    crossings = None
    if locus.disk_crossings is not None:
        dc = locus.disk_crossings
        crossings = DiskCrossingsOut(
            cos_eta=_f(dc.cos_eta, "disk_crossings.cos_eta"),
            points=_v(dc.points, "disk_crossings.points"),
            arcs=[
                PerimeterArcOut(
                    start_angle=_f(arc.start_angle, "disk_crossings.arcs.start_angle"),
                    end_angle=_f(arc.end_angle, "disk_crossings.arcs.end_angle"),
                    start=_v(arc.start, "disk_crossings.arcs.start"),
                    end=_v(arc.end, "disk_crossings.arcs.end"),
                )
                for arc in dc.arcs
            ],
        )
    boundary = None if locus.boundary is None else _v(locus.boundary, "boundary")
    residual = None if locus.boundary_residual is None else _f(locus.boundary_residual, "boundary_residual")
    return CorLocusResponse(
        kind=locus.kind,
        sense=locus.sense,
        message=translation_message(locus) if locus.kind == "translation" else None,
        disk_radius=_f(scene.disk_radius, "disk_radius"),
        center_of_mass=_v(scene.center_of_mass, "center_of_mass"),
        moment_arm=_f(locus.moment_arm, "moment_arm"),
        relative_moment_arm=_f(locus.relative_moment_arm, "relative_moment_arm"),
        book_alpha=_f(locus.book_alpha, "book_alpha"),
        axis=_v(locus.axis, "axis"),
        translation_direction=_v(locus.translation_direction, "translation_direction"),
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
            else _f(prep.contact_distance_to_outline, "contact_distance_to_outline")
        ),
        warnings=list(prep.warnings),
        method=method,
        locus_of="disk" if prep.footprint is None else "circumscribing_disk",
        certified=certified,
        elapsed_ms=elapsed_ms,
    )
