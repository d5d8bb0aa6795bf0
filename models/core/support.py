"""Discrete pressure distributions (supports) of a workpiece (book 3.1.5, 3.3.3, 7.5).

A support is a finite set of points with non-negative weights summing to one whose
centroid is the centre of mass. Uniform pressure on a disk or a polygon is discretised
here into cells whose weights are their areas and whose points are their exact area
centroids, so the discrete centroid is the exact one (up to round-off).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from models.core.errors import InvalidInput
from models.core.footprint import Footprint, area_centroid, inside_polygon, triangulate
from models.core.tolerances import SUPPORT_DEFAULT, CentroidTolerance

CM_SCALE_REL = 1e-3
"""The centroid check's length scale is at least this share of the CM's distance from the
origin (a support far from the origin is checked to the floats it can carry there)."""
SCALE_FLOOR = 1e-300
"""... and at least this (a support of one point at the CM has no size)."""


@dataclass(frozen=True)
class Support:
    """A discrete pressure distribution: points (k, 2) in the world frame and weights
    summing to 1 whose centroid is the centre of mass (3.1.5)."""

    points: np.ndarray
    weights: np.ndarray
    center_of_mass: np.ndarray

    @classmethod
    def create(cls, points: ArrayLike, weights: ArrayLike, center_of_mass: ArrayLike,
               tol: CentroidTolerance = SUPPORT_DEFAULT) -> "Support":
        w = np.asarray(points, dtype=float)
        if w.ndim != 2 or w.shape[1] != 2 or w.shape[0] == 0:
            raise InvalidInput("points", "need a list of [x, y] support points")
        if not np.all(np.isfinite(w)):
            raise InvalidInput("points", "must be finite numbers")
        p = np.asarray(weights, dtype=float).reshape(-1)
        if p.shape[0] != w.shape[0]:
            raise InvalidInput("weights", f"need one weight per point ({w.shape[0]}), got {p.shape[0]}")
        if not np.all(np.isfinite(p)) or np.any(p < 0.0):
            raise InvalidInput("weights", "must be finite and non-negative")
        total = float(p.sum())
        if not total > 0.0:
            raise InvalidInput("weights", "must not all be zero")
        p = p / total
        cm = np.asarray(center_of_mass, dtype=float)
        keep = p > 0.0
        w, p = w[keep], p[keep]
        size = float(np.max(np.linalg.norm(w - cm, axis=1)))
        centroid = p @ w
        if np.linalg.norm(centroid - cm) > tol.centroid_rel * max(size, float(np.linalg.norm(cm)) * CM_SCALE_REL,
                                                                  SCALE_FLOOR):
            raise InvalidInput(
                "weights",
                "cannot put the centroid of the support at the centre of mass: the weighted "
                f"centroid is {centroid.tolist()}, the centre of mass {cm.tolist()} (3.1.5)",
            )
        # Merge coincident points: one point mass each.
        uniq, inverse = np.unique(w, axis=0, return_inverse=True)
        if uniq.shape[0] != w.shape[0]:
            p = np.bincount(inverse.reshape(-1), weights=p)
            w = uniq
        return cls(points=w, weights=p, center_of_mass=cm)

    @classmethod
    def balanced(cls, points: ArrayLike, center_of_mass: ArrayLike, tol: CentroidTolerance = SUPPORT_DEFAULT) -> "Support":
        """The weights of 3 points that put their centroid at the CM (book 3.3.3), if they
        are all non-negative; raises InvalidInput otherwise (the book discards such tripods)."""
        w = np.asarray(points, dtype=float).reshape(-1, 2)
        if w.shape[0] != 3:
            raise InvalidInput("points", "a balanced support needs exactly three points")
        cm = np.asarray(center_of_mass, dtype=float)
        a = np.vstack([np.ones(3), (w - cm).T])
        try:
            p = np.linalg.solve(a, np.array([1.0, 0.0, 0.0]))
        except np.linalg.LinAlgError as exc:
            raise InvalidInput("points", "are collinear: no weights balance them") from exc
        if np.any(p < 0.0):
            raise InvalidInput("points", "do not surround the centre of mass: a weight would be negative")
        return cls.create(w, p, cm, tol)


@dataclass(frozen=True)
class SupportBatch:
    """Many supports of one size k as arrays (a columnar batch): points (B, k, 2) in the
    world frame and weights (B, k), each row positive, summing to 1, with its centroid at
    the common centre of mass (3.1.5). Unlike :meth:`Support.create` nothing is merged or
    dropped: row j of every answer is support j as given."""

    points: np.ndarray
    weights: np.ndarray
    center_of_mass: np.ndarray

    @classmethod
    def create(cls, points: ArrayLike, weights: ArrayLike, center_of_mass: ArrayLike,
               tol: CentroidTolerance = SUPPORT_DEFAULT) -> "SupportBatch":
        """Check every support at once; an error names the first bad support's index."""
        w = np.asarray(points, dtype=float)
        p = np.asarray(weights, dtype=float)
        if w.ndim != 3 or w.shape[2] != 2 or w.shape[0] == 0 or w.shape[1] == 0 or p.shape != w.shape[:2]:
            raise InvalidInput("points", "need points of shape (batch, k, 2) and weights (batch, k)")
        if not np.all(np.isfinite(w)):
            raise InvalidInput("points", "must be finite numbers")
        if not np.all(np.isfinite(p)) or np.any(p <= 0.0):
            raise InvalidInput("weights", f"support {_first(~np.all(np.isfinite(p) & (p > 0.0), axis=1))}: "
                               "every weight of a batch must be positive (drop the point instead)")
        p = p / p.sum(axis=1, keepdims=True)
        cm = np.asarray(center_of_mass, dtype=float)
        rel = w - cm
        size = np.max(np.linalg.norm(rel, axis=2), axis=1)
        off = np.linalg.norm(np.einsum("bk,bki->bi", p, rel), axis=1)
        scale = np.maximum(np.maximum(size, float(np.linalg.norm(cm)) * CM_SCALE_REL), SCALE_FLOOR)
        bad = off > tol.centroid_rel * scale
        if np.any(bad):
            raise InvalidInput("weights", f"support {_first(bad)}: cannot put its centroid at the centre of "
                               "mass (3.1.5)")
        if w.shape[1] > 1:
            order = np.lexsort((w[..., 1], w[..., 0]), axis=-1)
            s = np.take_along_axis(w, order[..., None], axis=1)
            same = np.any(np.all(s[:, 1:, :] == s[:, :-1, :], axis=2), axis=1)
            if np.any(same):
                raise InvalidInput("points", f"support {_first(same)}: two points coincide (merge them into one "
                                   "point with the sum of their weights)")
        return cls(points=w, weights=p, center_of_mass=cm)

    def __len__(self) -> int:
        return int(self.points.shape[0])


