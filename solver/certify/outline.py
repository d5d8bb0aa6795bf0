"""A footprint's outline in a dimensionless frame, seen from a candidate point r.

Both certified problems of :mod:`solver.locus` (membership, 3.2-3.3; the sticking locus,
4.1.4) reduce to the outline of the footprint F: their columns are affine along every ray
from r, so the pricing problem and the dual lower bound are 1-D problems over the outline
(the reduction is derived in :mod:`solver.certify.functional`). This module holds

* :class:`Outline`: F in a frame with origin at the centre of mass (CM), axes given by the
  problem, lengths divided by L (the disk radius, or a polygon's circumradius, 3.1.8), so
  every number computed in it is invariant under similarities of the scene (3.3.12);
* :class:`DiskPieces` and :class:`PolygonPieces`: the outline cut into pieces on which
  rho = |w - r| is monotone and u = (w - r)/rho smooth, with the point w(t), rho, u at any
  parameter t and sound bounds of their first and second derivatives on an interval.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from models.core.errors import InvalidInput
from models.core.footprint import Footprint, edge_feet, inside_polygon
from solver.core.tolerances import SolverTolerances

ON_BOUNDARY_REL = 1e-9
"""A candidate within this distance (/ L) of the footprint's outline is moved onto it: the
decision is then made for the moved point, exactly on the outline, where the one-sided
limits of (w - r)/|w - r| are known in closed form."""

CIRCLE_SAMPLES = 256
"""Pricing-grid points (and initial columns) on the disk's circle."""

EDGE_SAMPLES = 64
"""Most pricing-grid points (and initial columns) per polygon edge, vertices included."""

POLYGON_SAMPLES = 512
"""Pricing-grid points of a polygon in all, shared among the edges by length (at least 4
and at most EDGE_SAMPLES per edge)."""


@dataclass(frozen=True)
class Outline:
    """A footprint in a dimensionless frame: origin at the CM, lengths divided by
    ``length`` (L), ``frame`` holding the world components of the frame's unit vectors as
    its columns (a rotation: the problems use (v, J v)). The disk has ``vertices`` None
    (radius 1); a polygon's are counter-clockwise."""

    length: float
    center_of_mass: np.ndarray
    frame: np.ndarray
    vertices: np.ndarray | None

    @property
    def is_disk(self) -> bool:
        return self.vertices is None

    def to_world(self, pts: np.ndarray) -> np.ndarray:
        return self.center_of_mass + self.length * (np.asarray(pts, dtype=float) @ self.frame.T)

    def to_local(self, pts: object) -> np.ndarray:
        return ((np.asarray(pts, dtype=float) - self.center_of_mass) @ self.frame) / self.length

    def vector_to_local(self, v: object) -> np.ndarray:
        return np.asarray(v, dtype=float) @ self.frame

    def vector_to_world(self, v: object) -> np.ndarray:
        return self.frame @ np.asarray(v, dtype=float)

    def snap(self, r: np.ndarray) -> tuple[np.ndarray, bool]:
        """(r, on_outline): r moved onto the outline when within ON_BOUNDARY_REL of it (to a
        vertex first, else to the nearest edge point)."""
        if self.vertices is None:
            rad = float(np.hypot(r[0], r[1]))
            if abs(rad - 1.0) <= ON_BOUNDARY_REL:
                return r / rad, True
            return r, False
        vertex = self.snap_to_vertex(r)
        if vertex is not None:
            return vertex, True
        foot, d = edge_feet(self.vertices, r)
        k = int(np.argmin(d))
        if d[k] <= ON_BOUNDARY_REL:
            return foot[k], True
        return r, False

    def snap_to_vertex(self, r: np.ndarray) -> np.ndarray | None:
        """The polygon's vertex within ON_BOUNDARY_REL of r, or None (also for the disk)."""
        if self.vertices is None:
            return None
        v = self.vertices
        dv = np.hypot(v[:, 0] - r[0], v[:, 1] - r[1])
        k = int(np.argmin(dv))
        return v[k].copy() if dv[k] <= ON_BOUNDARY_REL else None

    def contains(self, r: np.ndarray, on_outline: bool) -> bool:
        """Whether r lies in the closed footprint."""
        if on_outline:
            return True
        if self.vertices is None:
            return float(np.hypot(r[0], r[1])) <= 1.0
        return bool(inside_polygon(self.vertices, r)[0])

    def reach(self, point: np.ndarray) -> float:
        """max |w - point| over the footprint (/ L)."""
        if self.vertices is None:
            return float(np.hypot(point[0], point[1])) + 1.0
        d = self.vertices - point
        return float(np.max(np.hypot(d[:, 0], d[:, 1])))


