"""The exact sticking locus of a push with pusher friction mu_c (book 4.1.4, 3.3.11.1).

The *sticking line* (4.1.2.1) is the line through the contact point c perpendicular to the
push direction p. A COR r on it moves the contact point along p, so pusher and part stick.
The *sticking locus* is the set of such r that are the COR of some pressure distribution on
the footprint with a contact force F inside the friction cone |F . t| <= mu_c F . n
(n = ``scene.normal``, t = ``scene.alpha_hat``). The book writes it as the union over
force angles phi in [-nu, nu] (nu = atan mu_c, 4.1) of the frictionless loci {COR}_phi
intersected with the line, approximates its lower end by the tip line (3.3.11.1) and has
no method for its upper end. Here both ends are computed exactly.

Positions on the line are s = (r - c) . J p (world units): the book's "up" for a push drawn
along +x. The rotation per unit push is omega = 1/s (CCW positive), so s > 0 turns the part
counter-clockwise and s < 0 clockwise; s = 0 (r = c) admits no push.

The feasibility problem
-----------------------
A twist x = (v, omega) sticks when v + omega J c = p, two rows A_c x = p with A_c^T F =
(F, (J c) . F) (:mod:`models.mpp`). Stationarity of the power f = sum_i P_i |v(w_i)| is
grad f = A_c^T F. For r on the sticking line with sigma = sign(s) (so that
v(c) = omega J (c - r) = omega s p is a positive multiple of p), the unit velocities are
sigma J d_i with d_i = (w_i - r)/|w_i - r|, and the conditions are, for weights P_i >= 0
with sum 1 and centroid at the CM (3.1.5):

  (i)   F = sigma J D,  D = sum_i P_i d_i;
  (ii)  sum_i P_i (w_i - c) . d_i = 0 (the table's friction forces have no moment about the
        contact point: the pusher's force acts there);
  (iii) F in the friction cone: e_+ . F >= 0 and e_- . F >= 0 with
        e_+- = sin(nu) n +- cos(nu) t (unit inward normals of the cone's edges; mu_c = 0
        gives F . t = 0, mu_c = inf gives F . n >= 0).

A point mass P0 at r (allowed when r lies in the footprint) contributes a subgradient z,
|z| <= P0: z to D and (r - c) . z to (ii), a second-order cone. With D in (i), (iii) reads
k_+- . D >= 0 with k = -sigma J e. So, with the columns

    G(w) = (1, w/L, (w - c) . d / L)  in R^4,     H(w) = (k_+ . d, k_- . d)  in R^2,

r is a sticking COR iff sum_j P_j G(w_j) + pm_G = (1, 0, 0, 0) and sum_j P_j H(w_j) + pm_H >= 0
for some P >= 0 on the footprint and point mass (P0, z). Conversely such a support has r as
its sticking COR: the conditions are the KKT conditions of the convex minimum-power problem
with the sticking rows (ch. 2), and its contact force is F.

Relation to the book: with F at angle phi from n, (i)-(ii) say that r is the frictionless
COR of the same support for the edge turned by phi (the KKT conditions of that problem with
multiplier |F|), and v(c) = p satisfies its contact row. So the sticking locus is exactly
the union over |phi| <= nu of {COR}_phi intersected with the sticking line (4.1.4), which
the tests check by a brute-force sweep of phi over the analytic disk loci.

Boundary reduction (as in :mod:`solver.membership`)
---------------------------------------------------
On a ray w = r + rho u (rho > 0) d = u is constant, (w - c) . d = rho + (r - c) . u and
H = (k . u) are affine in rho, so for any (y, lambda) the dual functional

    phi(w) = y . G(w) - lambda . H(w) = y0 + y_w . w + y_m rho + q . u,
    q = y_m (r - c) - lambda_+ k_+ - lambda_- k_-                            (*)

is affine along the ray. Its minimum over the footprint is on the outline or at rho -> 0,
the point-mass value y0 + y_w . r - |q| (when r is in the footprint); and every column of
an interior point is a convex combination of the columns of its ray segment's ends. Hence
supports on the outline plus a point mass at r suffice, and pricing and the dual bound are
1-D problems over the outline. (*) has the form of membership's functional (y_g . alpha ->
y_m, -s y_g -> q), so the same kind of Lipschitz and second-order bounds apply; they are
re-implemented here in a second form that stays tight for a far r (:meth:`_Query.lower_bounds`).

Certificates (Farkas): if lambda >= 0 and phi >= m on the whole footprint and point-mass
set, then for any feasible support y . b = y0 = int phi dP + lambda . int H dP >= m; so
m > y0 proves r outside. The L1-residual restricted master

    min ||e||_1 + t_+ + t_-,  sum P G + pm_G - e = b,  sum P H + pm_H + t >= 0,  t >= 0,

(cvxpy + Clarabel, compiled once per column capacity with Parameters; on rows conditioned
for far candidates by an equivalent row operation and scaling, see :class:`_Query`) has
duals with y . G_j - lambda . H_j >= 0 on its columns and y . b = -(its optimum); reported
duals are converted back to the columns above. Column generation over
the outline (grid + golden-section refinement) ends with a polished witness (inside), a
dual whose branch-and-bound bound over the outline separates (outside, certified), or, with
``certify=False``, grid pricing only: an "outside" then has ``certificate_kind`` "none" and
``lower_bound_method`` "grid" and is no certificate.

Findings (tests/solver/test_sticking.py, docs/benchmarks.md)
-----------------------------------------------------------
* The book's 6.3 experiment (disk, fence at 70 degrees, mu_c = 0.5, contact on the rim so
  the fence normal passes through the CM): the tip line meets the sticking line at
  y = -5.506 a (the book: -5.51 a); the exact sticking locus is y in [-5.528 a, -2.481 a].
* Each {COR}_phi dips below the tip line (4.1.4): the exact lower end lies 0.02 a beyond
  the tip-line estimate in the book's sketch types g/h. For a narrow cone (no tip reaches
  the sticking line, the unstated assumption of 4.1.4) the end is far above it (+2.85 a
  at mu_c = 0.05 for a near-translation push); for polygons the circumscribing disk's tip
  line is a poor estimate (+0.9 a for a square, +1.2 a for an L shape).
* The locus can be far away (|s| ~ 65-185 L when the cone nearly holds a line of force
  through the CM), and it can be two intervals for a non-convex footprint (a U shape).
* A pure translation along p sticks when the line through c along p passes through the CM
  and p is in the cone; the finite locus may then be empty (``translation_sticks``).
* At a COR on a support point (a point mass at r) the forward solver's mode test can
  reject sticking although a contact force in the cone exists (it tests one element of the
  set of multipliers); witnesses are then re-verified by a direct minimisation of the power
  over sticking twists.

Everything is computed in a dimensionless frame: origin at the CM, x along p, y along J p
(the book's drawing, sticking line vertical), lengths / L (disk radius or the polygon's
circumradius), so results are invariant under similarities of the scene; a mirror image
maps s to -s.
"""

from __future__ import annotations

import dataclasses
import math
import threading
import time
import warnings
from dataclasses import dataclass

import cvxpy as cp
import numpy as np
from scipy.optimize import nnls

from models.cor_disk import disk_cor_locus
from models.errors import InvalidInput
from models.footprint import Footprint
from models.mpp import perp
from models.scene import PushScene
from models.support import Support, random_balanced_tripods, uniform_disk_support, uniform_polygon_support
from models.tolerances import SOLVER_DEFAULT, SolverTolerances
from solver.errors import SolverError
from solver.forward import solve_forward, solve_forward_batch

# The footprint frame and the snapping distance are membership's; the outline pieces are
# re-implemented below with derivative bounds that stay tight for a far candidate.
from solver.membership import (  # the column-generation knobs and point-mass helpers are shared
    BASE_CAPACITY,
    CIRCLE_SAMPLES,
    COLUMNS_PER_ROUND,
    EDGE_SAMPLES,
    GOLDEN_ITERATIONS,
    MAX_WARM_POINTS,
    MIN_INTERVAL,
    ON_BOUNDARY_REL,
    POINT_MASS_RADIUS,
    POLISH_BELOW,
    POLYGON_SAMPLES,
    REPORT_WEIGHT_REL,
    ROUNDING_ALLOWANCE,
    Outline,
    _GOLD,
    _pm_back,
    _pm_feasible,
)

ON_LINE_REL = 1e-9
"""A query point farther than this (/ L) from the sticking line is refused; closer ones are
projected onto it."""

STRICT_WITNESS_RESIDUAL = 1e-12
"""Largest witness residual of an inside end of a locus bracket."""

SCAN_POINTS = 96
"""Uncertified probes of the locus scan (asinh-spaced about the CM's foot on the line)."""

SEED_TRIPODS = 256
"""Random balanced tripods (3.3.3) whose sticking-mode forward CORs seed the scan."""

SEARCH_LIMIT = 1e4
"""|s| / L searched when no bound applies (the contact, the CM and p are collinear and the
friction cone holds a line of force through the CM: the locus may be unbounded)."""

RANGE_MARGIN = 1e-6
"""Relative margin added outside the sound search range for the outermost probes."""

MAX_BRACKET_ROUNDS = 200
"""Cap on probes spent narrowing one end of an interval."""

MAX_WIDENINGS = 12
"""Times an end whose outside point cannot be certified is widened (the bracket doubled)
and re-certified. Far from the footprint (|s| >> L) a move of delta changes the geometry
by about delta/|s| only, so the dual margin of a point delta beyond the end shrinks like
delta L/|s|; the bracket then ends wider than the target ("wide")."""

WARM_PER_RESULT = 16
"""Support points (heaviest first) passed on from a previous query as warm columns."""

# --------------------------------------------------------------------------------------
# Results


