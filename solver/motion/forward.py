"""The motion of a pushed workpiece on a known support (book ch. 2, 3.2-3.3.3, 4.1).

Given support points w_i with weights P_i (centroid at the CM) and a push, the workpiece
moves so as to minimise the frictional power (the minimum power principle, ch. 2):

* mu_c = 0: minimise sum_i P_i |v(w_i)| over twists whose contact point advances along the
  normal as fast as the pusher, n . v(c) = n . p (3.3)-(3.7);
* mu_c > 0 (4.1): *sticking* (v(c) = p, the contact force must lie in the friction cone),
  or *slipping* up or down: then the force lies on a cone edge, at angle alpha +- nu with
  nu = atan(mu_c), and the motion is the frictionless one for that edge (4.1.3), scaled so
  the contact keeps up with the pusher. The mode whose own assumptions hold is returned.

Three independent back ends solve the convex minimum-power problem:

* ``newton``: exact non-smooth optima (COR on a support point) by a subgradient test,
  damped Newton elsewhere; compiled a problem at a time (solver.kernels.forward), with
  solver.motion.newton (vectorised over batches) as the reference and the path of the rare
  problem the kernel leaves unsolved;
* ``cvxpy``: the second-order cone programme, compiled once per support size and thread
  with cvxpy Parameters (DPP) and re-solved with Clarabel; optionally polished by exact
  KKT steps;
* ``casadi``: the dual problem (largest contact force that the support's friction forces,
  each of size at most P_i, can balance) solved by IPOPT; the twist is the multiplier of
  the balance equations.

Units: lengths are divided by L (largest |w_i - CM| or |c - CM|), forces and powers by
mu_s times the total weight. Results are reported in world units.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass
from typing import Literal

import numpy as np

from models.core.errors import InvalidInput
from models.core.mpp import perp
from models.core.scene import PushScene
from models.core.support import Support
from solver.core.backends import in_backend
from solver.core.errors import BackendNotFound, NotConverged
from solver.core.threads import CasadiFunction, PerThreadCache, ignore_inaccurate_solution_warning
from solver.core.tolerances import SOLVER_DEFAULT, SolverTolerances
from solver.kernels import codes as _codes
from solver.motion import newton as _newton

Method = Literal["newton", "cvxpy", "casadi"]
Mode = Literal["frictionless", "sticking", "slipping_up", "slipping_down"]
METHODS: tuple[str, ...] = ("newton", "cvxpy", "casadi")

_MODE_NAMES = ("frictionless", "sticking", "slipping_up", "slipping_down")


@dataclass(frozen=True)
class ForwardResult:
    """Motion per unit push (world frame) and how good it is.

    ``cor`` is None for a pure translation. ``omega`` is the rotation per unit push, rad per
    unit length, CCW positive; ``slip`` the slip of the pusher along alpha_hat per unit
    push. ``power`` is the dissipated power per unit push / (mu_s W); ``contact_force`` the
    force of the pusher on the part / (mu_s W) (world vector). ``kkt_residual`` is the
    dimensionless KKT residual and ``gap`` = power - contact force . pusher velocity, which
    is zero at the optimum (the pusher does all the work that friction dissipates).
    ``status`` is "optimal" when kkt_residual <= tol.kkt_accept and the mode is consistent.
    ``cor_on_support`` is the index of the support point the COR sits on, if any.
    ``iterations``: Newton iterations (0 for a COR found on a support point), or IPOPT's.
    ``raw_twist_error`` is, for polished cvxpy results, the distance (normalised units)
    between the conic solver's own answer and the polished one.
    """

    status: str
    method: str
    mode: str
    cor: np.ndarray | None
    velocity_cm: np.ndarray
    omega: float
    sense: str
    slip: float
    power: float
    contact_force: np.ndarray
    kkt_residual: float
    gap: float
    cor_on_support: int | None
    iterations: int
    solve_time_s: float
    raw_twist_error: float | None = None

    @property
    def complete(self) -> bool:
        """The answer is the optimum (``status`` "optimal"); "not_converged" (the KKT
        residual missed ``kkt_accept``) and "inconsistent" (no mode's assumptions held)
        are not."""
        return self.status == "optimal"

    @property
    def message(self) -> str:
        where = "a translation" if self.cor is None else f"COR ({self.cor[0]:.6g}, {self.cor[1]:.6g})"
        return f"{self.status} {self.mode} motion by {self.method}: {where}, KKT residual {self.kkt_residual:.2g}"


@dataclass(frozen=True)
class BatchResult(_newton.BatchConvergence):
    """Arrays over a batch; ``cor`` rows are NaN for translations; ``mode`` holds indices
    into MODES; ``converged`` is True where kkt <= tol.kkt_accept and the mode was
    consistent (``status`` "optimal" when it is everywhere). ``slip``, ``gap`` and
    ``iterations`` as in ForwardResult. ``reference_rows``: problems the compiled Newton
    solve did not solve, solved again on the reference path; ``fallbacks``: those of them
    the conic solver re-solved."""

    cor: np.ndarray
    omega: np.ndarray
    velocity_cm: np.ndarray
    power: np.ndarray
    contact_force: np.ndarray
    kkt_residual: np.ndarray
    mode: np.ndarray
    cor_on_support: np.ndarray
    converged: np.ndarray
    solve_time_s: float
    slip: np.ndarray
    gap: np.ndarray
    iterations: np.ndarray
    fallbacks: int = 0
    reference_rows: int = 0
    consistent: np.ndarray | None = None

    MODES = _MODE_NAMES

    @property
    def message(self) -> str:
        text = f"{self.converged_count()} supports converged"
        if self.reference_rows:
            text += f" ({self.reference_rows} re-solved on the reference path"
            text += f", {self.fallbacks} of them by the conic solver)" if self.fallbacks else ")"
        return text


# --------------------------------------------------------------------------------------
# Normalised problem data


@dataclass(frozen=True)
class SceneArrays:
    """The geometry of one push scene per problem of a batch (CM frame): the contact c
    (B, 2), the edge's normal n and direction alpha_hat (B, 2), the push direction (B, 2)
    and sin(alpha) (B,). One scene repeated (or given once, B = 1, for every problem of a
    batch), or a scene per problem (the same part at different poses, as a simulator steps
    many parts together)."""

    contact_rel: np.ndarray
    normal: np.ndarray
    alpha_hat: np.ndarray
    push_hat: np.ndarray
    sin_alpha: np.ndarray

    @classmethod
    def repeat(cls, scene: PushScene, b: int) -> SceneArrays:
        def rows(v: np.ndarray) -> np.ndarray:
            return np.broadcast_to(np.asarray(v, dtype=float), (b, 2)).copy()

        return cls(rows(scene.contact_rel), rows(scene.normal), rows(scene.alpha_hat), rows(scene.push_hat),
                   np.full(b, float(scene.sin_alpha)))

    @classmethod
    def stack(cls, scenes: list[PushScene]) -> SceneArrays:
        return cls(np.array([sc.contact_rel for sc in scenes], dtype=float),
                   np.array([sc.normal for sc in scenes], dtype=float),
                   np.array([sc.alpha_hat for sc in scenes], dtype=float),
                   np.array([sc.push_hat for sc in scenes], dtype=float),
                   np.array([sc.sin_alpha for sc in scenes], dtype=float))


def _length_scale(contact_rel: np.ndarray, w_rel: np.ndarray) -> np.ndarray:
    """L per problem: the largest distance of a support point or the contact from the CM.

    L = 0 (every support point and the contact at the CM) leaves the rotation free: the
    motion is not determined, which is refused as an input error."""
    # hypot, not norm: the squares of lengths below ~1e-154 underflow to zero
    lw = np.max(np.hypot(w_rel[..., 0], w_rel[..., 1]), axis=-1)
    ell = np.maximum(lw, np.hypot(contact_rel[:, 0], contact_rel[:, 1]))
    if not np.all(ell > 0.0):
        raise InvalidInput(
            "points",
            "every support point and the contact are at the centre of mass: the rotation is undetermined",
        )
    return ell


def _rows_frictionless(direction: np.ndarray, c_n: np.ndarray) -> np.ndarray:
    """(B, 1, 3) contact rows (d, d . J c) for unit force directions d (B, 2) and c/L (B, 2)."""
    jc = perp(c_n)
    b = c_n.shape[0]
    row = np.empty((b, 1, 3))
    row[:, 0, :2] = direction
    row[:, 0, 2] = np.einsum("bi,bi->b", jc, direction)
    return row


def _rows_sticking(c_n: np.ndarray) -> np.ndarray:
    """(B, 2, 3): v + omega J c = p."""
    jc = perp(c_n)
    b = c_n.shape[0]
    m = np.zeros((b, 2, 3))
    m[:, 0, 0] = 1.0
    m[:, 1, 1] = 1.0
    m[:, :, 2] = jc
    return m


class _Backend:
    def solve(self, w, p, m, q, tol: SolverTolerances):  # pragma: no cover - interface
        raise NotImplementedError


class _NewtonBackend(_Backend):
    name = "newton"

    def __init__(self):
        self.fallbacks = 0
        self.cone = None

    def solve(self, w, p, m, q, tol):
        sol = _newton.solve_batch(w, p, m, q, tol.kkt, tol.max_newton_iter, cone=self.cone)
        x, mult, kkt, vertex, iters = sol.x, sol.multipliers, sol.kkt, sol.vertex, sol.iterations
        # Rare failures (Newton stalled on a kink that is not the optimum) are re-solved by
        # the conic solver, polished; their count is reported.
        bad = np.nonzero(~sol.converged)[0]
        if bad.size:
            self.fallbacks += int(bad.size)
            xb, mb, kb, vb, ib, _ = _CvxpyBackend(polish=True).solve(w[bad], p[bad], m[bad], q[bad], tol)
            x, mult, kkt, vertex, iters = x.copy(), mult.copy(), kkt.copy(), vertex.copy(), iters.copy()
            x[bad], mult[bad], kkt[bad], vertex[bad], iters[bad] = xb, mb, kb, vb, ib
        return x, mult, kkt, vertex, iters, None


CACHE_SIZE = 32
"""Compiled problems kept per back end and thread (one per support size and row count;
support sizes are chosen by clients, so the oldest is dropped beyond this)."""

_CONIC_PROBLEMS: PerThreadCache = PerThreadCache(CACHE_SIZE)
"""(k, rows) -> this thread's compiled cvxpy problem and its variables and Parameters."""

_IPOPT_SOLVERS: PerThreadCache = PerThreadCache(CACHE_SIZE)
"""(k, rows, casadi_tol) -> this thread's CasADi/IPOPT Function of the dual problem."""


class _CvxpyBackend(_Backend):
    """Clarabel on the cone programme, one compiled problem per (k, rows) and thread,
    re-solved with new Parameter values."""

    name = "cvxpy"

    def __init__(self, polish: bool = True):
        self.polish = polish
        self.cone = None

    @staticmethod
    def _build(k: int, rows: int):
        import cvxpy as cp

        x = cp.Variable(3)
        jw = cp.Parameter((k, 2))
        pw = cp.Parameter(k, nonneg=True)
        m = cp.Parameter((rows, 3))
        q = cp.Parameter(rows)
        vel = cp.vstack([x[0] + x[2] * jw[:, 0], x[1] + x[2] * jw[:, 1]])  # (2, k)
        # sum_i P_i |v(w_i)| through epigraph variables t_i >= |v(w_i)|: the objective is
        # then affine in the Parameter P (DPP), so cvxpy compiles the problem once and only
        # substitutes new Parameter values on each solve
        speed = cp.Variable(k)
        con = m @ x == q
        prob = cp.Problem(cp.Minimize(pw @ speed), [con, cp.norm(vel, 2, axis=0) <= speed])
        return prob, x, jw, pw, m, q, con

    def solve(self, w, p, m, q, tol):
        import cvxpy as cp

        b, k, _ = w.shape
        rows = m.shape[1]
        prob, xv, jwp, pwp, mp, qp, con = _CONIC_PROBLEMS.get((k, rows), lambda: self._build(k, rows))
        xs = np.zeros((b, 3))
        for i in range(b):
            jwp.value = perp(w[i])
            pwp.value = p[i]
            mp.value = m[i]
            qp.value = q[i]
            try:
                ignore_inaccurate_solution_warning()
                # warm_start=False: a fresh Clarabel solve, so that the answer does not
                # depend on the problems this thread solved before
                with in_backend("clarabel"):
                    prob.solve(
                        solver=cp.CLARABEL,
                        warm_start=False,
                        tol_gap_abs=tol.conic_gap,
                        tol_gap_rel=tol.conic_gap,
                        tol_feas=tol.conic_gap,
                        tol_ktratio=tol.conic_ktratio,
                    )
            except cp.error.SolverError as exc:
                raise NotConverged(f"Clarabel failed on the minimum-power problem: {exc}") from exc
            if prob.status not in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE):
                raise NotConverged(f"minimum-power problem ended with status {prob.status}")
            xs[i] = xv.value
        if not self.polish:
            kkt, mult, vtx = _newton.kkt_residual(w, p, m, q, xs)
            return xs, mult, kkt, vtx, np.zeros(b, dtype=int), None
        # Polish: exact KKT steps from the conic answer (vertex test + Newton).
        sol = _newton.solve_batch(w, p, m, q, tol.kkt, tol.max_newton_iter, x0=xs, cone=self.cone)
        raw = np.linalg.norm(sol.x - xs, axis=1)
        return sol.x, sol.multipliers, sol.kkt, sol.vertex, sol.iterations, raw


