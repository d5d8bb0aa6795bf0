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
the columns G(w) = (1, w/L, g_r(w)/L) in R^5 (:func:`models.core.mpp.membership_columns`) and
b = (1, 0, 0, 0, 0): r is a COR for some pressure distribution on the footprint F iff b
lies in the convex hull of

    S = {G(w) : w in F, w != r}  (+ the point-mass set {(1, r/L, -s zeta/L) : |zeta| <= 1}
                                    when r lies in F),

the second part being a mass P0 at r itself: the subgradient of |w - r| at w = r is the
unit disk, so such a mass contributes (P0, P0 r/L, -s z/L) with |z| <= P0 (a second-order
cone). When r is outside F the term is absent. b is outside the hull iff some y in R^5
separates them (Farkas). Every column is affine along rays from r, so supports on the
outline plus the point mass suffice, and pricing and the dual bound are 1-D problems over
the outline: :mod:`solver.certify` decides the question by column generation (witness
inside, branch-and-bound certificate outside).

Rows near and far
-----------------
A candidate is decided on the rows above (:class:`PlainRows`). Far from the footprint
(|s| > ``FAR_REACH`` D, D = max |w - c| over F) one that they leave undecided is decided
again on an equivalent, conditioned pair in place of g_r . alpha and g_r . n
(:class:`ConditionedRows`): with m = n . (r - c),

    (w - c) . u = g . alpha - (m / s) g . n     (the moment about the contact c),
    n . u       = -(1 / s) g . n                (the friction force along alpha),

rewritten with u = d0 + Delta (d0 the direction from r to c, Delta = O(D/|r|) computed
without cancellation, :func:`solver.certify.functional.far_delta`) and scaled by
kappa = |c - r| / D, exactly as the sticking locus's rows (:mod:`solver.sketch.sticking`).
On the plain rows a point delta beyond a boundary |s| ~ 185 L away is separated by a
margin of order delta / s^2 (below ``certificate_margin``, "undecided"); on the
conditioned rows by order delta / |s|. The reported dual is always converted back to the
plain columns G.

Observations (tests/solver/locus/test_membership.py)
----------------------------------------------------
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

import dataclasses
import time
from dataclasses import dataclass

import numpy as np

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.core.mpp import perp
from models.core.scene import PushScene
from models.core.support import Support
from solver.certify.answer import CertifiedPoint, answer_fields
from solver.certify.colgen import Decision, Messages, decide
from solver.certify.functional import RayFunctional, far_delta
from solver.certify.outline import Outline, outline_in_frame, pieces_seen_from
from solver.core.budget import UNLIMITED, Budget
from solver.core.tolerances import SOLVER_DEFAULT, SolverTolerances
from solver.motion.forward import solve_forward

FAR_REACH = 2.0
"""A candidate with |s| > FAR_REACH * D (D the footprint's reach from the contact) that the
plain rows leave undecided is decided again on the conditioned rows (module docstring)."""

MESSAGES = Messages(
    inside="witness support satisfies (3.8) with the centroid at the CM",
    outside="certified dual: y . G >= lower bound on the whole footprint",
)


@dataclass(frozen=True)
class MembershipResult(CertifiedPoint):
    """Answer to "can ``cor`` be the COR of a push of this footprint?" with its certificate
    (the fields of :class:`solver.certify.answer.CertifiedPoint`), where

    * the witness support has its centroid at the CM and ``cor`` as its COR, weights
      summing to 1 with the point mass; the point mass contributes -s z / L to (3.8) (the
      subgradient of |w - r| at w = r scaled by the mass);
    * ``witness_residual`` is the L1 residual of the membership equations (on the
      conditioned rows for a far candidate, ``rows`` "far");
    * ``witness_forward_cor_error`` compares with the forward minimum-power solver's COR;
    * ``dual`` (5,) is the separating functional y on the columns of
      :func:`models.core.mpp.membership_columns` (world-aligned CM frame, lengths / L). Near the
      footprint it is computed with |y|_inf <= 1 in the locus frame, so |y_w|, |y_g| <=
      sqrt(2) here; a far candidate's is converted from the conditioned rows and can be
      larger; ``dual_margin`` = m_F - y . b;
    * ``rows``: "near" or "far" (module docstring).
    """

    rows: str = "near"


def outline_of(scene: PushScene, footprint: Footprint | None, tol: SolverTolerances = SOLVER_DEFAULT) -> Outline:
    """The footprint (or the scene's disk when None) in the dimensionless locus frame
    (docs/mechanics.md): origin at the CM, x along the scene's axis
    alpha' = sign(alpha . c) alpha_hat, y = z x alpha', lengths divided by L. Working in it
    makes every computed number invariant under translations, rotations, mirror images
    and scalings of the scene (3.3.12). A polygon's centre of mass must be the scene's
    (3.1.5); L is its circumradius (3.1.8)."""
    e1 = np.asarray(scene.axis, dtype=float)
    frame = np.column_stack([e1, perp(e1)])
    return outline_in_frame(scene.center_of_mass, scene.disk_radius, footprint, frame, tol)