@dataclass(frozen=True)
class StickingResult:
    """Answer to "can ``cor`` on the sticking line be the COR of a sticking push?".

    * ``status``: "inside" | "outside" | "undecided".
    * ``cor`` (world): the point decided; ``position`` s = (cor - contact) . J p (world
      length); ``omega`` = 1/s the rotation per unit push (CCW positive), ``sense``.
      Within ``ON_BOUNDARY_REL`` L of the footprint's outline the point is moved onto it.
    * ``certificate_kind``: "witness" (inside), "dual" (outside, sound), "contact" (r is
      the contact point: v(c) = 0 cannot follow the pusher), or "none".
    * ``witness_points`` (k, 2) world, ``witness_weights`` (k,), ``point_mass_at_cor`` P0
      and ``point_mass_subgradient`` z (world, |z| <= P0): a support with centroid at the
      CM whose sticking COR is ``cor`` (for non-inside results: the last master's support).
    * ``contact_force`` F (world, per mu_s times the weight, as
      :attr:`solver.forward.ForwardResult.contact_force`), ``force_angle`` its angle from n
      (CCW positive, within +-``friction_angle`` for a witness; NaN when F = 0, which
      happens only at the CM with all weight there), ``cone_slack`` min(e_+- . F) / |F|.
    * ``witness_residual``: L1 residual of the equalities plus the cone rows' violation
      (dimensionless); for "outside" the master's optimum.
    * Forward re-verification of a witness (:func:`solver.forward.solve_forward`, Newton),
      None when not done: ``witness_forward_mode`` and ``witness_forward_slip`` (world
      length along alpha_hat per unit push) of the solve with ``mu_c``;
      ``witness_forward_cor_error`` = |COR - cor| / L of the minimum-power *sticking*
      motion of the witness: from that solve when its mode is "sticking" (``witness_check``
      "forward"), else from a direct 1-D minimisation of the power over the sticking twists
      ("power_1d"). The mode differs from "sticking" when a point mass sits at r: the COR
      is then on a support point, the contact force is a set, and the forward solver tests
      one element of it (ours is in the cone); its slipping answer then has zero slip (the
      same motion), is flagged inconsistent, or is a second consistent motion (4.1 does not
      make the mode unique there). It also happens with F on the cone's edge.
    * ``dual``: (y0, y_w (2), y_m, lambda_+, lambda_-) on the world-aligned CM-frame
      columns G, H of the module docstring (lengths / L); ``dual_lower_bound`` m of
      phi = y . G - lambda . H over the footprint and point-mass set, ``dual_margin`` =
      m - y0 > 0 proves ``cor`` outside when ``lower_bound_method`` is
      "branch_and_bound"; "grid" (``certify=False``) is NOT a certificate.
    """

    status: str
    cor: np.ndarray
    position: float
    omega: float
    sense: str
    mu_c: float
    friction_angle: float
    certificate_kind: str
    witness_points: np.ndarray
    witness_weights: np.ndarray
    point_mass_at_cor: float
    point_mass_subgradient: np.ndarray
    contact_force: np.ndarray
    force_angle: float
    cone_slack: float
    witness_residual: float
    witness_forward_cor_error: float | None
    witness_forward_mode: str | None
    witness_forward_slip: float | None
    witness_check: str | None
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
# Geometry in the dimensionless push frame


@dataclass(frozen=True)
class _Geometry:
    """The footprint and push in the frame x = p, y = J p, origin at the CM, lengths / L.

    ``cone`` rows are the unit inward normals e_+, e_- of the friction cone's edges."""

    scene: PushScene
    outline: Outline
    c: np.ndarray
    n: np.ndarray
    t: np.ndarray
    cone: np.ndarray
    mu_c: float
    nu: float
    reach: float  # max |w - c| over the footprint, / L

    @property
    def length(self) -> float:
        return self.outline.length

    def point(self, s: float) -> np.ndarray:
        """The local point at position s (/ L) on the sticking line."""
        return np.array([self.c[0], self.c[1] + s])


def _check_mu(mu_c) -> float:
    mu = float(mu_c)
    if math.isnan(mu) or mu < 0.0:
        raise InvalidInput("mu_c", "must be a number >= 0 (math.inf: no limit on friction)")
    return mu


def _geometry(scene: PushScene, footprint: Footprint | None, mu_c: float, tol: SolverTolerances) -> _Geometry:
    p = np.asarray(scene.push_hat, dtype=float)
    frame = np.column_stack([p, perp(p)])
    cm = np.asarray(scene.center_of_mass, dtype=float)
    if footprint is None:
        outline = Outline(scene.disk_radius, cm.copy(), frame, None)
    else:
        ell = float(footprint.circumradius)
        if np.linalg.norm(footprint.center_of_mass - cm) > tol.centroid_rel * ell:
            raise InvalidInput(
                "center_of_mass",
                "the footprint's centre of mass differs from the push scene's: "
                f"{footprint.center_of_mass.tolist()} vs {cm.tolist()}",
            )
        outline = Outline(ell, cm.copy(), frame, ((footprint.vertices - cm) @ frame) / ell)
    c = outline.vector_to_local(scene.contact_rel) / outline.length
    n = outline.vector_to_local(scene.normal)
    t = outline.vector_to_local(scene.alpha_hat)
    nu = math.atan(mu_c)  # atan(inf) = pi/2
    sn, cs = math.sin(nu), (0.0 if math.isinf(mu_c) else math.cos(nu))
    cone = np.array([sn * n + cs * t, sn * n - cs * t])
    if outline.is_disk:
        reach = float(np.hypot(c[0], c[1])) + 1.0
    else:
        reach = float(np.max(np.hypot(outline.vertices[:, 0] - c[0], outline.vertices[:, 1] - c[1])))
    return _Geometry(scene, outline, c, n, t, cone, mu_c, nu, reach)


def _snap_on_line(geo: _Geometry, r: np.ndarray) -> tuple[np.ndarray, bool]:
    """(r, on_outline): r (on the sticking line) moved onto the outline when it is within
    ON_BOUNDARY_REL of it, along the line where the line crosses the outline there (so the
    point stays on the line), else to the nearest outline point (a vertex, or a point where
    the line grazes the outline)."""
    outline = geo.outline
    if outline.is_disk:
        rad = float(np.hypot(r[0], r[1]))
        if abs(rad - 1.0) > ON_BOUNDARY_REL:
            return r, False
        x = r[0]
        if abs(x) < 1.0:
            h = math.sqrt((1.0 - x) * (1.0 + x))
            y = math.copysign(h, r[1])
            if abs(y - r[1]) <= 2.0 * ON_BOUNDARY_REL:
                return np.array([x, y]), True
        return r / rad, True
    v = outline.vertices
    dv = np.hypot(v[:, 0] - r[0], v[:, 1] - r[1])
    k = int(np.argmin(dv))
    if dv[k] <= ON_BOUNDARY_REL:
        return v[k].copy(), True
    a, b = v, np.roll(v, -1, axis=0)
    ab = b - a
    # crossings of the vertical line x = r[0] with the edges
    with np.errstate(divide="ignore", invalid="ignore"):
        lam = (r[0] - a[:, 0]) / ab[:, 0]
    ok = np.isfinite(lam) & (lam >= 0.0) & (lam <= 1.0)
    if np.any(ok):
        ys = a[ok, 1] + lam[ok] * ab[ok, 1]
        j = int(np.argmin(np.abs(ys - r[1])))
        if abs(ys[j] - r[1]) <= 2.0 * ON_BOUNDARY_REL:
            idx = np.nonzero(ok)[0][j]
            return a[idx] + lam[idx] * ab[idx], True
    snapped, on = outline.snap(r)
    return snapped, on


class _DiskPieces:
    """The unit circle seen from r, parametrised by phi = theta - theta_r in [0, 2 pi]
    (membership's parametrisation): in the frame turned by theta_r (r on the +x axis at
    distance R), w - r = ((1 - R) - 2 sin^2(phi/2), sin phi), rho^2 = (1 - R)^2 +
    4 R sin^2(phi/2) without cancellation; pieces [0, pi] and [pi, 2 pi] (rho monotone).

    Derivative bounds (|w'| = |w''| = 1): the direction u turns at the rate
    g(rho) = 1/2 + (1 - R^2)/(2 rho^2) (from cross(w - r, w') = (1 - R^2 + rho^2)/2), which is
    monotone in rho, so |u'| <= max(|g(rho0)|, |g(rho1)|) on an interval (this stays of
    order 1/R for a far r, where the bound 1/2 + |1 - R^2|/(2 rho_min^2) would be 1);
    g' = -(1 - R^2) rho'/rho^3 with |rho'| <= 1, so |u''| <= sqrt((|1 - R^2|/rho_min^3)^2 +
    |u'|^4); rho'' = rho g^2 + u . w'', so |rho''| <= rho_max |u'|^2 + 1. On the circle
    (after snapping) rho = 2 sin(phi/2) and u = (-sin(phi/2), cos(phi/2)) exactly.
    """

    def __init__(self, r: np.ndarray, on_circle: bool):
        self.r = r
        self.on_circle = on_circle
        r_norm = float(np.hypot(r[0], r[1]))
        self.theta_r = math.atan2(r[1], r[0]) if r_norm > 0.0 else 0.0
        c, sn = math.cos(self.theta_r), math.sin(self.theta_r)
        self.rot = np.array([[c, -sn], [sn, c]])
        self.big_r = 1.0 if on_circle else r_norm
        self.one_minus_r2 = (1.0 - self.big_r) * (1.0 + self.big_r)
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
            e = np.stack([(1.0 - self.big_r) - 2.0 * sh * sh, np.sin(t)], axis=-1)
            rho = np.sqrt((1.0 - self.big_r) ** 2 + 4.0 * self.big_r * sh * sh)
            u_loc = e / rho[:, None]
        return w_loc @ self.rot.T, rho, u_loc @ self.rot.T

    def derivative_bounds(self, piece, t0, t1, rho0, rho1):
        """(V, A, R1, R2, U1, U2): bounds of |w'|, |w''|, |rho'|, |rho''|, |u'|, |u''|."""
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

    def sagitta(self, piece, length):
        return 1.0 - np.cos(0.5 * np.minimum(length, math.pi))

    def grid(self):
        return _grid(self)


