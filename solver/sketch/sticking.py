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
(F, (J c) . F) (:mod:`models.core.mpp`). Stationarity of the power f = sum_i P_i |v(w_i)| is
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

Boundary reduction (as in :mod:`solver.locus.membership`)
----------------------------------------------------------
On a ray w = r + rho u (rho > 0) d = u is constant, (w - c) . d = rho + (r - c) . u and
H = (k . u) are affine in rho, so for any (y, lambda) the dual functional

    phi(w) = y . G(w) - lambda . H(w) = y0 + y_w . w + y_m rho + q . u,
    q = y_m (r - c) - lambda_+ k_+ - lambda_- k_-                            (*)

is affine along the ray. Its minimum over the footprint is on the outline or at rho -> 0,
the point-mass value y0 + y_w . r - |q| (when r is in the footprint); and every column of
an interior point is a convex combination of the columns of its ray segment's ends. Hence
supports on the outline plus a point mass at r suffice, and pricing and the dual bound are
1-D problems over the outline. (*) is the ray functional of :mod:`solver.certify.functional`
(anchor c, d0 the direction from r to c), whose near and far forms give the sound bounds.

Certificates (Farkas): if lambda >= 0 and phi >= m on the whole footprint and point-mass
set, then for any feasible support y . b = y0 = int phi dP + lambda . int H dP >= m; so
m > y0 proves r outside. The L1-residual restricted master

    min ||e||_1 + t_+ + t_-,  sum P G + pm_G - e = b,  sum P H + pm_H + t >= 0,  t >= 0,

(:mod:`solver.certify.master`; on rows conditioned for far candidates by an equivalent
row operation and scaling, see :class:`StickingRows`) has
duals with y . G_j - lambda . H_j >= 0 on its columns and y . b = -(its optimum); reported
duals are converted back to the columns above. Column generation over
the outline (grid + golden-section refinement) ends with a polished witness (inside), a
dual whose branch-and-bound bound over the outline separates (outside, certified), or, with
``certify=False``, grid pricing only: an "outside" then has ``certificate_kind`` "none" and
``lower_bound_method`` "grid" and is no certificate.

Findings (tests/solver/sketch/test_sticking.py, docs/benchmarks.md)
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

import math
import time
from dataclasses import dataclass

import numpy as np

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.core.mpp import perp
from models.core.scene import PushScene
from models.core.support import Support
from solver.certify.answer import CertifiedPoint, answer_fields
from solver.certify.colgen import Messages, decide
from solver.certify.functional import RayFunctional, far_delta
from solver.certify.outline import ON_BOUNDARY_REL, Outline, outline_in_frame, pieces_seen_from
from solver.core.budget import UNLIMITED, Budget
from solver.core.tolerances import SOLVER_DEFAULT, SolverTolerances
from solver.motion.forward import solve_forward

ON_LINE_REL = 1e-9
"""A query point farther than this (/ L) from the sticking line is refused; closer ones are
projected onto it."""

# --------------------------------------------------------------------------------------
# Results


@dataclass(frozen=True)
class StickingResult(CertifiedPoint):
    """Answer to "can ``cor`` on the sticking line be the COR of a sticking push?" (the
    fields of :class:`solver.certify.answer.CertifiedPoint`), where

    * ``position`` s = (cor - contact) . J p (world length); ``omega`` = 1/s the rotation
      per unit push (CCW positive), ``sense``; ``mu_c`` and ``friction_angle`` nu;
    * ``certificate_kind`` may also be "contact" (r is the contact point: v(c) = 0 cannot
      follow the pusher);
    * the witness support has its centroid at the CM and ``cor`` as its sticking COR;
      ``contact_force`` F (world, per mu_s times the weight, as
      :attr:`solver.motion.forward.ForwardResult.contact_force`), ``force_angle`` its angle
      from n (CCW positive, within +-``friction_angle`` for a witness; NaN when F = 0, which
      happens only at the CM with all weight there), ``cone_slack`` min(e_+- . F) / |F|;
    * ``witness_residual``: L1 residual of the equalities plus the cone rows' violation;
    * forward re-verification of a witness (:func:`solver.motion.forward.solve_forward`,
      Newton), None when not done: ``witness_forward_mode`` and ``witness_forward_slip``
      (world length along alpha_hat per unit push) of the solve with ``mu_c``;
      ``witness_forward_cor_error`` = |COR - cor| / L of the minimum-power *sticking*
      motion of the witness: from that solve when its mode is "sticking"
      (``witness_check`` "forward"), else from a direct 1-D minimisation of the power over
      the sticking twists ("power_1d"). The mode differs from "sticking" when a point mass
      sits at r: the COR is then on a support point, the contact force is a set, and the
      forward solver tests one element of it (ours is in the cone); its slipping answer
      then has zero slip (the same motion), is flagged inconsistent, or is a second
      consistent motion (4.1 does not make the mode unique there). It also happens with F
      on the cone's edge;
    * ``dual``: (y0, y_w (2), y_m, lambda_+, lambda_-) on the world-aligned CM-frame
      columns G, H of the module docstring (lengths / L); the bound is of
      phi = y . G - lambda . H.
    """

    position: float
    omega: float
    sense: str
    mu_c: float
    friction_angle: float
    contact_force: np.ndarray
    force_angle: float
    cone_slack: float
    witness_forward_mode: str | None
    witness_forward_slip: float | None
    witness_check: str | None