def _first(mask: np.ndarray) -> int:
    return int(np.flatnonzero(mask)[0])


def uniform_disk_support(radius: float, center_of_mass: ArrayLike = (0.0, 0.0), rings: int = 32) -> Support:
    """Uniform pressure on a disk (figure 7-1), as annular-sector cells.

    Ring i spans radii [a i/n, a (i+1)/n] and is cut into 6(2i+1) equal sectors, so cells
    have about equal areas. Each point is its sector's exact centroid, at distance
    (2/3)(r2^3 - r1^3)/(r2^2 - r1^2) * sin(h)/h from the centre for half-angle h.
    """
    if not (math.isfinite(radius) and radius > 0.0 and radius * radius > 0.0):
        raise InvalidInput("disk_radius", "must be a positive number whose square is representable")
    if rings < 1:
        raise InvalidInput("rings", "must be at least 1")
    cm = np.asarray(center_of_mass, dtype=float)
    pts, wts = [], []
    for i in range(rings):
        r1, r2 = radius * i / rings, radius * (i + 1) / rings
        m = 6 * (2 * i + 1)
        h = math.pi / m
        rc = (2.0 / 3.0) * (r2**3 - r1**3) / (r2**2 - r1**2) * math.sin(h) / h
        th = (np.arange(m) + 0.5) * 2.0 * h
        pts.append(np.column_stack([rc * np.cos(th), rc * np.sin(th)]))
        wts.append(np.full(m, (r2**2 - r1**2) * h))
    w = np.vstack(pts) + cm
    p = np.concatenate(wts)
    return Support(points=w, weights=p / p.sum(), center_of_mass=cm)