class _CasadiBackend(_Backend):
    """IPOPT on the dual: maximise mu . q subject to sum_i A_i^T z_i = M^T mu, |z_i| <= P_i.

    z_i is the friction force of support i (3.5); the twist is the multiplier of the
    balance equations.
    """

    name = "casadi"

    @staticmethod
    def _build(k: int, rows: int, tol: SolverTolerances):
        import casadi as ca

        z = ca.SX.sym("z", 2 * k)  # z_i = P_i * zeta_i, |zeta_i| <= 1
        mu = ca.SX.sym("mu", rows)
        par = ca.SX.sym("par", 3 * k + 3 * rows + rows)  # jw (2k), P (k), M (3 rows), q
        jw = ca.reshape(par[: 2 * k], 2, k)
        pw = par[2 * k : 3 * k]
        mm = ca.reshape(par[3 * k : 3 * k + 3 * rows], rows, 3)
        q = par[3 * k + 3 * rows :]
        zz = ca.reshape(z, 2, k)
        force = ca.vertcat(
            ca.sum2(pw.T * zz[0, :]),
            ca.sum2(pw.T * zz[1, :]),
            ca.sum2(pw.T * (zz[0, :] * jw[0, :] + zz[1, :] * jw[1, :])),
        )
        balance = force - mm.T @ mu
        norms = zz[0, :].T ** 2 + zz[1, :].T ** 2
        nlp = {"x": ca.vertcat(z, mu), "p": par, "f": -ca.dot(mu, q), "g": ca.vertcat(balance, norms)}
        opts = {
            "ipopt.tol": tol.casadi_tol,
            "ipopt.acceptable_tol": tol.casadi_tol,
            "ipopt.print_level": 0,
            "print_time": False,
            "ipopt.sb": "yes",
            "ipopt.max_iter": 500,
        }
        return ca.nlpsol("mpp_dual", "ipopt", nlp, opts)

    def solve(self, w, p, m, q, tol):
        b, k, _ = w.shape
        rows = m.shape[1]
        solver = _IPOPT_SOLVERS.get((k, rows, tol.casadi_tol), lambda: CasadiFunction(lambda: self._build(k, rows, tol)))
        xs = np.zeros((b, 3))
        its = np.zeros(b, dtype=int)
        lbg = np.concatenate([np.zeros(3), np.zeros(k)])
        ubg = np.concatenate([np.zeros(3), np.ones(k)])
        for i in range(b):
            par = np.concatenate([perp(w[i]).T.reshape(-1, order="F"), p[i], m[i].reshape(-1, order="F"), q[i]])
            try:
                with in_backend("casadi"):
                    res = solver(x0=np.zeros(2 * k + rows), p=par, lbg=lbg, ubg=ubg)
            except RuntimeError as exc:
                raise NotConverged(f"IPOPT failed on the dual minimum-power problem: {exc}") from exc
            stats = solver.stats()
            if not stats.get("success", False):
                raise NotConverged(f"IPOPT ended with {stats.get('return_status')}")
            # Lagrangian f + lam_g . g: the balance multipliers are -x (f = -mu.q).
            xs[i] = np.asarray(res["lam_g"]).reshape(-1)[:3]
            its[i] = int(stats.get("iter_count", 0))
        xs = _orient(xs, m, q)
        kkt, mult, vtx = _newton.kkt_residual(w, p, m, q, xs)
        return xs, mult, kkt, vtx, its, None