# --------------------------------------------------------------------------------------
# Geometry in the dimensionless push frame


@dataclass(frozen=True)
class StickingGeometry:
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


def check_mu(mu_c) -> float:
    """mu_c as a float; InvalidInput unless it is a number >= 0 (math.inf allowed)."""
    mu = float(mu_c)
    if math.isnan(mu) or mu < 0.0:
        raise InvalidInput("mu_c", "must be a number >= 0 (math.inf: no limit on friction)")
    return mu


def sticking_geometry(
    scene: PushScene, footprint: Footprint | None, mu_c: float, tol: SolverTolerances = SOLVER_DEFAULT
) -> StickingGeometry:
    """The footprint (the scene's disk when None) and the push in the dimensionless push
    frame (x = p, y = J p, origin at the CM, lengths / L), with the friction cone of
    ``mu_c`` (checked by :func:`check_mu`)."""
    mu = check_mu(mu_c)
    p = np.asarray(scene.push_hat, dtype=float)
    frame = np.column_stack([p, perp(p)])
    outline = outline_in_frame(scene.center_of_mass, scene.disk_radius, footprint, frame, tol)
    c = outline.vector_to_local(scene.contact_rel) / outline.length
    n = outline.vector_to_local(scene.normal)
    t = outline.vector_to_local(scene.alpha_hat)
    nu = math.atan(mu)  # atan(inf) = pi/2
    sn, cs = math.sin(nu), (0.0 if math.isinf(mu) else math.cos(nu))
    cone = np.array([sn * n + cs * t, sn * n - cs * t])
    return StickingGeometry(scene, outline, c, n, t, cone, mu, nu, outline.reach(c))


def snap_on_line(geo: StickingGeometry, r: np.ndarray) -> tuple[np.ndarray, bool]:
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
    vertex = outline.snap_to_vertex(r)
    if vertex is not None:
        return vertex, True
    v = outline.vertices
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



# --------------------------------------------------------------------------------------
# One query


