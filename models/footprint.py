"""Polygon footprints of workpieces and their bounding disks (book 3.1.8)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from models.errors import InvalidInput
from models.tolerances import DEFAULT, Tolerances


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


def _segments_cross(vertices: np.ndarray, rel: float) -> bool:
    """True when two non-adjacent edges of the closed polygon touch or cross (O(n^2),
    vectorised); ``rel`` is the relative slack of "touch"."""
    n = len(vertices)
    p = vertices
    q = np.roll(vertices, -1, axis=0)
    i, j = np.triu_indices(n, k=2)
    keep = ~((i == 0) & (j == n - 1))  # first and last edges are adjacent
    i, j = i[keep], j[keep]
    if i.size == 0:
        return False
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
    return bool(np.any(proper | touch1 | touch2))


def _inside_convex_hull(points: np.ndarray, x: np.ndarray, slack: float) -> bool:
    """Whether x lies in the convex hull of points (monotone-chain hull)."""
    pts = sorted(map(tuple, points))
    if len(pts) < 3:
        return False

    def half(seq: list[tuple[float, ...]]) -> list[tuple[float, ...]]:
        out: list[tuple[float, ...]] = []
        for pt in seq:
            while len(out) >= 2 and (out[-1][0] - out[-2][0]) * (pt[1] - out[-2][1]) - (out[-1][1] - out[-2][1]) * (pt[0] - out[-2][0]) <= 0:
                out.pop()
            out.append(pt)
        return out

    hull = np.array(half(pts)[:-1] + half(pts[::-1])[:-1])
    edges = np.roll(hull, -1, axis=0) - hull
    return bool(np.all(_cross(edges, x - hull) >= -slack))


@dataclass(frozen=True)
class Footprint:
    """A simple polygon footprint, vertices counter-clockwise (world frame).

    ``circumradius`` is the book's a (3.1.8): the largest distance from the CM to the
    workpiece, attained at a vertex.
    """

    vertices: np.ndarray
    center_of_mass: np.ndarray
    area: float
    circumradius: float

    @classmethod
    def create(cls, vertices: ArrayLike, center_of_mass: ArrayLike | None = None,
               tolerances: Tolerances = DEFAULT) -> "Footprint":
        v = np.asarray(vertices, dtype=float)
        if v.ndim != 2 or v.shape[1] != 2:
            raise InvalidInput("workpiece", "must be a list of [x, y] vertices")
        if v.shape[0] < 3:
            raise InvalidInput("workpiece", "needs at least 3 vertices")
        if not np.all(np.isfinite(v)):
            raise InvalidInput("workpiece", "vertices must be finite numbers")
        if np.any(np.all(v == np.roll(v, -1, axis=0), axis=1)):
            raise InvalidInput("workpiece", "has repeated consecutive vertices")
        span = float(np.max(np.ptp(v, axis=0)))
        area = signed_area(v)
        if abs(area) <= tolerances.polygon_area_rel * span * span:
            raise InvalidInput("workpiece", "is degenerate: its vertices are (nearly) collinear")
        if area < 0.0:
            v = v[::-1].copy()
            area = -area
        vn, mean, _ = _normalised(v)  # crossing tests in span units: no over/underflow
        if _segments_cross(vn, tolerances.polygon_area_rel):
            raise InvalidInput("workpiece", "is not a simple polygon: two edges cross or touch")
        if center_of_mass is None:
            cm = area_centroid(v)
        else:
            cm = np.asarray(center_of_mass, dtype=float)
            if cm.shape != (2,) or not np.all(np.isfinite(cm)):
                raise InvalidInput("center_of_mass", "must be a finite point [x, y]")
            if not _inside_convex_hull(vn, (cm - mean) / span, slack=tolerances.polygon_area_rel):
                raise InvalidInput(
                    "center_of_mass",
                    "lies outside the convex hull of the workpiece: no pressure distribution "
                    "on the footprint can have its centroid there (3.1.5)",
                )
        radius = float(np.max(np.linalg.norm(v - cm, axis=1)))
        return cls(vertices=v, center_of_mass=cm, area=area, circumradius=radius)

    def distance_to_outline(self, point: ArrayLike) -> float:
        """Distance from ``point`` to the nearest edge of the polygon."""
        p = np.asarray(point, dtype=float)
        a = self.vertices
        b = np.roll(a, -1, axis=0)
        ab = b - a
        t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
        return float(np.min(np.linalg.norm(a + t[:, None] * ab - p, axis=1)))