def _orient(xs, m, q):
    """Fix the sign convention of multipliers: M x must equal q (not -q)."""
    mx = np.einsum("bri,bi->br", m, xs)
    sgn = np.sign(np.einsum("br,br->b", mx, q))
    sgn[sgn == 0] = 1.0
    return xs * sgn[:, None]


def _backend(method: str, polish: bool) -> _Backend:
    if method == "newton":
        return _NewtonBackend()
    if method == "cvxpy":
        return _CvxpyBackend(polish=polish)
    if method == "casadi":
        return _CasadiBackend()
    raise BackendNotFound("method", method, METHODS)


# --------------------------------------------------------------------------------------
# Modes (4.1)


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.einsum("bi,bi->b", a, b)


def _solve_normalised(geo: SceneArrays, w_rel, p, mu_c: float, backend: _Backend, tol: SolverTolerances):
    """Solve a batch in normalised units. Returns a dict of arrays (world-frame vectors)."""
    b = w_rel.shape[0]
    ell = _length_scale(geo.contact_rel, w_rel)
    w_n = w_rel / ell[:, None, None]
    c_n = geo.contact_rel / ell[:, None]
    n = geo.normal
    t = geo.alpha_hat
    push = geo.push_hat
    sin_a = geo.sin_alpha

    x = np.zeros((b, 3))
    force = np.zeros((b, 2))
    kkt = np.full(b, np.inf)
    vertex = np.full(b, -1)
    iters = np.zeros(b, dtype=int)
    mode = np.zeros(b, dtype=int)
    consistent = np.ones(b, dtype=bool)
    raw = np.full(b, np.nan)

    def frictionless(idx, direction):
        rows = _rows_frictionless(direction, c_n[idx])
        q = np.ones((idx.size, 1))
        xs, mult, k_, vtx, its, rw = backend.solve(w_n[idx], p[idx], rows, q, tol)
        # Scale so that the contact keeps up with the pusher: n . v(c) = n . p (3.3).
        vc = xs[:, :2] + xs[:, 2:3] * perp(c_n[idx])
        kappa = sin_a[idx] / _dot(vc, n[idx])
        return xs * kappa[:, None], mult[:, 0], kappa, k_, vtx, its, rw

    if mu_c == 0.0:
        idx = np.arange(b)
        xs, lam, kappa, k_, vtx, its, rw = frictionless(idx, n)
        x[:], kkt[:], vertex[:], iters[:] = xs, k_, vtx, its
        force[:] = lam[:, None] * n
        consistent &= kappa > 0.0
        if rw is not None:
            raw[:] = rw
        mode[:] = 0
    else:
        idx = np.arange(b)
        m = _rows_sticking(c_n)
        q = push.copy()
        # With the COR on a support point the contact force is a set: the Newton step
        # reports its member deepest in the cone (IPOPT's dual gives one member only).
        if hasattr(backend, "cone"):
            backend.cone = (n, t, mu_c)
        xs, mult, k_, vtx, its, rw = backend.solve(w_n, p, m, q, tol)
        if hasattr(backend, "cone"):
            backend.cone = None
        fn = _dot(mult, n)
        ft = _dot(mult, t)
        in_cone = (fn > 0.0) & (np.abs(ft) <= mu_c * fn * (1.0 + tol.kkt))
        x[:], force[:], kkt[:], vertex[:], iters[:] = xs, mult, k_, vtx, its
        if rw is not None:
            raw[:] = rw
        mode[:] = 1
        out = np.nonzero(~in_cone)[0]
        if out.size:
            # The force would leave the cone on the side of sign(ft): slip with the force on
            # that edge, d = (n + sigma mu_c t) / |.| (4.1.3).
            sigma = np.where(ft[out] >= 0.0, 1.0, -1.0)
            for sg in (1.0, -1.0):
                sel = out[sigma == sg]
                if sel.size == 0:
                    continue
                d = (n[sel] + sg * mu_c * t[sel]) / math.hypot(1.0, mu_c)
                xs2, lam, kappa, k2, vtx2, its2, rw2 = frictionless(sel, d)
                vc = xs2[:, :2] + xs2[:, 2:3] * perp(c_n[sel])
                rel = _dot(push[sel] - vc, t[sel])  # pusher relative to the part, along t
                # Friction on the part points along the pusher's relative slip.
                ok = (kappa > 0.0) & (lam > 0.0) & (np.sign(rel) == sg)
                x[sel], kkt[sel], vertex[sel], iters[sel] = xs2, k2, vtx2, its2 + iters[sel]
                force[sel] = lam[:, None] * d
                if rw2 is not None:
                    raw[sel] = rw2
                up = _dot(vc - push[sel], perp(push[sel])) > 0.0
                mode[sel] = np.where(up, 2, 3)
                consistent[sel] = ok
    # Back to world units: v is dimensionless already (per unit push); omega = x3 / L.
    omega = x[:, 2] / ell
    v = x[:, :2]
    return dict(
        x=x, v=v, omega=omega, ell=ell, force=force, kkt=kkt, vertex=vertex, iters=iters,
        mode=mode, consistent=consistent, raw=raw, w_n=w_n, p=p,
    )


