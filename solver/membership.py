"""Certified membership: can a given point r be the COR of a push? (book 3.2-3.3.3, 7.5)

Frictionless pusher (mu_c = 0). All lengths are divided by a footprint size L (the disk
radius, or a polygon's circumradius, 3.1.8) and measured from the centre of mass (CM), so
every number below is dimensionless and the same at every scale.

The membership problem
----------------------
For a candidate COR r let s = alpha . (c - r), the book's moment arm of (3.3). r is the COR
of a support {w_i, P_i} with no mass at r exactly when the gradient (3.8) of the power
(3.7) vanishes, i.e. sum_i P_i g_r(w_i) = 0 with

    g_r(w) = |w - r| alpha - s (w - r) / |w - r|            ((3.8)-(3.10) times P_i),

together with sum_i P_i = 1 and sum_i P_i w_i = 0 (the centroid is the CM, 3.1.5). With
the columns G(w) = (1, w/L, g_r(w)/L) in R^5 (:func:`models.mpp.membership_columns`) and
b = (1, 0, 0, 0, 0): r is a COR for some pressure distribution on the footprint F iff b
lies in the convex hull of

    S = {G(w) : w in F, w != r}  (+ the point-mass set {(1, r/L, -s zeta/L) : |zeta| <= 1}
                                    when r lies in F),

the second part being a mass P0 at r itself: the subgradient of |w - r| at w = r is the
unit disk, so such a mass contributes (P0, P0 r/L, -s z/L) with |z| <= P0 (a second-order
cone). When r is outside F the term is absent. The hull of S is compact (G is bounded
and its limits at r are point-mass elements), so b is outside it iff some y in R^5
separates them: min_{g in S} y . g > y . b (Farkas). Either sign of s is allowed (the sign
sets the sense of rotation, 3.3.1); s = 0 (r on the line of force) gives no COR except in
the degenerate translation scene with all weight at the CM.

Boundary reduction (why only the outline of F and a point mass at r matter)
---------------------------------------------------------------------------
Fix y = (y0, y_w, y_g) in R^5 and a unit vector u. On the ray w = r + rho u, rho > 0,
|w - r| = rho and (w - r)/|w - r| = u, so

    phi(w) = y . G(w) = y0 + y_w . (r + rho u)/L + (y_g . alpha) rho/L - s (y_g . u)/L

is AFFINE in rho (every component of G is: 1, w and rho alpha - s u). The ray meets the
closed set F in segments whose end points lie on the boundary dF, or at rho -> 0 when r is
in F, where phi tends to y0 + y_w . r/L - s (y_g . u)/L >= y0 + y_w . r/L - |s||y_g|/L,
the point-mass value. Hence

1. min_F phi = min(min_{dF} phi, point-mass value if r in F): the pricing problem of column
   generation and the dual lower bound are 1-D minimisations over the outline (polygon
   edges, or the circle of the disk);
2. every G(w) with w inside F is a convex combination of the G of the two ends of its
   ray segment (G is affine along the ray), so witnesses may be supported on dF plus a
   point mass at r. (A consequence: the locus of a footprint equals the locus of its
   outline plus, when r is inside, a mass at r.)

Algorithm
---------
Column generation on the restricted master

    min || sum_j P_j G_j + pm - b ||_1   over P >= 0, pm in the point-mass cone,

built once per column capacity with cvxpy Parameters and re-solved with Clarabel. Its
dual y (the equality multipliers, |y|_inf <= 1 by L1 duality, y . G_j >= 0 on the columns
and y . b = -residual at optimality) is the separating functional. Pricing minimises
phi = y . G over the outline: first golden-section refinement of the local minima of a
fixed grid, then a sound 1-D branch and bound (vectorised) with Lipschitz and
second-derivative bounds (derivations in :class:`_DiskOutline` and
:class:`_PolygonOutline`). Decisions:

* ``inside``: a witness (points on dF, weights, a mass at r) whose L1 residual after an
  exact polish is at most ``tol.membership_residual``;
* ``outside``: a dual y with certified margin m_F - y . b > ``tol.certificate_margin``,
  where m_F is the branch-and-bound lower bound of y . G over F (and the point-mass set);
* ``undecided`` otherwise (iteration, interval or time limits; or r within about the
  tolerances of the locus boundary), with what was reached.

Everything is computed in the dimensionless locus frame (:class:`Outline`), so results are
invariant under similarities of the scene (3.3.12); results are reported in the world.

Observations (tests/solver/test_membership.py)
----------------------------------------------
* The CM is a COR: all weight at the CM gives (1, 0, 0, 0, 0) with z = 0 (rotation about
  the CM dissipates nothing, (3.6)); the locus contains it, r_min (3.31) > 0 being the
  boundary's nearest distance.
* Membership is discontinuous across dF: on dF a point mass at r with the whole
  subgradient disk is allowed, just outside only supports near r remain, whose directions
  cover half of it. Where the locus reaches the outline (the disk's perimeter arcs for
  |alpha . c| >= a/sqrt 2, a square's vertex) points just beyond are outside by a wide
  margin.
* ``membership_residual`` is a tolerance, not an exact test: where (3.8) is insensitive
  to r (near the tip for small |alpha . c|/a) a witness with residual 5e-9 can belong to a
  point 5e-7 L outside the locus (its forward COR error then says so). Polished witnesses
  of points inside reach about 1e-16, so the default is strict (1e-12).
"""

from __future__ import annotations

import math
import threading
import time
import warnings
from dataclasses import dataclass

import cvxpy as cp
import numpy as np
from scipy.optimize import nnls

from models.errors import InvalidInput
from models.footprint import Footprint
from models.scene import PushScene
from models.support import Support
from models.tolerances import SOLVER_DEFAULT, SolverTolerances
from solver.errors import SolverError
from solver.forward import solve_forward

ON_BOUNDARY_REL = 1e-9
"""A candidate within this distance (/ L) of the footprint's outline is moved onto it: the
decision is then made for the moved point (``MembershipResult.cor``), exactly on dF, where
the one-sided limits of (w - r)/|w - r| are known in closed form."""