class _PolygonPieces:
    """Polygon edges w = A + t d (|d| = 1) seen from r, in edge coordinates (membership's
    parametrisation): w - r = tau d + h n with tau = t - tau_f, rho = hypot(tau, h); edges
    are split at the foot of r. Bounds: |w'| = 1, w'' = 0, |rho'| <= 1,
    rho'' = h^2/rho^3, |u'| = h/rho^2, |u''| <= sqrt(5) h/rho^3 (rho_min on the interval)."""

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

    def grid(self):
        return _grid(self)


def _grid(pieces):
    """(piece, t) of the pricing grid, per piece sorted, both ends included."""
    ps, ts = [], []
    for k, (lo, hi, n) in enumerate(zip(pieces.piece_lo, pieces.piece_hi, pieces.grid_counts)):
        ps.append(np.full(n, k))
        ts.append(np.linspace(lo, hi, n))
    return np.concatenate(ps), np.concatenate(ts)


class _Query:
    """One candidate r (local, on the sticking line) with its columns and dual functional.

    Conditioning for a far r. Writing d = d0 + Delta with d0 = (c - r)/|c - r| (the
    direction from r to the contact), the moment row (ii) is replaced by the equivalent row
    kappa (w - c) . Delta with right-hand side kappa c . d0 (row (ii) minus the combination
    -c . d0 (weight row) + d0 . (centroid rows)), and the cone rows are scaled by kappa,
    kappa = max(1, |s|/D) with D = max |w - c| over the footprint. A far r makes every
    (w - c) . Delta of order D^2/|s|; the rows are then O(1) and the master's duals and
    margins keep their meaning. (A row operation: feasibility is unchanged.) Delta is
    computed without cancellation from a = w - r, b = c - r:
    Delta = ((w - c)|b| - b ((w - c) . (a + b))/(|a| + |b|)) / (|a||b|).
    """

    def __init__(self, geo: _Geometry, r: np.ndarray, on_outline: bool, in_f: bool):
        self.geo = geo
        self.r = r
        self.c = geo.c
        self.rc = r - geo.c
        self.s = float(self.rc[1])
        self.abs_s = abs(self.s)
        self.sigma = 1.0 if self.s > 0.0 else -1.0
        self.d0 = np.array([0.0, -self.sigma])
        self.kappa = max(1.0, self.abs_s / geo.reach)
        self.k = -self.sigma * perp(geo.cone)  # rows k_+, k_- (unscaled)
        self.kk = self.kappa * self.k
        self.b = np.array([1.0, 0.0, 0.0, self.kappa * float(self.c @ self.d0)])
        self.in_f = in_f
        if geo.outline.is_disk:
            self.pieces = _DiskPieces(r, on_outline)
        else:
            self.pieces = _PolygonPieces(r, geo.outline.vertices, on_outline)
        self.r_norm = float(np.hypot(r[0], r[1]))
        # (a candidate snapped off the line, rc[0] != 0, keeps the plain form u - d0)
        self.far = self.abs_s > 2.0 * geo.reach and self.rc[0] == 0.0

    def delta(self, w, u, rho):
        """d - d0 for points w with d = u = (w - r)/rho."""
        if not self.far:
            return u - self.d0
        wc = w - self.c
        a_plus_b = (w - self.r) + (self.c - self.r)
        bvec = self.c - self.r
        proj = np.einsum("ij,ij->i", wc, a_plus_b) / (rho + self.abs_s)
        return (wc * self.abs_s - proj[:, None] * bvec[None, :]) / (rho * self.abs_s)[:, None]

    def columns(self, w, u, rho):
        """G (4, k) and H (2, k) of points w (unit directions u, distances rho > 0)."""
        m = self.kappa * np.einsum("ij,ij->i", w - self.c, self.delta(w, u, rho))
        g = np.vstack([np.ones(len(w)), w.T, m])
        h = self.kk @ u.T
        return g, h

    def pm_columns(self):
        """The point mass as columns on (P0, z0, z1): G part (4, 3) and H part (2, 3)."""
        ka = self.kappa
        pg = np.array(
            [
                [1.0, 0.0, 0.0],
                [self.r[0], 0.0, 0.0],
                [self.r[1], 0.0, 0.0],
                [ka * self.abs_s, ka * self.rc[0], ka * self.rc[1]],
            ]
        )
        ph = np.hstack([np.zeros((2, 1)), self.kk])
        return pg, ph

    # the dual functional phi = y . G - lambda . H -------------------------------------

    def evaluate(self, y, lam, piece, t):
        """(phi, ext) at outline points; ext columns: w_x, w_y, rho, |Delta|."""
        w, rho, u = self.pieces.geom(piece, t)
        dl = self.delta(w, u, rho)
        qv = lam @ self.kk
        val = y[0] + w @ y[1:3] + (y[3] * self.kappa) * np.einsum("ij,ij->i", w - self.c, dl) - u @ qv
        return val, np.column_stack([w, rho, np.hypot(dl[:, 0], dl[:, 1])])

    def phi(self, y, lam, piece, t):
        return self.evaluate(y, lam, piece, t)[0]

    def yb(self, y) -> float:
        return float(y @ self.b)

    def pm_value(self, y, lam) -> float:
        """min of phi over the point-mass set (1, r, kappa((r - c) . zeta + |s|), kappa k . zeta),
        |zeta| <= 1; +inf when r is outside the footprint."""
        if not self.in_f:
            return math.inf
        beta = y[3] * self.kappa
        q = beta * self.rc - lam @ self.kk
        return float(y[0] + y[1:3] @ self.r + beta * self.abs_s - math.hypot(q[0], q[1]))

    def original_dual(self, y, lam):
        """(y, lambda) on the unscaled columns (1, w, (w - c) . d) and (k . d): the same
        functional phi and the same y . b."""
        ka = self.kappa
        y0 = y[0] + y[3] * ka * float(self.c @ self.d0)
        yw = y[1:3] - y[3] * ka * self.d0
        return np.concatenate([[y0], yw, [y[3] * ka]]), ka * np.asarray(lam, dtype=float)

    def lower_bounds(self, y, lam, piece, t0, t1, f0, f1, e0, e1):
        """Sound lower bound of phi on each interval [t0, t1] of ``piece``: the largest of
        Lipschitz, second-order and zeroth-order bounds in two forms of phi, less a
        rounding allowance.

        Near form (*) of the module docstring: phi = a_o + b_o . w + beta rho + q_o . u with
        beta = kappa y_m, b_o = y_w - beta d0, q_o = beta (r - c) - kappa lambda . k.
        Far form: phi = a_n + y_w . w + (beta (w - c) - Q) . Delta with Q = kappa lambda . k,
        whose coefficients stay O(1) for a far r: with |Delta'| = |u'| <= U1,
        |Delta''| <= U2, |w - c| <= W and |Delta| <= Dm on the interval,
        |phi'| <= |y_w| V + |beta| V Dm + (|beta| W + |Q|) U1,
        |phi''| <= |y_w| A + |beta| A Dm + 2 |beta| V U1 + (|beta| W + |Q|) U2,
        phi >= min(a_n + y_w . w at the ends) - |y_w| sagitta - (|beta| W + |Q|) Dm.
        """
        w0, w1 = e0[:, :2], e1[:, :2]
        rho0, rho1 = e0[:, 2], e1[:, 2]
        dn0, dn1 = e0[:, 3], e1[:, 3]
        ell = t1 - t0
        v, acc, r1, r2, u1, u2 = self.pieces.derivative_bounds(piece, t0, t1, rho0, rho1)
        sag = self.pieces.sagitta(piece, ell)
        beta = float(y[3] * self.kappa)
        qv = lam @ self.kk
        qn = float(np.hypot(qv[0], qv[1]))
        yw = float(np.hypot(y[1], y[2]))
        # near form
        bo = y[1:3] - beta * self.d0
        bon = float(np.hypot(bo[0], bo[1]))
        qo = beta * self.rc - qv
        qon = float(np.hypot(qo[0], qo[1]))
        ao = y[0] + beta * float(self.c @ self.d0)
        k_o = bon * v + abs(beta) * r1 + qon * u1
        m_o = bon * acc + abs(beta) * r2 + qon * u2
        lb0_o = np.minimum(ao + w0 @ bo, ao + w1 @ bo) - bon * sag + np.minimum(beta * rho0, beta * rho1) - qon
        # far form
        half = 0.5 * ell * v
        wc0 = np.hypot(w0[:, 0] - self.c[0], w0[:, 1] - self.c[1])
        wc1 = np.hypot(w1[:, 0] - self.c[0], w1[:, 1] - self.c[1])
        wc = np.maximum(wc0, wc1) + half
        with np.errstate(invalid="ignore", over="ignore"):
            dm = np.minimum(2.0, np.maximum(dn0, dn1) + u1 * half)
        cn = abs(beta) * wc + qn
        with np.errstate(invalid="ignore", over="ignore"):
            k_n = yw * v + abs(beta) * v * dm + cn * u1
            m_n = yw * acc + abs(beta) * acc * dm + 2.0 * abs(beta) * v * u1 + cn * u2
        an = y[0] - float(qv @ self.d0)
        lb0_n = np.minimum(an + w0 @ y[1:3], an + w1 @ y[1:3]) - yw * sag - cn * dm
        eps = ROUNDING_ALLOWANCE
        rho_max = np.maximum(rho0, rho1)
        w_max = 1.0 + self.r_norm
        allow_n = eps * (abs(y[0]) + yw * w_max + abs(beta) * wc * 2.0 + 2.0 * qn + abs(float(qv @ self.d0)))
        allow_o = eps * (abs(ao) + bon * w_max + abs(beta) * (rho_max + w_max + self.r_norm) + qon)
        lbs = [lb0_o - allow_o, lb0_n - allow_n]
        for k, m in ((k_o, m_o), (k_n, m_n)):
            with np.errstate(invalid="ignore", over="ignore"):
                lb_lip = 0.5 * (f0 + f1 - k * ell)
            with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
                tau = np.where(m > 0.0, 0.5 * ell - (f1 - f0) / (m * ell), np.where(f1 < f0, ell, 0.0))
            tau = np.clip(np.nan_to_num(tau, nan=0.0), 0.0, ell)
            with np.errstate(invalid="ignore", over="ignore"):
                chord = f0 + (f1 - f0) * np.where(ell > 0.0, tau / np.where(ell > 0.0, ell, 1.0), 0.0)
                lb_2 = np.where(np.isfinite(m), chord - 0.5 * m * tau * (ell - tau), -np.inf)
                slack = allow_n + eps * (np.nan_to_num(k * ell, nan=np.inf, posinf=np.inf) + np.abs(f0) + np.abs(f1))
            lbs.append(np.nan_to_num(lb_lip, nan=-np.inf) - slack)
            lbs.append(np.nan_to_num(lb_2, nan=-np.inf) - slack)
        return np.maximum.reduce(lbs)