def _power_world(v, omega, w_rel, p):
    vel = v[:, None, :] + omega[:, None, None] * np.stack([-w_rel[..., 1], w_rel[..., 0]], axis=-1)
    return np.einsum("bk,bk->b", p, np.linalg.norm(vel, axis=2))


def solve_forward(
    scene: PushScene,
    support: Support,
    mu_c: float = 0.0,
    method: str = "newton",
    tol: SolverTolerances = SOLVER_DEFAULT,
    polish: bool = True,
) -> ForwardResult:
    """The COR and motion of ``support`` under the push ``scene`` (see module docstring)."""
    if not (math.isfinite(mu_c) and mu_c >= 0.0):
        raise InvalidInput("mu_c", "must be a finite number >= 0")
    if not np.allclose(support.center_of_mass, scene.center_of_mass, rtol=0.0, atol=1e-12 * max(1.0, float(np.linalg.norm(scene.center_of_mass)))):
        raise InvalidInput("support", "its centre of mass differs from the scene's")
    backend = _backend(method, polish)
    w_rel = (support.points - scene.center_of_mass)[None]
    p = support.weights[None]
    t0 = time.perf_counter()
    if method == "newton":
        b = _solve_batch(SceneArrays.repeat(scene, 1), np.asarray(scene.center_of_mass, dtype=float)[None],
                         support.points[None], support.weights[None], float(mu_c), tol, False)
        return _row_result(scene, b, tol, time.perf_counter() - t0)
    out = _solve_normalised(SceneArrays.repeat(scene, 1), w_rel, p, float(mu_c), backend, tol)
    elapsed = time.perf_counter() - t0
    return _single_result(scene, out, w_rel, p, backend.name, tol, elapsed)


