"""The push scene of a request (book 3.1.9), built once for every resource that has one.

:func:`prepare_push` reads the shape fields of ``/v1/cor/locus`` and ``/v1/cor/sketch``
(exactly one of ``disk_radius``, ``workpiece``, ``footprint``), :func:`disk_or_footprint`
those of ``/v1/cor/membership`` and ``/v1/cor/tripod-statistics`` (``disk_radius`` or
``footprint``); both build the ``PushScene`` (and ``Footprint``) of :mod:`models`, with
every error at the request's field. :class:`PreparedPush` adds what the service remarks.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.core.scene import PushScene
from service.common.inputs import exactly_one, footprint_of, located
from service.limits import CONTACT_IN_DISK_REL, CONTACT_ON_OUTLINE_REL

SHAPE_FIELDS = ("disk_radius", "workpiece", "footprint")
"""The ways of giving the workpiece's shape in ``prepare_push``, exactly one per request."""


@dataclass(frozen=True)
class PreparedPush:
    """A request's scene as domain objects, plus what the service remarks about it.

    ``footprint``: the polygon (None for a disk); ``shape_field``: the request field that
    gave the shape; ``contact_distance_to_outline``: with a polygon, how far the contact
    is from its outline."""

    scene: PushScene
    footprint: Footprint | None
    shape_field: str
    contact_distance_to_outline: float | None
    warnings: tuple[str, ...]


def contact_warnings(scene: PushScene) -> list[str]:
    """A remark when the contact lies outside the disk that should bound the workpiece."""
    c_norm = float(np.linalg.norm(scene.contact_rel))
    a = scene.disk_radius
    if c_norm > (1.0 + CONTACT_IN_DISK_REL) * a:
        return [
            f"contact_point is {c_norm:.6g} from the centre of mass, outside the disk of radius "
            f"a = {a:.6g} that should bound the workpiece"
        ]
    return []


DEPRECATED_WORKPIECE = ("`workpiece` is deprecated: send the polygon as `footprint` (the same meaning); `workpiece` "
                        "is kept for existing clients only")


def prepare_push(req) -> PreparedPush:
    """The scene of a request with ``disk_radius``, ``workpiece``, ``footprint`` (exactly one),
    ``center_of_mass``, ``contact_point``, ``edge_angle`` and ``push_direction``: a polygon
    is bounded by its circumscribing disk about the CM (3.1.8). Raises ``InvalidInput`` /
    ``FieldError`` (-> 422) for inconsistent input."""
    given = [name for name in SHAPE_FIELDS if getattr(req, name) is not None]
    if not given:
        raise InvalidInput("disk_radius", "give either disk_radius or footprint (or workpiece): exactly one of them")
    if len(given) > 1:
        raise InvalidInput(given[1], f"give exactly one of disk_radius, workpiece and footprint, not both {given[0]} and {given[1]}")
    field = given[0]
    footprint = None
    if field != "disk_radius":
        footprint = footprint_of(getattr(req, field), req.center_of_mass, (field,))
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
    warnings += contact_warnings(scene)
    if field == "workpiece":
        warnings.append(DEPRECATED_WORKPIECE)
    return PreparedPush(scene, footprint, field, outline_distance, tuple(warnings))


def push_scene(req, disk_radius: float, center_of_mass) -> PushScene:
    """The scene of the request's push fields with the given disk, errors located."""
    with located():
        return PushScene.create(disk_radius, req.contact_point, req.edge_angle, req.push_direction, center_of_mass)


def disk_or_footprint(req) -> tuple[PushScene, Footprint | None]:
    """Scene and footprint of a request with exactly one of ``disk_radius`` / ``footprint``."""
    exactly_one(req, ("disk_radius", "footprint"))
    footprint = None
    if req.footprint is not None:
        footprint = footprint_of(req.footprint, req.center_of_mass, ("footprint",))
        radius, cm = footprint.circumradius, footprint.center_of_mass
    else:
        radius = req.disk_radius
        cm = req.center_of_mass if req.center_of_mass is not None else (0.0, 0.0)
    return push_scene(req, radius, cm), footprint