# --------------------------------------------------------------------------------------
# Pricing: local refinement and branch and bound (as in solver.membership)


def _golden(q: _Query, y, lam, piece, lo, hi):
    a, b = np.asarray(lo, dtype=float).copy(), np.asarray(hi, dtype=float).copy()
    for _ in range(GOLDEN_ITERATIONS):
        c = b - _GOLD * (b - a)
        d = a + _GOLD * (b - a)
        f = q.phi(y, lam, np.concatenate([piece, piece]), np.concatenate([c, d]))
        left = f[: len(c)] < f[len(c):]
        b = np.where(left, d, b)
        a = np.where(left, a, c)
    n = len(a)
    cand = np.concatenate([lo, hi, a, b, 0.5 * (a + b)])
    fv = q.phi(y, lam, np.concatenate([piece] * 5), cand).reshape(5, n)
    best = np.argmin(fv, axis=0)
    return cand.reshape(5, n)[best, np.arange(n)], fv[best, np.arange(n)]


def _local_minima(q: _Query, y, lam, gt, gf, limit: int):
    idx_lo, idx_hi, idx_piece = [], [], []
    start = 0
    for k, n in enumerate(q.pieces.grid_counts):
        f = gf[start : start + n]
        left = np.concatenate([[np.inf], f[:-1]])
        right = np.concatenate([f[1:], [np.inf]])
        for i in np.nonzero((f <= left) & (f <= right))[0]:
            idx_lo.append(start + max(i - 1, 0))
            idx_hi.append(start + min(i + 1, n - 1))
            idx_piece.append(k)
        start += n
    if not idx_piece:
        return np.zeros(0, dtype=int), np.zeros(0), np.zeros(0)
    lo = gt[np.array(idx_lo)]
    hi = gt[np.array(idx_hi)]
    piece = np.array(idx_piece)
    centre_val = np.minimum(gf[np.array(idx_lo)], gf[np.array(idx_hi)])
    order = np.argsort(centre_val)[: 4 * limit]
    t, f = _golden(q, y, lam, piece[order], lo[order], hi[order])
    best = np.argsort(f)[:limit]
    return piece[order][best], t[best], f[best]


@dataclass
class _BnBResult:
    lower_bound: float
    certified: bool
    violators: tuple
    intervals: int


def _branch_and_bound(q: _Query, y, lam, gp, gt, target: float, max_intervals: int, deadline) -> _BnBResult:
    """Sound lower bound of phi over the outline, or points below ``target``
    (breadth-first bisection of the grid intervals, as in solver.membership)."""
    f_all, e_all = q.evaluate(y, lam, gp, gt)
    first = np.ones(len(gp), dtype=bool)
    last = np.ones(len(gp), dtype=bool)
    first[1:] = gp[1:] != gp[:-1]
    last[:-1] = gp[:-1] != gp[1:]
    i0 = np.nonzero(~last)[0]
    i1 = i0 + 1
    piece, t0, t1 = gp[i0], gt[i0], gt[i1]
    f0, f1, e0, e1 = f_all[i0], f_all[i1], e_all[i0], e_all[i1]
    certified_min = math.inf
    total = len(piece)
    while True:
        lb = q.lower_bounds(y, lam, piece, t0, t1, f0, f1, e0, e1)
        small = (t1 - t0) <= MIN_INTERVAL
        done = (lb >= target) | small
        if np.any(done):
            certified_min = min(certified_min, float(np.min(lb[done])))
        keep = ~done
        if not np.any(keep):
            return _BnBResult(certified_min, certified_min >= target, (), total)
        piece, t0, t1, f0, f1, e0, e1, lb = (arr[keep] for arr in (piece, t0, t1, f0, f1, e0, e1, lb))
        if total + len(piece) > max_intervals or (deadline is not None and time.perf_counter() > deadline):
            return _BnBResult(min(certified_min, float(np.min(lb))), False, (), total)
        tm = 0.5 * (t0 + t1)
        fm, em = q.evaluate(y, lam, piece, tm)
        total += len(piece)
        below = fm < target
        if np.any(below):
            order = np.argsort(fm[below])[:COLUMNS_PER_ROUND]
            return _BnBResult(
                min(certified_min, float(np.min(lb))), False,
                (piece[below][order], t0[below][order], t1[below][order]), total,
            )
        piece = np.concatenate([piece, piece])
        t0, t1 = np.concatenate([t0, tm]), np.concatenate([tm, t1])
        f0, f1 = np.concatenate([f0, fm]), np.concatenate([fm, f1])
        e0, e1 = np.concatenate([e0, em]), np.concatenate([em, e1])


# --------------------------------------------------------------------------------------
# Restricted master (cvxpy + Clarabel), compiled once per capacity


class _Master:
    """min ||e||_1 + sum t:  A P + q P0 + S z - e = b,  Hm P + Hz z + t >= 0,  t >= 0,
    P >= 0, |z| <= P0; A, Hm, q, S, Hz and b are Parameters."""

    def __init__(self, capacity: int):
        self.capacity = capacity
        self.a = cp.Parameter((4, capacity))
        self.hm = cp.Parameter((2, capacity))
        self.q = cp.Parameter(4)
        self.sz = cp.Parameter((4, 2))
        self.hz = cp.Parameter((2, 2))
        self.p = cp.Variable(capacity, nonneg=True)
        self.p0 = cp.Variable()
        self.z = cp.Variable(2)
        self.e = cp.Variable(4)
        self.t = cp.Variable(2, nonneg=True)
        self.b = cp.Parameter(4)
        self.eq = self.a @ self.p + self.q * self.p0 + self.sz @ self.z - self.e == self.b
        self.ineq = self.hm @ self.p + self.hz @ self.z + self.t >= 0
        self.problem = cp.Problem(
            cp.Minimize(cp.norm1(self.e) + cp.sum(self.t)), [self.eq, self.ineq, cp.SOC(self.p0, self.z)]
        )
        self.lock = threading.Lock()

    def solve(self, g, h, query: _Query, tol: SolverTolerances):
        n = g.shape[1]
        a = np.empty((4, self.capacity))
        a[:, :n] = g
        a[:, n:] = g[:, :1]  # padding: copies of column 0 (merged back below)
        hm = np.empty((2, self.capacity))
        hm[:, :n] = h
        hm[:, n:] = h[:, :1]
        q = np.zeros(4)
        sz = np.zeros((4, 2))
        hz = np.zeros((2, 2))
        if query.in_f:
            pg, ph = query.pm_columns()
            q[:] = pg[:, 0]
            sz[:] = pg[:, 1:]
            hz[:] = ph[:, 1:]
        with self.lock:
            self.b.value = query.b
            self.a.value = a
            self.hm.value = hm
            self.q.value = q
            self.sz.value = sz
            self.hz.value = hz
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", UserWarning)
                    self.problem.solve(
                        solver=cp.CLARABEL, tol_gap_abs=tol.conic_gap, tol_gap_rel=tol.conic_gap, tol_feas=tol.conic_gap
                    )
            except cp.error.SolverError as exc:
                raise SolverError(f"Clarabel failed on the sticking master: {exc}") from exc
            if self.problem.status not in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE) or self.p.value is None:
                raise SolverError(f"sticking master ended with status {self.problem.status}")
            p = np.clip(np.asarray(self.p.value, dtype=float), 0.0, None)
            y = np.asarray(self.eq.dual_value, dtype=float).reshape(4)
            lam = np.clip(np.asarray(self.ineq.dual_value, dtype=float).reshape(2), 0.0, None)
            p0 = float(self.p0.value) if query.in_f else 0.0
            z = np.asarray(self.z.value, dtype=float) if query.in_f else np.zeros(2)
        weights = p[:n].copy()
        weights[0] += float(np.sum(p[n:]))
        return weights, p0, z, y, lam


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
# Witness residual and polish


def _violations(b, g, h, weights, pmg, pmh, pm_x):
    """(L1 residual of the equalities, total violation of the cone rows, cone rows)."""
    lhs = g @ weights
    rows = h @ weights
    if pmg is not None:
        lhs = lhs + pmg @ pm_x
        rows = rows + pmh @ pm_x
    return float(np.sum(np.abs(lhs - b))), float(np.sum(np.maximum(-rows, 0.0))), rows


def _residual(b, g, h, weights, pmg, pmh, pm_x) -> float:
    eq, cone, _ = _violations(b, g, h, weights, pmg, pmh, pm_x)
    return eq + cone


def _pm_basis(pmg, pmh, pm_x, variant: str):
    """The point mass as extra columns: "free" (P0, z) with |z| <= P0, or "cone" (P0 alone,
    z = P0 zhat on the cone's boundary, zhat from the master)."""
    if variant == "free":
        return pmg, pmh, pm_x.copy()
    zn = math.hypot(pm_x[1], pm_x[2])
    zhat = pm_x[1:] / zn if zn > 0.0 else np.array([1.0, 0.0])
    e = np.array([1.0, zhat[0], zhat[1]])
    return (pmg @ e)[:, None], (pmh @ e)[:, None], np.array([pm_x[0]])


