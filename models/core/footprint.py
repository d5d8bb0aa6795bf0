"""The one polygon of the models: a part's footprint on the table (book 3.1.8).

Every capability takes a part's outline as a :class:`Footprint`: the loci and sketches
(the outline bounds where pressure may lie, 3.1.5), the push (its convex hull meets the
fence, 3.4), the feeder (its hull in the body frame, 5.1), the quasi-static check (its
moments, 6.8). One validation (``Footprint.create``) gives one verdict on an outline for
every route: a list of [x, y], finite, no vertex repeated, an extent whose squares are
normal floats, simple (no two edges cross or touch), not degenerate (collinear), the
centre of mass (CM) in the convex hull; each refusal names what is wrong and where.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike

from models.core.errors import InvalidInput
from models.core.tolerances import DEFAULT, Tolerances


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def _normalised(vertices: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Vertices about their mean in units of their span (so products of coordinates
    neither underflow for tiny parts nor overflow for huge ones), the mean, the span."""
    mean = vertices.mean(axis=0)
    span = float(np.max(np.ptp(vertices, axis=0)))
    if not span > 0.0:
        return vertices - mean, mean, 1.0
    return (vertices - mean) / span, mean, span


def signed_area(vertices: np.ndarray) -> float:
    """Shoelace area, positive for counter-clockwise vertex order (computed about the vertex
    mean in units of the span, so a small polygon far from the origin keeps its digits)."""
    v, _, span = _normalised(vertices)
    x, y = v[:, 0], v[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)) * span * span


def area_centroid(vertices: np.ndarray) -> np.ndarray:
    """Centroid of the polygon's area: the CM of a part of uniform density."""
    v, mean, span = _normalised(vertices)
    x, y = v[:, 0], v[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    w = x * yn - xn * y
    a6 = 3.0 * float(np.sum(w))
    return mean + span * np.array([np.sum((x + xn) * w), np.sum((y + yn) * w)]) / a6


def triangulate(vertices: ArrayLike) -> np.ndarray:
    """Ear-clipping triangulation of a simple counter-clockwise polygon (as
    :class:`Footprint` stores it): array (n - 2, 3, 2) of triangles, each counter-clockwise.
    Flat corners (collinear neighbours) are never clipped, so no triangle is degenerate.
    O(n^3), for the small polygons of parts."""
    v = np.asarray(vertices, dtype=float)

    def cross(o: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
        return float((a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]))

    idx = list(range(len(v)))
    tris = []
    while len(idx) > 3:
        n = len(idx)
        for k in range(n):
            i0, i1, i2 = idx[k - 1], idx[k], idx[(k + 1) % n]
            a, b, c = v[i0], v[i1], v[i2]
            if cross(a, b, c) <= 0.0:  # reflex or flat corner: not an ear
                continue
            others = (v[j] for j in idx if j not in (i0, i1, i2))
            if any(cross(a, b, q) >= 0.0 and cross(b, c, q) >= 0.0 and cross(c, a, q) >= 0.0 for q in others):
                continue  # another vertex inside or on the candidate ear
            tris.append([a, b, c])
            idx.pop(k)
            break
        else:
            raise InvalidInput("workpiece", "could not be triangulated: it is not a simple polygon")
    tris.append([v[idx[0]], v[idx[1]], v[idx[2]]])
    return np.array(tris)


def triangle_areas(tris: np.ndarray) -> np.ndarray:
    """Areas of triangles (k, 3, 2)."""
    ab = tris[:, 1] - tris[:, 0]
    ac = tris[:, 2] - tris[:, 0]
    return np.asarray(0.5 * np.abs(ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0]))