def _row_result(scene: PushScene, b: BatchResult, tol: SolverTolerances, elapsed: float) -> ForwardResult:
    """The ForwardResult of a batch of one (the compiled Newton path)."""
    cor = None if np.isnan(b.cor[0, 0]) else b.cor[0].copy()
    consistent = bool(b.consistent[0])
    kkt = float(b.kkt_residual[0])
    status = "optimal" if (kkt <= tol.kkt_accept and consistent) else ("inconsistent" if not consistent
                                                                       else "not_converged")
    omega = float(b.omega[0])
    vertex = int(b.cor_on_support[0])
    return ForwardResult(status=status, method="newton", mode=_MODE_NAMES[int(b.mode[0])], cor=cor,
                         velocity_cm=b.velocity_cm[0].copy(), omega=omega,
                         sense="none" if cor is None else ("ccw" if omega > 0.0 else "cw"), slip=float(b.slip[0]),
                         power=float(b.power[0]), contact_force=b.contact_force[0].copy(), kkt_residual=kkt,
                         gap=float(b.gap[0]), cor_on_support=vertex if vertex >= 0 else None,
                         iterations=int(b.iterations[0]), solve_time_s=elapsed)


def _single_result(scene, out, w_rel, p, method, tol, elapsed) -> ForwardResult:
    v = out["v"][0]
    omega = float(out["omega"][0])
    ell = float(out["ell"][0])
    kkt = float(out["kkt"][0])
    translation = abs(omega) * ell <= tol.translation_omega * max(float(np.linalg.norm(v)), 1e-300)
    cor = None if translation else scene.center_of_mass + perp(v) / omega
    vc = v + omega * perp(scene.contact_rel)
    force = out["force"][0]
    pw = float(_power_world(out["v"], out["omega"], w_rel, p)[0])
    # The pusher's force does work F . v(c) on the part; the table's friction dissipates it.
    gap = pw - float(force @ vc)
    status = "optimal" if (kkt <= tol.kkt_accept and out["consistent"][0]) else (
        "inconsistent" if not out["consistent"][0] else "not_converged"
    )
    sense = "none" if cor is None else ("ccw" if omega > 0.0 else "cw")
    vertex = int(out["vertex"][0])
    raw = out["raw"][0]
    return ForwardResult(
        status=status,
        method=method,
        mode=_MODE_NAMES[int(out["mode"][0])],
        cor=cor,
        velocity_cm=v.copy(),
        omega=omega,
        sense=sense,
        slip=float(scene.alpha_hat @ (scene.push_hat - vc)),
        power=pw,
        contact_force=force.copy(),
        kkt_residual=kkt,
        gap=gap,
        cor_on_support=vertex if vertex >= 0 else None,
        iterations=int(out["iters"][0]),
        solve_time_s=elapsed,
        raw_twist_error=None if not np.isfinite(raw) else float(raw),
    )