def _polish_once(m, target, weights, pm_cols, pm_coords, variant):
    """Least-norm correction of the positive weights (and point mass) so that m x = target
    to rounding; drops weights that turn negative and retries. (weights, pm) or None."""
    active = np.nonzero(weights > 0.0)[0]
    for _ in range(8):
        mm = m[:, active]
        x = weights[active]
        if pm_cols is not None:
            mm = np.hstack([mm, pm_cols])
            x = np.concatenate([x, pm_coords])
        x_new = x + np.linalg.lstsq(mm, target - mm @ x, rcond=None)[0]
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


def _exact_witness(g, h, weights, pm_x, query: _Query, accept: float):
    """Turn the master's approximate support into an exact small one.

    The cone rows become equalities with slack columns, [G 0; H -I] (P, t) = (b, 0) with
    P, t >= 0. With the point mass held at the master's value, non-negative least squares
    (Lawson and Hanson's active set, ending on at most 6 independent columns) picks a basic
    support; a least-norm correction of those weights, slacks and the point mass (free, on
    its cone's boundary, or absent) makes the rows hold to rounding. Returns
    (weights, pm_x, residual): the best small support if its residual is at most
    ``accept``, else the best of it and the input."""
    pmg, pmh = query.pm_columns() if query.in_f else (None, None)
    bq = query.b
    n = g.shape[1]
    given = (weights, pm_x, _residual(bq, g, h, weights, pmg, pmh, pm_x))
    best = (weights, pm_x, math.inf)
    m = np.block([[g, np.zeros((4, 2))], [h, -np.eye(2)]])
    tgt = np.concatenate([bq, np.zeros(2)])
    _, _, rows = _violations(bq, g, h, weights, pmg, pmh, pm_x)
    dense = np.where(weights > 1e-12 * float(np.max(weights, initial=0.0)), weights, 0.0)
    dense = np.concatenate([dense, np.maximum(rows, 0.0)])
    variants = ("free", "cone", "none") if query.in_f else ("none",)
    for variant in variants:
        if variant == "none":
            pm_cols, coords, target = None, np.zeros(0), tgt
        else:
            cg, ch, coords = _pm_basis(pmg, pmh, pm_x, variant)
            pm_cols = np.vstack([cg, ch])
            target = tgt - pm_cols @ coords
        basic = nnls(m, target)[0]
        for start in (basic, dense):
            out = _polish_once(m, tgt, start, pm_cols, coords, variant)
            if out is None:
                continue
            x1, c1 = out
            w1 = x1[:n]
            pm1 = _pm_back(pm_x, c1, variant) if pm_cols is not None else np.zeros(3)
            res1 = _residual(bq, g, h, w1, pmg, pmh, pm1)
            if res1 < best[2]:
                best = (w1, pm1, res1)
            if best[2] <= 1e-14:
                return best
    return best if best[2] <= accept or best[2] <= given[2] else given


# --------------------------------------------------------------------------------------
# One query


def _initial_columns(query: _Query, gp, gt, warm_local, min_rho: float):
    w_all, rho_all, u_all = query.pieces.geom(gp, gt)
    usable = rho_all > min_rho
    pts, u, rho = w_all[usable], u_all[usable], rho_all[usable]
    _, uniq = np.unique(np.round(pts, 14), axis=0, return_index=True)
    uniq = np.sort(uniq)
    pts, u, rho = pts[uniq], u[uniq], rho[uniq]
    if warm_local is not None and len(warm_local):
        e = warm_local - query.r
        wr = np.hypot(e[:, 0], e[:, 1])
        ok = wr > max(min_rho, ON_BOUNDARY_REL)
        if np.any(ok):
            pts = np.vstack([pts, warm_local[ok]])
            u = np.vstack([u, e[ok] / wr[ok][:, None]])
            rho = np.concatenate([rho, wr[ok]])
    g, h = query.columns(pts, u, rho)
    return pts, g, h


def _decide(
    geo: _Geometry,
    r_local: np.ndarray,
    tol: SolverTolerances,
    deadline: float | None,
    warm_points,
    verify_witness: bool,
    certify: bool,
    t_start: float,
    time_limit_s,
) -> StickingResult:
    outline = geo.outline
    ell = outline.length
    scene = geo.scene
    r, on_outline = _snap_on_line(geo, r_local)
    in_f = outline.contains(r, on_outline)
    s_loc = float(r[1] - geo.c[1])
    cor_world = outline.to_world(r)
    position = s_loc * ell
    friction = geo.nu
    common = dict(
        cor=cor_world, position=position, mu_c=geo.mu_c, friction_angle=friction, in_footprint=in_f,
        length_scale=ell,
    )
    if s_loc == 0.0:
        return StickingResult(
            status="outside", omega=math.nan, sense="none", certificate_kind="contact",
            witness_points=np.zeros((0, 2)), witness_weights=np.zeros(0), point_mass_at_cor=0.0,
            point_mass_subgradient=np.zeros(2), contact_force=np.zeros(2), force_angle=math.nan,
            cone_slack=math.nan, witness_residual=math.inf, witness_forward_cor_error=None,
            witness_forward_mode=None, witness_forward_slip=None, witness_check=None, dual=None,
            dual_lower_bound=None, dual_margin=None,
            lower_bound_method=None, iterations=0, n_columns=0, bnb_intervals=0,
            message="the contact point: a rotation about it cannot move the contact along the push",
            solve_time_s=time.perf_counter() - t_start, **common,
        )
    query = _Query(geo, r, on_outline, in_f)
    gp, gt = query.pieces.grid()
    min_rho = POINT_MASS_RADIUS if in_f else 0.0
    warm_local = None
    if warm_points is not None:
        warm_local = outline.to_local(np.asarray(warm_points, dtype=float).reshape(-1, 2)[:MAX_WARM_POINTS])
    pts, g, h = _initial_columns(query, gp, gt, warm_local, min_rho)
    pmg, pmh = query.pm_columns() if in_f else (None, None)

    status, kind, message = "undecided", "none", ""
    weights = np.zeros(g.shape[1])
    pm_x = np.zeros(3)
    residual = math.inf
    y = lam = None
    lower = margin = None
    method = None
    bnb_total = 0
    iterations = 0
    for iterations in range(1, tol.max_cg_iter + 1):
        if deadline is not None and time.perf_counter() > deadline:
            message = f"time limit {time_limit_s} s reached"
            iterations -= 1
            break
        weights, p0, z, y_raw, lam_raw = _master(g.shape[1]).solve(g, h, query, tol)
        if in_f:
            zn = math.hypot(z[0], z[1])
            p0 = max(p0, 0.0)
            if zn > p0:
                z = z * (p0 / zn) if zn > 0.0 else z
            pm_x = np.array([p0, z[0], z[1]])
        residual = _residual(query.b, g, h, weights, pmg, pmh, pm_x)
        if residual <= max(POLISH_BELOW, tol.membership_residual):
            weights, pm_x, residual = _exact_witness(g, h, weights, pm_x, query, tol.membership_residual)
            if residual <= tol.membership_residual:
                status, kind = "inside", "witness"
                message = "witness support: sticking stationarity with the force in the friction cone"
                break
        scale = max(1.0, float(np.max(np.abs(y_raw))), float(np.max(lam_raw)))
        y, lam = y_raw / scale, lam_raw / scale
        yb = query.yb(y)
        pm_val = query.pm_value(y, lam)
        gf = query.phi(y, lam, gp, gt)
        lp, lt, lf = _local_minima(query, y, lam, gt, gf, COLUMNS_PER_ROUND)
        t_cert = yb + tol.certificate_margin
        improving = lf < -tol.pricing_tol
        if not certify:
            lower = float(min(np.min(gf), np.min(lf, initial=math.inf), pm_val))
            margin = lower - yb
            method = "grid"
            if margin > tol.certificate_margin:
                status = "outside"
                message = "grid pricing separates the candidate (not a certificate)"
                break
            if not np.any(improving):
                message = "restricted master optimal on the grid; residual too small to decide"
                break
            new_p, new_t = lp[improving], lt[improving]
        else:
            if not np.any(lf < t_cert) and pm_val >= t_cert:
                target = t_cert if t_cert < -tol.pricing_tol else -tol.pricing_tol
                bnb = _branch_and_bound(query, y, lam, gp, gt, target, tol.max_bnb_intervals, deadline)
                bnb_total += bnb.intervals
                lower = min(bnb.lower_bound, pm_val)
                margin = lower - yb
                method = "branch_and_bound"
                if bnb.certified and margin > tol.certificate_margin:
                    status, kind = "outside", "dual"
                    message = "certified dual: y . G - lambda . H >= lower bound on the whole footprint"
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
                lo = np.maximum(vlo - half, query.pieces.piece_lo[vp])
                hi = np.minimum(vhi + half, query.pieces.piece_hi[vp])
                vt, _ = _golden(query, y, lam, vp, lo, hi)
                new_p = np.concatenate([lp[improving], vp])
                new_t = np.concatenate([lt[improving], vt])
            else:
                new_p, new_t = lp[improving], lt[improving]
            if new_p.size == 0:
                message = "no improving column found"
                break
        nw, nrho, nu_ = query.pieces.geom(new_p, new_t)
        ok = nrho > min_rho
        if not np.any(ok):
            message = "pricing points coincide with the candidate"
            break
        g2, h2 = query.columns(nw[ok], nu_[ok], nrho[ok])
        g = np.hstack([g, g2])
        h = np.hstack([h, h2])
        pts = np.vstack([pts, nw[ok]])
        weights = np.concatenate([weights, np.zeros(int(np.sum(ok)))])
    else:
        message = message or f"no decision after {tol.max_cg_iter} column-generation rounds"

    if status == "inside":
        sel = weights > 0.0
    else:
        sel = weights > REPORT_WEIGHT_REL * float(np.max(weights, initial=0.0))
    p_mass = float(pm_x[0]) if in_f else 0.0
    z_loc = pm_x[1:3] if in_f else np.zeros(2)
    wl = pts[sel]
    ww = weights[sel]
    e = wl - r
    d = e / np.hypot(e[:, 0], e[:, 1])[:, None]
    dvec = ww @ d + z_loc if len(ww) else z_loc.copy()
    f_loc = query.sigma * perp(dvec)
    f_norm = float(np.hypot(f_loc[0], f_loc[1]))
    angle = math.atan2(float(f_loc @ geo.t), float(f_loc @ geo.n)) if f_norm > 0.0 else math.nan
    slack = float(np.min(geo.cone @ f_loc)) / f_norm if f_norm > 0.0 else 0.0
    wit_pts = outline.to_world(wl)
    forward_err = forward_mode = forward_slip = check = None
    if status == "inside" and verify_witness:
        forward_err, forward_mode, forward_slip, check = _forward_check(scene, geo, wit_pts, ww, p_mass, cor_world, tol)
    dual = None
    if status != "inside" and y is not None:
        yo, lo_ = query.original_dual(y, lam)
        dual = np.concatenate([[yo[0]], outline.frame @ yo[1:3], [yo[3]], lo_])
    if status == "inside":
        lower = margin = method = None
    omega = 1.0 / position
    return StickingResult(
        status=status,
        omega=omega,
        sense="ccw" if omega > 0.0 else "cw",
        certificate_kind=kind,
        witness_points=wit_pts,
        witness_weights=ww,
        point_mass_at_cor=p_mass,
        point_mass_subgradient=outline.frame @ z_loc,
        contact_force=outline.frame @ f_loc,
        force_angle=angle,
        cone_slack=slack,
        witness_residual=float(residual),
        witness_forward_cor_error=forward_err,
        witness_forward_mode=forward_mode,
        witness_forward_slip=forward_slip,
        witness_check=check,
        dual=dual,
        dual_lower_bound=lower,
        dual_margin=margin,
        lower_bound_method=method,
        iterations=iterations,
        n_columns=int(g.shape[1]),
        bnb_intervals=bnb_total,
        message=message,
        solve_time_s=time.perf_counter() - t_start,
        **common,
    )