class StickingRows:
    """One candidate r (local, on the sticking line): its columns and dual functional
    (:class:`solver.certify.colgen.Rows`).

    Conditioning for a far r. Writing d = d0 + Delta with d0 = (c - r)/|c - r| (the
    direction from r to the contact), the moment row (ii) is replaced by the equivalent row
    kappa (w - c) . Delta with right-hand side kappa c . d0 (row (ii) minus the combination
    -c . d0 (weight row) + d0 . (centroid rows)), and the cone rows are scaled by kappa,
    kappa = max(1, |s|/D) with D = max |w - c| over the footprint. A far r makes every
    (w - c) . Delta of order D^2/|s|; the rows are then O(1) and the master's duals and
    margins keep their meaning. (A row operation: feasibility is unchanged.) Beyond
    2 D, Delta is computed without cancellation
    (:func:`solver.certify.functional.far_delta`).
    """

    def __init__(self, geo: StickingGeometry, r: np.ndarray, on_outline: bool, in_f: bool):
        self.r = r
        self.c = geo.c
        self.rc = r - geo.c
        self.abs_s = abs(float(self.rc[1]))
        self.sigma = 1.0 if self.rc[1] > 0.0 else -1.0
        self.d0 = np.array([0.0, -self.sigma])
        self.kappa = max(1.0, self.abs_s / geo.reach)
        self.k = -self.sigma * perp(geo.cone)  # rows k_+, k_- (unscaled)
        self.kk = self.kappa * self.k
        self.b = np.array([1.0, 0.0, 0.0, self.kappa * float(self.c @ self.d0)])
        self.in_footprint = in_f
        self.pieces = pieces_seen_from(geo.outline, r, on_outline)
        # (a candidate snapped off the line, rc[0] != 0, keeps the plain form u - d0)
        self.far = self.abs_s > 2.0 * geo.reach and self.rc[0] == 0.0

    def _delta(self, w: np.ndarray, u: np.ndarray, rho: np.ndarray) -> np.ndarray:
        return far_delta(w, u, rho, self.r, self.c) if self.far else u - self.d0

    def columns(self, w: np.ndarray, u: np.ndarray, rho: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """G (4, k) and H (2, k) of points w (unit directions u, distances rho > 0)."""
        m = self.kappa * np.einsum("ij,ij->i", w - self.c, self._delta(w, u, rho))
        return np.vstack([np.ones(len(w)), w.T, m]), self.kk @ u.T

    def point_mass_columns(self) -> tuple[np.ndarray, np.ndarray]:
        """The point mass on (P0, z0, z1): G part (4, 3) and H part (2, 3)."""
        ka = self.kappa
        pg = np.array([
            [1.0, 0.0, 0.0],
            [self.r[0], 0.0, 0.0],
            [self.r[1], 0.0, 0.0],
            [ka * self.abs_s, ka * self.rc[0], ka * self.rc[1]],
        ])
        return pg, np.hstack([np.zeros((2, 1)), self.kk])

    def functional(self, y: np.ndarray, lam: np.ndarray) -> RayFunctional:
        """phi = y . G - lambda . H = (y0 - Q . d0) + y_w . w + (kappa y_m (w - c) - Q) . Delta,
        Q = kappa lambda . k: the ray functional with anchor c."""
        qv = lam @ self.kk
        return RayFunctional(self.r, float(y[0] - qv @ self.d0), y[1:3].copy(), float(y[3] * self.kappa), qv,
                             self.c, self.d0, far=self.far)

    def original_dual(self, y: np.ndarray, lam: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(y, lambda) on the unscaled columns (1, w, (w - c) . d) and (k . d): the same
        functional phi and the same y . b."""
        ka = self.kappa
        y0 = y[0] + y[3] * ka * float(self.c @ self.d0)
        yw = y[1:3] - y[3] * ka * self.d0
        return np.concatenate([[y0], yw, [y[3] * ka]]), ka * np.asarray(lam, dtype=float)


MESSAGES = Messages(
    inside="witness support: sticking stationarity with the force in the friction cone",
    outside="certified dual: y . G - lambda . H >= lower bound on the whole footprint",
)


def decide_on_line(
    geo: StickingGeometry,
    r_local: np.ndarray,
    tol: SolverTolerances,
    budget: Budget,
    warm_points=None,
    verify_witness: bool = True,
    certify: bool = True,
) -> StickingResult:
    """Decide the local point ``r_local`` on the sticking line (see
    :func:`sticking_feasibility`; ``warm_points`` in the world frame)."""
    t_start = time.perf_counter()
    outline = geo.outline
    ell = outline.length
    scene = geo.scene
    r, on_outline = snap_on_line(geo, r_local)
    in_f = outline.contains(r, on_outline)
    s_loc = float(r[1] - geo.c[1])
    cor_world = outline.to_world(r)
    position = s_loc * ell
    if s_loc == 0.0:
        return StickingResult(
            status="outside", cor=cor_world, certificate_kind="contact", witness_points=np.zeros((0, 2)),
            witness_weights=np.zeros(0), point_mass_at_cor=0.0, point_mass_subgradient=np.zeros(2),
            witness_residual=math.inf, witness_forward_cor_error=None, dual=None, dual_lower_bound=None,
            dual_margin=None, lower_bound_method=None, iterations=0, n_columns=0, bnb_intervals=0,
            in_footprint=in_f, length_scale=ell,
            message="the contact point: a rotation about it cannot move the contact along the push",
            solve_time_s=time.perf_counter() - t_start, position=position, omega=math.nan, sense="none",
            mu_c=geo.mu_c, friction_angle=geo.nu, contact_force=np.zeros(2), force_angle=math.nan,
            cone_slack=math.nan, witness_forward_mode=None, witness_forward_slip=None, witness_check=None,
        )
    rows = StickingRows(geo, r, on_outline, in_f)
    warm_local = None
    if warm_points is not None:
        warm_local = outline.to_local(np.asarray(warm_points, dtype=float).reshape(-1, 2))
    dec = decide(rows, tol, budget, MESSAGES, warm_local, certify)

    p_mass = float(dec.point_mass[0]) if in_f else 0.0
    z_loc = dec.point_mass[1:3] if in_f else np.zeros(2)
    wl, ww = dec.points, dec.weights
    e = wl - r
    d = e / np.hypot(e[:, 0], e[:, 1])[:, None]
    dvec = ww @ d + z_loc if len(ww) else z_loc.copy()
    f_loc = rows.sigma * perp(dvec)
    f_norm = float(np.hypot(f_loc[0], f_loc[1]))
    angle = math.atan2(float(f_loc @ geo.t), float(f_loc @ geo.n)) if f_norm > 0.0 else math.nan
    slack = float(np.min(geo.cone @ f_loc)) / f_norm if f_norm > 0.0 else 0.0
    forward_err = forward_mode = forward_slip = check = None
    if dec.status == "inside" and verify_witness:
        forward_err, forward_mode, forward_slip, check = _forward_check(
            scene, geo, outline.to_world(wl), ww, p_mass, cor_world, tol)
    dual = None
    if dec.y is not None and dec.lam is not None:
        yo, lo_ = rows.original_dual(dec.y, dec.lam)
        dual = np.concatenate([[yo[0]], outline.vector_to_world(yo[1:3]), [yo[3]], lo_])
    omega = 1.0 / position
    return StickingResult(
        **answer_fields(dec, outline, r, in_f, dual, forward_err, time.perf_counter() - t_start),
        position=position, omega=omega, sense="ccw" if omega > 0.0 else "cw", mu_c=geo.mu_c,
        friction_angle=geo.nu, contact_force=outline.vector_to_world(f_loc), force_angle=angle,
        cone_slack=slack, witness_forward_mode=forward_mode, witness_forward_slip=forward_slip,
        witness_check=check,
    )


def sticking_motion_position(w_local, weights, c_local, s_guess: float) -> float:
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


def _forward_check(scene, geo: StickingGeometry, pts, weights, p_mass, cor_world, tol):
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
    s_star = sticking_motion_position(geo.outline.to_local(support.points), support.weights, geo.c, s_loc)
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
    budget: Budget = UNLIMITED,
    warm_points=None,
    verify_witness: bool = True,
    certify: bool = True,
) -> StickingResult:
    """Is ``r_world`` (on the sticking line) the COR of a sticking push for some pressure
    distribution on the footprint (the scene's disk when None)? See the module docstring.

    ``mu_c`` >= 0 (math.inf allowed). A point farther than ``ON_LINE_REL`` L from the
    sticking line is refused (InvalidInput), a closer one projected onto it. ``budget``:
    the query stops undecided when it expires. ``certify=False`` decides "outside" on grid
    pricing only (no certificate).
    """
    geo = sticking_geometry(scene, footprint, mu_c, tol)
    r_in = np.asarray(r_world, dtype=float)
    if r_in.shape != (2,) or not np.all(np.isfinite(r_in)):
        raise InvalidInput("cor", "must be a finite point [x, y]")
    r = geo.outline.to_local(r_in)
    if abs(r[0] - geo.c[0]) > ON_LINE_REL * max(1.0, abs(r[1])):
        raise InvalidInput(
            "cor",
            "is not on the sticking line (the line through the contact point perpendicular to the push)",
        )
    return decide_on_line(geo, np.array([geo.c[0], r[1]]), tol, budget, warm_points, verify_witness, certify)
