"""Batched exact solver of the minimum-power problem on point supports (book 3.2-3.3.3).

Every problem of a batch is, in units of its length scale L (lengths / L, omega * L),

    minimise  f(x) = sum_i P_i |A_i x|,   A_i x = v + omega J w_i,   subject to  M x = q,

with one contact row (frictionless pusher, or slipping along a friction-cone edge, 4.1.3)
or two (sticking contact: the contact point moves with the pusher, 4.1.2). f is convex and
positively homogeneous, smooth except where the COR sits on a support point (A_i x = 0).

The book's Newton iteration on the COR (3.11) fails there and at infinity (translation).
Here, with one contact row:

1. the non-smooth optima are found first and exactly: the rotation about support point j
   that satisfies the contact row is optimal iff the gradient of the other terms can be
   balanced by a subgradient z of the j-th term, |z| <= P_j, plus a multiple of the row --
   a 3x3 linear system (``_vertex_optima``);
   (for supports of more than 16 points, Newton runs first and only the support points
   nearest a stalled iterate are tested, which keeps the cost linear in k);
2. all other problems are smooth at their optimum: damped Newton on f restricted to the
   2-D constraint plane, whose points are twists, so a translation is an ordinary point
   rather than a COR at infinity (``_newton_plane``).

With two rows (sticking) the constraint set is a line, the problem one-dimensional: a
safeguarded Newton iteration on the monotone derivative, which also brackets a kink
(``_newton_line``).

Work is vectorised over the batch, structure-of-arrays, with closed-form 2x2 algebra. This
is the reference of the compiled per-problem solve (solver.kernels.forward: the same
algorithm and constants), which the forward solver calls first.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from solver.kernels.codes import ARMIJO, MAX_HALVINGS, NEAREST, ROUNDOFF, TINY, VERTEX_FIRST_MAX_K


class BatchConvergence:
    """The Outcome of a batch result with a boolean array ``converged`` (one entry per
    problem): "optimal" and complete when every problem converged, else "not_converged"."""

    converged: np.ndarray

    @property
    def status(self) -> str:
        return "optimal" if bool(np.all(self.converged)) else "not_converged"

    @property
    def complete(self) -> bool:
        return self.status == "optimal"

    def converged_count(self) -> str:
        """"k of n": how many problems converged."""
        return f"{int(np.count_nonzero(self.converged))} of {int(self.converged.size)}"


@dataclass(frozen=True)
class BatchSolution(BatchConvergence):
    """Per-problem results over the batch.

    x: (B, 3) optimal twists (normalised units). multipliers: (B, rows): grad f = M^T mult.
    kkt: (B,) KKT residual. vertex: (B,) support index the COR sits on, -1 if none.
    iterations: (B,) Newton iterations. converged: (B,) kkt <= tolerance. solve_time_s:
    seconds for the batch.
    """

    x: np.ndarray
    multipliers: np.ndarray
    power: np.ndarray
    kkt: np.ndarray
    vertex: np.ndarray
    iterations: np.ndarray
    converged: np.ndarray
    solve_time_s: float

    @property
    def message(self) -> str:
        return f"{self.converged_count()} problems met the KKT tolerance"


SUM_COLUMNS_BELOW = 8
"""Row sums over fewer support points than this are added column by column: bitwise what
numpy's reduction gives (it sums pairwise only from 8 terms on), and ~10x faster on the
(B, 3) arrays of tripods, where ``.sum(1)`` was a fifth of a 590,000-tripod batch."""


def sum_rows(x):
    """``x.sum(1)`` of a (B, k) array (see SUM_COLUMNS_BELOW)."""
    k = x.shape[1]
    if k >= SUM_COLUMNS_BELOW or k == 0:
        return x.sum(1)
    total = x[:, 0].copy()
    for j in range(1, k):
        total += x[:, j]
    return total


def _unit_or_zero(ux, uy):
    rho = np.sqrt(ux * ux + uy * uy)
    inv = 1.0 / np.maximum(rho, TINY)
    return ux * inv, uy * inv, rho


def gradient(x, wx, wy, p):
    """grad f at twists x (B, 3): sum_i P_i (u_i, (J w_i) . u_i), u_i unit velocity."""
    ux = x[:, 0:1] - x[:, 2:3] * wy
    uy = x[:, 1:2] + x[:, 2:3] * wx
    ex, ey, _ = _unit_or_zero(ux, uy)
    pe_x, pe_y = p * ex, p * ey
    return np.stack([sum_rows(pe_x), sum_rows(pe_y), sum_rows(pe_y * wx - pe_x * wy)], axis=1)


def power(x, wx, wy, p):
    ux = x[:, 0:1] - x[:, 2:3] * wy
    uy = x[:, 1:2] + x[:, 2:3] * wx
    return sum_rows(p * np.sqrt(ux * ux + uy * uy))


def _vertex_optima(wx, wy, p, a, q, slack, candidates=None, return_z=False):
    """For one contact row a.x = q: the best exact optimum with the COR on a support point.

    ``candidates``: support indices to try (default all). Returns (x, lambda, violation,
    index[, z]); violation <= slack means optimal; z is the balancing subgradient.
    """
    b, k = wx.shape
    best_x = np.zeros((b, 3))
    best_lam = np.zeros(b)
    best_viol = np.full(b, np.inf)
    best_idx = np.full(b, -1)
    best_z = np.zeros((b, 2))
    for j in range(k) if candidates is None else candidates:
        # Rotation about w_j: x = omega (w_yj, -w_xj, 1).
        den = a[:, 0] * wy[:, j] - a[:, 1] * wx[:, j] + a[:, 2]
        ok = (np.abs(den) > TINY) & (p[:, j] > 0.0)
        omega = np.where(ok, q / np.where(ok, den, 1.0), 0.0)
        # Velocities of the others: omega J (w_i - w_j).
        dx = wx - wx[:, j : j + 1]
        dy = wy - wy[:, j : j + 1]
        ux = -omega[:, None] * dy
        uy = omega[:, None] * dx
        ex, ey, rho = _unit_or_zero(ux, uy)
        pj = p.copy()
        pj[:, j] = 0.0
        # Coincident points were merged by the caller; a zero rho elsewhere has no weight.
        gx = sum_rows(pj * ex)
        gy = sum_rows(pj * ey)
        gw = sum_rows(pj * (ey * wx - ex * wy))
        # g + (z, Jw_j . z) = lambda a. With z = lambda a_v - g_v:
        # Jw_j . (lambda a_v - g_v) - lambda a_w = -g_w  ->  lambda (Jw_j . a_v - a_w) = Jw_j . g_v - g_w
        jwx, jwy = -wy[:, j], wx[:, j]
        lam = np.where(ok, (jwx * gx + jwy * gy - gw) / np.where(ok, -den, 1.0), 0.0)
        zx = lam * a[:, 0] - gx
        zy = lam * a[:, 1] - gy
        viol = np.where(ok, np.maximum(np.hypot(zx, zy) - p[:, j], 0.0), np.inf)
        better = viol < best_viol
        best_viol = np.where(better, viol, best_viol)
        best_lam = np.where(better, lam, best_lam)
        best_idx = np.where(better, j, best_idx)
        best_x[better] = np.stack([omega * wy[:, j], -omega * wx[:, j], omega], axis=1)[better]
        best_z[better] = np.stack([zx, zy], axis=1)[better]
    if return_z:
        return best_x, best_lam, best_viol, best_idx, best_z
    return best_x, best_lam, best_viol, best_idx


def _plane_basis(a):
    """Orthonormal n1, n2 (B, 3) spanning the plane a . x = 0, and xp = q a/|a|^2 direction."""
    an = a / np.linalg.norm(a, axis=1, keepdims=True)
    # Householder-free: cross with the coordinate axis least aligned with a.
    axis = np.argmin(np.abs(an), axis=1)
    e = np.zeros_like(an)
    e[np.arange(len(an)), axis] = 1.0
    n1 = np.cross(an, e)
    n1 /= np.linalg.norm(n1, axis=1, keepdims=True)
    n2 = np.cross(an, n1)
    return n1, n2


def _newton_plane(wx, wy, p, a, q, kkt_tol, max_iter, x0=None):
    """Damped Newton on f over {x : a . x = q} (one row). Returns x, lambda, kkt, iters."""
    b = wx.shape[0]
    a2 = np.einsum("bi,bi->b", a, a)
    xp = a * (q / a2)[:, None]
    n1, n2 = _plane_basis(a)
    # Velocity fields of xp and of the basis twists at the support points.
    def field(t):
        return t[:, 0:1] - t[:, 2:3] * wy, t[:, 1:2] + t[:, 2:3] * wx

    px, py = field(xp)
    e1x, e1y = field(n1)
    e2x, e2y = field(n2)
    if x0 is not None:
        y1 = np.einsum("bi,bi->b", x0 - xp, n1)
        y2 = np.einsum("bi,bi->b", x0 - xp, n2)
    else:
        y1 = np.zeros(b)
        y2 = np.zeros(b)
    kkt = np.full(b, np.inf)
    iters = np.zeros(b, dtype=int)
    reg = np.zeros(b)
    act = np.arange(b)
    for it in range(max_iter + 1):
        if act.size == 0:
            break
        # Gather the active problems.
        P = p[act]
        Y1, Y2 = y1[act], y2[act]
        E1x, E1y, E2x, E2y = e1x[act], e1y[act], e2x[act], e2y[act]
        PX, PY = px[act], py[act]
        ux = PX + Y1[:, None] * E1x + Y2[:, None] * E2x
        uy = PY + Y1[:, None] * E1y + Y2[:, None] * E2y
        ex, ey, rho = _unit_or_zero(ux, uy)
        pe_x, pe_y = P * ex, P * ey
        g1 = sum_rows(pe_x * E1x + pe_y * E1y)
        g2 = sum_rows(pe_x * E2x + pe_y * E2y)
        res = np.hypot(g1, g2)
        kkt[act] = res
        live = res > kkt_tol
        if it == max_iter or not np.any(live):
            break
        if not np.all(live):
            act = act[live]
            P, Y1, Y2 = P[live], Y1[live], Y2[live]
            E1x, E1y, E2x, E2y = E1x[live], E1y[live], E2x[live], E2y[live]
            PX, PY = PX[live], PY[live]
            ex, ey, rho = ex[live], ey[live], rho[live]
            g1, g2 = g1[live], g2[live]
        iters[act] += 1
        # Hessian in the plane: sum_i P_i/rho_i (t.E_d)(t.E_e), t = J e.
        coef = P / np.maximum(rho, TINY)
        t1 = -ey * E1x + ex * E1y
        t2 = -ey * E2x + ex * E2y
        h11 = sum_rows(coef * t1 * t1)
        h12 = sum_rows(coef * t1 * t2)
        h22 = sum_rows(coef * t2 * t2)
        lam = (reg[act] + 1e-14) * 0.5 * (h11 + h22)
        h11r, h22r = h11 + lam, h22 + lam
        det = h11r * h22r - h12 * h12
        with np.errstate(divide="ignore", invalid="ignore"):
            s1 = -(h22r * g1 - h12 * g2) / det
            s2 = -(h11r * g2 - h12 * g1) / det
        slope = g1 * s1 + g2 * s2
        bad = ~(slope < 0.0) | ~np.isfinite(s1) | ~np.isfinite(s2)
        s1 = np.where(bad, -g1, s1)
        s2 = np.where(bad, -g2, s2)
        slope = np.where(bad, -(g1 * g1 + g2 * g2), slope)
        f0 = sum_rows(P * rho)
        roundoff = -slope <= ROUNDOFF * f0
        tstep = np.ones(act.size)
        accepted = np.zeros(act.size, dtype=bool)
        sub = np.arange(act.size)
        for _ in range(MAX_HALVINGS):
            T1 = Y1[sub] + tstep[sub] * s1[sub]
            T2 = Y2[sub] + tstep[sub] * s2[sub]
            vx = PX[sub] + T1[:, None] * E1x[sub] + T2[:, None] * E2x[sub]
            vy = PY[sub] + T1[:, None] * E1y[sub] + T2[:, None] * E2y[sub]
            ft = sum_rows(P[sub] * np.sqrt(vx * vx + vy * vy))
            ok = (ft <= f0[sub] + ARMIJO * tstep[sub] * slope[sub]) | (roundoff[sub] & (tstep[sub] == 1.0))
            good = sub[ok]
            y1[act[good]] = T1[ok]
            y2[act[good]] = T2[ok]
            accepted[good] = True
            sub = sub[~ok]
            if sub.size == 0:
                break
            tstep[sub] *= 0.5
        # Levenberg-like damping: relax after full steps, stiffen after short ones.
        full = accepted & (tstep == 1.0)
        reg[act] = np.where(full, reg[act] * 0.1, np.maximum(reg[act] * 10.0, 1e-10))
        if sub.size:
            # Not even a tiny step verified: take it anyway so round-off never stalls.
            y1[act[sub]] = Y1[sub] + tstep[sub] * s1[sub]
            y2[act[sub]] = Y2[sub] + tstep[sub] * s2[sub]
    x = xp + y1[:, None] * n1 + y2[:, None] * n2
    g = gradient(x, wx, wy, p)
    lam = np.einsum("bi,bi->b", g, a) / a2
    return x, lam, kkt, iters


def _newton_line(wx, wy, p, xp, kdir, kkt_tol, max_iter):
    """Minimise phi(t) = f(xp + t k) (convex, 1-D): safeguarded Newton on phi'.

    The subgradient of phi is monotone. A bracket [lo, hi] with phi'(lo) < 0 < phi'(hi)
    is grown first, then Newton steps are accepted only inside it (else bisection). A kink
    (the COR on a support point) is bracketed to round-off and its KKT residual is the
    distance of 0 from the one-sided derivatives there.
    """
    b = wx.shape[0]
    knorm = np.linalg.norm(kdir, axis=1)
    kk = kdir / knorm[:, None]

    def field(t):
        return t[:, 0:1] - t[:, 2:3] * wy, t[:, 1:2] + t[:, 2:3] * wx

    px, py = field(xp)
    kx, ky = field(kk)

    def deriv(t, P=p, PX=px, PY=py, KX=kx, KY=ky):
        ux = PX + t[:, None] * KX
        uy = PY + t[:, None] * KY
        ex, ey, rho = _unit_or_zero(ux, uy)
        d1 = sum_rows(P * (ex * KX + ey * KY))
        tt = -ey * KX + ex * KY
        d2 = sum_rows(P / np.maximum(rho, TINY) * tt * tt)
        return d1, d2

    # Bracket: phi'(t) -> +-sum P_i |k(w_i)| as t -> +-inf.
    scale = np.maximum(sum_rows(p * np.sqrt(px * px + py * py)) / np.maximum(sum_rows(p * np.sqrt(kx * kx + ky * ky)), TINY), 1.0)
    lo = -scale
    hi = scale.copy()
    for _ in range(200):
        dlo, _ = deriv(lo)
        grow = dlo >= 0.0
        if not np.any(grow):
            break
        lo = np.where(grow, 2.0 * lo, lo)
    for _ in range(200):
        dhi, _ = deriv(hi)
        grow = dhi <= 0.0
        if not np.any(grow):
            break
        hi = np.where(grow, 2.0 * hi, hi)
    t = np.zeros(b)
    t = np.clip(t, lo, hi)
    iters = np.zeros(b, dtype=int)
    kkt = np.full(b, np.inf)
    width_old = hi - lo
    for it in range(max_iter):
        d1, d2 = deriv(t)
        kkt = np.abs(d1)
        live = (kkt > kkt_tol) & (hi - lo > 4.0 * np.finfo(float).eps * np.maximum(np.abs(t), 1.0))
        if not np.any(live):
            break
        iters += live
        lo = np.where(live & (d1 < 0.0), t, lo)
        hi = np.where(live & (d1 > 0.0), t, hi)
        with np.errstate(divide="ignore", invalid="ignore"):
            tn = t - d1 / d2
        inside = np.isfinite(tn) & (tn > lo) & (tn < hi)
        # Near a kink Newton can bounce inside the bracket: every other iteration, bisect
        # unless the bracket has at least halved since the last check.
        if it % 2 == 1:
            slow = (hi - lo) > 0.5 * width_old
            inside &= ~slow
            width_old = hi - lo
        tn = np.where(inside, tn, 0.5 * (lo + hi))
        t = np.where(live, tn, t)
    # A kink: the one-sided derivatives straddle zero -> optimal, residual 0.
    h = 8.0 * np.finfo(float).eps * np.maximum(np.abs(t), 1.0)
    dm, _ = deriv(t - h)
    dp, _ = deriv(t + h)
    kink = (dm <= 0.0) & (dp >= 0.0)
    kkt = np.where(kink & (kkt > kkt_tol), 0.0, kkt)
    x = xp + t[:, None] * kk
    return x, kkt, iters


def solve_batch(w, p, m, q, kkt_tol: float, max_iter: int, x0=None, cone=None) -> BatchSolution:
    """Solve a batch of minimum-power problems (see the module docstring).

    w: (B, k, 2) support points / L (CM at the origin; no two coincident), p: (B, k)
    weights summing to 1, m: (B, rows, 3) constraint rows (rows = 1 or 2), q: (B, rows).
    ``x0``: optional starting twists (B, 3), used by the one-row Newton iteration.
    ``cone``: (n, t, mu_c) of a sticking contact (two rows: v(c) = p, M = [I, J c]; n and t
    (2,) or one per problem (B, 2)): where
    the COR sits on a support point the contact force is a set, and the member deepest
    inside the friction cone is reported (:func:`_vertex_contact_force`).
    """
    t0 = time.perf_counter()
    w = np.asarray(w, dtype=float)
    p = np.asarray(p, dtype=float)
    m = np.asarray(m, dtype=float)
    q = np.asarray(q, dtype=float)
    wx, wy = w[..., 0], w[..., 1]
    b = w.shape[0]
    rows = m.shape[1]
    vertex = np.full(b, -1)
    iters = np.zeros(b, dtype=int)
    if rows == 1 and w.shape[1] > VERTEX_FIRST_MAX_K:
        # Many support points: the O(k^2) test of every point is too dear. Newton first;
        # a converged smooth KKT point is optimal (f is convex). Where Newton stalls, the
        # iterate has run into a kink: test the few nearest support points exactly.
        a, qq = m[:, 0, :], q[:, 0]
        x, lam, kkt, iters = _newton_plane(wx, wy, p, a, qq, kkt_tol, max_iter, x0)
        mult = lam[:, None].copy()
        bad = np.nonzero(kkt > kkt_tol)[0]
        if bad.size:
            ux = x[bad, 0:1] - x[bad, 2:3] * wy[bad]
            uy = x[bad, 1:2] + x[bad, 2:3] * wx[bad]
            near = np.argsort(ux * ux + uy * uy, axis=1)[:, :NEAREST]
            for rank in range(near.shape[1]):
                for jj in np.unique(near[:, rank]):
                    sel = bad[near[:, rank] == jj]
                    xv, lam_v, viol, _ = _vertex_optima(wx[sel], wy[sel], p[sel], a[sel], qq[sel], kkt_tol, [int(jj)])
                    ok = viol <= kkt_tol
                    x[sel[ok]] = xv[ok]
                    mult[sel[ok], 0] = lam_v[ok]
                    kkt[sel[ok]] = viol[ok]
                    vertex[sel[ok]] = jj
            lam = mult[:, 0]
            _escape_kinks(wx, wy, p, a, qq, x, lam, kkt, vertex, iters, kkt_tol, max_iter)
            mult = lam[:, None]
    elif rows == 1:
        a, qq = m[:, 0, :], q[:, 0]
        xv, lam_v, viol, idx = _vertex_optima(wx, wy, p, a, qq, kkt_tol)
        at_vertex = viol <= kkt_tol
        x = xv
        mult = lam_v[:, None].copy()
        kkt = np.where(at_vertex, viol, np.inf)
        vertex = np.where(at_vertex, idx, -1)
        todo = np.nonzero(~at_vertex)[0]
        if todo.size:
            xs, lam, k_, its = _newton_plane(
                wx[todo], wy[todo], p[todo], a[todo], qq[todo], kkt_tol, max_iter,
                None if x0 is None else np.asarray(x0, dtype=float)[todo],
            )
            x[todo] = xs
            mult[todo, 0] = lam
            kkt[todo] = k_
            iters[todo] = its
            if np.any(k_ > kkt_tol):
                lam_all = mult[:, 0].copy()
                _escape_kinks(wx, wy, p, a, qq, x, lam_all, kkt, vertex, iters, kkt_tol, max_iter)
                mult[:, 0] = lam_all
    elif rows == 2:
        # Null direction of the two rows, and a particular solution.
        kdir = np.cross(m[:, 0, :], m[:, 1, :])
        xp = np.einsum("bij,bj->bi", np.linalg.pinv(m), q)
        x, kkt, iters = _newton_line(wx, wy, p, xp, kdir, kkt_tol, max_iter)
        g = gradient(x, wx, wy, p)
        mult = np.einsum("bij,bj->bi", np.linalg.pinv(np.swapaxes(m, 1, 2)), g)
        d = np.linalg.norm(w - _cor_points(x)[:, None, :], axis=2)
        near = d.min(axis=1) <= 1e3 * np.finfo(float).eps * np.maximum(1.0, np.linalg.norm(w, axis=2).max(axis=1))
        vertex = np.where(near, d.argmin(axis=1), -1)
        if cone is not None and np.any(near):
            _vertex_contact_force(w, p, m, x, vertex, mult, cone)
    else:  # pragma: no cover - guarded by callers
        raise ValueError("one or two constraint rows")
    pw = power(x, wx, wy, p)
    return BatchSolution(x, mult, pw, kkt, vertex, iters, kkt <= kkt_tol, time.perf_counter() - t0)


def _escape_kinks(wx, wy, p, a, q, x, lam, kkt, vertex, iters, kkt_tol, max_iter, rounds=3):
    """Problems where Newton stalled: the iterate ran into a kink (a support point j) that
    is not the optimum. There the vertex test gives the balancing subgradient z with
    |z| > P_j, and the twist d in the constraint plane with A_j d = z/|z| is a descent
    direction: f'(x_j; d) = P_j - |z| < 0. Step along it, then resume Newton. In place."""
    for _ in range(rounds):
        bad = np.nonzero(kkt > kkt_tol)[0]
        if bad.size == 0:
            return
        xb = x[bad]
        ux = xb[:, 0:1] - xb[:, 2:3] * wy[bad]
        uy = xb[:, 1:2] + xb[:, 2:3] * wx[bad]
        j = np.argmin(ux * ux + uy * uy, axis=1)
        starts = np.zeros((bad.size, 3))
        for jj in np.unique(j):
            s = np.nonzero(j == jj)[0]
            sel = bad[s]
            xv, lam_v, viol, _, z = _vertex_optima(
                wx[sel], wy[sel], p[sel], a[sel], q[sel], kkt_tol, [int(jj)], return_z=True
            )
            ok = viol <= kkt_tol
            x[sel[ok]], lam[sel[ok]], kkt[sel[ok]], vertex[sel[ok]] = xv[ok], lam_v[ok], viol[ok], jj
            # Descent direction: [A_j; a] d = [z/|z|; 0], A_j d = d_v + d_w J w_j.
            mat = np.zeros((sel.size, 3, 3))
            mat[:, 0, 0] = 1.0
            mat[:, 1, 1] = 1.0
            mat[:, 0, 2] = -wy[sel, jj]
            mat[:, 1, 2] = wx[sel, jj]
            mat[:, 2, :] = a[sel]
            zn = z / np.maximum(np.linalg.norm(z, axis=1, keepdims=True), TINY)
            rhs = np.concatenate([zn, np.zeros((sel.size, 1))], axis=1)
            d = np.linalg.solve(mat, rhs[..., None])[..., 0]
            f0 = power(xv, wx[sel], wy[sel], p[sel])
            t = np.linalg.norm(xv, axis=1) / np.maximum(np.linalg.norm(d, axis=1), TINY)
            found = np.zeros(sel.size, dtype=bool)
            best = xv.copy()
            for _ in range(60):
                trial = xv + t[:, None] * d
                ft = power(trial, wx[sel], wy[sel], p[sel])
                good = (ft < f0) & ~found
                best[good] = trial[good]
                found |= good
                if found.all():
                    break
                t = np.where(found, t, 0.5 * t)
            starts[s] = best
        redo = bad[kkt[bad] > kkt_tol]
        if redo.size == 0:
            return
        pos = np.searchsorted(bad, redo)
        xs, lm, k_, its = _newton_plane(wx[redo], wy[redo], p[redo], a[redo], q[redo], kkt_tol, max_iter, starts[pos])
        x[redo], lam[redo], kkt[redo] = xs, lm, k_
        iters[redo] += its