def solve_forward_batch(
    scene: PushScene,
    points,
    weights,
    mu_c: float = 0.0,
    tol: SolverTolerances = SOLVER_DEFAULT,
    check_centroid: bool = True,
    compiled: bool = True,
) -> BatchResult:
    """Solve many supports of equal size k at once with the Newton back end.

    ``points`` (B, k, 2) world frame, ``weights`` (B, k) non-negative (normalised here);
    each centroid must be the CM unless ``check_centroid`` is False. ``compiled``: the
    compiled per-problem solve (False: the vectorised reference, solver.motion.newton).
    """
    w = np.asarray(points, dtype=float)
    if w.ndim != 3 or w.shape[2] != 2:
        raise InvalidInput("points", "need points of shape (batch, k, 2) and weights (batch, k)")
    cms = np.asarray(scene.center_of_mass, dtype=float).reshape(1, 2)
    return _solve_batch(SceneArrays.repeat(scene, 1), cms, w, weights, mu_c, tol, check_centroid, compiled)


def solve_forward_scenes(
    scenes: list[PushScene],
    points,
    weights,
    mu_c: float = 0.0,
    tol: SolverTolerances = SOLVER_DEFAULT,
    check_centroid: bool = True,
    compiled: bool = True,
) -> BatchResult:
    """Like :func:`solve_forward_batch`, with a scene per support: ``scenes[i]`` pushes the
    support ``points[i]`` (world frame, its centroid that scene's CM), so many parts at
    different poses (a simulator stepping them together) are solved in one batch."""
    w = np.asarray(points, dtype=float)
    if w.ndim != 3 or w.shape[2] != 2 or len(scenes) != w.shape[0]:
        raise InvalidInput("points", "need points of shape (batch, k, 2), weights (batch, k) and one scene per support")
    cms = np.array([sc.center_of_mass for sc in scenes], dtype=float).reshape(-1, 2)
    return _solve_batch(SceneArrays.stack(scenes), cms, w, weights, mu_c, tol, check_centroid, compiled)