def uniform_polygon_support(footprint: Footprint, subdivisions: int = 16) -> Support:
    """Uniform pressure on a polygon footprint, as sub-triangles of an ear-clipping
    triangulation: each triangle is cut into subdivisions^2 congruent triangles whose
    centroids carry their areas. The centroid is exact, so it is the footprint's area
    centroid; a footprint with another CM is refused (uniform pressure puts the CM at the
    area centroid)."""
    if subdivisions < 1:
        raise InvalidInput("subdivisions", "must be at least 1")
    v = footprint.vertices
    cm = footprint.center_of_mass
    ac = area_centroid(v)
    if np.linalg.norm(ac - cm) > 1e-9 * footprint.circumradius:
        raise InvalidInput(
            "center_of_mass",
            "differs from the area centroid: uniform pressure puts the centre of mass at the area centroid",
        )
    n = subdivisions
    pts, wts = [], []
    # Barycentric grid of the n^2 sub-triangles (upright and inverted).
    for a, b, c in triangulate(v):
        e1, e2 = (b - a) / n, (c - a) / n
        area = 0.5 * abs(e1[0] * e2[1] - e1[1] * e2[0])
        for i in range(n):
            for j in range(n - i):
                base = a + i * e1 + j * e2
                pts.append(base + (e1 + e2) / 3.0)
                wts.append(area)
                if i + j < n - 1:
                    pts.append(base + 2.0 * (e1 + e2) / 3.0)
                    wts.append(area)
    w = np.array(pts)
    p = np.array(wts)
    p = p / p.sum()
    # Re-centre the round-off of the sum exactly on the CM (a shift of ~1e-16 L).
    w = w + (cm - p @ w)
    return Support(points=w, weights=p, center_of_mass=cm)


def balancing_weights(rel: np.ndarray, min_det: float) -> tuple[np.ndarray, np.ndarray]:
    """The weights that put the centroid of tripods ``rel`` (m, 3, 2), relative to the CM,
    at the CM: the solution p of [1 1 1; x; y] p = (1, 0, 0), by Cramer's rule (each p_i
    the signed area of the CM's triangle with the other two feet over the tripod's; ten
    times faster than a batched LU solve). Returns the weights of the tripods whose
    determinant exceeds ``min_det`` in size, and which those are (m,)."""
    x, y = rel[..., 0], rel[..., 1]
    areas = np.stack([x[:, 1] * y[:, 2] - x[:, 2] * y[:, 1], x[:, 2] * y[:, 0] - x[:, 0] * y[:, 2],
                      x[:, 0] * y[:, 1] - x[:, 1] * y[:, 0]], axis=1)
    det = areas[:, 0] + areas[:, 1] + areas[:, 2]
    ok = np.abs(det) > min_det
    return areas[ok] / det[ok, None], ok


def random_balanced_tripods(
    rng: np.random.Generator,
    n: int,
    radius: float,
    center_of_mass: ArrayLike = (0.0, 0.0),
    footprint: Footprint | None = None,
    max_draws: int = 200,
) -> tuple[np.ndarray, np.ndarray]:
    """``n`` random tripods as in the book's figure 3-5 (3.3.3): three points uniform in the
    disk of ``radius`` about the CM (or in ``footprint``), weighted so that their centroid
    is the CM; draws needing a negative weight are discarded, as the book does.

    Returns points (n, 3, 2) and weights (n, 3). The caller supplies the seeded generator.
    Gives up with InvalidInput after ``max_draws`` rounds of candidates (a footprint that
    fills little of its bounding box, or a CM near the edge of the hull, accept few).
    """
    cm = np.asarray(center_of_mass if footprint is None else footprint.center_of_mass, dtype=float)
    pts_out, wts_out, have = [], [], 0
    for _ in range(max_draws):
        if have >= n:
            break
        m = max(64, 6 * (n - have))
        if footprint is None:
            r = radius * np.sqrt(rng.uniform(size=(m, 3)))
            th = rng.uniform(0.0, 2.0 * math.pi, size=(m, 3))
            w = np.stack([r * np.cos(th), r * np.sin(th)], axis=-1) + cm
        else:
            lo = footprint.vertices.min(axis=0)
            hi = footprint.vertices.max(axis=0)
            cand = rng.uniform(lo, hi, size=(4 * m, 2))
            cand = cand[inside_polygon(footprint.vertices, cand)]
            k = (len(cand) // 3) * 3
            w = cand[:k].reshape(-1, 3, 2)
        p, ok = balancing_weights(w - cm, 1e-12 * (radius if footprint is None else footprint.circumradius) ** 2)
        good = np.all(p >= 0.0, axis=1)
        pts_out.append(w[ok][good])
        wts_out.append(p[good])
        have += int(good.sum())
    if have < n:
        raise InvalidInput(
            "footprint" if footprint is not None else "center_of_mass",
            f"random tripods balanced about the centre of mass are too rare here: {have} of {n} "
            f"found in {max_draws} rounds of draws",
        )
    return np.concatenate(pts_out)[:n], np.concatenate(wts_out)[:n]