def _vertex_contact_force(w, p, m, x, vertex, mult, cone):
    """Sticking with the COR on support point j: stationarity reads
    g_o + (z, J w_j . z) = (F, J c . F), g_o the gradient of the other terms, |z| <= P_j.
    So F = g_ov + z with J(w_j - c) . z = J c . g_ov - g_ow: z = z0 + tau e, e along
    w_j - c, z0 across it, |tau| |e| <= sqrt(P_j^2 - |z0|^2). Among those forces, the one
    with the largest friction-cone margin mu_c F . n - |F . t| (concave, piecewise linear in
    tau: its maximum is at an end or where F . t = 0) is written into ``mult``. In place."""
    n_all, t_all, mu_c = cone  # (2,) or one row per problem (B, 2)
    n_all, t_all = np.asarray(n_all, dtype=float), np.asarray(t_all, dtype=float)
    for b in np.nonzero(vertex >= 0)[0]:
        n = n_all[b] if n_all.ndim == 2 else n_all
        t = t_all[b] if t_all.ndim == 2 else t_all
        j = int(vertex[b])
        wx, wy = w[b, :, 0][None], w[b, :, 1][None]
        pj = p[b].copy()
        pj[j] = 0.0
        g = gradient(x[b][None], wx, wy, pj[None])[0]
        jc = m[b, :, 2]  # J c (the third column of [I, J c])
        c = np.array([jc[1], -jc[0]])
        dv = w[b, j] - c
        dn = float(np.hypot(dv[0], dv[1]))
        if dn == 0.0:
            continue
        e = dv / dn
        jd = np.array([-dv[1], dv[0]])
        k = float(jc @ g[:2] - g[2])
        z0 = k * jd / (dn * dn)
        rem = p[b, j] ** 2 - float(z0 @ z0)
        if rem < 0.0:
            continue
        tm = math.sqrt(rem)
        base = g[:2] + z0
        cands = [-tm, tm]
        et = float(e @ t)
        if et != 0.0:
            tau0 = -float(base @ t) / et
            if -tm < tau0 < tm:
                cands.append(tau0)
        if math.isinf(mu_c):
            best = max(cands, key=lambda tau: float((base + tau * e) @ n))
        else:
            best = max(cands, key=lambda tau: mu_c * float((base + tau * e) @ n) - abs(float((base + tau * e) @ t)))
        mult[b] = base + best * e