CIRCLE_SAMPLES = 256
"""Initial columns (and pricing grid) on the disk's circle."""

EDGE_SAMPLES = 64
"""Most initial columns (and pricing grid points) per polygon edge, vertices included."""

POLYGON_SAMPLES = 512
"""Initial columns of a polygon in all, shared among the edges by length (at least 4 and
at most EDGE_SAMPLES per edge)."""

COLUMNS_PER_ROUND = 4
"""Most new columns added per column-generation round."""

POINT_MASS_RADIUS = 1e-7
"""With r in the footprint, columns at support points closer than this (/ L) to r are not
used: G(w) is then within this distance of the point-mass set, which the master has."""

BASE_CAPACITY = 320
"""Column capacities of the compiled restricted masters are BASE_CAPACITY * 2^k (one cached
problem each): a query holds the grid (CIRCLE_SAMPLES, or EDGE_SAMPLES per edge plus
splits), the warm points and up to 2 * COLUMNS_PER_ROUND new columns per round."""

GOLDEN_ITERATIONS = 48
"""Golden-section steps of the local pricing refinement (bracket shrinks by 0.618 each)."""

ROUNDING_ALLOWANCE = 32.0 * np.finfo(float).eps
"""Relative rounding allowance subtracted from every branch-and-bound lower bound. The
outline is evaluated in coordinates centred on r (edge coordinates, or the circle turned to
r), where w - r, rho and u carry relative rounding errors only; the data computed once per
query (R = |r|, the feet of r) are exact for a candidate within a few ulps of r."""

MIN_INTERVAL = 1e-13
"""Branch-and-bound intervals shorter than this (parameter units, ~ L) are not split
further; their (valid, possibly weak) bound is kept."""

POLISH_BELOW = 1e-6
"""The exact witness polish is tried once the master's L1 residual is below this (the
master alone reaches only the conic solver's accuracy, about 1e-10)."""

REPORT_WEIGHT_REL = 1e-9
"""Support points of a non-inside result with weights below this fraction of the largest
are left out of the reported (approximate) support."""

MAX_WARM_POINTS = 64
"""Most warm-start points taken from a caller (the first ones are kept)."""

_B = np.array([1.0, 0.0, 0.0, 0.0, 0.0])
_GOLD = 0.5 * (math.sqrt(5.0) - 1.0)


@dataclass(frozen=True)
class MembershipResult:
    """Answer to "can ``cor`` be the COR of a push of this footprint?" with its certificate.

    * ``status``: "inside" | "outside" | "undecided".
    * ``cor``: the point decided (world frame). It is the query, except within
      ``ON_BOUNDARY_REL`` * L of the footprint's outline, where it is moved onto it.
    * ``certificate_kind``: "witness" (inside), "dual" (outside, sound), or "none".
    * ``witness_points`` (k, 2) world frame, ``witness_weights`` (k,), and
      ``point_mass_at_cor``: a support with its centroid at the CM for which ``cor`` is the
      COR, weights summing to 1 with the point mass. ``point_mass_subgradient`` z (2,),
      |z| <= point_mass_at_cor: the point mass contributes -s z / L to (3.8) (the
      subgradient of |w - r| at w = r scaled by the mass). For "outside" and "undecided"
      results the support is the best one of the last restricted master.
    * ``witness_residual``: L1 residual (in the locus frame, dimensionless) of the
      membership equations for that support; for an "outside" result it is the restricted
      master's optimum, an upper bound of the L1 distance from b to the hull of S.
    * ``witness_forward_cor_error``: |COR of the witness found by the forward minimum-power
      solver - cor| / L, or None when not re-verified.
    * ``dual`` (5,): the separating functional y on the columns of
      :func:`models.mpp.membership_columns` (world-aligned CM frame, lengths / L). It is
      computed in the locus frame with |y|_inf <= 1 there, so |y_w|, |y_g| <= sqrt(2) here.
      ``dual_lower_bound`` m_F:
      a lower bound of y . G over the footprint and the point-mass set; ``dual_margin`` =
      m_F - y . b, > 0 proves ``cor`` outside. With ``lower_bound_method`` "grid" (from
      ``certify=False``) the bound is only the minimum over sampled points and refined local
      minima: NOT a certificate. "branch_and_bound" is sound over the continuous outline.
    * ``in_footprint``: whether ``cor`` lies in the (closed) footprint, so that a point mass
      at it is allowed.
    """

    status: str
    cor: np.ndarray
    certificate_kind: str
    witness_points: np.ndarray
    witness_weights: np.ndarray
    point_mass_at_cor: float
    point_mass_subgradient: np.ndarray
    witness_residual: float
    witness_forward_cor_error: float | None
    dual: np.ndarray | None
    dual_lower_bound: float | None
    dual_margin: float | None
    lower_bound_method: str | None
    iterations: int
    n_columns: int
    bnb_intervals: int
    in_footprint: bool
    length_scale: float
    message: str
    solve_time_s: float


# --------------------------------------------------------------------------------------
# Footprints in the dimensionless locus frame