def _sticking_motion_position(w_local, weights, c_local, s_guess: float) -> float:
    """Position s (/ L) of the COR of the minimum-power sticking motion of a support, by
    a direct 1-D minimisation: sticking twists are v = p - omega J c (one parameter), the
    power f(omega) = sum P_i |p + omega J (w_i - c)| is convex, and its minimiser is the
    first omega where the right derivative is >= 0 (bisection to rounding). Independent of
    the KKT conditions (i)-(iii); returns nan for a translation (omega = 0)."""
    b = perp(np.asarray(w_local, dtype=float) - c_local)
    pw = np.asarray(weights, dtype=float)
    e1 = np.array([1.0, 0.0])

    def dright(om: float) -> float:
        v = e1[None, :] + om * b
        sp = np.hypot(v[:, 0], v[:, 1])
        bn = np.hypot(b[:, 0], b[:, 1])
        with np.errstate(invalid="ignore", divide="ignore"):
            term = np.where(sp > 0.0, np.einsum("ij,ij->i", v, b) / sp, bn)
        return float(pw @ term)

    om0 = 1.0 / s_guess
    step = max(abs(om0), 1e-3)
    lo, hi = om0 - step, om0 + step
    for _ in range(200):
        if dright(lo) < 0.0:
            break
        lo -= step
        step *= 2.0
    step = max(abs(om0), 1e-3)
    for _ in range(200):
        if dright(hi) >= 0.0:
            break
        hi += step
        step *= 2.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        if dright(mid) >= 0.0:
            hi = mid
        else:
            lo = mid
    return 1.0 / hi if hi != 0.0 else math.nan


def _forward_check(scene, geo: _Geometry, pts, weights, p_mass, cor_world, tol):
    """(|COR of the sticking motion - cor| / L, forward mode, slip, how) of the witness
    support. It is solved forward with the pusher friction (4.1); in sticking mode its COR is
    compared. Otherwise (a point mass at r: the forward solver tests one contact force of
    the set; see StickingResult) the minimum-power sticking motion is found by a direct
    1-D minimisation of the power over sticking twists (``how`` "power_1d")."""
    supp, sw = pts, weights
    if p_mass > 0.0:
        supp = np.vstack([supp, cor_world])
        sw = np.concatenate([sw, [p_mass]])
    support = Support.create(supp, sw, scene.center_of_mass, tol)
    mu = geo.mu_c if math.isfinite(geo.mu_c) else 1e300
    fwd = solve_forward(scene, support, mu_c=mu, method="newton", tol=tol)
    mode, slip = fwd.mode, float(fwd.slip)
    if mode in ("sticking", "frictionless"):
        if fwd.cor is None:
            return math.inf, mode, slip, "forward"
        return float(np.linalg.norm(fwd.cor - cor_world) / geo.length), mode, slip, "forward"
    r_loc = geo.outline.to_local(cor_world)
    s_loc = float(r_loc[1] - geo.c[1])
    s_star = _sticking_motion_position(geo.outline.to_local(support.points), support.weights, geo.c, s_loc)
    err = abs(s_star - s_loc) if math.isfinite(s_star) else math.inf
    return float(err), mode, slip, "power_1d"


def sticking_point(scene: PushScene, position: float) -> np.ndarray:
    """The world point at signed distance ``position`` from the contact along J p."""
    return np.asarray(scene.contact_point, dtype=float) + float(position) * perp(np.asarray(scene.push_hat))


def sticking_feasibility(
    scene: PushScene,
    r_world,
    mu_c: float,
    footprint: Footprint | None = None,
    tol: SolverTolerances = SOLVER_DEFAULT,
    time_limit_s: float | None = None,
    warm_points=None,
    verify_witness: bool = True,
    certify: bool = True,
) -> StickingResult:
    """Is ``r_world`` (on the sticking line) the COR of a sticking push for some pressure
    distribution on the footprint (the scene's disk when None)? See the module docstring.

    ``mu_c`` >= 0 (math.inf allowed). A point farther than ``ON_LINE_REL`` L from the
    sticking line is refused (InvalidInput), a closer one projected onto it.
    ``certify=False`` decides "outside" on grid pricing only (no certificate).
    """
    t_start = time.perf_counter()
    deadline = None if time_limit_s is None else t_start + float(time_limit_s)
    mu = _check_mu(mu_c)
    geo = _geometry(scene, footprint, mu, tol)
    r_in = np.asarray(r_world, dtype=float)
    if r_in.shape != (2,) or not np.all(np.isfinite(r_in)):
        raise InvalidInput("cor", "must be a finite point [x, y]")
    r = geo.outline.to_local(r_in)
    if abs(r[0] - geo.c[0]) > ON_LINE_REL * max(1.0, abs(r[1])):
        raise InvalidInput(
            "cor",
            "is not on the sticking line (the line through the contact point perpendicular to the push)",
        )
    r = np.array([geo.c[0], r[1]])
    return _decide(geo, r, tol, deadline, warm_points, verify_witness, certify, t_start, time_limit_s)


# --------------------------------------------------------------------------------------
# The locus along the line


@dataclass(frozen=True)
class LocusEnd:
    """One end of an interval of the sticking locus.

    ``status``: "bracketed" (``feasible`` inside with a witness and ``infeasible`` outside,
    ``width`` <= tol.boundary_bracket * L apart; ``certified`` when the outside end has a
    branch-and-bound dual), "wide" (as bracketed, but the outside end had to be moved out
    beyond the target width before it could be certified: ``width`` says how wide),
    "contact" (the interval runs up to within half the target width of the contact point,
    which is excluded: no push turns the part about it), "search_limit" (still feasible at
    the search cap: the locus may be unbounded), or "undecided" (time limit, or a query the
    solver could not decide; the bracket reached is reported).
    Positions are world lengths along J p from the contact; ``position`` is the bracket's
    midpoint and ``point`` its world point.
    """

    side: str
    status: str
    position: float
    point: np.ndarray
    feasible_position: float | None
    infeasible_position: float | None
    width: float
    certified: bool
    feasible: StickingResult | None
    infeasible: StickingResult | None


@dataclass(frozen=True)
class StickingInterval:
    lower: LocusEnd
    upper: LocusEnd


@dataclass(frozen=True)
class TipLineEstimate:
    """The book's approximation of the sticking locus's end by the tip line (4.1.4,
    3.3.11.1): ``position`` where the tip line (of the scene's disk,
    :func:`models.cor_disk.disk_cor_locus`) meets the sticking line (None if parallel),
    ``end`` the end on its side ("lower" for s < 0), ``error`` = exact end - estimate
    (world length, None if no interval lies on that side), ``error_bound`` the exact end's
    half bracket, ``beyond`` whether the exact end lies farther from the contact than the
    tip line (the book's "dip")."""

    position: float | None
    point: np.ndarray | None
    end: str | None
    error: float | None
    error_bound: float | None
    beyond: bool | None


@dataclass(frozen=True)
class StickingLocus:
    """The sticking locus (4.1.4) along the sticking line.

    ``intervals``: the feasible intervals found (a scan, then bracketed ends), ordered by
    position; ``lower``/``upper`` the outermost ends; ``multiple_intervals`` when the scan
    found more than one. ``search_range`` (world lengths along J p): a sound outer bound of
    the locus (``search_bound`` names the bounds that gave it, see
    :func:`sticking_search_range`) or the search cap.
    ``scan_positions``/``scan_status``: the probes. ``seed_positions``: sticking CORs of
    random tripods and uniform pressure (forward solves) used as feasible seeds.
    ``status``: "found", "empty" (no feasible probe: the scan can miss a locus narrower
    than its spacing; an empty search range is sound), or "incomplete" (time limit or an
    undecided end). ``time_limited``: the time limit stopped the computation.
    ``translation_sticks``: a pure translation along p (the COR at infinity on the sticking
    line) is a sticking motion: the line through c along p passes through the CM (within
    ``translation_rel``) and p lies in the friction cone. It is not part of ``intervals``.
    """

    status: str
    mu_c: float
    friction_angle: float
    contact_point: np.ndarray
    direction: np.ndarray
    length_scale: float
    intervals: tuple[StickingInterval, ...]
    lower: LocusEnd | None
    upper: LocusEnd | None
    multiple_intervals: bool
    search_range: tuple[float, float]
    search_bound: str
    scan_positions: np.ndarray
    scan_status: tuple[str, ...]
    seed_positions: np.ndarray
    tip_line: TipLineEstimate
    n_queries: int
    solve_time_s: float
    time_limited: bool
    complete: bool
    message: str
    translation_sticks: bool = False


