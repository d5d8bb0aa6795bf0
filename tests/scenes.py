"""Shared scenes and geometric helpers for the tests (seeded, no I/O)."""

from __future__ import annotations

import math

import numpy as np

from models.core.scene import PushScene

SEED = 20261122

# mu = |alpha . c| / a for each regime of the boundary (models/locus/cor_disk.py docstring):
# outer+inner, outer+arc+inner, arc+inner (contact outside the disk).
MU_OUTER_INNER = (1e-3, 0.05, 0.3, 0.6, 0.7)
MU_WITH_ARC = (0.72, 0.9, 0.99)
MU_ON_DISK = (1.0, 1.5, 3.0)
ALL_MU = MU_OUTER_INNER + MU_WITH_ARC + MU_ON_DISK


def scene_for_mu(mu: float, a: float = 1.0, along: float = 0.2, cm=(0.0, 0.0),
                 edge_angle: float = math.pi / 2, push_direction: float = 0.0) -> PushScene:
    """Book-like scene (figure 3-3): push along +x on a vertical edge, contact placed so
    that alpha . c = mu a. ``along`` shifts the contact along the line of force."""
    probe = PushScene.create(a, np.asarray(cm, float) + [0.0, 0.0], edge_angle, push_direction, cm)
    contact = np.asarray(cm, float) + mu * a * probe.alpha_hat + along * a * probe.normal
    return PushScene.create(a, contact, edge_angle, push_direction, cm)


def point_in_polygon(points: np.ndarray, polygon: np.ndarray) -> np.ndarray:
    """Even-odd rule, vectorised over points (k, 2)."""
    pts = np.atleast_2d(points)
    x, y = pts[:, 0:1], pts[:, 1:2]
    a = polygon
    b = np.roll(polygon, -1, axis=0)
    cond = (a[:, 1] > y) != (b[:, 1] > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        xint = a[:, 0] + (y - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    return np.sum(cond & (x < xint), axis=1) % 2 == 1


def polygon_grid(vertices: np.ndarray, cells: int) -> np.ndarray:
    """The midpoints of a square grid's cells inside the polygon, ``cells`` across its larger
    side: a quadrature of the polygon's area, independent of the code under test."""
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    h = float(np.max(hi - lo)) / cells
    xs = np.arange(lo[0] + h / 2, hi[0], h)
    ys = np.arange(lo[1] + h / 2, hi[1], h)
    grid = np.array(np.meshgrid(xs, ys)).reshape(2, -1).T
    return grid[point_in_polygon(grid, vertices)]


def distance_to_polyline(points: np.ndarray, polygon: np.ndarray) -> np.ndarray:
    """Distance from each point to the closed polygon's edges."""
    pts = np.atleast_2d(points)[:, None, :]
    a = polygon[None]
    ab = np.roll(polygon, -1, axis=0)[None] - a
    t = np.clip(np.sum((pts - a) * ab, axis=-1) / np.sum(ab * ab, axis=-1), 0.0, 1.0)
    return np.min(np.linalg.norm(a + t[..., None] * ab - pts, axis=-1), axis=1)


def random_tripods(rng: np.random.Generator, count: int, a: float = 1.0):
    """Tripods uniformly in the disk whose weights put the centroid at the origin
    (book 3.3.3: a tripod needing a negative weight is discarded)."""
    out = []
    while len(out) < count:
        r = a * np.sqrt(rng.uniform(0, 1, 3))
        th = rng.uniform(0, 2 * math.pi, 3)
        w = np.column_stack([r * np.cos(th), r * np.sin(th)])
        m = np.vstack([np.ones(3), w.T])
        try:
            p = np.linalg.solve(m, np.array([1.0, 0.0, 0.0]))
        except np.linalg.LinAlgError:
            continue
        if np.all(p > 1e-3):
            out.append((w, p))
    return out


def circle_radius(p0: np.ndarray, p1: np.ndarray, p2: np.ndarray) -> float:
    """Radius of the circle through three points."""
    a = np.linalg.norm(p1 - p0)
    b = np.linalg.norm(p2 - p1)
    c = np.linalg.norm(p2 - p0)
    area2 = abs((p1[0] - p0[0]) * (p2[1] - p0[1]) - (p1[1] - p0[1]) * (p2[0] - p0[0]))
    return a * b * c / (2.0 * area2)


# The nine COR sketches of figure 4-6 (book 4.1.5-4.1.6, reconstructed: docs/mechanics.md).
# (letter, mirrored, (contact x, contact y, edge angle in degrees, mu_c)); disk a = 1 at the
# origin, push along +x. Found by a seeded search over scenes; each is robust to moving the
# contact by 0.01.
SKETCH_SCENES = [
    ("a", False, (1.07, -1.4, 131, 0.1)),
    ("a", True, (0.41, -0.69, 7, 0.05)),
    ("b", False, (-0.04, 1.17, 168, 0.22)),
    ("b", True, (-0.29, -0.9, 16, 0.54)),
    ("c", False, (0.21, -0.53, 107, 0.2)),
    ("c", True, (0.02, 0.95, 39, 0.07)),
    ("d", False, (1.13, -1.32, 61, 0.09)),
    ("d", True, (1.19, 1.38, 109, 0.41)),
    ("e", False, (-0.18, 1.36, 90, 0.29)),
    ("e", True, (-0.41, -0.25, 97, 0.08)),
    ("f", False, (-0.15, 0.89, 42, 0.06)),
    ("f", True, (0.13, 1.31, 147, 0.05)),
    ("g", False, (-0.6, 0.52, 36, 2.37)),
    ("g", True, (0.94, 1.24, 109, 0.99)),
    ("h", False, (-0.33, 1.17, 41, 0.64)),
    ("h", True, (-0.4, -1.18, 113, 2.23)),
    ("i", False, (-0.28, 1.23, 8, 1.45)),
    ("i", True, (0.56, 0.45, 124, 0.25)),
]

CONFIGS = {
    "a": ("P", "P"), "b": ("P", "S"), "c": ("S", "S"), "d": ("P", "O"), "e": ("S", "O"),
    "f": ("O", "O"), "g": ("P", "W"), "h": ("S", "W"), "i": ("O", "W"),
}
SHORT = {"pure_slipping": "P", "same_sided_split": "S", "opposite_sided_split": "O", "wrapped": "W"}