def _solve_batch(geo: SceneArrays, cms: np.ndarray, w: np.ndarray, weights, mu_c: float, tol: SolverTolerances,
                 check_centroid: bool, compiled: bool = True) -> BatchResult:
    p = np.asarray(weights, dtype=float)
    if p.shape != w.shape[:2]:
        raise InvalidInput("points", "need points of shape (batch, k, 2) and weights (batch, k)")
    if not (math.isfinite(mu_c) and mu_c >= 0.0):
        raise InvalidInput("mu_c", "must be a finite number >= 0")
    if compiled:
        return _batch_compiled(geo, cms, w, p, float(mu_c), tol, check_centroid)
    b = w.shape[0]
    if geo.contact_rel.shape[0] == 1 and b != 1:  # one scene for every support
        geo = _geometry_rows(geo, np.zeros(b, dtype=int))
    if cms.shape[0] == 1 and b != 1:
        cms = np.repeat(cms, b, axis=0)
    if not (np.all(np.isfinite(w)) and np.all(np.isfinite(p))) or np.any(p < 0.0):
        raise InvalidInput("weights", "must be finite and non-negative, points finite")
    tot = p.sum(axis=1)
    if np.any(tot <= 0.0):
        raise InvalidInput("weights", "every support needs a positive total weight")
    p = p / tot[:, None]
    w_rel = w - cms[:, None, :]
    if check_centroid:
        ell = np.max(np.linalg.norm(w_rel, axis=2), axis=1)
        off = np.linalg.norm(np.einsum("bk,bki->bi", p, w_rel), axis=1)
        bad = np.nonzero(off > tol.centroid_rel * ell)[0]
        if bad.size:
            raise InvalidInput("weights", f"support {int(bad[0])} does not have its centroid at the centre of mass")
    t0 = time.perf_counter()
    backend = _NewtonBackend()
    out = _solve_normalised(geo, w_rel, p, float(mu_c), backend, tol)
    elapsed = time.perf_counter() - t0
    v, omega = out["v"], out["omega"]
    translation = np.abs(omega) * out["ell"] <= tol.translation_omega * np.linalg.norm(v, axis=1)
    cor = np.full(v.shape, np.nan)
    rot = ~translation
    cor[rot] = cms[rot] + perp(v[rot]) / omega[rot, None]
    vc = v + omega[:, None] * perp(geo.contact_rel)
    power = _power_world(v, omega, w_rel, p)
    return BatchResult(
        cor=cor,
        omega=omega,
        velocity_cm=v,
        power=power,
        contact_force=out["force"],
        kkt_residual=out["kkt"],
        mode=out["mode"],
        cor_on_support=out["vertex"],
        converged=(out["kkt"] <= tol.kkt_accept) & out["consistent"],
        solve_time_s=elapsed,
        slip=_dot(geo.push_hat - vc, geo.alpha_hat),
        gap=power - np.einsum("bi,bi->b", out["force"], vc),
        iterations=out["iters"],
        fallbacks=backend.fallbacks,
        consistent=out["consistent"],
    )