def _min_lever(geo: _Geometry) -> float:
    """min over |phi| <= nu of |alpha_phi . c| / L (alpha turned by phi with the cone)."""
    a = float(geo.t @ geo.c)
    b = float(perp(geo.t) @ geo.c)
    nu = geo.nu
    vals = [abs(a * math.cos(ph) + b * math.sin(ph)) for ph in (-nu, nu)]
    # zero of a cos phi + b sin phi in (-pi/2, pi/2]
    zero = math.pi / 2 if b == 0.0 else math.atan(-a / b)
    if abs(zero) <= nu:
        return 0.0
    return min(vals)


def _search_range(geo: _Geometry) -> tuple[float, float, str]:
    """A sound outer bound [lo, hi] (/ L) of the sticking locus along the line.

    * footprint: with a point mass at r, r lies in the footprint, inside the unit disk;
    * moment (ii): for r outside the footprint, |d - (+-J p)| <= 2 |w - c| / |s|, so
      |sum P (w - c) . d + c . J p| <= 2 D^2 / |s| with D = max |w - c| over the footprint;
      (ii) then needs |s| <= 2 D^2 / |c . J p|;
    * disk loci: each {COR}_phi of the circumscribing disk lies within
      max(1, 1 / |alpha_phi . c|) of the CM (3.37, and a for |alpha . c| >= a), and the
      footprint's loci lie in its disk's (7.5).
    The result is the intersection of the moment and disk bounds, joined with the
    footprint's chord; when neither bounds the line, +-SEARCH_LIMIT.
    """
    cx, cy = float(geo.c[0]), float(geo.c[1])
    names = []
    # footprint chord: |r| <= 1 with r = (cx, cy + s)
    chord = None
    if abs(cx) <= 1.0:
        hh = math.sqrt((1.0 - cx) * (1.0 + cx))
        chord = (-cy - hh, -cy + hh)
    lo, hi = -math.inf, math.inf
    if abs(cy) > 0.0:
        sm = 2.0 * geo.reach**2 / abs(cy)
        lo, hi = -sm, sm
        names.append("moment")
    g = _min_lever(geo)
    if g > 0.0:
        big_r = 1.0 / min(1.0, g)
        if big_r < abs(cx):
            dl, dh = math.inf, -math.inf  # the line misses every locus
        else:
            hh = math.sqrt((big_r - abs(cx)) * (big_r + abs(cx)))
            dl, dh = -cy - hh, -cy + hh
        lo, hi = max(lo, dl), min(hi, dh)
        names.append("disk_loci")
    if not names:
        lo, hi = -SEARCH_LIMIT, SEARCH_LIMIT
        names.append("cap")
    if chord is not None:
        if lo > hi:
            lo, hi = chord
        else:
            lo, hi = min(lo, chord[0]), max(hi, chord[1])
        names.append("footprint")
    return lo, hi, "+".join(names)


def sticking_search_range(
    scene: PushScene, mu_c: float, footprint: Footprint | None = None, tol: SolverTolerances = SOLVER_DEFAULT
) -> tuple[float, float, str]:
    """A sound outer bound (lo, hi) of the sticking locus's positions s (world lengths along
    J p from the contact) and the names of the bounds that gave it ("moment", "disk_loci",
    "footprint", joined by "+"; see :func:`_search_range`), or +-SEARCH_LIMIT L with "cap"
    when neither the moment nor the disk-loci bound applies."""
    geo = _geometry(scene, footprint, _check_mu(mu_c), tol)
    lo, hi, how = _search_range(geo)
    return lo * geo.length, hi * geo.length, how


def _tip_line(scene: PushScene) -> tuple[float | None, np.ndarray | None]:
    loc = disk_cor_locus(scene, outputs=("tip_line",))
    tl = loc.tip_line
    if tl is None:
        return None, None
    e2 = perp(np.asarray(scene.push_hat))
    nrm = perp(tl.direction)
    den = float(e2 @ nrm)
    if abs(den) <= scene.tolerances.grazing_sin:
        return None, None
    s = float((tl.point - scene.contact_point) @ nrm) / den
    return s, scene.contact_point + s * e2


def _seed_positions(geo: _Geometry, footprint, n_tripods: int, seed: int, tol) -> np.ndarray:
    """Positions (/ L) of sticking-mode forward CORs of random tripods (3.3.3) and of
    uniform pressure: feasible points to seed the scan."""
    scene = geo.scene
    mu = geo.mu_c if math.isfinite(geo.mu_c) else 1e300
    out = []
    e2 = perp(np.asarray(scene.push_hat))
    if n_tripods > 0:
        try:
            rng = np.random.default_rng(seed)
            pts, wts = random_balanced_tripods(rng, n_tripods, geo.length, scene.center_of_mass, footprint)
            b = solve_forward_batch(scene, pts, wts, mu_c=mu, tol=tol, check_centroid=False)
            ok = (b.mode == 1) & b.converged & np.all(np.isfinite(b.cor), axis=1)
            out.append((b.cor[ok] - scene.contact_point) @ e2)
        except InvalidInput:
            pass
    try:
        if footprint is None:
            support = uniform_disk_support(scene.disk_radius, scene.center_of_mass, rings=8)
        else:
            support = uniform_polygon_support(footprint, subdivisions=4)
        f = solve_forward(scene, support, mu_c=mu, tol=tol)
        if f.mode == "sticking" and f.cor is not None and f.status == "optimal":
            out.append(np.array([(f.cor - scene.contact_point) @ e2]))
    except InvalidInput:
        pass
    if not out:
        return np.zeros(0)
    return np.concatenate(out) / geo.length


class _LineSearch:
    """Queries along the sticking line (positions / L), cached, with warm starts."""

    def __init__(self, geo: _Geometry, tol: SolverTolerances, deadline):
        self.geo = geo
        self.tol = dataclasses.replace(tol, membership_residual=min(tol.membership_residual, STRICT_WITNESS_RESIDUAL))
        self.deadline = deadline
        self.n_queries = 0
        self.warm: np.ndarray | None = None
        self.cache: dict[tuple[float, bool, bool], StickingResult] = {}

    def expired(self) -> bool:
        return self.deadline is not None and time.perf_counter() > self.deadline

    def __call__(self, s: float, certify: bool = False, verify: bool = False) -> StickingResult:
        key = (float(s), certify, verify)
        if key in self.cache:
            return self.cache[key]
        self.n_queries += 1
        t0 = time.perf_counter()
        res = _decide(self.geo, self.geo.point(s), self.tol, self.deadline, self.warm, verify, certify, t0, None)
        if res.witness_points.size:
            order = np.argsort(res.witness_weights)[::-1][:WARM_PER_RESULT]
            new = res.witness_points[order]
            self.warm = new if self.warm is None else np.vstack([new, self.warm])[:MAX_WARM_POINTS]
        self.cache[key] = res
        return res


def _local_position(geo: _Geometry, res: StickingResult) -> float:
    return res.position / geo.length


def _bracket_end(search: _LineSearch, side: str, s_in: float, s_out: float, out_kind: str) -> LocusEnd:
    """Narrow [s_in (inside), s_out] to half the bracket width with uncertified probes, then
    certify both ends (the witness re-verified by a forward solve, a branch-and-bound dual).

    ``out_kind``: "probe" (s_out was decided outside, possibly by grid pricing only),
    "contact" (s_out = 0, the contact point) or "limit" (s_out is the search cap).
    A probe within rounding of the end (undecided) is stepped around by a quarter and a
    half of the target width. An outside end too close to the end to certify (its dual
    margin below tol.certificate_margin) is moved outwards by a quarter of the width,
    twice, then the bracket is doubled (status "wide" when it ends wider than the target).
    When the certified query finds the grid's "outside" end inside, the grid is no longer
    trusted for this end: certified probes step outwards, doubling, to a certified outside
    point, and the bisection continues with certified probes."""
    geo = search.geo
    target = search.tol.boundary_bracket
    outward = 1.0 if side == "upper" else -1.0
    res_in = res_out = None
    status = "undecided"
    nudges = widenings = rounds = 0
    trust_grid = True
    bisecting = True
    while rounds < MAX_BRACKET_ROUNDS and not search.expired():
        rounds += 1
        if bisecting and abs(s_out - s_in) > 0.5 * target:
            mid = 0.5 * (s_in + s_out)
            if mid in (s_in, s_out, 0.0):
                bisecting = False
                continue
            res = search(mid, certify=not trust_grid)
            if res.status == "undecided" and trust_grid:
                res = search(mid, certify=True)
            sm = _local_position(geo, res)
            if res.status == "inside":
                s_in = sm
            elif res.status == "outside":
                s_out, out_kind = sm, "probe"
            else:
                # within rounding of the end: step a little to either side of it
                moved = False
                for frac in (0.25, 0.5):
                    s_try = mid + outward * frac * target
                    if (s_try - mid) * (s_out - s_try) > 0.0:
                        r_try = search(s_try, certify=not trust_grid)
                        if r_try.status == "outside":
                            s_out, out_kind, moved = _local_position(geo, r_try), "probe", True
                            break
                for frac in (0.25, 0.5):
                    s_try = mid - outward * frac * target
                    if (s_try - s_in) * (mid - s_try) > 0.0:
                        r_try = search(s_try, certify=not trust_grid)
                        if r_try.status == "inside":
                            s_in, moved = _local_position(geo, r_try), True
                            break
                bisecting = moved
            continue
        bisecting = False
        res_in = search(s_in, certify=True, verify=True)
        if res_in.status != "inside":
            break
        if out_kind == "contact":
            status = "contact"
            break
        res_out = search(s_out, certify=True)
        if res_out.status == "outside":
            status = "bracketed" if abs(s_out - s_in) <= target * (1.0 + 1e-9) else "wide"
            break
        if res_out.status == "inside":
            if out_kind == "limit":
                s_in, res_in = s_out, search(s_out, certify=True, verify=True)
                status = "search_limit"
                break
            # the grid's "outside" was wrong: certified steps outwards, doubling
            trust_grid = False
            step = max(target, abs(s_out - s_in))
            s_in = s_out
            for _ in range(64):
                s_try = s_in + outward * step
                if (s_try > 0.0) != (s_in > 0.0):
                    s_out, out_kind = 0.0, "contact"
                    break
                r_try = search(s_try, certify=True)
                if r_try.status == "inside":
                    s_in = _local_position(geo, r_try)
                    step *= 2.0
                    continue
                s_out, out_kind = _local_position(geo, r_try), "probe"
                break
            nudges = widenings = 0
            bisecting = True
            continue
        # undecided outside end
        if out_kind == "limit":
            break
        if nudges < 2 and abs(s_out - s_in) <= 0.75 * target:
            nudges += 1
            s_new = s_out + outward * 0.25 * target
        elif widenings < MAX_WIDENINGS:
            widenings += 1
            s_new = s_in + 2.0 * (s_out - s_in)
        else:
            break
        if (s_new > 0.0) != (s_in > 0.0):
            s_new, out_kind = 0.0, "contact"
        s_out = s_new
    width = abs(s_out - s_in) * geo.length
    certified = bool(
        status in ("bracketed", "wide") and res_out is not None and res_out.certificate_kind == "dual"
        and res_in is not None and res_in.certificate_kind == "witness"
    )
    mid = s_in if status in ("contact", "search_limit") else 0.5 * (s_in + s_out)
    return LocusEnd(
        side=side,
        status=status,
        position=mid * geo.length,
        point=geo.outline.to_world(geo.point(mid)),
        feasible_position=s_in * geo.length,
        infeasible_position=None if out_kind == "limit" else s_out * geo.length,
        width=width,
        certified=certified,
        feasible=res_in,
        infeasible=res_out,
    )


