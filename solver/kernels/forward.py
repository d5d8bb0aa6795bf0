"""The forward minimum-power solve of one support, compiled (numba): the per-row twin of
:mod:`solver.motion.newton` and of the modes of :mod:`solver.motion.forward` (book
3.2-3.3.3, 4.1), for batches (590,000 tripods, figure 3-5) and for the simulator's steps.

Each problem is solved on its own, in units of its length scale L, by the algorithm of
:mod:`solver.motion.newton` (that module is the reference this one is tested against):

* one contact row a . x = q (frictionless, or slipping along a friction-cone edge,
  4.1.3): the rotations about support points first (an exact subgradient test, 3x3
  algebra), then damped Newton on the constraint plane, then a step out of a kink Newton
  ran into; for more than :data:`VERTEX_FIRST_MAX_K` points Newton first and the nearest
  points tested;
* two rows (sticking, 4.1.2): a safeguarded Newton iteration on the constraint line.

Modes (4.1): with mu_c > 0 the sticking solve comes first and is kept if its contact force
lies in the friction cone; otherwise the part slips with the force on the cone edge on the
side the force left by (:func:`solve_modes`). A row whose solves did not meet the KKT
tolerance is flagged (``failed``): the caller re-solves it on the reference path, which
falls back on the conic solver.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, types

from solver.kernels import ensure_cache
from solver.kernels.codes import (
    ARMIJO,
    BAD_CENTROID,
    BAD_LENGTH,
    BAD_TOTAL,
    BAD_VALUES,
    EPS,
    ESCAPE_HALVINGS,
    ESCAPE_ROUNDS,
    I_CONSISTENT,
    I_FAILED,
    I_ITERS,
    I_MODE,
    I_VERTEX,
    LINE_GROWTH,
    MAX_HALVINGS,
    MODE_FRICTIONLESS,
    MODE_SLIPPING_DOWN,
    MODE_SLIPPING_UP,
    MODE_STICKING,
    NEAREST,
    O_COR_X,
    O_COR_Y,
    O_FX,
    O_FY,
    O_GAP,
    O_KKT,
    O_OMEGA,
    O_POWER,
    O_SLIP,
    O_VX,
    O_VY,
    ROUNDOFF,
    TINY,
    VERTEX_FIRST_MAX_K,
)

FAST = {"contract", "arcp", "nsz"}
"""LLVM's fast-math flags that keep infinities and NaNs (the vertex test's 'no candidate' is
an infinite violation): fused multiply-adds, reciprocals, signless zeros."""

CACHE = True
"""Compiled code kept on disk (numba's cache; solver/kernels/__init__.py says where)."""
ensure_cache()  # before the first function is compiled or loaded

ENTRY_POINTS = ("solve_supports",)
"""Compiled with explicit signatures when the module is imported (the others are compiled
into them)."""


@njit(cache=CACHE, fastmath=FAST)
def power_at(x0, x1, x2, wx, wy, p):
    """f(x) = sum_i P_i |v(w_i)| for the twist (x0, x1, x2)."""
    f = 0.0
    for i in range(wx.shape[0]):
        ux = x0 - x2 * wy[i]
        uy = x1 + x2 * wx[i]
        f += p[i] * math.sqrt(ux * ux + uy * uy)
    return f


@njit(cache=CACHE, fastmath=FAST)
def gradient_at(x0, x1, x2, wx, wy, p, skip=-1):
    """grad f at the twist: sum_i P_i (u_i, (J w_i) . u_i), u_i the unit velocity of w_i;
    without the term of support point ``skip`` (-1: none)."""
    g0 = 0.0
    g1 = 0.0
    g2 = 0.0
    for i in range(wx.shape[0]):
        if i == skip:
            continue
        ux = x0 - x2 * wy[i]
        uy = x1 + x2 * wx[i]
        inv = 1.0 / max(math.sqrt(ux * ux + uy * uy), TINY)
        pex = p[i] * ux * inv
        pey = p[i] * uy * inv
        g0 += pex
        g1 += pey
        g2 += pey * wx[i] - pex * wy[i]
    return g0, g1, g2


@njit(cache=CACHE, fastmath=FAST)
def vertex_test(wx, wy, p, a0, a1, a2, q, j):
    """The rotation about support point j that satisfies a . x = q, and how far it is from
    optimal: (x0, x1, x2, lambda, violation, z_x, z_y); optimal iff violation <= 0 (to a
    tolerance): the other terms' gradient balanced by a subgradient z of the j-th term,
    |z| <= P_j, plus lambda times the row (a 3x3 system; newton._vertex_optima)."""
    den = a0 * wy[j] - a1 * wx[j] + a2
    if not (abs(den) > TINY and p[j] > 0.0):
        return 0.0, 0.0, 0.0, 0.0, math.inf, 0.0, 0.0
    omega = q / den
    gx = 0.0
    gy = 0.0
    gw = 0.0
    for i in range(wx.shape[0]):
        if i == j:
            continue
        ux = -omega * (wy[i] - wy[j])
        uy = omega * (wx[i] - wx[j])
        inv = 1.0 / max(math.sqrt(ux * ux + uy * uy), TINY)
        ex = ux * inv
        ey = uy * inv
        gx += p[i] * ex
        gy += p[i] * ey
        gw += p[i] * (ey * wx[i] - ex * wy[i])
    lam = (-wy[j] * gx + wx[j] * gy - gw) / -den
    zx = lam * a0 - gx
    zy = lam * a1 - gy
    viol = max(math.sqrt(zx * zx + zy * zy) - p[j], 0.0)  # normalised units: no over- or underflow
    return omega * wy[j], -omega * wx[j], omega, lam, viol, zx, zy


@njit(cache=CACHE, fastmath=FAST)
def best_vertex(wx, wy, p, a0, a1, a2, q):
    """The support point whose rotation is closest to optimal (the first of equals):
    (x0, x1, x2, lambda, violation, index)."""
    bx0 = 0.0
    bx1 = 0.0
    bx2 = 0.0
    blam = 0.0
    bviol = math.inf
    bidx = -1
    for j in range(wx.shape[0]):
        x0, x1, x2, lam, viol, _, _ = vertex_test(wx, wy, p, a0, a1, a2, q, j)
        if viol < bviol:
            bx0, bx1, bx2, blam, bviol, bidx = x0, x1, x2, lam, viol, j
    return bx0, bx1, bx2, blam, bviol, bidx


@njit(cache=CACHE, fastmath=FAST)
def _plane_basis(a0, a1, a2):
    """Orthonormal n1, n2 spanning the plane a . x = 0 (newton._plane_basis)."""
    na = math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
    b0, b1, b2 = a0 / na, a1 / na, a2 / na
    ab0, ab1, ab2 = abs(b0), abs(b1), abs(b2)
    if ab0 <= ab1 and ab0 <= ab2:
        e0, e1, e2 = 1.0, 0.0, 0.0
    elif ab1 <= ab2:
        e0, e1, e2 = 0.0, 1.0, 0.0
    else:
        e0, e1, e2 = 0.0, 0.0, 1.0
    c0 = b1 * e2 - b2 * e1
    c1 = b2 * e0 - b0 * e2
    c2 = b0 * e1 - b1 * e0
    nc = math.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
    c0, c1, c2 = c0 / nc, c1 / nc, c2 / nc
    return c0, c1, c2, b1 * c2 - b2 * c1, b2 * c0 - b0 * c2, b0 * c1 - b1 * c0


@njit(cache=CACHE, fastmath=FAST)
def newton_plane(wx, wy, p, a0, a1, a2, q, kkt_tol, max_iter, start, x0s0, x0s1, x0s2, work):
    """Damped Newton on f over {x : a . x = q}, from the twist x0s when ``start``
    (newton._newton_plane): (x0, x1, x2, lambda, kkt, iterations). ``work``: (6, k)
    scratch."""
    k = wx.shape[0]
    a2n = a0 * a0 + a1 * a1 + a2 * a2
    xp0, xp1, xp2 = a0 * (q / a2n), a1 * (q / a2n), a2 * (q / a2n)
    n10, n11, n12, n20, n21, n22 = _plane_basis(a0, a1, a2)
    px, py, e1x, e1y, e2x, e2y = work[0], work[1], work[2], work[3], work[4], work[5]
    for i in range(k):
        px[i] = xp0 - xp2 * wy[i]
        py[i] = xp1 + xp2 * wx[i]
        e1x[i] = n10 - n12 * wy[i]
        e1y[i] = n11 + n12 * wx[i]
        e2x[i] = n20 - n22 * wy[i]
        e2y[i] = n21 + n22 * wx[i]
    y1 = 0.0
    y2 = 0.0
    if start:
        d0, d1, d2 = x0s0 - xp0, x0s1 - xp1, x0s2 - xp2
        y1 = d0 * n10 + d1 * n11 + d2 * n12
        y2 = d0 * n20 + d1 * n21 + d2 * n22
    kkt = math.inf
    iters = 0
    reg = 0.0
    for it in range(max_iter + 1):
        g1 = 0.0
        g2 = 0.0
        h11 = 0.0
        h12 = 0.0
        h22 = 0.0
        f0 = 0.0
        for i in range(k):
            ux = px[i] + y1 * e1x[i] + y2 * e2x[i]
            uy = py[i] + y1 * e1y[i] + y2 * e2y[i]
            rho = math.sqrt(ux * ux + uy * uy)
            inv = 1.0 / max(rho, TINY)
            ex = ux * inv
            ey = uy * inv
            pex = p[i] * ex
            pey = p[i] * ey
            g1 += pex * e1x[i] + pey * e1y[i]
            g2 += pex * e2x[i] + pey * e2y[i]
            coef = p[i] / max(rho, TINY)
            t1 = -ey * e1x[i] + ex * e1y[i]
            t2 = -ey * e2x[i] + ex * e2y[i]
            h11 += coef * t1 * t1
            h12 += coef * t1 * t2
            h22 += coef * t2 * t2
            f0 += p[i] * rho
        kkt = math.sqrt(g1 * g1 + g2 * g2)
        if kkt <= kkt_tol or it == max_iter:
            break
        iters += 1
        lam = (reg + 1e-14) * 0.5 * (h11 + h22)
        h11r = h11 + lam
        h22r = h22 + lam
        det = h11r * h22r - h12 * h12
        s1 = -(h22r * g1 - h12 * g2) / det if det != 0.0 else math.nan
        s2 = -(h11r * g2 - h12 * g1) / det if det != 0.0 else math.nan
        slope = g1 * s1 + g2 * s2
        if not (slope < 0.0) or not math.isfinite(s1) or not math.isfinite(s2):
            s1 = -g1
            s2 = -g2
            slope = -(g1 * g1 + g2 * g2)
        roundoff = -slope <= ROUNDOFF * f0
        tstep = 1.0
        accepted = False
        for _ in range(MAX_HALVINGS):
            t1_ = y1 + tstep * s1
            t2_ = y2 + tstep * s2
            ft = 0.0
            for i in range(k):
                vx = px[i] + t1_ * e1x[i] + t2_ * e2x[i]
                vy = py[i] + t1_ * e1y[i] + t2_ * e2y[i]
                ft += p[i] * math.sqrt(vx * vx + vy * vy)
            if ft <= f0 + ARMIJO * tstep * slope or (roundoff and tstep == 1.0):
                y1 = t1_
                y2 = t2_
                accepted = True
                break
            tstep *= 0.5
        # Levenberg-like damping: relax after full steps, stiffen after short ones
        if accepted and tstep == 1.0:
            reg *= 0.1
        else:
            reg = max(reg * 10.0, 1e-10)
        if not accepted:  # not even a tiny step verified: take it anyway so round-off never stalls
            y1 = y1 + tstep * s1
            y2 = y2 + tstep * s2
    x0 = xp0 + y1 * n10 + y2 * n20
    x1 = xp1 + y1 * n11 + y2 * n21
    x2 = xp2 + y1 * n12 + y2 * n22
    g0, g1_, g2_ = gradient_at(x0, x1, x2, wx, wy, p)
    lam_out = (g0 * a0 + g1_ * a1 + g2_ * a2) / a2n
    return x0, x1, x2, lam_out, kkt, iters


@njit(cache=CACHE, fastmath=FAST)
def _solve3(m00, m01, m02, m10, m11, m12, m20, m21, m22, r0, r1, r2):
    """x with M x = r (Cramer's rule; M is 3x3)."""
    det = (m00 * (m11 * m22 - m12 * m21) - m01 * (m10 * m22 - m12 * m20) + m02 * (m10 * m21 - m11 * m20))
    d0 = (r0 * (m11 * m22 - m12 * m21) - m01 * (r1 * m22 - m12 * r2) + m02 * (r1 * m21 - m11 * r2))
    d1 = (m00 * (r1 * m22 - m12 * r2) - r0 * (m10 * m22 - m12 * m20) + m02 * (m10 * r2 - r1 * m20))
    d2 = (m00 * (m11 * r2 - r1 * m21) - m01 * (m10 * r2 - r1 * m20) + r0 * (m10 * m21 - m11 * m20))
    return d0 / det, d1 / det, d2 / det


@njit(cache=CACHE, fastmath=FAST)
def _nearest_support(x0, x1, x2, wx, wy):
    best = math.inf
    jb = 0
    for i in range(wx.shape[0]):
        ux = x0 - x2 * wy[i]
        uy = x1 + x2 * wx[i]
        r2 = ux * ux + uy * uy
        if r2 < best:
            best = r2
            jb = i
    return jb


@njit(cache=CACHE, fastmath=FAST)
def escape_kink(wx, wy, p, a0, a1, a2, q, x0, x1, x2, lam, kkt, vertex, iters, kkt_tol, max_iter, work):
    """Newton stalled on a kink (support point j) that is not the optimum: step along the
    descent direction d in the constraint plane with A_j d = z/|z| (f'(x_j; d) = P_j - |z|
    < 0) and resume Newton (newton._escape_kinks). Returns the updated
    (x0, x1, x2, lambda, kkt, vertex, iterations)."""
    for _ in range(ESCAPE_ROUNDS):
        if kkt <= kkt_tol:
            break
        j = _nearest_support(x0, x1, x2, wx, wy)
        v0, v1, v2, lam_v, viol, zx, zy = vertex_test(wx, wy, p, a0, a1, a2, q, j)
        if viol <= kkt_tol:
            return v0, v1, v2, lam_v, viol, j, iters
        zn = max(math.hypot(zx, zy), TINY)
        d0, d1, d2 = _solve3(1.0, 0.0, -wy[j], 0.0, 1.0, wx[j], a0, a1, a2, zx / zn, zy / zn, 0.0)
        f0 = power_at(v0, v1, v2, wx, wy, p)
        t = math.sqrt(v0 * v0 + v1 * v1 + v2 * v2) / max(math.sqrt(d0 * d0 + d1 * d1 + d2 * d2), TINY)
        s0, s1, s2 = v0, v1, v2
        for _ in range(ESCAPE_HALVINGS):
            tr0, tr1, tr2 = v0 + t * d0, v1 + t * d1, v2 + t * d2
            if power_at(tr0, tr1, tr2, wx, wy, p) < f0:
                s0, s1, s2 = tr0, tr1, tr2
                break
            t *= 0.5
        x0, x1, x2, lam, kkt, its = newton_plane(wx, wy, p, a0, a1, a2, q, kkt_tol, max_iter, True, s0, s1, s2, work)
        iters += its
    return x0, x1, x2, lam, kkt, vertex, iters


@njit(cache=CACHE, fastmath=FAST)
def solve_one_row(wx, wy, p, a0, a1, a2, q, kkt_tol, max_iter, work):
    """min f subject to a . x = q (newton.solve_batch, one row): (x0, x1, x2, lambda, kkt,
    vertex index or -1, iterations). ``work``: (6, k) scratch."""
    k = wx.shape[0]
    if k > VERTEX_FIRST_MAX_K:
        x0, x1, x2, lam, kkt, iters = newton_plane(wx, wy, p, a0, a1, a2, q, kkt_tol, max_iter, False, 0.0, 0.0, 0.0,
                                                   work)
        vertex = -1
        if kkt > kkt_tol:
            # the NEAREST support points to the stalled iterate, nearest first; a later one
            # that passes the test replaces an earlier one, as in the reference
            u0, u1, u2 = x0, x1, x2
            prev0 = prev1 = -1
            for rank in range(min(NEAREST, k)):
                best = math.inf
                j = -1
                for i in range(k):
                    ux = u0 - u2 * wy[i]
                    uy = u1 + u2 * wx[i]
                    r2 = ux * ux + uy * uy
                    if i != prev0 and i != prev1 and r2 < best:
                        best = r2
                        j = i
                if rank == 0:
                    prev0 = j
                else:
                    prev1 = j
                v0, v1, v2, lam_v, viol, _, _ = vertex_test(wx, wy, p, a0, a1, a2, q, j)
                if viol <= kkt_tol:
                    x0, x1, x2, lam, kkt, vertex = v0, v1, v2, lam_v, viol, j
            x0, x1, x2, lam, kkt, vertex, iters = escape_kink(wx, wy, p, a0, a1, a2, q, x0, x1, x2, lam, kkt, vertex,
                                                              iters, kkt_tol, max_iter, work)
        return x0, x1, x2, lam, kkt, vertex, iters
    x0, x1, x2, lam, viol, idx = best_vertex(wx, wy, p, a0, a1, a2, q)
    if viol <= kkt_tol:
        return x0, x1, x2, lam, viol, idx, 0
    x0, x1, x2, lam, kkt, iters = newton_plane(wx, wy, p, a0, a1, a2, q, kkt_tol, max_iter, False, 0.0, 0.0, 0.0, work)
    if kkt > kkt_tol:
        return escape_kink(wx, wy, p, a0, a1, a2, q, x0, x1, x2, lam, kkt, -1, iters, kkt_tol, max_iter, work)
    return x0, x1, x2, lam, kkt, -1, iters


@njit(cache=CACHE, fastmath=FAST)
def _line_derivatives(t, wx, wy, p, px, py, kx, ky):
    """phi'(t) and phi''(t) of phi(t) = f(xp + t k)."""
    d1 = 0.0
    d2 = 0.0
    for i in range(wx.shape[0]):
        ux = px[i] + t * kx[i]
        uy = py[i] + t * ky[i]
        rho = math.sqrt(ux * ux + uy * uy)
        inv = 1.0 / max(rho, TINY)
        ex = ux * inv
        ey = uy * inv
        d1 += p[i] * (ex * kx[i] + ey * ky[i])
        tt = -ey * kx[i] + ex * ky[i]
        d2 += p[i] / max(rho, TINY) * tt * tt
    return d1, d2


@njit(cache=CACHE, fastmath=FAST)
def solve_sticking(wx, wy, p, c0, c1, q0, q1, kkt_tol, max_iter, work):
    """min f subject to v + omega J c = q (two rows, 4.1.2): safeguarded Newton on the
    monotone derivative along the constraint line (newton._newton_line). Returns (x0, x1,
    x2, multipliers m0, m1 (the contact force), kkt, vertex index or -1, iterations).
    ``work``: (6, k) scratch."""
    k = wx.shape[0]
    jc0, jc1 = -c1, c0
    # the rows [1, 0, jc0], [0, 1, jc1]: their null direction and the least-norm solution
    kd0, kd1, kd2 = -jc0, -jc1, 1.0
    kn = math.sqrt(kd0 * kd0 + kd1 * kd1 + kd2 * kd2)
    kk0, kk1, kk2 = kd0 / kn, kd1 / kn, kd2 / kn
    g00 = 1.0 + jc0 * jc0
    g01 = jc0 * jc1
    g11 = 1.0 + jc1 * jc1
    det = g00 * g11 - g01 * g01
    y0 = (g11 * q0 - g01 * q1) / det
    y1 = (g00 * q1 - g01 * q0) / det
    xp0, xp1, xp2 = y0, y1, jc0 * y0 + jc1 * y1
    px, py, kx, ky = work[0], work[1], work[2], work[3]
    sp = 0.0
    sk = 0.0
    for i in range(k):
        px[i] = xp0 - xp2 * wy[i]
        py[i] = xp1 + xp2 * wx[i]
        kx[i] = kk0 - kk2 * wy[i]
        ky[i] = kk1 + kk2 * wx[i]
        sp += p[i] * math.sqrt(px[i] * px[i] + py[i] * py[i])
        sk += p[i] * math.sqrt(kx[i] * kx[i] + ky[i] * ky[i])
    scale = max(sp / max(sk, TINY), 1.0)
    lo = -scale
    hi = scale
    for _ in range(LINE_GROWTH):
        dlo, _ = _line_derivatives(lo, wx, wy, p, px, py, kx, ky)
        if not dlo >= 0.0:
            break
        lo *= 2.0
    for _ in range(LINE_GROWTH):
        dhi, _ = _line_derivatives(hi, wx, wy, p, px, py, kx, ky)
        if not dhi <= 0.0:
            break
        hi *= 2.0
    t = min(max(0.0, lo), hi)
    iters = 0
    kkt = math.inf
    width_old = hi - lo
    for it in range(max_iter):
        d1, d2 = _line_derivatives(t, wx, wy, p, px, py, kx, ky)
        kkt = abs(d1)
        if not (kkt > kkt_tol and hi - lo > 4.0 * EPS * max(abs(t), 1.0)):
            break
        iters += 1
        if d1 < 0.0:
            lo = t
        if d1 > 0.0:
            hi = t
        tn = t - d1 / d2 if d2 != 0.0 else math.nan
        inside = math.isfinite(tn) and lo < tn < hi
        # near a kink Newton can bounce inside the bracket: every other iteration, bisect
        # unless the bracket has at least halved since the last check
        if it % 2 == 1:
            if (hi - lo) > 0.5 * width_old:
                inside = False
            width_old = hi - lo
        t = tn if inside else 0.5 * (lo + hi)
    # a kink: the one-sided derivatives straddle zero -> optimal, residual 0
    h = 8.0 * EPS * max(abs(t), 1.0)
    dm, _ = _line_derivatives(t - h, wx, wy, p, px, py, kx, ky)
    dp, _ = _line_derivatives(t + h, wx, wy, p, px, py, kx, ky)
    if dm <= 0.0 and dp >= 0.0 and kkt > kkt_tol:
        kkt = 0.0
    x0, x1, x2 = xp0 + t * kk0, xp1 + t * kk1, xp2 + t * kk2
    # the multipliers: least squares of M^T m = grad f, M^T = [[1, 0], [0, 1], [jc0, jc1]]
    g0, g1, g2 = gradient_at(x0, x1, x2, wx, wy, p)
    r0 = g0 + jc0 * g2
    r1 = g1 + jc1 * g2
    m0 = (g11 * r0 - g01 * r1) / det
    m1 = (g00 * r1 - g01 * r0) / det
    vertex = -1
    if abs(x2) > TINY:
        cx, cy = -x1 / x2, x0 / x2
        wmax = 1.0
        dbest = math.inf
        for i in range(k):
            wmax = max(wmax, math.hypot(wx[i], wy[i]))
            d = math.hypot(wx[i] - cx, wy[i] - cy)
            if d < dbest:
                dbest = d
                vertex = i
        if not dbest <= 1e3 * EPS * wmax:
            vertex = -1
    return x0, x1, x2, m0, m1, kkt, vertex, iters


@njit(cache=CACHE, fastmath=FAST)
def vertex_contact_force(wx, wy, p, c0, c1, x0, x1, x2, j, n0, n1, t0, t1, mu_c, m0, m1):
    """Sticking with the COR on support point j: the contact force is a set; its member
    deepest in the friction cone (newton._vertex_contact_force). Returns (m0, m1)."""
    g0, g1, g2 = gradient_at(x0, x1, x2, wx, wy, p, j)
    jc0, jc1 = -c1, c0
    dv0, dv1 = wx[j] - c0, wy[j] - c1
    dn = math.hypot(dv0, dv1)
    if dn == 0.0:
        return m0, m1
    e0, e1 = dv0 / dn, dv1 / dn
    kq = jc0 * g0 + jc1 * g1 - g2
    z00, z01 = kq * -dv1 / (dn * dn), kq * dv0 / (dn * dn)
    rem = p[j] * p[j] - (z00 * z00 + z01 * z01)
    if rem < 0.0:
        return m0, m1
    tm = math.sqrt(rem)
    b0, b1 = g0 + z00, g1 + z01
    best_tau = -tm
    best_val = -math.inf
    et = e0 * t0 + e1 * t1
    for c in range(3):
        if c == 0:
            tau = -tm
        elif c == 1:
            tau = tm
        else:
            if et == 0.0:
                break
            tau = -(b0 * t0 + b1 * t1) / et
            if not (-tm < tau < tm):
                break
        f0, f1 = b0 + tau * e0, b1 + tau * e1
        val = mu_c * (f0 * n0 + f1 * n1) - abs(f0 * t0 + f1 * t1)
        if val > best_val:
            best_val = val
            best_tau = tau
    return b0 + best_tau * e0, b1 + best_tau * e1


@njit(cache=CACHE, fastmath=FAST)
def _frictionless(wx, wy, p, c0, c1, d0, d1, n0, n1, sin_a, kkt_tol, max_iter, work):
    """The frictionless solve with the contact force along the unit d, scaled so that the
    contact keeps up with the pusher, n . v(c) = n . p (3.3): (x0, x1, x2, lambda, kappa,
    kkt, vertex, iterations)."""
    a2 = -c1 * d0 + c0 * d1
    x0, x1, x2, lam, kkt, vertex, iters = solve_one_row(wx, wy, p, d0, d1, a2, 1.0, kkt_tol, max_iter, work)
    vc0 = x0 - x2 * c1
    vc1 = x1 + x2 * c0
    kappa = sin_a / (vc0 * n0 + vc1 * n1)
    return x0 * kappa, x1 * kappa, x2 * kappa, lam, kappa, kkt, vertex, iters


@njit(cache=CACHE, fastmath=FAST)
def _slipping(wx, wy, p, c0, c1, n0, n1, t0, t1, push0, push1, sin_a, mu_c, sg, kkt_tol, max_iter, work):
    """Slipping with the contact force on the friction cone's edge on side ``sg`` (4.1.3):
    the frictionless motion for that edge (x0, x1, x2, force0, force1, kkt, vertex,
    iterations, mode, consistent, failed)."""
    hyp = math.hypot(1.0, mu_c)
    d0 = (n0 + sg * mu_c * t0) / hyp
    d1 = (n1 + sg * mu_c * t1) / hyp
    y0, y1, y2, lam, kappa, k2, v2, its = _frictionless(wx, wy, p, c0, c1, d0, d1, n0, n1, sin_a, kkt_tol, max_iter,
                                                        work)
    vc0 = y0 - y2 * c1
    vc1 = y1 + y2 * c0
    rel = (push0 - vc0) * t0 + (push1 - vc1) * t1  # the pusher relative to the part, along t
    sign_rel = 1.0 if rel > 0.0 else (-1.0 if rel < 0.0 else 0.0)
    ok = kappa > 0.0 and lam > 0.0 and sign_rel == sg
    up = (vc0 - push0) * -push1 + (vc1 - push1) * push0 > 0.0
    mode = MODE_SLIPPING_UP if up else MODE_SLIPPING_DOWN
    return y0, y1, y2, lam * d0, lam * d1, k2, v2, its, mode, ok, not k2 <= kkt_tol


@njit(cache=CACHE, fastmath=FAST)
def solve_modes(wx, wy, p, c0, c1, n0, n1, t0, t1, push0, push1, sin_a, mu_c, kkt_tol, cone_tol, max_iter, work,
                slip_first):
    """The motion of one problem in normalised units (forward._solve_normalised): the
    frictionless one (mu_c = 0) or the mode of 4.1 whose assumptions hold. Returns (x0, x1,
    x2, force0, force1, kkt, vertex, iterations, mode, consistent, failed, side): ``failed``
    when a solve it relied on missed ``kkt_tol`` (the reference re-solves it), ``side`` the
    cone's edge a slip is on (+-1; 0 without one). ``slip_first`` (+-1; 0: none): the side
    of the previous step's slip, tried first and kept if its own assumptions hold, which
    they do for one mode only (4.1; a simulator's step mostly slips as the last one did).
    ``work``: (6, k) scratch, so that nothing is allocated per solve."""
    if mu_c == 0.0:
        x0, x1, x2, lam, kappa, kkt, vertex, iters = _frictionless(wx, wy, p, c0, c1, n0, n1, n0, n1, sin_a, kkt_tol,
                                                                   max_iter, work)
        return (x0, x1, x2, lam * n0, lam * n1, kkt, vertex, iters, MODE_FRICTIONLESS, kappa > 0.0,
                not kkt <= kkt_tol, 0.0)
    tried = 0
    if slip_first != 0.0:
        out = _slipping(wx, wy, p, c0, c1, n0, n1, t0, t1, push0, push1, sin_a, mu_c, slip_first, kkt_tol, max_iter,
                        work)
        if out[9] and not out[10]:
            return out[0], out[1], out[2], out[3], out[4], out[5], out[6], out[7], out[8], True, False, slip_first
        tried = out[7]
    x0, x1, x2, m0, m1, kkt, vertex, iters = solve_sticking(wx, wy, p, c0, c1, push0, push1, kkt_tol, max_iter, work)
    iters += tried
    if vertex >= 0:
        m0, m1 = vertex_contact_force(wx, wy, p, c0, c1, x0, x1, x2, vertex, n0, n1, t0, t1, mu_c, m0, m1)
    failed = not kkt <= kkt_tol
    fn = m0 * n0 + m1 * n1
    ft = m0 * t0 + m1 * t1
    if fn > 0.0 and abs(ft) <= mu_c * fn * (1.0 + cone_tol):
        return x0, x1, x2, m0, m1, kkt, vertex, iters, MODE_STICKING, True, failed, 0.0
    # the force would leave the cone on the side of sign(ft): slip with it on that edge (4.1.3)
    sg = 1.0 if ft >= 0.0 else -1.0
    out = _slipping(wx, wy, p, c0, c1, n0, n1, t0, t1, push0, push1, sin_a, mu_c, sg, kkt_tol, max_iter, work)
    return (out[0], out[1], out[2], out[3], out[4], out[5], out[6], out[7] + iters, out[8], out[9], failed or out[10],
            sg)


@njit(cache=CACHE, fastmath=FAST)
def norm(x, y):
    """|(x, y)| in world units, which may lie anywhere from 1e-300 to 1e300: the plain root
    of the squares where they neither over- nor underflow, else math.hypot (four times
    slower)."""
    r2 = x * x + y * y
    if 1e-290 < r2 < 1e290:
        return math.sqrt(r2)
    return math.hypot(x, y)


@njit(cache=CACHE, fastmath=FAST)
def _note(bad, fault, r):
    """Support r has ``fault``: kept if it is the first found with it."""
    if bad[fault] < 0:
        bad[fault] = r


@njit(cache=CACHE, fastmath=FAST)
def _largest(wx, wy):
    """The largest |w_i| (the centroid test's scale)."""
    big = 0.0
    for i in range(wx.shape[0]):
        big = max(big, norm(wx[i], wy[i]))
    return big


_F1, _F2, _F3 = types.float64[:], types.float64[:, :], types.float64[:, :, :]
SOLVE_SUPPORTS_SIGNATURE = (_F3, _F2, _F2, _F2, _F2, _F2, _F2, _F1, types.float64, _F1)

@njit([SOLVE_SUPPORTS_SIGNATURE], cache=CACHE, fastmath=FAST)
def solve_supports(points, weights, cms, contact_rel, normal, alpha_hat, push_hat, sin_alpha, mu_c, tol):
    """Every support of a batch (points (B, k, 2) world frame, weights (B, k) >= 0, its CM
    ``cms`` (B or 1, 2); the scene's geometry per row or one row for all: contact relative
    to the CM, normal, alpha_hat, push direction (G, 2), sin alpha (G,)) pushed with contact
    friction ``mu_c``. ``tol``: kkt, kkt for the cone test, Newton's iteration cap, the
    translation test (|omega| L <= it |v|), the centroid test (|centroid - CM| <= it L; inf:
    not checked).

    Returns (real (B, 11): the O_* columns, world frame; int (B, 5): the I_* columns; bad
    (4,): the first support found with each BAD_* fault, or -1). Supports after a fault are
    still solved where they can be; the caller refuses the batch."""
    b, k = weights.shape
    real = np.full((b, 11), np.nan)
    ints = np.zeros((b, 5), dtype=np.int64)
    bad = np.full(4, -1, dtype=np.int64)
    wx = np.empty(k)
    wy = np.empty(k)
    p = np.empty(k)
    work = np.empty((6, k))
    kkt_tol, cone_tol, max_iter, trans_tol, centroid_tol = tol[0], tol[1], int(tol[2]), tol[3], tol[4]
    one_cm = cms.shape[0] == 1
    one_scene = contact_rel.shape[0] == 1
    for r in range(b):
        c = 0 if one_cm else r
        g = 0 if one_scene else r
        total = 0.0
        finite = True
        for i in range(k):
            wi = weights[r, i]
            if not (math.isfinite(points[r, i, 0]) and math.isfinite(points[r, i, 1]) and math.isfinite(wi)) or wi < 0.0:
                finite = False
            total += wi
        if not finite:
            _note(bad, BAD_VALUES, r)
            continue
        if not total > 0.0:
            _note(bad, BAD_TOTAL, r)
            continue
        c0, c1 = contact_rel[g, 0], contact_rel[g, 1]
        ell = norm(c0, c1)
        cx = 0.0
        cy = 0.0
        for i in range(k):
            p[i] = weights[r, i] / total
            wx[i] = points[r, i, 0] - cms[c, 0]
            wy[i] = points[r, i, 1] - cms[c, 1]
            ell = max(ell, norm(wx[i], wy[i]))
            cx += p[i] * wx[i]
            cy += p[i] * wy[i]
        if norm(cx, cy) > centroid_tol * _largest(wx, wy):
            _note(bad, BAD_CENTROID, r)
            continue
        if not ell > 0.0:
            _note(bad, BAD_LENGTH, r)
            continue
        power = 0.0
        for i in range(k):
            wx[i] /= ell
            wy[i] /= ell
        out = solve_modes(wx, wy, p, c0 / ell, c1 / ell, normal[g, 0], normal[g, 1], alpha_hat[g, 0], alpha_hat[g, 1],
                          push_hat[g, 0], push_hat[g, 1], sin_alpha[g], mu_c, kkt_tol, cone_tol, max_iter, work, 0.0)
        v0, v1, omega = out[0], out[1], out[2] / ell
        f0, f1 = out[3], out[4]
        vc0 = v0 - omega * c1
        vc1 = v1 + omega * c0
        for i in range(k):  # in world units: the support points are ell * w
            ux = v0 - omega * wy[i] * ell
            uy = v1 + omega * wx[i] * ell
            power += p[i] * math.sqrt(ux * ux + uy * uy)
        real[r, O_VX], real[r, O_VY], real[r, O_OMEGA] = v0, v1, omega
        real[r, O_FX], real[r, O_FY], real[r, O_KKT] = f0, f1, out[5]
        if not abs(omega) * ell <= trans_tol * norm(v0, v1):
            real[r, O_COR_X] = cms[c, 0] - v1 / omega
            real[r, O_COR_Y] = cms[c, 1] + v0 / omega
        real[r, O_POWER] = power
        real[r, O_SLIP] = (push_hat[g, 0] - vc0) * alpha_hat[g, 0] + (push_hat[g, 1] - vc1) * alpha_hat[g, 1]
        real[r, O_GAP] = power - (f0 * vc0 + f1 * vc1)
        ints[r, I_VERTEX], ints[r, I_ITERS], ints[r, I_MODE] = out[6], out[7], out[8]
        ints[r, I_CONSISTENT] = 1 if out[9] else 0
        ints[r, I_FAILED] = 1 if out[10] else 0
    return real, ints, bad