_BAD_INPUT = (
    ("weights", "must be finite and non-negative, points finite"),
    ("weights", "every support needs a positive total weight"),
    ("weights", "support {} does not have its centroid at the centre of mass"),
    ("points", "every support point and the contact are at the centre of mass: the rotation is undetermined"),
)
"""What solver.kernels.forward.solve_supports' faults (BAD_*) are refused with, in order."""


def _batch_compiled(geo: SceneArrays, cms: np.ndarray, w: np.ndarray, p: np.ndarray, mu_c: float,
                    tol: SolverTolerances, check_centroid: bool) -> BatchResult:
    """The batch on the compiled path (solver.kernels.forward.solve_supports: the checks of
    the reference path, the solve and the answer's quantities, a support at a time); a
    support the kernel did not solve to ``tol.kkt`` is solved again on the reference path
    (solver.motion.newton, whose own failures go to the conic solver)."""
    from solver.kernels import forward as kernel  # loaded on first use (a web process never needs it)

    t0 = time.perf_counter()
    # the kernel's signature takes writable float arrays (a support from Ray's object store is read-only)
    geometry = [np.require(getattr(geo, f), dtype=float, requirements=["W"]) for f in _GEOMETRY]
    real, ints, bad = kernel.solve_supports(
        np.require(w, dtype=float, requirements=["W"]), np.require(p, dtype=float, requirements=["W"]),
        np.require(cms, dtype=float, requirements=["W"]), *geometry, mu_c,
        np.array([tol.kkt, tol.kkt, tol.max_newton_iter, tol.translation_omega,
                  tol.centroid_rel if check_centroid else np.inf]))
    for fault, (field_name, reason) in enumerate(_BAD_INPUT):
        if bad[fault] >= 0:
            raise InvalidInput(field_name, reason.format(int(bad[fault])))
    k = _codes
    consistent = ints[:, k.I_CONSISTENT].astype(bool)
    out = BatchResult(
        cor=real[:, [k.O_COR_X, k.O_COR_Y]], omega=real[:, k.O_OMEGA], velocity_cm=real[:, [k.O_VX, k.O_VY]],
        power=real[:, k.O_POWER], contact_force=real[:, [k.O_FX, k.O_FY]], kkt_residual=real[:, k.O_KKT],
        mode=ints[:, k.I_MODE], cor_on_support=ints[:, k.I_VERTEX],
        converged=(real[:, k.O_KKT] <= tol.kkt_accept) & consistent, solve_time_s=0.0, slip=real[:, k.O_SLIP],
        gap=real[:, k.O_GAP], iterations=ints[:, k.I_ITERS], consistent=consistent)
    redo = np.nonzero(ints[:, k.I_FAILED])[0]
    fallbacks = 0
    if redo.size:
        ref = _solve_batch(_geometry_rows(geo, redo if geo.contact_rel.shape[0] > 1 else np.zeros_like(redo)),
                           cms[redo] if cms.shape[0] > 1 else np.repeat(cms, redo.size, axis=0), w[redo], p[redo],
                           mu_c, tol, False, compiled=False)
        for name in ("cor", "omega", "velocity_cm", "power", "contact_force", "kkt_residual", "mode", "cor_on_support",
                     "converged", "slip", "gap", "iterations", "consistent"):
            getattr(out, name)[redo] = getattr(ref, name)
        fallbacks = ref.fallbacks
    return dataclasses.replace(out, solve_time_s=time.perf_counter() - t0, fallbacks=fallbacks,
                               reference_rows=int(redo.size))


_GEOMETRY = ("contact_rel", "normal", "alpha_hat", "push_hat", "sin_alpha")


def _geometry_rows(geo: SceneArrays, rows: np.ndarray) -> SceneArrays:
    """The scene geometry of the problems ``rows``."""
    return SceneArrays(*(getattr(geo, f)[rows] for f in _GEOMETRY))