def _scan_positions(lo: float, hi: float, centre: float, n: int) -> np.ndarray:
    """n positions in [lo, hi], uniform in asinh(s - centre) (dense near the footprint,
    geometric far out), plus both ends."""
    centre = min(max(centre, lo), hi)
    u0, u1 = math.asinh(lo - centre), math.asinh(hi - centre)
    u = np.linspace(u0, u1, max(n, 2))
    return centre + np.sinh(u)


def sticking_locus(
    scene: PushScene,
    mu_c: float,
    footprint: Footprint | None = None,
    tol: SolverTolerances = SOLVER_DEFAULT,
    time_limit_s: float | None = None,
    scan_points: int = SCAN_POINTS,
    seed_tripods: int = SEED_TRIPODS,
    seed: int = 0,
) -> StickingLocus:
    """The sticking locus along the sticking line (book 4.1.4), each end bracketed to
    tol.boundary_bracket * L by a (feasible, infeasible) pair of queries.

    1. A sound search range (:func:`sticking_search_range`).
    2. Feasible seeds: sticking-mode forward CORs of ``seed_tripods`` random tripods (3.3.3,
       seeded by ``seed``) and of uniform pressure.
    3. A scan of ``scan_points`` uncertified probes over the range plus the seeds; maximal
       runs of feasible probes (never across the contact point, s = 0) are the intervals.
       A locus piece narrower than the scan's spacing that no seed hits can be missed.
    4. Each interval end is narrowed by bisection with uncertified probes and certified at
       both ends of its final bracket (:func:`_bracket_end`).
    5. The tip line's crossing (3.3.11.1) and its error against the exact end on its side.
    """
    t0 = time.perf_counter()
    deadline = None if time_limit_s is None else t0 + float(time_limit_s)
    mu = _check_mu(mu_c)
    geo = _geometry(scene, footprint, mu, tol)
    ell = geo.length
    search = _LineSearch(geo, tol, deadline)
    lo, hi, bound_name = _search_range(geo)
    s_tip, tip_point = _tip_line(scene)
    e2_world = perp(np.asarray(scene.push_hat))
    # translation along p: friction -p at the CM, balanced by a force along p through c
    translation = bool(
        abs(float(geo.c[1])) <= scene.tolerances.translation_rel
        and float(np.min(geo.cone @ np.array([1.0, 0.0]))) >= 0.0
    )

    def finish(status, intervals, scan_s, scan_st, seeds, message, time_limited):
        if translation:
            message += "; a pure translation along the push sticks (COR at infinity on the line)"
        lower = intervals[0].lower if intervals else None
        upper = intervals[-1].upper if intervals else None
        tip = _tip_estimate(s_tip, tip_point, intervals)
        complete = status in ("found", "empty") and not time_limited
        return StickingLocus(
            status=status, mu_c=mu, friction_angle=geo.nu, contact_point=np.asarray(scene.contact_point, float).copy(),
            direction=e2_world, length_scale=ell, intervals=tuple(intervals), lower=lower, upper=upper,
            multiple_intervals=len(intervals) > 1, search_range=(lo * ell, hi * ell), search_bound=bound_name,
            scan_positions=np.asarray(scan_s, dtype=float) * ell, scan_status=tuple(scan_st),
            seed_positions=np.asarray(seeds, dtype=float) * ell, tip_line=tip, n_queries=search.n_queries,
            solve_time_s=time.perf_counter() - t0, time_limited=time_limited, complete=complete, message=message,
            translation_sticks=translation,
        )

    if not lo <= hi:
        msg = "the sticking line misses every frictionless locus of the cone (sound bound)"
        return finish("empty", [], [], [], [], msg, False)

    seeds = _seed_positions(geo, footprint, seed_tripods, seed, tol)
    seeds = seeds[(seeds >= lo) & (seeds <= hi) & (seeds != 0.0)]
    if seeds.size > 32:
        seeds = np.quantile(seeds, np.linspace(0.0, 1.0, 32))
    capped = bound_name == "cap"
    margin = RANGE_MARGIN * max(1.0, hi - lo)
    lo_p, hi_p = (lo, hi) if capped else (lo - margin, hi + margin)
    centre = float(np.clip(-geo.c[1], lo, hi))
    probes = np.concatenate([_scan_positions(lo_p, hi_p, centre, scan_points), seeds])
    probes = np.unique(probes[probes != 0.0])
    scan_s, scan_st = [], []
    time_limited = False
    for s in probes:
        if search.expired():
            time_limited = True
            break
        res = search(float(s))
        if res.status == "undecided":
            res = search(float(s), certify=True)
        scan_s.append(_local_position(geo, res))
        scan_st.append(res.status)
    order = np.argsort(scan_s)
    scan_s = [scan_s[i] for i in order]
    scan_st = [scan_st[i] for i in order]
    # runs of "inside" separated by outside/undecided probes and by the contact point
    marks = [(s, st) for s, st in zip(scan_s, scan_st)]
    marks.append((0.0, "contact"))
    marks.sort(key=lambda m: m[0])
    runs = []
    i = 0
    while i < len(marks):
        if marks[i][1] != "inside":
            i += 1
            continue
        j = i
        while j + 1 < len(marks) and marks[j + 1][1] == "inside":
            j += 1
        runs.append((i, j))
        i = j + 1
    intervals = []
    incomplete = time_limited
    for i, j in runs:
        if i > 0:
            below = marks[i - 1]
            kind_lo = "contact" if below[1] == "contact" else "probe"
            s_out_lo = below[0]
        else:
            kind_lo, s_out_lo = ("limit", lo_p) if capped else ("probe", lo_p)
        if j + 1 < len(marks):
            above = marks[j + 1]
            kind_hi = "contact" if above[1] == "contact" else "probe"
            s_out_hi = above[0]
        else:
            kind_hi, s_out_hi = ("limit", hi_p) if capped else ("probe", hi_p)
        if intervals and intervals[-1].upper.feasible_position is not None and (
            intervals[-1].upper.feasible_position >= marks[i][0] * ell
        ):
            continue  # the previous interval's upper end was found beyond this run already
        lower_end = _bracket_end(search, "lower", marks[i][0], s_out_lo, kind_lo)
        upper_end = _bracket_end(search, "upper", marks[j][0], s_out_hi, kind_hi)
        if intervals and lower_end.feasible_position <= intervals[-1].upper.feasible_position:
            # one interval split by an undecided or wrongly graded probe: merge
            intervals[-1] = StickingInterval(intervals[-1].lower, upper_end)
        else:
            intervals.append(StickingInterval(lower_end, upper_end))
    for iv in intervals:
        if iv.lower.status == "undecided" or iv.upper.status == "undecided":
            incomplete = True
    time_limited = time_limited or search.expired()
    if not intervals:
        status = "incomplete" if time_limited else "empty"
        msg = "no feasible probe on the sticking line" + (" (time limit)" if time_limited else "")
        return finish(status, [], scan_s, scan_st, seeds, msg, time_limited)
    undecided_probes = scan_st.count("undecided")
    msg = f"{len(intervals)} interval(s); {undecided_probes} undecided scan probe(s)"
    return finish("incomplete" if incomplete else "found", intervals, scan_s, scan_st, seeds, msg, time_limited)


def _tip_estimate(s_tip, tip_point, intervals) -> TipLineEstimate:
    if s_tip is None:
        return TipLineEstimate(None, None, None, None, None, None)
    if s_tip < 0.0:
        side = [iv.lower for iv in intervals if iv.lower.position < 0.0]
        end = side[0] if side else None
        name = "lower"
    else:
        side = [iv.upper for iv in intervals if iv.upper.position > 0.0]
        end = side[-1] if side else None
        name = "upper"
    if end is None or end.status not in ("bracketed", "wide", "contact"):
        return TipLineEstimate(s_tip, tip_point, name, None, None, None)
    err = end.position - s_tip
    return TipLineEstimate(s_tip, tip_point, name, err, 0.5 * end.width, abs(end.position) > abs(s_tip))