class PlainRows:
    """The plain rows (1, w, rho alpha - s u) with b = (1, 0, 0, 0, 0); the dual functional
    y0 + y_w . w + (y_g . alpha) rho - s y_g . u (anchor r, no far form)."""

    def __init__(self, outline: Outline, r: np.ndarray, on_outline: bool, in_f: bool,
                 alpha: np.ndarray, s: float):
        self.r, self.alpha, self.s = r, alpha, s
        self.in_footprint = in_f
        self.pieces = pieces_seen_from(outline, r, on_outline)
        self.b = np.array([1.0, 0.0, 0.0, 0.0, 0.0])

    def columns(self, w: np.ndarray, u: np.ndarray, rho: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        g = rho[:, None] * self.alpha[None, :] - self.s * u
        return np.vstack([np.ones(len(w)), w.T, g.T]), np.zeros((0, len(w)))

    def point_mass_columns(self) -> tuple[np.ndarray, np.ndarray]:
        r, s = self.r, self.s
        pg = np.array([[1.0, 0.0, 0.0], [r[0], 0.0, 0.0], [r[1], 0.0, 0.0], [0.0, -s, 0.0], [0.0, 0.0, -s]])
        return pg, np.zeros((0, 3))

    def functional(self, y: np.ndarray, lam: np.ndarray) -> RayFunctional:
        zero = np.zeros(2)
        return RayFunctional(self.r, float(y[0]), y[1:3].copy(), float(y[3:5] @ self.alpha), self.s * y[3:5],
                             self.r, zero, far=False)

    def plain_dual(self, y: np.ndarray) -> np.ndarray:
        """y on the plain columns (here: y itself)."""
        return y


class ConditionedRows:
    """The conditioned rows (1, w, kappa (w - c) . Delta, kappa n . Delta) with
    b = (1, 0, 0, kappa c . d0, -kappa n . d0) (module docstring)."""

    def __init__(self, outline: Outline, r: np.ndarray, on_outline: bool, in_f: bool,
                 alpha: np.ndarray, n: np.ndarray, c: np.ndarray, s: float, reach: float):
        self.r, self.alpha, self.n, self.c, self.s = r, alpha, n, c, s
        self.in_footprint = in_f
        self.pieces = pieces_seen_from(outline, r, on_outline)
        self.rc = r - c
        self.dist = float(np.hypot(self.rc[0], self.rc[1]))
        self.d0 = -self.rc / self.dist
        self.kappa = self.dist / reach
        ka = self.kappa
        self.b = np.array([1.0, 0.0, 0.0, ka * float(c @ self.d0), -ka * float(n @ self.d0)])

    def columns(self, w: np.ndarray, u: np.ndarray, rho: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        dl = far_delta(w, u, rho, self.r, self.c)
        moment = self.kappa * np.einsum("ij,ij->i", w - self.c, dl)
        direction = self.kappa * (dl @ self.n)
        return np.vstack([np.ones(len(w)), w.T, moment, direction]), np.zeros((0, len(w)))

    def point_mass_columns(self) -> tuple[np.ndarray, np.ndarray]:
        ka, r, rc, n = self.kappa, self.r, self.rc, self.n
        pg = np.array([
            [1.0, 0.0, 0.0],
            [r[0], 0.0, 0.0],
            [r[1], 0.0, 0.0],
            [ka * self.dist, ka * rc[0], ka * rc[1]],
            [-ka * float(n @ self.d0), ka * n[0], ka * n[1]],
        ])
        return pg, np.zeros((0, 3))

    def functional(self, y: np.ndarray, lam: np.ndarray) -> RayFunctional:
        return RayFunctional(self.r, float(y[0]), y[1:3].copy(), self.kappa * float(y[3]),
                             -self.kappa * float(y[4]) * self.n, self.c, self.d0, far=True)

    def plain_dual(self, y: np.ndarray) -> np.ndarray:
        """The same functional on the plain columns (1, w, g): with beta = kappa y_3,
        q = -kappa y_4 n and m = n . (r - c), y_g = beta alpha - ((beta m + kappa y_4)/s) n
        (module docstring)."""
        fn = self.functional(y, np.zeros(0))
        a_o, b_o, _ = fn.near_coefficients()
        m = float(self.n @ self.rc)
        y_g = fn.beta * self.alpha - ((fn.beta * m + self.kappa * float(y[4])) / self.s) * self.n
        return np.concatenate([[a_o], b_o, y_g])


def _forward_cor(scene: PushScene, points_world: np.ndarray, weights: np.ndarray, tol: SolverTolerances):
    """COR of a support by the forward minimum-power solver (exact Newton, 3.7); world
    frame, or None for a translation."""
    support = Support.create(points_world, weights, scene.center_of_mass, tol)
    return solve_forward(scene, support, mu_c=0.0, method="newton", tol=tol).cor


def membership(
    scene: PushScene,
    r_world,
    footprint: Footprint | None = None,
    tol: SolverTolerances = SOLVER_DEFAULT,
    budget: Budget = UNLIMITED,
    warm_points=None,
    verify_witness: bool = True,
    certify: bool = True,
) -> MembershipResult:
    """Is ``r_world`` the COR of some pressure distribution on the footprint? (see module)

    ``footprint``: a polygon whose centre of mass is the scene's, or None for the scene's
    disk. ``budget``: the query stops undecided when it expires. ``warm_points`` (k, 2)
    world: extra initial support points on the footprint's outline (e.g. the previous
    query's witness). ``verify_witness``: re-solve the forward problem for an inside
    witness. ``certify=False`` skips the branch and bound: an "outside" answer is then
    based on the grid only (``lower_bound_method`` "grid", ``certificate_kind`` "none")
    and is no certificate.
    """
    t_start = time.perf_counter()
    outline = outline_of(scene, footprint, tol)
    ell = outline.length
    r_in = np.asarray(r_world, dtype=float)
    if r_in.shape != (2,) or not np.all(np.isfinite(r_in)):
        raise InvalidInput("cor", "must be a finite point [x, y]")
    r_local = outline.to_local(r_in)
    dist = float(np.hypot(r_local[0], r_local[1]))
    if not dist <= tol.max_cor_distance_rel:  # also catches an overflow to inf or nan
        raise InvalidInput(
            "cor",
            f"is {float(np.hypot(*(r_in - scene.center_of_mass))):.3g} from the centre of mass, more than "
            f"{tol.max_cor_distance_rel:g} times the part's size L = {ell:.3g}: beyond what the certificates "
            "resolve (give the part's size in a unit closer to the distances)",
        )
    r, on_outline = outline.snap(r_local)
    in_f = outline.contains(r, on_outline)
    alpha = outline.vector_to_local(scene.alpha_hat)
    c = outline.vector_to_local(scene.contact_rel) / ell
    s = float(alpha @ (c - r))
    warm_local = None if warm_points is None else outline.to_local(np.asarray(warm_points, dtype=float).reshape(-1, 2))
    rows: PlainRows | ConditionedRows = PlainRows(outline, r, on_outline, in_f, alpha, s)
    dec: Decision = decide(rows, tol, budget, MESSAGES, warm_local, certify)
    reach = outline.reach(c)
    if dec.status == "undecided" and abs(s) > FAR_REACH * reach and not budget.expired():
        # far from the footprint the plain rows lose the margin (module docstring): decide
        # again on the conditioned rows, warm-started with the plain master's support
        rows = ConditionedRows(outline, r, on_outline, in_f, alpha, outline.vector_to_local(scene.normal), c, s, reach)
        warm = dec.points if warm_local is None else np.vstack([dec.points, warm_local])
        plain = dec
        dec = decide(rows, tol, budget, MESSAGES, warm, certify)
        dec = dataclasses.replace(dec, iterations=plain.iterations + dec.iterations,
                                  bnb_intervals=plain.bnb_intervals + dec.bnb_intervals)

    forward_err = None
    if dec.status == "inside" and verify_witness:
        supp, sw = outline.to_world(dec.points), dec.weights
        p_mass = float(dec.point_mass[0]) if in_f else 0.0
        if p_mass > 0.0:
            supp = np.vstack([supp, outline.to_world(r)])
            sw = np.concatenate([sw, [p_mass]])
        fwd = _forward_cor(scene, supp, sw, tol)
        forward_err = None if fwd is None else float(np.linalg.norm(fwd - outline.to_world(r)) / ell)
    dual = None
    if dec.y is not None:
        y = rows.plain_dual(dec.y)
        dual = np.concatenate([[y[0]], outline.vector_to_world(y[1:3]), outline.vector_to_world(y[3:5])])
    fields = answer_fields(dec, outline, r, in_f, dual, forward_err, time.perf_counter() - t_start)
    return MembershipResult(**fields, rows="far" if isinstance(rows, ConditionedRows) else "near")


@dataclass(frozen=True)
class MembershipProblem:
    """"Can ``cor`` (world) be the COR of the push ``scene``, for some pressure distribution
    on ``footprint`` (None: the scene's disk)?" Frictionless pusher (book 3.3.2-3.3.13)."""

    scene: PushScene
    cor: np.ndarray
    footprint: Footprint | None = None
    tol: SolverTolerances = SOLVER_DEFAULT


def decide_membership(problem: MembershipProblem, budget: Budget = UNLIMITED) -> MembershipResult:
    """:func:`membership` of ``problem`` within ``budget`` (undecided when it runs out)."""
    return membership(problem.scene, problem.cor, problem.footprint, tol=problem.tol, budget=budget)