def inside_polygon(vertices: np.ndarray, points: ArrayLike) -> np.ndarray:
    """Even-odd test of points (m, 2) against a simple polygon (k, 2): a boolean per point.
    A point exactly on an edge may land on either side."""
    pts = np.atleast_2d(np.asarray(points, dtype=float))
    a = np.asarray(vertices, dtype=float)
    b = np.roll(a, -1, axis=0)
    x, y = pts[:, 0:1], pts[:, 1:2]
    cond = (a[:, 1] > y) != (b[:, 1] > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        xc = a[:, 0] + (y - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    return np.asarray(np.sum(cond & (x < xc), axis=1) % 2 == 1)


def _segments_cross(vertices: np.ndarray, rel: float) -> tuple[int, int, bool] | None:
    """The first two non-adjacent edges (i, j: from vertex i to i + 1) of the closed polygon
    that cross (True) or touch (False), or None (O(n^2), vectorised); ``rel`` is the
    relative slack of "touch"."""
    n = len(vertices)
    p = vertices
    q = np.roll(vertices, -1, axis=0)
    i, j = np.triu_indices(n, k=2)
    keep = ~((i == 0) & (j == n - 1))  # first and last edges are adjacent
    i, j = i[keep], j[keep]
    if i.size == 0:
        return None
    d1 = _cross(q[i] - p[i], p[j] - p[i])
    d2 = _cross(q[i] - p[i], q[j] - p[i])
    d3 = _cross(q[j] - p[j], p[i] - p[j])
    d4 = _cross(q[j] - p[j], q[i] - p[j])
    proper = (d1 * d2 < 0) & (d3 * d4 < 0)
    span = float(np.max(np.abs(vertices - vertices.mean(axis=0))))
    flat = rel * span * span

    def within(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:  # c inside the bounding box of segment ab
        return np.all((np.minimum(a, b) - rel * span <= c) & (c <= np.maximum(a, b) + rel * span), axis=-1)

    # An end point of one edge lying on the other edge: the polygon touches itself.
    touch1 = (np.abs(d1) <= flat) & within(p[i], q[i], p[j])
    touch2 = (np.abs(d2) <= flat) & within(p[i], q[i], q[j])
    hit = np.flatnonzero(proper | touch1 | touch2)
    if hit.size == 0:
        return None
    k = int(hit[0])
    return int(i[k]), int(j[k]), bool(proper[k])


def convex_hull_indices(points: ArrayLike, collinear_rel: float = DEFAULT.polygon_area_rel) -> list[int]:
    """Indices of the convex hull's vertices, counter-clockwise from the lowest x (then y),
    collinear points dropped (Andrew's monotone chain). A point is collinear when the turn
    it makes is at most ``collinear_rel`` times the squared span of the points (points that
    were collinear before a rotation stay so after rounding)."""
    pts = np.asarray(points, dtype=float)
    span = float(np.max(np.ptp(pts, axis=0))) if len(pts) else 0.0
    slack = collinear_rel * span * span
    order = sorted(range(len(pts)), key=lambda i: (pts[i, 0], pts[i, 1]))

    def chain(seq: list[int]) -> list[int]:
        out: list[int] = []
        for i in seq:
            while len(out) >= 2 and _cross(pts[out[-1]] - pts[out[-2]], pts[i] - pts[out[-2]]) <= slack:
                out.pop()
            out.append(i)
        return out

    lower = chain(order)
    upper = chain(order[::-1])
    return lower[:-1] + upper[:-1]


def edge_feet(vertices: np.ndarray, point: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """For each edge i of the closed polygon (``vertices[i]`` to ``vertices[i + 1]``) the
    point of the edge nearest to ``point`` (the projection, clipped to the edge) and its
    distance: arrays (n, 2) and (n,)."""
    p = np.asarray(point, dtype=float)
    a = np.asarray(vertices, dtype=float)
    ab = np.roll(a, -1, axis=0) - a
    t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
    feet = a + t[:, None] * ab
    return feet, np.hypot(feet[:, 0] - p[0], feet[:, 1] - p[1])


@dataclass(frozen=True)
class SquareRange:
    """Lengths whose squares are normal floating-point numbers (areas, squared distances):
    below ``low`` they underflow (a 1e-300 square has an area of 0), above ``high`` overflow."""

    low: float = float(np.sqrt(np.finfo(float).tiny)) * 4.0
    high: float = float(np.sqrt(np.finfo(float).max)) / 4.0


FLOAT_SQUARES = SquareRange()


def _check_outline(v: np.ndarray, tolerances: Tolerances) -> None:
    """The outline's own checks, each with its true reason (field "workpiece")."""
    if v.ndim != 2 or v.shape[1] != 2:
        raise InvalidInput("workpiece", "must be a list of [x, y] vertices")
    if v.shape[0] < 3:
        raise InvalidInput("workpiece", "needs at least 3 vertices")
    if not np.all(np.isfinite(v)):
        raise InvalidInput("workpiece", "vertices must be finite numbers")
    _, first, counts = np.unique(v + 0.0, axis=0, return_index=True, return_counts=True)  # -0.0 is 0.0
    if np.any(counts > 1):
        i = int(first[np.argmax(counts > 1)])
        j = int(np.flatnonzero(np.all(v == v[i], axis=1))[1])
        raise InvalidInput("workpiece", f"repeats a vertex: vertices {i} and {j} are the same point {v[i].tolist()} "
                                        "(a simple polygon visits each point once)")
    span = float(np.max(np.ptp(v, axis=0)))
    if not FLOAT_SQUARES.low <= span <= FLOAT_SQUARES.high:
        raise InvalidInput("workpiece", f"spans {span:.3g}: outside [{FLOAT_SQUARES.low:.3g}, {FLOAT_SQUARES.high:.3g}], "
                                        "where its squared lengths and area would underflow or overflow in floating "
                                        "point; give it in another unit")


def _checked_center_of_mass(v: np.ndarray, normalised: tuple[np.ndarray, np.ndarray, float],
                            center_of_mass: ArrayLike | None, tolerances: Tolerances) -> np.ndarray:
    """The CM given (finite, in the convex hull of the CCW outline ``v``, 3.1.5) or, when
    None, the centroid of the area (a part of uniform density). ``normalised``: ``v`` about
    its mean in units of its span (:func:`_normalised`)."""
    if center_of_mass is None:
        return area_centroid(v)
    cm = np.asarray(center_of_mass, dtype=float)
    if cm.shape != (2,) or not np.all(np.isfinite(cm)):
        raise InvalidInput("center_of_mass", "must be a finite point [x, y]")
    vn, mean, span = normalised
    hull = vn[convex_hull_indices(vn, 0.0)]
    edges = np.roll(hull, -1, axis=0) - hull
    if not np.all(_cross(edges, (cm - mean) / span - hull) >= -tolerances.polygon_area_rel):
        raise InvalidInput(
            "center_of_mass",
            "lies outside the convex hull of the workpiece: no pressure distribution "
            "on the footprint can have its centroid there (3.1.5)",
        )
    return cm


@dataclass(frozen=True)
class Footprint:
    """A simple polygon, vertices counter-clockwise, with its centre of mass.

    ``circumradius`` is the book's a (3.1.8): the largest distance from the CM to the
    workpiece, attained at a vertex (of the hull). ``hull_indices``: the convex hull,
    counter-clockwise, as indices into ``vertices`` (collinear points dropped), starting
    at the vertex of least x relative to the CM. ``input_reversed``: the outline was given
    clockwise, so ``vertices`` is its reverse (:meth:`input_index` maps back).
    """

    vertices: np.ndarray
    center_of_mass: np.ndarray
    area: float
    circumradius: float
    hull_indices: tuple[int, ...]
    input_reversed: bool = False

    @classmethod
    def create(cls, vertices: ArrayLike, center_of_mass: ArrayLike | None = None,
               tolerances: Tolerances = DEFAULT) -> "Footprint":
        v = np.asarray(vertices, dtype=float)
        _check_outline(v, tolerances)
        span = float(np.max(np.ptp(v, axis=0)))
        area = signed_area(v)
        reversed_ = area < 0.0
        if reversed_:
            v = v[::-1].copy()
            area = -area
        # crossing before area: a symmetric bow-tie has no net area, yet is not "collinear"
        normalised = _normalised(v)  # crossing and hull tests in span units: no over/underflow
        crossing = _segments_cross(normalised[0], tolerances.polygon_area_rel)
        if crossing is not None:
            n = len(v)

            def edge(k: int) -> str:  # in the input's numbering
                a, b = (n - 1 - k, (n - 2 - k) % n) if reversed_ else (k, (k + 1) % n)
                return f"{min(a, b)}-{max(a, b)}" if {a, b} != {0, n - 1} else f"{n - 1}-0"

            i, j, proper = crossing
            raise InvalidInput("workpiece", f"is self-intersecting, not a simple polygon: its edges {edge(i)} and "
                                            f"{edge(j)} (between those vertices) {'cross' if proper else 'touch'}")
        if area <= tolerances.polygon_area_rel * span * span:
            raise InvalidInput("workpiece", "is degenerate: its vertices are (nearly) collinear")
        cm = _checked_center_of_mass(v, normalised, center_of_mass, tolerances)
        q = v - cm
        lengths = np.hypot(q[:, 0], q[:, 1])
        radius = float(np.max(lengths))
        hull = convex_hull_indices(q / radius, tolerances.polygon_area_rel)
        return cls(vertices=v, center_of_mass=cm, area=area, circumradius=radius,
                   hull_indices=tuple(int(i) for i in hull), input_reversed=reversed_)

    def centred(self) -> "Footprint":
        """The same footprint in its body frame: the CM at the origin."""
        return replace(self, vertices=self.vertices - self.center_of_mass, center_of_mass=np.zeros(2))

    def input_index(self, i: int) -> int:
        """The index in the outline as given of vertex ``i`` of ``vertices``."""
        return len(self.vertices) - 1 - int(i) if self.input_reversed else int(i)

    def hull_edge_of_input(self, i: int, tolerances: Tolerances = DEFAULT) -> int | None:
        """The hull edge that edge ``i`` of the outline as given (from its vertex i to vertex
        i + 1) lies on, or None when it is not on the convex hull. A hull edge may span
        several outline edges (collinear vertices are not hull vertices): the outline edge
        must run, in CCW order, between the hull edge's ends and lie on its line."""
        n = len(self.vertices)
        a, b = (n - 1 - i % n, n - 1 - (i + 1) % n) if self.input_reversed else (i % n, (i + 1) % n)
        start = b if self.input_reversed else a  # the edge's first vertex in CCW order
        h = self.hull_indices
        for j in range(len(h)):
            lo, hi = h[j], h[(j + 1) % len(h)]
            if (start - lo) % n >= (hi - lo) % n:
                continue  # not between this hull edge's ends
            p0, p1 = self.vertices[lo], self.vertices[hi]
            d = p1 - p0
            length = float(np.hypot(*d))
            for k in (start, (start + 1) % n):
                off = self.vertices[k] - p0
                if abs(float(d[0] * off[1] - d[1] * off[0])) > tolerances.polygon_area_rel * self.circumradius * length:
                    return None
            return j
        return None

    @cached_property
    def hull(self) -> np.ndarray:
        """The convex hull's vertices (counter-clockwise), array (m, 2)."""
        return self.vertices[list(self.hull_indices)]

    @property
    def hull_size(self) -> int:
        return len(self.hull_indices)

    def hull_edge(self, j: int) -> tuple[np.ndarray, float, np.ndarray]:
        """(start h_j, length L_j, unit direction e_j) of hull edge j (h_j to h_{j+1})."""
        m = self.hull_size
        p = self.vertices[self.hull_indices[j % m]]
        d = self.vertices[self.hull_indices[(j + 1) % m]] - p
        length = float(math.hypot(float(d[0]), float(d[1])))
        return p, length, d / length

    def hull_edge_angle(self, j: int) -> float:
        """The direction angle of hull edge j."""
        _, _, e = self.hull_edge(j)
        return math.atan2(float(e[1]), float(e[0]))

    def cm_over_hull_edge(self, j: int) -> tuple[float, float]:
        """(u_c, h_c): the CM's position along hull edge j from h_j, and its height above
        the edge (> 0 inside)."""
        p, _, e = self.hull_edge(j)
        c = self.center_of_mass - p
        return float(c @ e), float(c @ np.array([-e[1], e[0]]))

    def nearest_on_outline(self, point: ArrayLike) -> np.ndarray:
        """The point of the outline nearest to ``point`` (its projection onto the outline)."""
        feet, dist = edge_feet(self.vertices, point)
        return feet[int(np.argmin(dist))]

    def distance_to_outline(self, point: ArrayLike) -> float:
        """Distance from ``point`` to the nearest edge of the polygon."""
        _, dist = edge_feet(self.vertices, point)
        return float(np.min(dist))