def outline_in_frame(
    center_of_mass: np.ndarray,
    disk_radius: float,
    footprint: Footprint | None,
    frame: np.ndarray,
    tol: SolverTolerances,
) -> Outline:
    """The footprint (the disk of ``disk_radius`` about the CM when None) in ``frame``
    (2 x 2, a rotation, columns in world components). A polygon's centre of mass must be
    the scene's (3.1.5); its L is its circumradius (3.1.8)."""
    cm = np.asarray(center_of_mass, dtype=float)
    if footprint is None:
        return Outline(float(disk_radius), cm.copy(), frame, None)
    ell = float(footprint.circumradius)
    if np.linalg.norm(footprint.center_of_mass - cm) > tol.centroid_rel * ell:
        raise InvalidInput(
            "center_of_mass",
            "the footprint's centre of mass differs from the push scene's: "
            f"{footprint.center_of_mass.tolist()} vs {cm.tolist()}",
        )
    return Outline(ell, cm.copy(), frame, ((footprint.vertices - cm) @ frame) / ell)


# --------------------------------------------------------------------------------------
# The outline seen from r: 1-D pieces with derivative bounds


class Pieces(Protocol):
    """Pieces of the outline, each a parameter interval [piece_lo, piece_hi] on which
    rho = |w - r| is monotone and u = (w - r)/rho smooth; ``grid_counts`` points per
    piece make the pricing grid; ``r`` is the point they are seen from."""

    r: np.ndarray
    piece_lo: np.ndarray
    piece_hi: np.ndarray
    grid_counts: np.ndarray

    def geom(self, piece: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(w (k, 2), rho (k,), u (k, 2)) at the parameters; u is its one-sided limit
        where rho = 0."""
        ...

    def derivative_bounds(
        self, piece: np.ndarray, t0: np.ndarray, t1: np.ndarray, rho0: np.ndarray, rho1: np.ndarray
    ) -> tuple[np.ndarray, ...]:
        """(V, A, R1, R2, U1, U2) on each interval: |w'| <= V, |w''| <= A, |rho'| <= R1,
        |rho''| <= R2, |u'| <= U1, |u''| <= U2."""
        ...

    def sagitta(self, piece: np.ndarray, length: np.ndarray) -> np.ndarray:
        """Largest distance of the outline from the chord over an interval of ``length``."""
        ...


def grid(pieces: Pieces) -> tuple[np.ndarray, np.ndarray]:
    """(piece, t) of the pricing grid, sorted per piece, both ends of every piece included."""
    ps, ts = [], []
    for k, (lo, hi, n) in enumerate(zip(pieces.piece_lo, pieces.piece_hi, pieces.grid_counts)):
        ps.append(np.full(int(n), k))
        ts.append(np.linspace(lo, hi, int(n)))
    return np.concatenate(ps), np.concatenate(ts)


class DiskPieces:
    """The circle |w| = 1 seen from r, parametrised by phi = theta - theta_r in [0, 2 pi].

    In the frame turned by theta_r (r on the +x axis at distance R):
    w - r = ((1 - R) - 2 sin^2(phi/2), sin phi), rho^2 = (1 - R)^2 + 4 R sin^2(phi/2),
    free of cancellation. Pieces [0, pi] and [pi, 2 pi] (rho increases, then decreases).

    Derivative bounds (|w'| = |w''| = 1): the direction of u turns at the rate
    g(rho) = 1/2 + (1 - R^2)/(2 rho^2) (from cross(w - r, w') = (1 - R^2 + rho^2)/2),
    monotone in rho, so |u'| <= U1 = max(|g(rho0)|, |g(rho1)|) on an interval. This stays
    of order 1/R for a far r, where the cruder 1/2 + |1 - R^2|/(2 rho_min^2) would be 1
    (the far-field bound). g' = -(1 - R^2) rho'/rho^3 with |rho'| <= 1, so
    |u''| <= sqrt((|1 - R^2|/rho_min^3)^2 + U1^4); rho'' = rho g^2 + u . w'', so
    |rho''| <= rho_max U1^2 + 1. On the circle (R = 1 after snapping)
    w - r = 2 sin(phi/2) (-sin(phi/2), cos(phi/2)): rho = 2 sin(phi/2) and
    u = (-sin(phi/2), cos(phi/2)) exactly, |u'| = 1/2, |u''| = 1/4, |rho''| <= 1/2.
    """

    def __init__(self, r: np.ndarray, on_circle: bool):
        self.r = r
        self.on_circle = on_circle
        r_norm = float(np.hypot(r[0], r[1]))
        theta_r = math.atan2(r[1], r[0]) if r_norm > 0.0 else 0.0
        c, sn = math.cos(theta_r), math.sin(theta_r)
        self.rot = np.array([[c, -sn], [sn, c]])
        self.big_r = 1.0 if on_circle else r_norm
        self.one_minus_r2 = (1.0 - self.big_r) * (1.0 + self.big_r)
        self.piece_lo = np.array([0.0, math.pi])
        self.piece_hi = np.array([math.pi, 2.0 * math.pi])
        self.grid_counts = np.array([CIRCLE_SAMPLES // 2 + 1] * 2)

    def geom(self, piece: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        t = np.asarray(t, dtype=float)
        half = 0.5 * t
        sh = np.sin(half)
        w_loc = np.stack([np.cos(t), np.sin(t)], axis=-1)
        if self.on_circle:
            rho = 2.0 * np.abs(sh)
            u_loc = np.stack([-sh, np.cos(half)], axis=-1)
        else:
            e = np.stack([(1.0 - self.big_r) - 2.0 * sh * sh, np.sin(t)], axis=-1)
            rho = np.sqrt((1.0 - self.big_r) ** 2 + 4.0 * self.big_r * sh * sh)
            u_loc = e / rho[:, None]
        return w_loc @ self.rot.T, rho, u_loc @ self.rot.T

    def derivative_bounds(
        self, piece: np.ndarray, t0: np.ndarray, t1: np.ndarray, rho0: np.ndarray, rho1: np.ndarray
    ) -> tuple[np.ndarray, ...]:
        ones = np.ones(np.shape(t0))
        if self.on_circle:
            return ones, ones, ones, 0.5 * ones, 0.5 * ones, 0.25 * ones
        rmin = np.minimum(rho0, rho1)
        rmax = np.maximum(rho0, rho1)
        q = self.one_minus_r2
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            u1 = np.maximum(np.abs(0.5 + q / (2.0 * rho0 * rho0)), np.abs(0.5 + q / (2.0 * rho1 * rho1)))
            u1 = np.where(rmin > 0.0, u1, np.inf)
            u2 = np.sqrt((abs(q) / rmin**3) ** 2 + u1**4)
        r2 = rmax * u1 * u1 + 1.0
        return ones, ones, ones, r2, u1, u2

    def sagitta(self, piece: np.ndarray, length: np.ndarray) -> np.ndarray:
        return 1.0 - np.cos(0.5 * np.minimum(length, math.pi))


class PolygonPieces:
    """Polygon edges w = A + t d (|d| = 1, t in [0, l]) seen from r, in edge coordinates:
    w - r = tau d + h n with tau = t - tau_f (tau_f the foot of r on the edge's line) and
    h = |foot - r|, so rho = hypot(tau, h) and u = (tau d + h n)/rho without cancellation;
    an edge through r (after snapping) has h = 0 exactly and u = sign(tau) d. Edges are
    split at the foot when it falls inside them, so rho is monotone on a piece.

    Bounds (|w'| = 1, w'' = 0): |rho'| <= 1, rho'' = h^2/rho^3; the angle of u turns at
    rate h/rho^2 and its derivative is bounded by 2h/rho^3, so |u'| <= h/rho_min^2 and
    |u''| <= sqrt(4 h^2/rho^6 + h^4/rho^8) <= sqrt(5) h/rho_min^3. With h = 0, u is
    constant on the piece.
    """

    def __init__(self, r: np.ndarray, vertices: np.ndarray, on_outline: bool):
        self.r = r
        a = vertices
        b = np.roll(vertices, -1, axis=0)
        ab = b - a
        lengths = np.hypot(ab[:, 0], ab[:, 1])
        d = ab / lengths[:, None]
        tau_f = np.einsum("ij,ij->i", r - a, d)
        foot = a + tau_f[:, None] * d
        hvec = foot - r
        h = np.hypot(hvec[:, 0], hvec[:, 1])
        normal = np.stack([-d[:, 1], d[:, 0]], axis=-1)
        with np.errstate(invalid="ignore", divide="ignore"):
            n_unit = np.where(h[:, None] > 0.0, hvec / h[:, None], normal)
        if on_outline:
            # r was moved onto the outline: edges through it get h = 0 exactly.
            r_norm = float(np.hypot(r[0], r[1]))
            through = (h <= 4.0 * np.finfo(float).eps * (1.0 + r_norm)) & (tau_f >= -ON_BOUNDARY_REL) & (
                tau_f <= lengths + ON_BOUNDARY_REL
            )
            h = np.where(through, 0.0, h)
            tau_f = np.where(through, np.clip(tau_f, 0.0, lengths), tau_f)
        self.edge_a, self.edge_d, self.edge_n = a, d, n_unit
        self.edge_h, self.edge_tf = h, tau_f
        per_edge = np.clip(np.round(POLYGON_SAMPLES * lengths / lengths.sum()), 4, EDGE_SAMPLES)
        lo, hi, edge, side, counts = [], [], [], [], []
        for k in range(len(a)):
            cuts = [0.0, float(lengths[k])]
            if 0.0 < tau_f[k] < lengths[k]:
                cuts = [0.0, float(tau_f[k]), float(lengths[k])]
            for j in range(len(cuts) - 1):
                lo.append(cuts[j])
                hi.append(cuts[j + 1])
                edge.append(k)
                mid = 0.5 * (cuts[j] + cuts[j + 1])
                side.append(1.0 if mid >= tau_f[k] else -1.0)
                frac = (cuts[j + 1] - cuts[j]) / lengths[k]
                counts.append(max(2, int(round(per_edge[k] * frac)) + 1))
        self.piece_lo = np.array(lo)
        self.piece_hi = np.array(hi)
        self.piece_edge = np.array(edge, dtype=int)
        self.piece_side = np.array(side)
        self.grid_counts = np.array(counts)

    def geom(self, piece: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        piece = np.asarray(piece, dtype=int)
        t = np.asarray(t, dtype=float)
        k = self.piece_edge[piece]
        d = self.edge_d[k]
        tau = t - self.edge_tf[k]
        h = self.edge_h[k]
        w = self.edge_a[k] + t[:, None] * d
        rho = np.hypot(tau, h)
        e = tau[:, None] * d + h[:, None] * self.edge_n[k]
        with np.errstate(invalid="ignore", divide="ignore"):
            u = np.where(rho[:, None] > 0.0, e / rho[:, None], self.piece_side[piece][:, None] * d)
        return w, rho, u

    def derivative_bounds(
        self, piece: np.ndarray, t0: np.ndarray, t1: np.ndarray, rho0: np.ndarray, rho1: np.ndarray
    ) -> tuple[np.ndarray, ...]:
        k = self.piece_edge[np.asarray(piece, dtype=int)]
        h = self.edge_h[k]
        rmin = np.minimum(rho0, rho1)
        n = np.shape(t0)
        ones = np.ones(n)
        with np.errstate(divide="ignore", invalid="ignore"):
            u1 = np.where(h > 0.0, h / (rmin * rmin), 0.0)
            u2 = np.where(h > 0.0, math.sqrt(5.0) * h / rmin**3, 0.0)
            r2 = np.where(h > 0.0, h * h / rmin**3, 0.0)
        return ones, np.zeros(n), ones, r2, u1, u2

    def sagitta(self, piece: np.ndarray, length: np.ndarray) -> np.ndarray:
        return np.zeros(np.shape(length))


def pieces_seen_from(outline: Outline, r: np.ndarray, on_outline: bool) -> DiskPieces | PolygonPieces:
    """The outline of ``outline`` as 1-D pieces seen from r (local frame)."""
    if outline.vertices is None:
        return DiskPieces(r, on_outline)
    return PolygonPieces(r, outline.vertices, on_outline)