def _cor_points(x):
    om = np.where(np.abs(x[:, 2]) > TINY, x[:, 2], np.nan)
    return np.stack([-x[:, 1] / om, x[:, 0] / om], axis=1)



def kkt_residual(w, p, m, q, x, vertex_rel: float = 1e-7):
    """KKT residual and multipliers of given twists x (B, 3), for answers of other solvers.

    Smooth points: the part of grad f not spanned by the rows. Where (one row) the COR is
    within ``vertex_rel`` (relative) of a support point, the exact subgradient test of that
    point is used instead. Returns (kkt, multipliers, vertex index or -1).
    """
    w = np.asarray(w, dtype=float)
    wx, wy = w[..., 0], w[..., 1]
    b = w.shape[0]
    g = gradient(x, wx, wy, p)
    mt = np.swapaxes(m, 1, 2)
    mult = np.einsum("bij,bj->bi", np.linalg.pinv(mt), g)
    kkt = np.linalg.norm(g - np.einsum("bij,bj->bi", mt, mult), axis=1)
    vertex = np.full(b, -1)
    if m.shape[1] == 1:
        ux = x[:, 0:1] - x[:, 2:3] * wy
        uy = x[:, 1:2] + x[:, 2:3] * wx
        rho = np.sqrt(ux * ux + uy * uy) / np.maximum(np.linalg.norm(x, axis=1), TINY)[:, None]
        j = rho.argmin(axis=1)
        near = np.nonzero(rho[np.arange(b), j] <= vertex_rel)[0]
        for jj in np.unique(j[near]):
            sel = near[j[near] == jj]
            _, lam, viol, _ = _vertex_optima(wx[sel], wy[sel], p[sel], m[sel, 0, :], q[sel, 0], 0.0, [int(jj)])
            kkt[sel] = viol
            mult[sel, 0] = lam
            vertex[sel] = jj
    return kkt, mult, vertex
