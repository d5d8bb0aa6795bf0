"""A part on a belt meeting placed fences, simulated quasi-statically, compiled (numba): the
loop of solver/feeder/simulate.py (the reference, book 5.1, 6.4-6.6) for many parts at once,
each through every fence of a belt, the forward solve of each step the compiled one of
:mod:`solver.kernels.forward`.

Frames and contacts as in solver/feeder/simulate.py: the world frame of the belt (moving in
-y, fences fixed); a fence is the segment from its free end E along w for its length, its
face normal n; a part's hull (body frame, relative to the CM) drifts with the belt until it
touches a fence, then a vertex on the face or E on an edge is a point contact (a forward
solve: the twist is held for a step, the contact re-imposed after it, a step through the
fence halved), an edge flush slides exactly or jams (|tan gamma| <= mu_c, 6.4), and E on an
edge lying along the belt lets the part go.

One call runs a batch: part i starts at its given CM (or above the first fence) and meets
fence 0, 1, ... in turn, each run starting where the last ended, until it stops. Every run
returns its summary (status, steps, the end pose, whether an edge came flush, the largest
|x| of the hull over its poses, what its forward solves did); the runs of the first
``record`` parts also their trajectories and events, in flat buffers with offsets. A run
whose forward solve the compiled Newton could not finish stops with status
``REFERENCE`` and is run again by the caller on the reference path.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, types

from solver.kernels import ensure_cache
from solver.kernels.codes import (
    ALONG,
    COUNT_SIDE,
    D0,
    D1,
    E_ON_EDGE,
    END,
    EV_ALONG,
    EV_CONTACT_AGAIN,
    EV_END,
    EV_END_CORNER,
    EV_FIRST_CONTACT,
    EV_FLUSH,
    EV_JAM,
    EV_LEFT,
    EV_MISSED,
    EV_OVERLAP,
    EV_STALLED,
    EV_VERTEX,
    EV_VERTEX_CORNER,
    FLUSH,
    GRAZING,
    GRAZING_PUSH,
    GRAZING_SIN,
    JAM,
    JAMMED,
    LEFT,
    MISSED,
    MODE_COUNT,
    OVERLAP,
    PUSH_ANGLE,
    REFERENCE,
    S_CM_X,
    S_CM_Y,
    S_EVENTS_FROM,
    S_EVENTS_TO,
    S_FLUSHED,
    S_MAX_ANGLE,
    S_MAX_KKT,
    S_MAX_X,
    S_MODES,
    S_NOT_OPTIMAL,
    S_PATH_FROM,
    S_PATH_TO,
    S_PUSH,
    S_SOLVES,
    S_START_THETA,
    S_START_X,
    S_START_Y,
    S_STATUS,
    S_STEPS,
    S_THETA,
    STALLED,
    STEP_LIMIT,
    SUMMARY,
    TRANSLATION_TURN,
    VERTEX,
)
from solver.kernels.forward import FAST, norm, solve_modes

CACHE = True
ensure_cache()  # before the first function is compiled or loaded


@njit(cache=CACHE, fastmath=FAST)
def _grow(buf, n):
    """``buf`` with room for row n (doubled when full)."""
    if n < buf.shape[0]:
        return buf
    new = np.empty((2 * buf.shape[0], buf.shape[1]))
    new[: buf.shape[0]] = buf
    return new


@njit(cache=CACHE, fastmath=FAST)
def _pose_hull(cm0, cm1, theta, body, out):
    c = math.cos(theta)
    s = math.sin(theta)
    for i in range(body.shape[0]):
        out[i, 0] = cm0 + (body[i, 0] * c - body[i, 1] * s)
        out[i, 1] = cm1 + (body[i, 0] * s + body[i, 1] * c)


@njit(cache=CACHE, fastmath=FAST)
def _inward_normal(hull, i):
    """The unit normal of hull edge i (from vertex i to the next) into the hull."""
    j = (i + 1) % hull.shape[0]
    q0 = hull[j, 0] - hull[i, 0]
    q1 = hull[j, 1] - hull[i, 1]
    ln = norm(q0, q1)
    return -q1 / ln, q0 / ln


@njit(cache=CACHE, fastmath=FAST)
def _overlaps(hull, e0, e1, w0, w1, length, tol):
    """Whether the fence passes through the hull deeper than ``tol`` (the segment clipped by
    the hull's edges, each kept ``tol`` inside)."""
    m = hull.shape[0]
    lo = 0.0
    hi = length
    for i in range(m):
        nx, ny = _inward_normal(hull, i)
        base = nx * (e0 - hull[i, 0]) + ny * (e1 - hull[i, 1]) - tol
        rate = nx * w0 + ny * w1
        if rate == 0.0:
            if base <= 0.0:
                return False
            continue
        cut = -base / rate
        if rate > 0.0:
            lo = max(lo, cut)
        else:
            hi = min(hi, cut)
        if lo >= hi:
            return False
    return True


@njit(cache=CACHE, fastmath=FAST)
def _gaps(hull, e0, e1, gaps):
    """E's distance to each edge it can push (inf for an edge facing away from it)."""
    m = hull.shape[0]
    for i in range(m):
        j = (i + 1) % m
        q0 = hull[j, 0] - hull[i, 0]
        q1 = hull[j, 1] - hull[i, 1]
        r0 = e0 - hull[i, 0]
        r1 = e1 - hull[i, 1]
        u = min(max((r0 * q0 + r1 * q1) / (q0 * q0 + q1 * q1), 0.0), 1.0)
        if q0 < -GRAZING * norm(q0, q1):  # perp(q) . D < 0: E and the edge separate
            gaps[i] = math.inf
        else:
            gaps[i] = norm(r0 - u * q0, r1 - u * q1)


@njit(cache=CACHE, fastmath=FAST)
def _next_contact(hull, e0, e1, w0, w1, n0, n1, length, floor):
    """The drift (in -y, more than ``floor``) after which the part first touches the fence,
    or -1: a vertex drifting onto the face, or E rising onto an edge."""
    best = math.inf
    cos_g = n0 * D0 + n1 * D1
    m = hull.shape[0]
    for i in range(m):
        lam = ((hull[i, 0] - e0) * n0 + (hull[i, 1] - e1) * n1) / cos_g
        s = (hull[i, 0] - lam * D0 - e0) * w0 + (hull[i, 1] - lam * D1 - e1) * w1
        if lam > floor and 0.0 <= s <= length:
            best = min(best, lam)
    for i in range(m):
        j = (i + 1) % m
        ed0 = hull[j, 0] - hull[i, 0]
        ed1 = hull[j, 1] - hull[i, 1]
        den = D0 * -ed1 + D1 * ed0
        if abs(den) <= 1e-12 * norm(ed0, ed1):
            continue  # an edge along the belt's motion: E slides along it
        r0 = e0 - hull[i, 0]
        r1 = e1 - hull[i, 1]
        lam = (r0 * ed1 - r1 * ed0) / den
        mu = (r0 * D1 - r1 * D0) / den
        if lam > floor and 0.0 <= mu <= 1.0:
            best = min(best, lam)
    return -1.0 if math.isinf(best) else best


@njit(cache=CACHE, fastmath=FAST)
def _advance(cm0, cm1, theta, v0, v1, omega, at0, at1, h):
    """The pose moved by the twist (found with the CM at ``at``) held for a push h: a
    rotation by omega h about its COR, fixed in the world (solver.sim.kinematics.advance)."""
    turn = omega * h
    if abs(turn) <= TRANSLATION_TURN:
        return cm0 + v0 * h, cm1 + v1 * h, theta + turn
    r0 = at0 + -v1 / omega
    r1 = at1 + v0 / omega
    c = math.cos(turn)
    s = math.sin(turn)
    d0 = cm0 - r0
    d1 = cm1 - r1
    return r0 + (c * d0 - s * d1), r1 + (s * d0 + c * d1), theta + turn


@njit(cache=CACHE, fastmath=FAST)
def _reimpose(cm0, cm1, theta, contact, index, body, hull, e0, e1, w0, w1, n0, n1, length):
    """The contact made exact again after a step (solver.feeder.simulate._reimpose)."""
    m = body.shape[0]
    _pose_hull(cm0, cm1, theta, body, hull)
    i = index
    if contact == FLUSH:
        # the lower end of the edge over the fence goes onto the face (an end past E may
        # stand a rounding-sized tilt above it)
        j = (i + 1) % m
        si = (hull[i, 0] - e0) * w0 + (hull[i, 1] - e1) * w1
        sj = (hull[j, 0] - e0) * w0 + (hull[j, 1] - e1) * w1
        on_i = 0.0 <= si <= length
        on_j = 0.0 <= sj <= length
        if on_i and on_j:
            zi = (hull[i, 0] - e0) * n0 + (hull[i, 1] - e1) * n1
            zj = (hull[j, 0] - e0) * n0 + (hull[j, 1] - e1) * n1
            i = j if zj < zi else i
        elif on_j:
            i = j
    if contact == VERTEX or contact == FLUSH:
        level = n0 * e0 + n1 * e1
        off = level - (n0 * hull[i, 0] + n1 * hull[i, 1])
        return cm0 + off * n0, cm1 + off * n1
    ne0, ne1 = _inward_normal(hull, i)
    off = (ne0 * e0 + ne1 * e1) - (ne0 * hull[i, 0] + ne1 * hull[i, 1])
    return cm0 + off * ne0, cm1 + off * ne1


@njit(cache=CACHE, fastmath=FAST)
def _flush_distance(cm0, cm1, theta, v0, v1, edge, body, hull, e0, e1, w0, w1, n0, n1, f0, f1):
    """The push until the sliding part's next event: E reaching the edge's downstream
    vertex, or (past it) the force line through the CM."""
    rate = -(v0 * w0 + v1 * w1)
    if rate <= 0.0:
        return 0.0
    m = body.shape[0]
    _pose_hull(cm0, cm1, theta, body, hull)
    j = (edge + 1) % m
    s_a = min((hull[edge, 0] - e0) * w0 + (hull[edge, 1] - e1) * w1, (hull[j, 0] - e0) * w0 + (hull[j, 1] - e1) * w1)
    if s_a > 0.0:
        return s_a / rate
    zc = (cm0 - e0) * n0 + (cm1 - e1) * n1
    fn = f0 * n0 + f1 * n1
    x0 = cm0 - zc / fn * f0
    x1 = cm1 - zc / fn * f1
    return max((x0 - e0) * w0 + (x1 - e1) * w1, 0.0) / rate


@njit(cache=CACHE, fastmath=FAST)
def _turn_to_along(hull, edge, omega):
    """The push after which edge ``edge`` turning at ``omega`` lies along the belt (inf if
    it turns away)."""
    j = (edge + 1) % hull.shape[0]
    q0 = hull[j, 0] - hull[edge, 0]
    q1 = hull[j, 1] - hull[edge, 1]
    off = math.atan2(-q1 * D0 + q0 * D1, q0 * D0 + q1 * D1) % math.pi
    if omega > 0.0:
        return off / omega
    if omega < 0.0:
        return (math.pi - off) / -omega
    return math.inf


@njit(cache=CACHE, fastmath=FAST)
def _checked_step(cm0, cm1, theta, v0, v1, omega, contact, index, body, hull, e0, e1, w0, w1, n0, n1, length,
                  f0, f1, step, min_step, tol_c):
    """The pose after one step in a contact (re-imposed) and the push it took: ``step`` (a
    flush slide: to its next event; E on an edge: never past the edge lying along the belt),
    halved until the fence does not pass through the part, down to ``min_step``."""
    h = step
    if contact == FLUSH:
        h = max(h, _flush_distance(cm0, cm1, theta, v0, v1, index, body, hull, e0, e1, w0, w1, n0, n1, f0, f1))
    elif contact == END:
        _pose_hull(cm0, cm1, theta, body, hull)
        h = min(h, _turn_to_along(hull, index, omega))
    while True:
        a0, a1, th = _advance(cm0, cm1, theta, v0, v1, omega, cm0, cm1, h)
        a0, a1 = _reimpose(a0, a1, th, contact, index, body, hull, e0, e1, w0, w1, n0, n1, length)
        _pose_hull(a0, a1, th, body, hull)
        if not _overlaps(hull, e0, e1, w0, w1, length, tol_c) or h <= min_step:
            return a0, a1, th, h
        h *= 0.5


@njit(cache=CACHE, fastmath=FAST)
def _solve(cm0, cm1, theta, contact, index, body, hull, support, weights, work, e0, e1, gamma, mu_c,
           kkt_tol, kkt_accept, max_iter, counts):
    """The forward solve (3.7, 4.1) of a point contact at the pose: vertex ``index`` on the
    face (VERTEX) or E on edge ``index`` (END); the part pushed along +D in the belt's frame.
    Returns (v0, v1, omega) in the fence's frame (the belt's motion -D added) and a code:
    0 solved, 1 the compiled solve failed (the caller runs the reference), 2 a grazing push
    (models.core.scene refuses it). ``counts``: solves, not optimal, max KKT, max force
    angle, the solves of each mode, the side of the last slip (COUNT_SIDE). ``work``: (8, k)
    scratch."""
    m = body.shape[0]
    _pose_hull(cm0, cm1, theta, body, hull)
    if contact == VERTEX:
        c0, c1 = hull[index, 0], hull[index, 1]
        edge = gamma
    else:
        j = (index + 1) % m
        c0, c1 = e0, e1
        edge = math.atan2(hull[j, 1] - hull[index, 1], hull[j, 0] - hull[index, 0])
    p0, p1 = math.cos(PUSH_ANGLE), math.sin(PUSH_ANGLE)
    t0, t1 = math.cos(edge), math.sin(edge)
    sn0, sn1 = -t1, t0
    sin_a = sn0 * p0 + sn1 * p1
    if abs(sin_a) <= GRAZING_SIN:
        return 0.0, 0.0, 0.0, 2
    if sin_a < 0.0:
        sn0, sn1, sin_a = -sn0, -sn1, -sin_a
    ah0, ah1 = -sn1, sn0
    cr0, cr1 = c0 - cm0, c1 - cm1
    wx, wy = work[0], work[1]
    cth = math.cos(theta)
    sth = math.sin(theta)
    k = support.shape[0]
    ell = norm(cr0, cr1)
    for i in range(k):
        x = (cm0 + (support[i, 0] * cth - support[i, 1] * sth)) - cm0
        y = (cm1 + (support[i, 0] * sth + support[i, 1] * cth)) - cm1
        wx[i] = x
        wy[i] = y
        ell = max(ell, norm(x, y))
    for i in range(k):
        wx[i] /= ell
        wy[i] /= ell
    out = solve_modes(wx, wy, weights, cr0 / ell, cr1 / ell, sn0, sn1, ah0, ah1, p0, p1, sin_a, mu_c, kkt_tol,
                      kkt_tol, max_iter, work[2:], counts[COUNT_SIDE])
    x0, x1, x2, fo0, fo1, kkt, _, _, mode, consistent, failed, side = out
    counts[COUNT_SIDE] = side
    if failed:
        return 0.0, 0.0, 0.0, 1
    counts[0] += 1.0
    if not (kkt <= kkt_accept and consistent):
        counts[1] += 1.0
    counts[2] = max(counts[2], kkt)
    counts[3] = max(counts[3], math.atan2(abs(fo0 * ah0 + fo1 * ah1), fo0 * sn0 + fo1 * sn1))
    counts[4 + mode] += 1.0
    return x0 - D0, x1 - D1, x2 / ell, 0


@njit(cache=CACHE, fastmath=FAST)
def _mode(cm0, cm1, theta, hull, touching, n_touch, gaps, e0, e1, w0, w1, n0, n1, length, gamma, mu_c, f0, f1,
          tol_c):
    """The contact at a pose in contact (solver.feeder.simulate._mode): (contact, index,
    needs a forward solve, v0, v1) with the exact translation of a flush slide."""
    m = hull.shape[0]
    edge_e = 0
    for i in range(1, m):
        if gaps[i] < gaps[edge_e]:
            edge_e = i
    flush = -1
    for t in range(n_touch):
        v = touching[t]
        for side in range(2):
            if side == 0:
                j = (v - 1) % m
                o = j
            else:
                j = v
                o = (v + 1) % m
            o_touch = False
            for t2 in range(n_touch):
                if touching[t2] == o:
                    o_touch = True
            sv = (hull[v, 0] - e0) * w0 + (hull[v, 1] - e1) * w1
            if o_touch or (gaps[j] <= E_ON_EDGE * tol_c and abs(sv) > tol_c):
                flush = j
    if flush >= 0:
        va = flush
        vb = (flush + 1) % m
        sa = (hull[va, 0] - e0) * w0 + (hull[va, 1] - e1) * w1
        sb = (hull[vb, 0] - e0) * w0 + (hull[vb, 1] - e1) * w1
        if sb < sa or (sb == sa and vb < va):  # (s_a, v_a): the downstream vertex, toward E
            va, vb, sa, sb = vb, va, sb, sa
        supported_lo = max(sa, 0.0)
        carried = abs(math.tan(gamma)) <= mu_c
        fd0, fd1 = (D0, D1) if carried else (f0, f1)
        zc = (cm0 - e0) * n0 + (cm1 - e1) * n1
        fn = fd0 * n0 + fd1 * n1
        x0 = cm0 - zc / fn * fd0
        x1 = cm1 - zc / fn * fd1
        s_x = (x0 - e0) * w0 + (x1 - e1) * w1
        if supported_lo - tol_c <= s_x <= sb + tol_c:
            if carried:
                return JAM, -1, False, 0.0, 0.0
            scale = (n0 * D0 + n1 * D1) / (f0 * n0 + f1 * n1)
            return FLUSH, flush, False, scale * f0 - D0, scale * f1 - D1
        # the force line misses the supported part: pivot on the end it passes
        if s_x > sb:
            return VERTEX, vb, True, 0.0, 0.0
        if sa >= 0.0:
            return VERTEX, va, True, 0.0, 0.0
        n_touch = 0
        edge_e = flush
    if n_touch > 0:
        return VERTEX, touching[0], True, 0.0, 0.0
    j = (edge_e + 1) % m
    q0 = hull[j, 0] - hull[edge_e, 0]
    q1 = hull[j, 1] - hull[edge_e, 1]
    if abs(-q1 * D0 + q0 * D1) <= GRAZING * norm(q0, q1):
        return ALONG, -1, False, -D0, -D1  # the edge lies along the belt: E no longer pushes
    return END, edge_e, True, 0.0, 0.0


@njit(cache=CACHE, fastmath=FAST)
def _vertex_at_end(hull, e0, e1, tol_c):
    k = 0
    best = math.inf
    for i in range(hull.shape[0]):
        d = norm(hull[i, 0] - e0, hull[i, 1] - e1)
        if d < best:
            best = d
            k = i
    return k if best <= E_ON_EDGE * tol_c else -1


@njit(cache=CACHE, fastmath=FAST)
def _append(buf, n, record, a, b, c, d):
    """Row n of a recorded run's buffer (an event: push, code, index, value; a pose: push,
    cm x, cm y, theta), and the buffer's new length; nothing for a run not recorded."""
    if not record:
        return buf, n
    buf = _grow(buf, n)
    buf[n, 0] = a
    buf[n, 1] = b
    buf[n, 2] = c
    buf[n, 3] = d
    return buf, n + 1


@njit(cache=CACHE, fastmath=FAST)
def _max_x(hull):
    x = 0.0
    for i in range(hull.shape[0]):
        x = max(x, abs(hull[i, 0]))
    return x


_ENTRY_EVENT = (EV_VERTEX, EV_END, EV_FLUSH)


@njit(cache=CACHE, fastmath=FAST)
def _corner_step(cm0, cm1, theta, contact, index, body, hull, support, weights, work, seg, gamma, mu_c, f0, f1,
                 step, min_step, tol_c, tol, counts):
    """A step refused down to ``min_step`` with a vertex at E: the first of the contacts
    there (the vertex on the face, E on either edge at it) whose step advances
    (solver.feeder.simulate._step_at_corner). Returns (found, contact, index, cm x, cm y,
    theta, push, solve code)."""
    e0, e1, w0, w1, n0, n1, length = seg[0], seg[1], seg[2], seg[3], seg[4], seg[5], seg[6]
    m = body.shape[0]
    _pose_hull(cm0, cm1, theta, body, hull)
    corner = _vertex_at_end(hull, e0, e1, tol_c)
    if corner < 0:
        return False, contact, index, cm0, cm1, theta, 0.0, 0
    for alt in range(3):
        if alt == 0:
            c_alt, i_alt = VERTEX, corner
        elif alt == 1:
            c_alt, i_alt = END, (corner - 1) % m
        else:
            c_alt, i_alt = END, corner
        if c_alt == contact and i_alt == index:
            continue
        u0, u1, om, code = _solve(cm0, cm1, theta, c_alt, i_alt, body, hull, support, weights, work, e0, e1, gamma,
                                  mu_c, tol[0], tol[1], int(tol[2]), counts)
        if code != 0:
            return False, contact, index, cm0, cm1, theta, 0.0, code
        b0, b1, th, h = _checked_step(cm0, cm1, theta, u0, u1, om, c_alt, i_alt, body, hull, e0, e1, w0, w1, n0, n1,
                                      length, f0, f1, step, min_step, tol_c)
        if h > min_step:
            return True, c_alt, i_alt, b0, b1, th, h, 0
    return False, contact, index, cm0, cm1, theta, 0.0, 0


@njit(cache=CACHE, fastmath=FAST)
def _touching(hull, seg, tol_c, touching):
    """The hull vertices on the fence's face (within ``tol_c``), in order: how many."""
    e0, e1, w0, w1, n0, n1, length = seg[0], seg[1], seg[2], seg[3], seg[4], seg[5], seg[6]
    n_touch = 0
    for i in range(hull.shape[0]):
        z = (hull[i, 0] - e0) * n0 + (hull[i, 1] - e1) * n1
        s = (hull[i, 0] - e0) * w0 + (hull[i, 1] - e1) * w1
        if abs(z) <= tol_c and 0.0 <= s <= length:
            touching[n_touch] = i
            n_touch += 1
    return n_touch


@njit(cache=CACHE, fastmath=FAST)
def _summarise(summary, status, steps, push, cm0, cm1, theta, flushed, max_x, counts, n_ev, n_path):
    summary[S_STATUS] = status
    summary[S_STEPS] = steps
    summary[S_PUSH] = push
    summary[S_CM_X] = cm0
    summary[S_CM_Y] = cm1
    summary[S_THETA] = theta
    summary[S_FLUSHED] = 1.0 if flushed else 0.0
    summary[S_MAX_X] = max_x
    summary[S_SOLVES] = counts[0]
    summary[S_NOT_OPTIMAL] = counts[1]
    summary[S_MAX_KKT] = counts[2]
    summary[S_MAX_ANGLE] = counts[3]
    for i in range(MODE_COUNT):
        summary[S_MODES + i] = counts[4 + i]
    summary[S_EVENTS_TO] = n_ev
    summary[S_PATH_TO] = n_path


@njit(cache=CACHE, fastmath=FAST)
def run_fence(body, support, weights, cm0, cm1, theta, seg, gamma, mu_c, a, settings, tol, record, path, n_path,
              events, n_ev, summary, work, hull, gaps, touching):
    """One part through one fence (solver.feeder.simulate._fence_run), from the pose (cm,
    theta). ``seg``: E (2), w (2), n (2), length. ``settings``: step, contact_tol, min_step,
    max_steps, stall_steps (lengths relative to a). ``tol``: kkt, kkt_accept, max Newton
    iterations. Writes ``summary`` (the S_* columns); returns the buffers and their lengths."""
    e0, e1, w0, w1, n0, n1, length = seg[0], seg[1], seg[2], seg[3], seg[4], seg[5], seg[6]
    step, tol_c, min_step = settings[0] * a, settings[1] * a, settings[2] * a
    f0, f1 = n0 + mu_c * w0, n1 + mu_c * w1
    counts = np.zeros(COUNT_SIDE + 1)
    summary[S_START_X], summary[S_START_Y], summary[S_START_THETA] = cm0, cm1, theta
    summary[S_EVENTS_FROM], summary[S_PATH_FROM] = n_ev, n_path
    push = 0.0
    path, n_path = _append(path, n_path, record, push, cm0, cm1, theta)
    n_events_run, last_code, last_index = 0, -1, -1
    status, stalled, steps = STEP_LIMIT, 0, 0
    touched = flushed = False
    _pose_hull(cm0, cm1, theta, body, hull)
    max_x = _max_x(hull)
    if _overlaps(hull, e0, e1, w0, w1, length, tol_c):
        status = OVERLAP
        events, n_ev = _append(events, n_ev, record, push, EV_OVERLAP, -1, 0.0)
    for _ in range(0 if status == OVERLAP else int(settings[3])):
        _pose_hull(cm0, cm1, theta, body, hull)
        n_touch = _touching(hull, seg, tol_c, touching)
        _gaps(hull, e0, e1, gaps)
        e_contact = gaps.min() <= tol_c
        touched = touched or n_touch > 0 or e_contact
        if n_touch == 0 and not e_contact:  # drift with the belt onto the fence, or away
            lam = _next_contact(hull, e0, e1, w0, w1, n0, n1, length, tol_c)
            if lam < 0.0:
                status = LEFT if touched else MISSED
                events, n_ev = _append(events, n_ev, record, push, EV_LEFT if touched else EV_MISSED, -1, theta)
                break
            cm0, cm1, push, steps = cm0 - lam * D0, cm1 - lam * D1, push + lam, steps + 1
            path, n_path = _append(path, n_path, record, push, cm0, cm1, theta)
            _pose_hull(cm0, cm1, theta, body, hull)
            max_x = max(max_x, _max_x(hull))
            if last_code != EV_FIRST_CONTACT and last_code != EV_CONTACT_AGAIN:
                last_code, last_index = EV_FIRST_CONTACT if n_events_run == 0 else EV_CONTACT_AGAIN, -1
                events, n_ev = _append(events, n_ev, record, push, last_code, -1, 0.0)
                n_events_run += 1
            continue
        contact, index, solve, v0, v1 = _mode(cm0, cm1, theta, hull, touching, n_touch, gaps, e0, e1, w0, w1, n0,
                                              n1, length, gamma, mu_c, f0, f1, tol_c)
        omega = 0.0
        if solve:
            v0, v1, omega, code = _solve(cm0, cm1, theta, contact, index, body, hull, support, weights, work, e0, e1,
                                         gamma, mu_c, tol[0], tol[1], int(tol[2]), counts)
            if code != 0:
                status = REFERENCE if code == 1 else GRAZING_PUSH
                break
        if contact == ALONG or contact == JAM:
            status = LEFT if contact == ALONG else JAMMED
            code = EV_ALONG if contact == ALONG else EV_JAM
            events, n_ev = _append(events, n_ev, record, push, code, -1, theta if contact == ALONG else mu_c)
            break
        entry = _ENTRY_EVENT[contact]
        if not (last_code == entry and last_index == index):
            flushed = flushed or contact == FLUSH
            events, n_ev = _append(events, n_ev, record, push, entry, index, 0.0)
            n_events_run, last_code, last_index = n_events_run + 1, entry, index
        a0, a1, th, h = _checked_step(cm0, cm1, theta, v0, v1, omega, contact, index, body, hull, e0, e1, w0, w1,
                                      n0, n1, length, f0, f1, step, min_step, tol_c)
        if h <= min_step:
            found, c2, i2, b0, b1, th2, h2, code = _corner_step(cm0, cm1, theta, contact, index, body, hull, support,
                                                                weights, work, seg, gamma, mu_c, f0, f1, step,
                                                                min_step, tol_c, tol, counts)
            if code != 0:
                status = REFERENCE if code == 1 else GRAZING_PUSH
                break
            if found:
                contact, index, a0, a1, th, h = c2, i2, b0, b1, th2, h2
                last_code, last_index = (EV_VERTEX_CORNER if c2 == VERTEX else EV_END_CORNER), i2
                events, n_ev = _append(events, n_ev, record, push, last_code, i2, 0.0)
                n_events_run += 1
        stalled = stalled + 1 if h <= min_step else 0
        if stalled >= int(settings[4]):
            status = STALLED
            events, n_ev = _append(events, n_ev, record, push, EV_STALLED, contact * 1000 + index, h)
            break
        cm0, cm1, theta, push, steps = a0, a1, th, push + h, steps + 1
        path, n_path = _append(path, n_path, record, push, cm0, cm1, theta)
        _pose_hull(cm0, cm1, theta, body, hull)
        max_x = max(max_x, _max_x(hull))
    _summarise(summary, status, steps, push, cm0, cm1, theta, flushed, max_x, counts, n_ev, n_path)
    return path, n_path, events, n_ev


@njit(cache=CACHE, fastmath=FAST)
def start_above(body, theta, seg, a, start_along, clearance, hull):
    """The CM of a part placed just above the fence at ``start_along`` of its length from E:
    ``clearance`` part radii of belt travel before it touches the face."""
    e0, e1, w0, w1, n0, n1, length = seg[0], seg[1], seg[2], seg[3], seg[4], seg[5], seg[6]
    _pose_hull(e0, e1, theta, body, hull)
    zmin = math.inf
    for i in range(body.shape[0]):
        zmin = min(zmin, (hull[i, 0] - e0) * n0 + (hull[i, 1] - e1) * n1)
    lift = clearance * a * (n0 * D0 + n1 * D1) - zmin
    return e0 + start_along * length * w0 + lift * n0, e1 + start_along * length * w1 + lift * n1


_F1, _F2, _F3 = types.float64[:], types.float64[:, :], types.float64[:, :, :]
RUN_BELT_SIGNATURE = (_F2, _F3, _F2, _F2, _F1, types.boolean[:], _F2, _F1, _F2, types.float64, _F1, _F1, _F1,
                      types.int64, types.int64, types.int64)


@njit([RUN_BELT_SIGNATURE], cache=CACHE, fastmath=FAST)
def run_belt(body, supports, weights, starts, thetas, given, segs, gammas, mus, a, settings, tol, start_along,
             record, first, last):
    """Parts ``first`` .. ``last - 1`` through the fences ``segs`` (F, 7) in order: part i
    from its CM ``starts[i]`` when ``given[i]``, else above fence 0 at ``start_along[i]`` of
    its length; orientation ``thetas[i]``, support ``supports[i]`` (k, 2) with ``weights[i]``,
    mu_c ``mus[i, f]`` at fence f. A part goes on to the next fence while its run there
    ended "left" or "missed". Returns the summaries (parts, fences, SUMMARY; status -1 for a
    fence not reached) and the trajectories and events of parts below ``record``."""
    n_fences = segs.shape[0]
    m = body.shape[0]
    k = supports.shape[1]
    summaries = np.full((last - first, n_fences, SUMMARY), -1.0)
    path = np.empty((256, 4))
    events = np.empty((64, 4))
    n_path = 0
    n_ev = 0
    work = np.empty((8, k))
    hull = np.empty((m, 2))
    gaps = np.empty(m)
    touching = np.empty(m, dtype=np.int64)
    for i in range(first, last):
        theta = thetas[i]
        if given[i]:
            cm0, cm1 = starts[i, 0], starts[i, 1]
        else:
            cm0, cm1 = start_above(body, theta, segs[0], a, start_along[i], settings[5], hull)
        for f in range(n_fences):
            out = summaries[i - first, f]
            path, n_path, events, n_ev = run_fence(body, supports[i], weights[i], cm0, cm1, theta, segs[f], gammas[f],
                                                   mus[i, f], a, settings, tol, i < record, path, n_path, events,
                                                   n_ev, out, work, hull, gaps, touching)
            status = int(out[S_STATUS])
            if status != LEFT and status != MISSED:
                break
            cm0, cm1, theta = out[S_CM_X], out[S_CM_Y], out[S_THETA]
    return summaries, path[:n_path].copy(), events[:n_ev].copy()


ENTRY_POINTS = ("run_belt",)
