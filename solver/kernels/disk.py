"""The analytic disk COR locus (book 3.3.4-3.3.12), compiled (numba): its boundary polygon,
built point for point as :func:`models.locus.cor_disk.boundary_local` builds it (that
module is the reference these kernels are tested against), and what the sweeps of
chapter 4 ask of it, whole sweeps in one call.

* :func:`half_ring` is one half boundary: the pieces' plan (:class:`_HalfPlan` of the
  reference: r_min (3.31), the disk crossing (3.32), the corner where the outer dipods
  reach the disk, the points shared by length), the outer dipods (3.21), (3.34), (3.35)
  solved for rho by the same bracketed Illinois iteration, the perimeter arc and the inner
  piece (3.30); and the largest residual of their equations.
* :func:`sticking_spans` is the sticking sweep of 4.1.4 at many force angles phi: for each,
  the frictionless scene of the force turned by phi (models.sketch.disk_sketch.force_scene),
  its boundary in the world, the sticking line's intervals inside it and the part of them
  where sticking agrees with that locus's sense (disk_sketch.sticking_spans).

The arithmetic is the reference's, operation for operation, without fast-math, but for one
thing: an outer point's root solve starts from a narrow bracket about the root its two
neighbours extrapolate to (falling back on the reference's bracket when that one does not
hold the root), about 3 evaluations of (3.35) a point instead of 11, converged to the same
tolerance; so points agree with the reference's to that tolerance (1e-14 in log rho) and
rounding (numpy's and libm's transcendental functions may differ in the last bit). A
force angle whose scene the reference would refuse, or whose boundary misses its residual
tolerance, is marked :data:`SPAN_REFERENCE`: the caller asks the reference, which says why.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, types

from solver.kernels import ensure_cache
from solver.kernels.codes import SPAN_FOUND, SPAN_NONE, SPAN_REFERENCE

CACHE = True
"""Compiled code kept on disk (numba's cache; solver/kernels/__init__.py says where)."""
ensure_cache()  # before the first function is compiled or loaded

ENTRY_POINTS = ("sticking_spans", "rings")
"""Compiled with explicit signatures when the module is imported (the others are compiled
into them)."""

SQRT_HALF = math.sqrt(0.5)
WARM_WIDTH = 0.5
"""The half-width of an outer point's first bracket, in steps between the last two roots
(about the extrapolation's error many times over on the smooth outer piece)."""


@njit(cache=CACHE)
def _dipod_mu(rho, sa, ca):
    """The dipod moment arm of (3.21)/(3.35) at distance rho (models.locus.cor_disk._dipod_terms)
    and (v_x, v_y), whose direction gives eta (3.34)."""
    dp = math.hypot(rho + ca, sa)
    dm = math.hypot(rho - ca, sa)
    big_d = dp * dm
    big_s = dp + dm
    q = rho * rho + 1.0
    vx = -2.0 * rho * sa * ca / (big_d * big_s)
    vy = 0.5 * ((rho + ca) / dp + (rho - ca) / dm)
    num = 2.0 * rho * rho * sa * sa * (q + big_d) / ((big_d + rho * rho - 1.0) * big_s * big_d)
    return num / math.hypot(vx, vy), vx, vy


@njit(cache=CACHE)
def _g(x, sa, ca, mu):
    """log(mu(x)/mu), x = log rho, and the dipod's (v_x, v_y) there."""
    m, vx, vy = _dipod_mu(math.exp(x), sa, ca)
    return math.log(m / mu), m, vx, vy


@njit(cache=CACHE)
def _outer_point(omega, mu, rtol, max_iter, guess, width):
    """rho of (3.35) at dipod angle omega: Illinois on g(x) = log(mu(x)/mu), x = log rho
    (models.locus.cor_disk.outer_boundary, point for point), from the bracket
    [guess - width, guess + width] when it holds the root (the neighbouring points' roots
    extrapolated: a few iterations), else from the reference's [0, log(1/mu)]. Returns
    (rho, eta, relative residual of (3.35), iterations, converged, x)."""
    sa = math.sin(omega)
    ca = math.cos(omega)
    x_top = math.log(1.0 / mu)
    narrow = False
    g_lo = g_hi = 0.0
    x_lo = x_hi = 0.0
    if width > 0.0:
        x_lo = max(guess - width, 0.0)
        x_hi = min(guess + width, x_top)
        if x_lo < x_hi:
            g_lo = _g(x_lo, sa, ca, mu)[0]
            g_hi = _g(x_hi, sa, ca, mu)[0]
            narrow = g_lo > 0.0 and g_hi < 0.0
    if not narrow:
        x_lo = 0.0
        x_hi = x_top
        g_lo = _g(x_lo, sa, ca, mu)[0]
        g_hi = _g(x_hi, sa, ca, mu)[0]
    done = g_hi >= 0.0
    x = x_hi if done else 0.5 * (x_lo + x_hi)
    side = 0.0
    it = 0
    m = vx = vy = math.nan
    if not done:
        for it in range(1, max_iter + 1):
            denom = g_hi - g_lo
            if denom != 0.0:
                x_new = x_hi - g_hi * (x_hi - x_lo) / denom
            else:
                x_new = 0.5 * (x_lo + x_hi)
            if not (x_new > x_lo and x_new < x_hi):
                x_new = 0.5 * (x_lo + x_hi)
            g_new, m, vx, vy = _g(x_new, sa, ca, mu)
            upper = g_new < 0.0
            if upper and side == -1.0:
                g_lo = 0.5 * g_lo
            if not upper and side == 1.0:
                g_hi = 0.5 * g_hi
            if upper:
                x_hi = x_new
                g_hi = g_new
                side = -1.0
            else:
                x_lo = x_new
                g_lo = g_new
                side = 1.0
            x = x_new
            if abs(g_new) <= rtol or x_hi - x_lo <= rtol * max(1.0, abs(x_new)):
                done = True
                break
    rho = math.exp(x)
    if it == 0:  # the root at the bracket's end: not evaluated there by the loop
        m, vx, vy = _dipod_mu(rho, sa, ca)
    return rho, math.atan2(-vx, vy), abs(m - mu) / mu, it, done, x


@njit(cache=CACHE)
def _inner_cos(rho, mu):
    """cos(eta) of the inner boundary (3.30), cancellation-free (cor_disk.inner_boundary_cos_eta)."""
    x = (rho + 1.0) ** 2 + mu * mu
    return (rho * rho * (rho + 1.0) + mu * mu * (rho - 1.0)) / (rho * (rho * math.sqrt(x) + mu))


@njit(cache=CACHE)
def _inner_residual(rho, eta, mu):
    """Relative residual of (3.26)/(3.28) (cor_disk.inner_boundary_residual)."""
    b = rho / (rho + 1.0)
    s = mu + rho * math.cos(eta)
    q = rho * rho / s
    lhs = (q - (rho - b) * math.cos(eta)) ** 2 + ((rho - b) * math.sin(eta)) ** 2
    return (math.sqrt(lhs) - b) / b


@njit(cache=CACHE)
def _clip1(x):
    return min(max(x, -1.0), 1.0)


@njit(cache=CACHE)
def _length(x0, y0, x1, y1):
    dx = x0 - x1
    dy = y0 - y1
    return math.sqrt(dx * dx + dy * dy)


@njit(cache=CACHE)
def _allocate(lengths, total, minimum, counts):
    """Split ``total`` points among the three pieces by length, at least ``minimum`` each
    (cor_disk._allocate: floors, then the remainder to the largest fractions, ties in order)."""
    spare = total
    length_sum = 0.0
    for i in range(3):
        counts[i] = minimum if lengths[i] > 0.0 else 0
        spare -= counts[i]
        if lengths[i] > 0.0:
            length_sum += lengths[i]
    if spare > 0 and length_sum > 0.0:
        frac = np.zeros(3)
        extra = 0
        for i in range(3):
            share = spare * lengths[i] / length_sum if lengths[i] > 0.0 else 0.0
            whole = math.floor(share)
            counts[i] += int(whole)
            extra += int(whole)
            frac[i] = share - whole
        taken = np.zeros(3, dtype=np.bool_)
        for _ in range(spare - extra):
            best = -1
            for i in range(3):
                if not taken[i] and (best < 0 or frac[i] > frac[best]):
                    best = i
            taken[best] = True
            counts[best] += 1


@njit(cache=CACHE)
def _linspace(start, stop, num, i):
    """Element i of numpy.linspace(start, stop, num)."""
    if i == num - 1:
        return stop
    return i * ((stop - start) / (num - 1)) + start


@njit(cache=CACHE)
def half_ring(mu, n_half, rtol, max_iter, rho, eta):
    """One half boundary, tip (eta = 0) to r_min (eta = pi), into ``rho`` and ``eta``
    (cor_disk.half_boundary): (points written, largest residual, iterations, converged)."""
    rho_min = mu / (2.0 + mu)
    cos_a = 2.0 / (math.sqrt(mu * mu + 4.0) + mu)
    eta_a = math.acos(min(1.0, cos_a))
    has_outer = mu < 1.0
    omega_c = 0.0
    eta_c = 0.0
    if has_outer:
        if mu >= SQRT_HALF:
            omega_c = 0.5 * math.pi - 2.0 * math.acos(min(mu, 1.0))
            eta_c = math.acos(mu)
        else:
            eta_c = eta_a
    rho_tip = 1.0 / min(mu, 1.0)
    lengths = np.zeros(3)
    if has_outer:
        lengths[0] = _length(-rho_tip * math.cos(0.0), rho_tip * math.sin(0.0), -math.cos(eta_c), math.sin(eta_c))
    lengths[1] = max(0.0, eta_a - eta_c)
    mid = 0.5 * (1.0 + rho_min)
    eta_mid = math.acos(_clip1(_inner_cos(mid, mu)))
    mx, my = -mid * math.cos(eta_mid), mid * math.sin(eta_mid)
    lengths[2] = (_length(-math.cos(eta_a), math.sin(eta_a), mx, my)
                  + _length(mx, my, -rho_min * math.cos(math.pi), rho_min * math.sin(math.pi)))
    joints = -1
    for i in range(3):
        if lengths[i] > 0.0:
            joints += 1
    counts = np.zeros(3, dtype=np.int64)
    _allocate(lengths, n_half + joints, 2, counts)
    n_outer, n_arc, n_inner = counts[0], counts[1], counts[2]

    k = 0
    residual = 0.0
    iterations = 0
    converged = True
    if has_outer:
        rho[k], eta[k] = rho_tip, 0.0
        k += 1
        x1 = x2 = 0.0  # the last two roots (log rho), extrapolated to the next point's bracket
        for i in range(1, n_outer - 1):
            omega = omega_c + (0.5 * math.pi - omega_c) * (1.0 - _linspace(0.0, 1.0, n_outer, i))
            step = x1 - x2
            width = WARM_WIDTH * abs(step) if i > 2 else 0.0
            r, e, res, it, ok, x = _outer_point(omega, mu, rtol, max_iter, x1 + step, width)
            x2, x1 = x1, x
            rho[k], eta[k] = r, e
            k += 1
            residual = max(residual, res)
            iterations = max(iterations, it)
            converged = converged and ok
        rho[k], eta[k] = 1.0, eta_c
        k += 1
    if lengths[1] > 0.0:
        for i in range(1 if has_outer else 0, n_arc):
            rho[k], eta[k] = 1.0, _linspace(eta_c, eta_a, n_arc, i)
            k += 1
    # the inner piece: rho = rho_min + (1 - rho_min) t^2, t from 1 to 0, without its first point
    for i in range(1, n_inner):
        t = _linspace(1.0, 0.0, n_inner, i)
        r = rho_min + (1.0 - rho_min) * t * t
        e = math.pi if i == n_inner - 1 else math.acos(_clip1(_inner_cos(r, mu)))
        rho[k], eta[k] = r, e
        k += 1
        if i < n_inner - 1:
            residual = max(residual, abs(_inner_residual(r, e, mu)))
    return k, residual, iterations, converged


@njit(cache=CACHE)
def _ring(mu, n_points, rtol, max_iter, ring):
    """The closed boundary (n, 2), counter-clockwise from the tip, in the locus frame
    (cor_disk.boundary_local: the half, then its mirror image): (points, residual,
    iterations, converged)."""
    n_half = (n_points + 1) // 2 + 1
    rho = np.empty(n_half + 3)
    eta = np.empty(n_half + 3)
    h, residual, iterations, ok = half_ring(mu, n_half, rtol, max_iter, rho, eta)
    n = 2 * h - 2
    # full = upper (h points) then the mirrored upper[h-2 .. 1]; the ring is full reversed
    # and rolled by one: ring[0] = full[0], ring[k] = full[n - k]
    for k in range(n):
        j = 0 if k == 0 else n - k
        if j < h:
            ring[k, 0] = -rho[j] * math.cos(eta[j])
            ring[k, 1] = rho[j] * math.sin(eta[j])
        else:
            u = h - 2 - (j - h)
            ring[k, 0] = -rho[u] * math.cos(eta[u])
            ring[k, 1] = -(rho[u] * math.sin(eta[u]))
    return n, residual, iterations, ok


@njit(cache=CACHE)
def ring_size(n_points):
    """The number of points of :func:`_ring` for ``n_points`` (an odd count rounded up)."""
    return 2 * ((n_points + 1) // 2 + 1) - 2


_F1, _F2, _F3 = types.float64[:], types.float64[:, :], types.float64[:, :, :]
RINGS_SIGNATURE = (_F1, types.int64, types.float64, types.int64, _F3, _F1, types.int64[:], types.boolean[:])


@njit([RINGS_SIGNATURE], cache=CACHE)
def rings(mus, n_points, rtol, max_iter, out, residual, iterations, converged):
    """The locus-frame boundary of each relative moment arm ``mus[b]`` into ``out[b]``
    ((B, ring_size(n_points), 2)), with its residual, iterations and convergence
    (cor_disk.boundary_locals)."""
    for b in range(mus.shape[0]):
        _, res, it, ok = _ring(mus[b], n_points, rtol, max_iter, out[b])
        residual[b], iterations[b], converged[b] = res, it, ok


SPANS_SIGNATURE = (_F1, types.int64, _F1, _F1, _F1, _F1, _F1, _F2, _F1, types.int8[:])


@njit([SPANS_SIGNATURE], cache=CACHE)
def sticking_spans(phis, n_points, scene, jp, tol, lo, hi, work, ts, status):
    """The sticking sweep (4.1.4) at every force angle ``phis[i]``: into ``lo[i]``, ``hi[i]``
    the extent along the sticking line (t from the contact along ``jp``) of the points of
    {COR}_phi where sticking agrees with its sense, with ``status[i]`` :data:`SPAN_FOUND`,
    :data:`SPAN_NONE` (a translation, or no such point) or :data:`SPAN_REFERENCE`.

    ``scene`` = (a, cm_x, cm_y, contact_x, contact_y, normal_x, normal_y, edge_angle),
    ``tol`` = (root_rtol, root_max_iter, translation_rel, max_relative_moment_arm,
    boundary_residual_rel, grazing_sin); ``work`` is (ring_size(n_points), 2) or larger and
    ``ts`` holds ring_size(n_points) floats."""
    a, cm0, cm1, cp0, cp1, n0, n1, edge = scene[0], scene[1], scene[2], scene[3], scene[4], scene[5], scene[6], scene[7]
    rtol, max_iter, trans_rel, max_arm, res_tol, grazing = tol[0], int(tol[1]), tol[2], tol[3], tol[4], tol[5]
    ring = work
    c0, c1 = cp0 - cm0, cp1 - cm1
    nrm0, nrm1 = -jp[1], jp[0]
    for i in range(phis.shape[0]):
        phi = phis[i]
        status[i] = SPAN_NONE
        # the scene of the force turned by phi (disk_sketch.force_scene, PushScene.create)
        d0 = math.cos(phi) * n0 - math.sin(phi) * n1
        d1 = math.sin(phi) * n0 + math.cos(phi) * n1
        push = math.atan2(d1, d0)
        p0, p1 = math.cos(push), math.sin(push)
        e = edge + phi
        tn0, tn1 = -math.sin(e), math.cos(e)
        sin_alpha = tn0 * p0 + tn1 * p1
        if not abs(sin_alpha) > grazing:
            status[i] = SPAN_REFERENCE
            continue
        if sin_alpha < 0.0:
            tn0, tn1 = -tn0, -tn1
        ah0, ah1 = -tn1, tn0
        m = ah0 * c0 + ah1 * c1
        if not abs(m) <= max_arm * a:
            status[i] = SPAN_REFERENCE
            continue
        mu = abs(m) / a
        if mu <= trans_rel:
            continue  # a translation: no bounded locus
        n, residual, _, ok = _ring(mu, n_points, rtol, max_iter, ring)
        if not (ok and residual <= res_tol):
            status[i] = SPAN_REFERENCE
            continue
        e10, e11 = (ah0, ah1) if m >= 0.0 else (-ah0, -ah1)
        e20, e21 = -e11, e10
        # the world boundary (scene.to_world(local * a)), relative to the contact, and its
        # side of the sticking line
        for k in range(n):
            lx = ring[k, 0] * a
            ly = ring[k, 1] * a
            ring[k, 0] = cm0 + lx * e10 + ly * e20 - cp0
            ring[k, 1] = cm1 + lx * e11 + ly * e21 - cp1
        n_t = 0
        s_first = ring[0, 0] * nrm0 + ring[0, 1] * nrm1
        s_i = s_first
        for k in range(n):
            j = k + 1 if k + 1 < n else 0
            s_j = s_first if j == 0 else ring[j, 0] * nrm0 + ring[j, 1] * nrm1
            if (s_i > 0.0) != (s_j > 0.0):
                u = s_i / (s_i - s_j)
                q0 = ring[k, 0] + u * (ring[j, 0] - ring[k, 0])
                q1 = ring[k, 1] + u * (ring[j, 1] - ring[k, 1])
                ts[n_t] = q0 * jp[0] + q1 * jp[1]
                n_t += 1
            s_i = s_j
        if n_t < 2:
            continue
        found = np.sort(ts[:n_t])
        best_lo, best_hi = math.inf, -math.inf
        for k in range(0, n_t - 1, 2):
            t_lo, t_hi = found[k], found[k + 1]
            # r = c + t J p: (c - r) . J p = -t must have the sign of m_phi
            if m > 0.0:
                t_hi = min(t_hi, 0.0)
            else:
                t_lo = max(t_lo, 0.0)
            if t_hi > t_lo:
                best_lo = min(best_lo, t_lo)
                best_hi = max(best_hi, t_hi)
        if best_lo <= best_hi:
            lo[i], hi[i] = best_lo, best_hi
            status[i] = SPAN_FOUND
