"""Input limits and service-level tolerances, in one place.

Every limit here is enforced by the request schemas (:mod:`service.schemas`), shows up
in the OpenAPI document as ``minimum``/``maximum``/``minItems``/``maxItems``, and is
listed in docs/api.md. A request outside them is answered with HTTP 422 naming the field.
Lengths are in whatever unit the client uses consistently; angles are radians.
"""

from __future__ import annotations

MAX_ABS_COORDINATE = 1e9
"""Largest |x| or |y| of any point (contact, centre of mass, workpiece vertex)."""

MAX_DISK_RADIUS = 1e9
"""disk_radius must lie in (0, MAX_DISK_RADIUS]."""

MAX_ABS_ANGLE = 1e6
"""Largest |edge_angle| and |push_direction| in radians (beyond this an angle carries
less than ~1e-10 rad of precision)."""

MIN_N_POINTS = 8
MAX_N_POINTS = 20_000
DEFAULT_N_POINTS = 256
"""Number of boundary points of the COR locus polygon (odd counts are rounded up to even
by the model, because the locus is mirror symmetric)."""

MIN_POLYGON_VERTICES = 3
MAX_POLYGON_VERTICES = 1000
"""Vertex count of a workpiece polygon."""

CONTACT_ON_OUTLINE_REL = 1e-9
"""A contact point farther than CONTACT_ON_OUTLINE_REL * a from the workpiece outline
(a = disk radius used) is reported in ``warnings`` as not on the outline."""

CONTACT_IN_DISK_REL = 1e-9
"""A contact point farther than (1 + CONTACT_IN_DISK_REL) * a from the centre of mass lies
outside the bounding disk; this is reported in ``warnings`` (the book assumes the disk
bounds the whole workpiece, contact included)."""