@dataclass(frozen=True)
class Outline:
    """A footprint in the dimensionless locus frame (docs/architecture.md): origin at the
    CM, x along the scene's axis alpha' = sign(alpha . c) alpha_hat, y = z x alpha', lengths
    divided by L. ``frame`` holds the world components of the frame's unit vectors as its
    columns. The disk has ``vertices`` None (radius 1); a polygon's are counter-clockwise.

    Working in this frame makes every computed number invariant under translations,
    rotations, mirror images and scalings of the scene (3.3.12), including the L1 residual
    of the restricted master, which a fixed world frame would not be.
    """

    length: float
    center_of_mass: np.ndarray
    frame: np.ndarray
    vertices: np.ndarray | None

    @property
    def is_disk(self) -> bool:
        return self.vertices is None

    def to_world(self, pts: np.ndarray) -> np.ndarray:
        return self.center_of_mass + self.length * (np.asarray(pts, dtype=float) @ self.frame.T)

    def to_local(self, pts) -> np.ndarray:
        return ((np.asarray(pts, dtype=float) - self.center_of_mass) @ self.frame) / self.length

    def vector_to_local(self, v) -> np.ndarray:
        return np.asarray(v, dtype=float) @ self.frame

    def dual_to_world(self, y: np.ndarray) -> np.ndarray:
        """A functional on the local columns (1, w, g) as one on world-aligned CM-frame
        columns of :func:`models.mpp.membership_columns` (same length unit L)."""
        return np.concatenate([[y[0]], self.frame @ y[1:3], self.frame @ y[3:5]])

    def snap(self, r: np.ndarray) -> tuple[np.ndarray, bool]:
        """(r, on_outline): r moved onto the outline when within ON_BOUNDARY_REL of it."""
        if self.is_disk:
            rad = float(np.hypot(r[0], r[1]))
            if abs(rad - 1.0) <= ON_BOUNDARY_REL:
                return r / rad, True
            return r, False
        v = self.vertices
        dv = np.hypot(v[:, 0] - r[0], v[:, 1] - r[1])
        k = int(np.argmin(dv))
        if dv[k] <= ON_BOUNDARY_REL:
            return v[k].copy(), True
        a, b = v, np.roll(v, -1, axis=0)
        ab = b - a
        t = np.clip(np.einsum("ij,ij->i", r - a, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
        foot = a + t[:, None] * ab
        d = np.hypot(foot[:, 0] - r[0], foot[:, 1] - r[1])
        k = int(np.argmin(d))
        if d[k] <= ON_BOUNDARY_REL:
            return foot[k], True
        return r, False

    def contains(self, r: np.ndarray, on_outline: bool) -> bool:
        """Whether r lies in the closed footprint."""
        if on_outline:
            return True
        if self.is_disk:
            return float(np.hypot(r[0], r[1])) <= 1.0
        a = self.vertices
        b = np.roll(a, -1, axis=0)
        cond = (a[:, 1] > r[1]) != (b[:, 1] > r[1])
        with np.errstate(divide="ignore", invalid="ignore"):
            xint = a[:, 0] + (r[1] - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
        return bool(np.sum(cond & (r[0] < xint)) % 2 == 1)


def outline_of(scene: PushScene, footprint: Footprint | None, tol: SolverTolerances = SOLVER_DEFAULT) -> Outline:
    """The dimensionless outline of ``footprint`` (or of the scene's disk when None).

    A polygon's centre of mass must be the scene's (3.1.5); L is its circumradius (3.1.8).
    """
    e1 = np.asarray(scene.axis, dtype=float)
    frame = np.column_stack([e1, [-e1[1], e1[0]]])
    if footprint is None:
        return Outline(scene.disk_radius, scene.center_of_mass.copy(), frame, None)
    ell = float(footprint.circumradius)
    if np.linalg.norm(footprint.center_of_mass - scene.center_of_mass) > tol.centroid_rel * ell:
        raise InvalidInput(
            "center_of_mass",
            "the footprint's centre of mass differs from the push scene's: "
            f"{footprint.center_of_mass.tolist()} vs {scene.center_of_mass.tolist()}",
        )
    verts = ((footprint.vertices - scene.center_of_mass) @ frame) / ell
    return Outline(ell, scene.center_of_mass.copy(), frame, verts)


# --------------------------------------------------------------------------------------
# The outline as 1-D pieces seen from a fixed r: evaluation and derivative bounds


class _Pieces:
    """Pieces of the outline, each a parameter interval on which rho = |w - r| is monotone
    and (w - r)/|w - r| is smooth (pieces end wherever r projects onto the outline).

    Subclasses give ``geom(piece, t) -> (w, rho, u)`` (u's one-sided limit where rho = 0)
    and ``derivative_bounds(piece, t0, t1, rho0, rho1)`` -> (V, A, R1, R2, U1, U2) with
    |w'| <= V, |w''| <= A, |rho'| <= R1, |rho''| <= R2, |u'| <= U1, |u''| <= U2 on the
    interval.
    """

    piece_lo: np.ndarray
    piece_hi: np.ndarray
    grid_counts: np.ndarray

    def __init__(self, r: np.ndarray, alpha: np.ndarray, s: float):
        self.r = r
        self.alpha = alpha
        self.s = s
        self.r_norm = float(np.hypot(r[0], r[1]))

    def geom(self, piece: np.ndarray, t: np.ndarray):  # pragma: no cover - interface
        raise NotImplementedError

    def derivative_bounds(self, piece, t0, t1, rho0, rho1):  # pragma: no cover - interface
        raise NotImplementedError

    def sagitta(self, piece, length):  # pragma: no cover - interface
        raise NotImplementedError

    # -- shared -----------------------------------------------------------------------

    def grid(self):
        """(piece, t) of the pricing grid, per piece sorted, both ends included."""
        pieces, ts = [], []
        for k, (lo, hi, n) in enumerate(zip(self.piece_lo, self.piece_hi, self.grid_counts)):
            pieces.append(np.full(n, k))
            ts.append(np.linspace(lo, hi, n))
        return np.concatenate(pieces), np.concatenate(ts)

    def columns(self, w, rho, u) -> np.ndarray:
        """G(w) = (1, w, rho alpha - s u) for points with rho > 0, shape (5, k)."""
        g = rho[:, None] * self.alpha[None, :] - self.s * u
        return np.vstack([np.ones(len(w)), w.T, g.T])

    def phi(self, y: np.ndarray, piece, t):
        """(phi, affine part y0 + y_w . w, w, rho, u) at the points."""
        w, rho, u = self.geom(piece, t)
        aff = y[0] + w @ y[1:3]
        val = aff + (y[3:5] @ self.alpha) * rho - self.s * (u @ y[3:5])
        return val, aff, w, rho

    def lower_bounds(self, y, piece, t0, t1, f0, f1, a0, a1, rho0, rho1):
        """Sound lower bound of phi on each interval [t0, t1] of ``piece``.

        The largest of three bounds, minus a rounding allowance:
        * Lipschitz (Piyavskii): (f0 + f1 - K l)/2 with |phi'| <= K;
        * second order: the minimum of the chord minus (M/2) tau (l - tau), |phi''| <= M;
        * zeroth order: min of the affine part, of (y_g . alpha) rho, and -|s||y_g|.
        With phi = y0 + y_w . w + (y_g . alpha) rho - s y_g . u:
        K = |y_w| V + |y_g . alpha| R1 + |s||y_g| U1, M = |y_w| A + |y_g . alpha| R2 +
        |s||y_g| U2.
        """
        yw = float(np.hypot(y[1], y[2]))
        yg = float(np.hypot(y[3], y[4]))
        ya = float(abs(y[3:5] @ self.alpha))
        sy = abs(self.s) * yg
        ell = t1 - t0
        v, acc, r1, r2, u1, u2 = self.derivative_bounds(piece, t0, t1, rho0, rho1)
        k = yw * v + ya * r1 + sy * u1
        m = yw * acc + ya * r2 + sy * u2
        lb_lip = 0.5 * (f0 + f1 - k * ell)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            # minimiser of the chord minus the parabola; with M = 0 the lower chord end
            tau = np.where(m > 0.0, 0.5 * ell - (f1 - f0) / (m * ell), np.where(f1 < f0, ell, 0.0))
        tau = np.clip(np.nan_to_num(tau, nan=0.0), 0.0, ell)
        with np.errstate(invalid="ignore", over="ignore"):
            chord = f0 + (f1 - f0) * np.where(ell > 0.0, tau / np.where(ell > 0.0, ell, 1.0), 0.0)
            lb_2 = np.where(np.isfinite(m), chord - 0.5 * m * tau * (ell - tau), -np.inf)
        yga = float(y[3:5] @ self.alpha)
        lb_0 = (
            np.minimum(a0, a1) - yw * self.sagitta(piece, ell)
            + np.minimum(yga * rho0, yga * rho1) - sy
        )
        lb = np.maximum(np.maximum(np.nan_to_num(lb_lip, nan=-np.inf), lb_2), lb_0)
        rho_max = np.maximum(rho0, rho1)
        w_max = 1.0 + self.r_norm
        allowance = ROUNDING_ALLOWANCE * (abs(y[0]) + yw * w_max + ya * (rho_max + w_max) + sy)
        return lb - allowance


class _DiskOutline(_Pieces):
    """The circle |w| = 1 seen from r, parametrised by phi = theta - theta_r in [0, 2 pi].

    In the frame turned by theta_r (r on the +x axis at distance R):
    w - r = ((1 - R) - 2 sin^2(phi/2), sin phi), rho^2 = (1 - R)^2 + 4 R sin^2(phi/2),
    free of cancellation. Pieces [0, pi] and [pi, 2 pi] (rho increases, then decreases).

    Bounds (|w'| = |w''| = 1): rho' = u . w' so |rho'| <= 1; the direction angle of u turns
    at rate 1/2 + (1 - R^2)/(2 rho^2) (from cross(w - r, w') = (1 - R cos phi) and
    rho^2 = 1 + R^2 - 2R cos phi), so |u'| <= U1 = 1/2 + |1 - R^2|/(2 rho_min^2); its
    derivative is -(1 - R^2) rho'/rho^3, so |u''| <= sqrt((|1 - R^2|/rho_min^3)^2 + U1^4);
    rho'' = rho (angle rate)^2 + u . w'', so |rho''| <= rho_max U1^2 + 1.
    On the circle (R = 1 after snapping) w - r = 2 sin(phi/2) (-sin(phi/2), cos(phi/2)):
    rho = 2 sin(phi/2), u = (-sin(phi/2), cos(phi/2)) exactly, |u'| = 1/2, |u''| = 1/4,
    |rho'| <= 1, |rho''| <= 1/2.
    """

    def __init__(self, r, alpha, s, on_circle: bool):
        super().__init__(r, alpha, s)
        self.on_circle = on_circle
        self.theta_r = math.atan2(r[1], r[0]) if self.r_norm > 0.0 else 0.0
        c, sn = math.cos(self.theta_r), math.sin(self.theta_r)
        self.rot = np.array([[c, -sn], [sn, c]])
        self.R = 1.0 if on_circle else self.r_norm
        self.one_minus_r2 = abs(1.0 - self.R) * (1.0 + self.R)
        self.piece_lo = np.array([0.0, math.pi])
        self.piece_hi = np.array([math.pi, 2.0 * math.pi])
        self.grid_counts = np.array([CIRCLE_SAMPLES // 2 + 1] * 2)

    def geom(self, piece, t):
        t = np.asarray(t, dtype=float)
        half = 0.5 * t
        sh = np.sin(half)
        w_loc = np.stack([np.cos(t), np.sin(t)], axis=-1)
        if self.on_circle:
            rho = 2.0 * np.abs(sh)
            u_loc = np.stack([-sh, np.cos(half)], axis=-1)
        else:
            e = np.stack([(1.0 - self.R) - 2.0 * sh * sh, np.sin(t)], axis=-1)
            rho = np.sqrt((1.0 - self.R) ** 2 + 4.0 * self.R * sh * sh)
            u_loc = e / rho[:, None]
        return w_loc @ self.rot.T, rho, u_loc @ self.rot.T

    def derivative_bounds(self, piece, t0, t1, rho0, rho1):
        n = np.shape(t0)
        ones = np.ones(n)
        if self.on_circle:
            return ones, ones, ones, 0.5 * ones, 0.5 * ones, 0.25 * ones
        rmin = np.minimum(rho0, rho1)
        rmax = np.maximum(rho0, rho1)
        q = self.one_minus_r2
        u1 = 0.5 + q / (2.0 * rmin * rmin)
        u2 = np.sqrt((q / rmin**3) ** 2 + u1**4)
        r2 = rmax * u1 * u1 + 1.0
        return ones, ones, ones, r2, u1, u2

    def sagitta(self, piece, length):
        return 1.0 - np.cos(0.5 * np.minimum(length, math.pi))


class _PolygonOutline(_Pieces):
    """Polygon edges w = A + t d (|d| = 1, t in [0, l]) seen from r, in edge coordinates:
    w - r = tau d + h n with tau = t - tau_f (tau_f the foot of r on the edge's line) and
    h = |foot - r|, so rho = hypot(tau, h) and u = (tau d + h n)/rho without cancellation;
    an edge through r (after snapping) has h = 0 exactly and u = sign(tau) d.
    Edges are split at the foot when it falls inside them, so rho is monotone on a piece.

    Bounds (|w'| = 1, w'' = 0): |rho'| <= 1, rho'' = h^2/rho^3; the angle of u turns at rate
    h/rho^2 and its derivative is bounded by 2h/rho^3, so |u'| <= h/rho_min^2 and
    |u''| <= sqrt(4 h^2/rho^6 + h^4/rho^8) <= sqrt(5) h/rho_min^3. With h = 0 phi is affine.
    """

    def __init__(self, r, alpha, s, vertices: np.ndarray, on_outline: bool):
        super().__init__(r, alpha, s)
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
            through = (h <= 4.0 * np.finfo(float).eps * (1.0 + self.r_norm)) & (tau_f >= -ON_BOUNDARY_REL) & (
                tau_f <= lengths + ON_BOUNDARY_REL
            )
            h = np.where(through, 0.0, h)
            tau_f = np.where(through, np.clip(tau_f, 0.0, lengths), tau_f)
        self.edge_a, self.edge_d, self.edge_n = a, d, n_unit
        self.edge_h, self.edge_tf = h, tau_f
        per_edge = np.clip(np.round(POLYGON_SAMPLES * lengths / lengths.sum()), 4, EDGE_SAMPLES)
        lo, hi, edge, side, counts = [], [], [], [], []
        for k in range(len(a)):
            cuts = [0.0, lengths[k]]
            if 0.0 < tau_f[k] < lengths[k]:
                cuts = [0.0, tau_f[k], lengths[k]]
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

    def geom(self, piece, t):
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

    def derivative_bounds(self, piece, t0, t1, rho0, rho1):
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

    def sagitta(self, piece, length):
        return np.zeros(np.shape(length))


def _pieces_for(outline: Outline, r, alpha, s, on_outline: bool) -> _Pieces:
    if outline.is_disk:
        return _DiskOutline(r, alpha, s, on_outline)
    return _PolygonOutline(r, alpha, s, outline.vertices, on_outline)


# --------------------------------------------------------------------------------------
# Pricing: local refinement and branch and bound


def _golden(pieces: _Pieces, y, piece, lo, hi):
    """Vectorised golden-section minimisation of phi on [lo, hi] of each ``piece``; the
    best of the final bracket's points and its ends is returned as (t, phi)."""
    a, b = np.asarray(lo, dtype=float).copy(), np.asarray(hi, dtype=float).copy()
    for _ in range(GOLDEN_ITERATIONS):
        c = b - _GOLD * (b - a)
        d = a + _GOLD * (b - a)
        f = pieces.phi(y, np.concatenate([piece, piece]), np.concatenate([c, d]))[0]
        left = f[: len(c)] < f[len(c):]
        b = np.where(left, d, b)
        a = np.where(left, a, c)
    n = len(a)
    cand = np.concatenate([lo, hi, a, b, 0.5 * (a + b)])
    fv = pieces.phi(y, np.concatenate([piece] * 5), cand)[0].reshape(5, n)
    best = np.argmin(fv, axis=0)
    return cand.reshape(5, n)[best, np.arange(n)], fv[best, np.arange(n)]


def _local_minima(pieces: _Pieces, y, gp, gt, gf, limit: int):
    """Refine the grid's local minima (per piece) by golden section; returns the ``limit``
    lowest as (piece, t, value)."""
    idx_lo, idx_hi, idx_piece = [], [], []
    start = 0
    for k, n in enumerate(pieces.grid_counts):
        f = gf[start : start + n]
        left = np.concatenate([[np.inf], f[:-1]])
        right = np.concatenate([f[1:], [np.inf]])
        loc = np.nonzero((f <= left) & (f <= right))[0]
        for i in loc:
            idx_lo.append(start + max(i - 1, 0))
            idx_hi.append(start + min(i + 1, n - 1))
            idx_piece.append(k)
        start += n
    if not idx_piece:
        return np.zeros(0, dtype=int), np.zeros(0), np.zeros(0)
    lo = gt[np.array(idx_lo)]
    hi = gt[np.array(idx_hi)]
    piece = np.array(idx_piece)
    # keep the most promising brackets (lowest grid value inside the bracket)
    centre_val = np.minimum(gf[np.array(idx_lo)], gf[np.array(idx_hi)])
    order = np.argsort(centre_val)[: 4 * limit]
    t, f = _golden(pieces, y, piece[order], lo[order], hi[order])
    best = np.argsort(f)[:limit]
    return piece[order][best], t[best], f[best]


@dataclass
class _BnBResult:
    lower_bound: float
    certified: bool  # every interval's bound >= target
    violators: tuple  # (piece, lo, hi) of points found below target
    violator_values: np.ndarray
    intervals: int


def _branch_and_bound(
    pieces: _Pieces, y, gp, gt, gf, target: float, max_intervals: int, deadline: float | None
) -> _BnBResult:
    """Sound lower bound of phi over the outline, or points below ``target``.

    Breadth-first bisection of the grid intervals; an interval is discarded once its lower
    bound reaches ``target`` (its bound enters the certified minimum) and split otherwise.
    Stops at the first level that samples phi below ``target``.
    """
    pieces_idx, t0, t1, f0, f1 = [], [], [], [], []
    start = 0
    for k, n in enumerate(pieces.grid_counts):
        sl = slice(start, start + n)
        pieces_idx.append(np.full(n - 1, k))
        t0.append(gt[sl][:-1])
        t1.append(gt[sl][1:])
        f0.append(gf[sl][:-1])
        f1.append(gf[sl][1:])
        start += n
    piece = np.concatenate(pieces_idx)
    t0 = np.concatenate(t0)
    t1 = np.concatenate(t1)
    _, a0, _, rho0 = pieces.phi(y, piece, t0)
    f0 = np.concatenate(f0)
    _, a1, _, rho1 = pieces.phi(y, piece, t1)
    f1 = np.concatenate(f1)
    certified_min = math.inf
    total = len(piece)
    while True:
        lb = pieces.lower_bounds(y, piece, t0, t1, f0, f1, a0, a1, rho0, rho1)
        small = (t1 - t0) <= MIN_INTERVAL
        done = (lb >= target) | small
        if np.any(done):
            certified_min = min(certified_min, float(np.min(lb[done])))
        keep = ~done
        if not np.any(keep):
            return _BnBResult(certified_min, certified_min >= target, (), np.zeros(0), total)
        piece, t0, t1, f0, f1, a0, a1, rho0, rho1, lb = (
            arr[keep] for arr in (piece, t0, t1, f0, f1, a0, a1, rho0, rho1, lb)
        )
        over = total + len(piece) > max_intervals or (deadline is not None and time.perf_counter() > deadline)
        if over:
            return _BnBResult(min(certified_min, float(np.min(lb))), False, (), np.zeros(0), total)
        tm = 0.5 * (t0 + t1)
        fm, am, _, rhom = pieces.phi(y, piece, tm)
        total += len(piece)
        below = fm < target
        if np.any(below):
            order = np.argsort(fm[below])[:COLUMNS_PER_ROUND]
            return _BnBResult(
                min(certified_min, float(np.min(lb))), False,
                (piece[below][order], t0[below][order], t1[below][order]), fm[below][order], total,
            )
        piece = np.concatenate([piece, piece])
        t0, t1 = np.concatenate([t0, tm]), np.concatenate([tm, t1])
        f0, f1 = np.concatenate([f0, fm]), np.concatenate([fm, f1])
        a0, a1 = np.concatenate([a0, am]), np.concatenate([am, a1])
        rho0, rho1 = np.concatenate([rho0, rhom]), np.concatenate([rhom, rho1])


# --------------------------------------------------------------------------------------
# Restricted master (cvxpy + Clarabel), compiled once per capacity


class _Master:
    """min ||A P + q P0 + S z - b||_1, P >= 0, |z| <= P0; A, q, S are Parameters."""

    def __init__(self, capacity: int):
        self.capacity = capacity
        self.a = cp.Parameter((5, capacity))
        self.q = cp.Parameter(5)
        self.s = cp.Parameter((5, 2))
        self.p = cp.Variable(capacity, nonneg=True)
        self.p0 = cp.Variable()
        self.z = cp.Variable(2)
        self.e = cp.Variable(5)
        self.eq = self.a @ self.p + self.q * self.p0 + self.s @ self.z - self.e == _B
        self.problem = cp.Problem(cp.Minimize(cp.norm1(self.e)), [self.eq, cp.SOC(self.p0, self.z)])
        self.lock = threading.Lock()

    def solve(self, cols: np.ndarray, r: np.ndarray, s: float, on: bool, tol: SolverTolerances):
        n = cols.shape[1]
        a = np.empty((5, self.capacity))
        a[:, :n] = cols
        a[:, n:] = cols[:, :1]  # padding: copies of column 0 (merged back below)
        q = np.zeros(5)
        smat = np.zeros((5, 2))
        if on:
            q[:3] = (1.0, r[0], r[1])
            smat[3, 0] = smat[4, 1] = -s
        with self.lock:
            self.a.value = a
            self.q.value = q
            self.s.value = smat
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", UserWarning)
                    self.problem.solve(
                        solver=cp.CLARABEL,
                        tol_gap_abs=tol.conic_gap,
                        tol_gap_rel=tol.conic_gap,
                        tol_feas=tol.conic_gap,
                    )
            except cp.error.SolverError as exc:
                raise SolverError(f"Clarabel failed on the membership master: {exc}") from exc
            if self.problem.status not in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE) or self.p.value is None:
                raise SolverError(f"membership master ended with status {self.problem.status}")
            p = np.clip(np.asarray(self.p.value, dtype=float), 0.0, None)
            y = np.asarray(self.eq.dual_value, dtype=float).reshape(5)
            p0 = float(self.p0.value) if on else 0.0
            z = np.asarray(self.z.value, dtype=float) if on else np.zeros(2)
        weights = p[:n].copy()
        weights[0] += float(np.sum(p[n:]))
        return weights, p0, z, y


_MASTERS: dict[int, _Master] = {}
_MASTERS_LOCK = threading.Lock()


def _master(n_columns: int) -> _Master:
    cap = BASE_CAPACITY
    while cap < n_columns:
        cap *= 2
    with _MASTERS_LOCK:
        if cap not in _MASTERS:
            _MASTERS[cap] = _Master(cap)
        return _MASTERS[cap]


# --------------------------------------------------------------------------------------
# Witness polish


def _pm_columns(r, s):
    return np.array([[1.0, r[0], r[1], 0.0, 0.0], [0.0, 0.0, 0.0, -s, 0.0], [0.0, 0.0, 0.0, 0.0, -s]]).T


def _residual(cols, weights, pm_cols, pm_x):
    lhs = cols @ weights
    if pm_cols is not None:
        lhs = lhs + pm_cols @ pm_x
    return float(np.sum(np.abs(lhs - _B)))


def _pm_basis(r, s, pm_x, variant: str):
    """The point mass at r as extra columns and coordinates: "free" (P0, z) with |z| <= P0,
    or "cone" (P0 alone, z = P0 zhat fixed on the cone's boundary)."""
    if variant == "free":
        return _pm_columns(r, s), pm_x.copy()
    zn = math.hypot(pm_x[1], pm_x[2])
    zhat = pm_x[1:] / zn if zn > 0.0 else np.array([1.0, 0.0])
    col = np.array([1.0, r[0], r[1], -s * zhat[0], -s * zhat[1]])
    return col[:, None], np.array([pm_x[0]])


def _pm_back(pm_x, coords, variant: str):
    if variant == "free":
        return coords
    zn = math.hypot(pm_x[1], pm_x[2])
    zhat = pm_x[1:] / zn if zn > 0.0 else np.array([1.0, 0.0])
    return np.array([coords[0], coords[0] * zhat[0], coords[0] * zhat[1]])


def _pm_feasible(coords, variant: str) -> bool:
    if variant == "free":
        return coords[0] >= 0.0 and math.hypot(coords[1], coords[2]) <= coords[0]
    return coords[0] >= 0.0


def _polish_once(cols, weights, pm_cols, pm_coords, variant):
    """Least-norm correction on the positive weights (and the point mass) so that the
    membership equations hold to rounding; drops weights that turn negative and retries.
    Returns (weights, pm_coords) or None."""
    active = np.nonzero(weights > 0.0)[0]
    for _ in range(8):
        m = cols[:, active]
        x = weights[active]
        if pm_cols is not None:
            m = np.hstack([m, pm_cols])
            x = np.concatenate([x, pm_coords])
        x_new = x + np.linalg.lstsq(m, _B - m @ x, rcond=None)[0]
        w_new = np.zeros_like(weights)
        w_new[active] = x_new[: active.size]
        pm_new = x_new[active.size:]
        neg = x_new[: active.size] < 0.0
        if not np.any(neg):
            if pm_cols is None or _pm_feasible(pm_new, variant):
                return w_new, pm_new
            return None
        active = active[~neg]
    return None


def _exact_witness(cols, weights, r, s, pm_x, in_f: bool):
    """Turn the master's approximate support into an exact, small one.

    With the point mass held at the master's value, non-negative least squares (Lawson and
    Hanson's active set, which ends on at most 5 linearly independent columns) picks the
    support; a least-norm correction of those weights and of the point mass (free, on its
    cone's boundary, or absent) then makes the membership equations hold to rounding. If
    that fails, the correction is tried on all the master's positive weights. Returns
    (weights, pm_x, residual) of the best result (possibly the input)."""
    pm_full = _pm_columns(r, s) if in_f else None
    best = (weights, pm_x, _residual(cols, weights, pm_full, pm_x))
    variants = ("free", "cone", "none") if in_f else ("none",)
    dense = np.where(weights > 1e-12 * float(np.max(weights, initial=0.0)), weights, 0.0)
    for variant in variants:
        if variant == "none":
            pm_cols, coords = None, np.zeros(0)
            target = _B
        else:
            pm_cols, coords = _pm_basis(r, s, pm_x, variant)
            target = _B - pm_cols @ coords
        basic = nnls(cols, target)[0]
        for start in (basic, dense):
            out = _polish_once(cols, start, pm_cols, coords, variant)
            if out is None:
                continue
            w1, c1 = out
            pm1 = _pm_back(pm_x, c1, variant) if pm_cols is not None else np.zeros(3)
            res1 = _residual(cols, w1, pm_full, pm1)
            if res1 < best[2]:
                best = (w1, pm1, res1)
            if best[2] <= 1e-14:
                return best
    return best


# --------------------------------------------------------------------------------------
# Forward re-verification


def _forward_cor(scene: PushScene, points_world: np.ndarray, weights: np.ndarray, tol: SolverTolerances):
    """COR of a support by the forward minimum-power solver (exact Newton, 3.7); world
    frame, or None for a translation."""
    support = Support.create(points_world, weights, scene.center_of_mass, tol)
    return solve_forward(scene, support, mu_c=0.0, method="newton", tol=tol).cor


# --------------------------------------------------------------------------------------
# The query


def _initial_columns(pieces: _Pieces, outline: Outline, gp, gt, warm_points, min_rho: float):
    """Columns at the pricing grid's distinct points farther than ``min_rho`` from r and at
    up to MAX_WARM_POINTS caller-supplied points (world frame, on the outline)."""
    w_all, rho_all, u_all = pieces.geom(gp, gt)
    usable = rho_all > min_rho
    pts = w_all[usable]
    cols = pieces.columns(pts, rho_all[usable], u_all[usable])
    _, uniq = np.unique(np.round(pts, 14), axis=0, return_index=True)
    uniq = np.sort(uniq)
    pts, cols = pts[uniq], cols[:, uniq]
    if warm_points is not None:
        wp = outline.to_local(np.asarray(warm_points, dtype=float).reshape(-1, 2)[:MAX_WARM_POINTS])
        e = wp - pieces.r
        rho = np.hypot(e[:, 0], e[:, 1])
        ok = rho > max(min_rho, ON_BOUNDARY_REL)
        if np.any(ok):
            pts = np.vstack([pts, wp[ok]])
            cols = np.hstack([cols, pieces.columns(wp[ok], rho[ok], e[ok] / rho[ok][:, None])])
    return pts, cols


def membership(
    scene: PushScene,
    r_world,
    footprint: Footprint | None = None,
    tol: SolverTolerances = SOLVER_DEFAULT,
    time_limit_s: float | None = None,
    warm_points=None,
    verify_witness: bool = True,
    certify: bool = True,
) -> MembershipResult:
    """Is ``r_world`` the COR of some pressure distribution on the footprint? (see module)

    ``footprint``: a polygon whose centre of mass is the scene's, or None for the scene's
    disk. ``warm_points`` (k, 2) world: extra initial support points on the footprint's
    outline (e.g. the previous query's witness). ``verify_witness``: re-solve the forward
    problem for an inside witness. ``certify=False`` skips the branch and bound: an
    "outside" answer is then based on the grid only (``lower_bound_method`` "grid",
    ``certificate_kind`` "none") and is no certificate.
    """
    t_start = time.perf_counter()
    deadline = None if time_limit_s is None else t_start + float(time_limit_s)
    outline = outline_of(scene, footprint, tol)
    ell = outline.length
    r_in = np.asarray(r_world, dtype=float)
    if r_in.shape != (2,) or not np.all(np.isfinite(r_in)):
        raise InvalidInput("cor", "must be a finite point [x, y]")
    r, on_outline = outline.snap(outline.to_local(r_in))
    in_f = outline.contains(r, on_outline)
    alpha = outline.vector_to_local(scene.alpha_hat)
    c = outline.vector_to_local(scene.contact_rel) / ell
    s = float(alpha @ (c - r))
    pieces = _pieces_for(outline, r, alpha, s, on_outline)
    gp, gt = pieces.grid()
    # With r in F, support points within POINT_MASS_RADIUS of r are left to the point mass
    # (their columns are within that distance of point-mass elements).
    min_rho = POINT_MASS_RADIUS if in_f else 0.0
    pts, cols = _initial_columns(pieces, outline, gp, gt, warm_points, min_rho)

    pm_cols = _pm_columns(r, s) if in_f else None
    status, kind, message = "undecided", "none", ""
    weights = np.zeros(cols.shape[1])
    pm_x = np.zeros(3)
    residual = math.inf
    y = None
    lower = margin = None
    method = None
    bnb_total = 0
    iterations = 0
    forward_err = None
    for iterations in range(1, tol.max_cg_iter + 1):
        if deadline is not None and time.perf_counter() > deadline:
            message = f"time limit {time_limit_s} s reached"
            iterations -= 1
            break
        master = _master(cols.shape[1])
        weights, p0, z, y_raw = master.solve(cols, r, s, in_f, tol)
        if in_f:
            zn = math.hypot(z[0], z[1])
            p0 = max(p0, 0.0)
            if zn > p0:
                z = z * (p0 / zn) if zn > 0.0 else z
            pm_x = np.array([p0, z[0], z[1]])
        residual = _residual(cols, weights, pm_cols, pm_x)
        if residual <= max(POLISH_BELOW, tol.membership_residual):
            weights, pm_x, residual = _exact_witness(cols, weights, r, s, pm_x, in_f)
            if residual <= tol.membership_residual:
                status, kind = "inside", "witness"
                message = "witness support satisfies (3.8) with the centroid at the CM"
                break
        y = y_raw / max(1.0, float(np.max(np.abs(y_raw))))
        yb = float(y[0])
        pm_val = float(y[0] + y[1:3] @ r - abs(s) * math.hypot(y[3], y[4])) if in_f else math.inf
        gf = pieces.phi(y, gp, gt)[0]
        lp, lt, lf = _local_minima(pieces, y, gp, gt, gf, COLUMNS_PER_ROUND)
        t_cert = yb + tol.certificate_margin
        improving = lf < -tol.pricing_tol
        if not certify:
            lower = float(min(np.min(gf), np.min(lf, initial=math.inf), pm_val))
            margin = lower - yb
            method = "grid"
            if margin > tol.certificate_margin:
                # y separates b from every grid column: outside as far as the grid sees
                # (the certify branch stops on the same margin, bounded soundly).
                status = "outside"
                message = "grid pricing separates the candidate (not a certificate)"
                break
            if not np.any(improving):
                message = "restricted master optimal on the grid; residual too small to decide"
                break
            new_p, new_t = lp[improving], lt[improving]
        else:
            new_p = new_t = None
            if not np.any(lf < t_cert) and pm_val >= t_cert:
                target = t_cert if t_cert < -tol.pricing_tol else -tol.pricing_tol
                bnb = _branch_and_bound(pieces, y, gp, gt, gf, target, tol.max_bnb_intervals, deadline)
                bnb_total += bnb.intervals
                lower = min(bnb.lower_bound, pm_val)
                margin = lower - yb
                method = "branch_and_bound"
                if bnb.certified and margin > tol.certificate_margin:
                    status, kind = "outside", "dual"
                    message = "certified dual: y . G >= lower bound on the whole footprint"
                    break
                if bnb.certified:
                    message = (
                        f"column generation converged (pricing >= -{tol.pricing_tol:g}) with residual "
                        f"{residual:.3g} between the inside and outside thresholds"
                    )
                    break
                if len(bnb.violators) == 0:
                    message = "branch and bound hit its interval or time limit"
                    break
                vp, vlo, vhi = bnb.violators
                half = vhi - vlo
                lo = np.maximum(vlo - half, pieces.piece_lo[vp])
                hi = np.minimum(vhi + half, pieces.piece_hi[vp])
                vt, _ = _golden(pieces, y, vp, lo, hi)
                new_p = np.concatenate([lp[improving], vp])
                new_t = np.concatenate([lt[improving], vt])
            else:
                new_p, new_t = lp[improving], lt[improving]
            if new_p.size == 0:
                message = "no improving column found"
                break
        nw, nrho, nu = pieces.geom(new_p, new_t)
        ok = nrho > min_rho
        if not np.any(ok):
            message = "pricing points coincide with the candidate"
            break
        cols = np.hstack([cols, pieces.columns(nw[ok], nrho[ok], nu[ok])])
        pts = np.vstack([pts, nw[ok]])
        weights = np.concatenate([weights, np.zeros(int(np.sum(ok)))])
    else:
        message = message or f"no decision after {tol.max_cg_iter} column-generation rounds"

    if status == "inside":
        sel = weights > 0.0
    else:
        sel = weights > REPORT_WEIGHT_REL * float(np.max(weights, initial=0.0))
    wit_pts = outline.to_world(pts[sel])
    wit_w = weights[sel]
    p_mass = float(pm_x[0]) if in_f else 0.0
    cor_world = outline.to_world(r)
    if status == "inside" and verify_witness:
        supp = wit_pts
        sw = wit_w
        if p_mass > 0.0:
            supp = np.vstack([supp, cor_world])
            sw = np.concatenate([sw, [p_mass]])
        fwd = _forward_cor(scene, supp, sw, tol)
        forward_err = None if fwd is None else float(np.linalg.norm(fwd - cor_world) / ell)
    if status == "inside":
        y = lower = margin = method = None
    return MembershipResult(
        status=status,
        cor=cor_world,
        certificate_kind=kind,
        witness_points=wit_pts,
        witness_weights=wit_w,
        point_mass_at_cor=p_mass,
        point_mass_subgradient=outline.frame @ pm_x[1:3] if in_f else np.zeros(2),
        witness_residual=float(residual),
        witness_forward_cor_error=forward_err,
        dual=None if y is None else outline.dual_to_world(y),
        dual_lower_bound=lower,
        dual_margin=margin,
        lower_bound_method=method,
        iterations=iterations,
        n_columns=int(cols.shape[1]),
        bnb_intervals=bnb_total,
        in_footprint=in_f,
        length_scale=ell,
        message=message,
        solve_time_s=time.perf_counter() - t_start,
    )
