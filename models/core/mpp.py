"""Minimum-power mechanics of a pushed workpiece on a known support (book ch. 2, 3.2-3.3.2).

Everything here is pure numpy and works in a frame whose origin is the centre of mass (CM).
A planar motion per unit push is the twist ``x = (v_x, v_y, omega)``: the velocity of a
point ``w`` of the workpiece is ``v + omega * J w`` with ``J`` the rotation by +90 degrees
(``J (x, y) = (-y, x)``). Its centre of rotation (COR) is ``r = J v / omega`` (3.1.4).

The frictional power per unit push, divided by mu_s * total weight, is (3.6)-(3.7)

    f(x) = sum_i P_i |v + omega J w_i|,     sum_i P_i = 1,   sum_i P_i w_i = 0,

and a frictionless pusher imposes the single contact constraint ``a . x = b`` with
``a = (n, n . J c)`` and ``b = n . p`` (3.3). A pusher force ``F`` applied at ``c`` does
the work ``F . v(c) = (F, F . J c) . x`` so ``a`` is also the generalised force of a unit
normal force: the stationarity condition of the minimum-power problem is
``grad f(x) = lambda a`` with ``lambda >= 0`` the contact force (ch. 2).

Rewritten about the COR (omega != 0, r on no support point) the stationarity condition
is the book's (3.8):  ``d_r alpha - s v_r = 0`` with ``s = alpha . (c - r)``, ``d_r`` (3.9)
and ``v_r`` (3.10). Here ``alpha`` is the unit vector ``J n`` along the edge. The sign of
``s`` fixes the sense of rotation: ``omega = -(n . p) / s`` (3.3).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike


def perp(v: np.ndarray) -> np.ndarray:
    """J v: rotate vectors (..., 2) by +90 degrees."""
    v = np.asarray(v, dtype=float)
    if v.ndim == 1:  # one vector, the common case: no stacking (the same numbers)
        return np.array([-v[1], v[0]])
    out = np.empty(v.shape)
    out[..., 0] = -v[..., 1]
    out[..., 1] = v[..., 0]
    return out


def contact_generalized_force(direction: np.ndarray, contact_rel: np.ndarray) -> np.ndarray:
    """The twist-space covector (F, F . J c) of a unit force along ``direction`` applied at
    ``c`` (CM frame): its product with a twist is the work rate of that force (ch. 2)."""
    d = np.asarray(direction, dtype=float)
    c = np.asarray(contact_rel, dtype=float)
    return np.concatenate([d, [float(d @ perp(c))]])


def point_velocities(x: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Velocities v + omega J w_i of points ``w`` (k, 2) under twist ``x`` (3,)."""
    x = np.asarray(x, dtype=float)
    return x[:2] + x[2] * perp(w)


def power(x: np.ndarray, w: np.ndarray, weights: np.ndarray) -> float:
    """Frictional power per unit push / (mu_s * weight): sum_i P_i |v(w_i)| (3.6)."""
    return float(np.asarray(weights) @ np.linalg.norm(point_velocities(x, w), axis=1))


def lever(contact_rel: ArrayLike, alpha_hat: ArrayLike, r: ArrayLike) -> float:
    """s = alpha . (c - r), the book's moment arm of (3.3) for a COR ``r``."""
    return float(np.asarray(alpha_hat) @ (np.asarray(contact_rel) - np.asarray(r)))


def weighted_distance_direction(r: ArrayLike, w: ArrayLike, weights: ArrayLike) -> tuple[float, np.ndarray]:
    """(d_r, v_r) of (3.9)-(3.10) for a support of points ``w`` none of which is ``r``."""
    d = np.asarray(w, dtype=float) - np.asarray(r, dtype=float)
    dist = np.linalg.norm(d, axis=1)
    p = np.asarray(weights, dtype=float)
    return float(p @ dist), (p / dist) @ d


def stationarity_residual(r: ArrayLike, w: ArrayLike, weights: ArrayLike, contact_rel: ArrayLike,
                          alpha_hat: ArrayLike) -> np.ndarray:
    """d_r alpha - s v_r of (3.8): zero exactly when ``r`` is the COR of the support
    (for a COR on no support point)."""
    d_r, v_r = weighted_distance_direction(r, w, weights)
    s = lever(contact_rel, alpha_hat, r)
    return d_r * np.asarray(alpha_hat, dtype=float) - s * v_r


def membership_columns(r: ArrayLike, w: ArrayLike, contact_rel: ArrayLike, alpha_hat: ArrayLike, length: float) -> np.ndarray:
    """Columns G(w) = (1, w/L, g_r(w)/L) of the membership problem for a candidate COR r.

    ``r`` is the COR of a support (no mass at r) iff ``sum_i P_i G(w_i) = (1, 0, 0, 0, 0)``
    for weights P_i >= 0: total weight 1, centroid at the CM (3.1.5), and (3.8) with
    g_r(w) = |w - r| alpha - s (w - r)/|w - r|, summed with the weights. Lengths are divided
    by ``length`` so every entry is O(1). ``w`` must not contain ``r``. Shape (5, k).
    """
    w = np.asarray(w, dtype=float).reshape(-1, 2)
    r = np.asarray(r, dtype=float)
    alpha_hat = np.asarray(alpha_hat, dtype=float)
    s = lever(contact_rel, alpha_hat, r)
    d = w - r
    dist = np.linalg.norm(d, axis=1)
    g = dist[:, None] * alpha_hat[None, :] - s * d / dist[:, None]
    return np.vstack([np.ones(len(w)), w.T / length, g.T / length])


MASON_TRANSLATION_REL = 1e-14
"""Default moment (per unit |c| and unit force) at or below which Mason's rules see no turn."""


def mason_sense(contact_rel: ArrayLike, normal: ArrayLike, push_hat: ArrayLike, mu_c: float,
                translation_rel: float = MASON_TRANSLATION_REL) -> str:
    """Sense of rotation by Mason's rules (1.6.2): 'ccw', 'cw' or 'none' (translation).

    The pusher's force lies in the friction cone of half-angle atan(mu_c) about the inward
    normal ``n``. Its moment about the CM is c x F. If the cone's edges give moments of
    one sign (or one edge a zero moment), that is the sense; if they straddle the CM, the
    line of motion (the push direction through c) decides. When every force the cone
    allows passes through the CM (mu_c = 0 and the normal through the CM: both edges
    zero), the part translates whatever the push direction. A moment counts as zero at
    or below ``translation_rel`` (per unit |c| and unit force; pass the solver's
    translation tolerance to agree with it), and never below 64 ulps.
    """
    c = np.asarray(contact_rel, dtype=float)
    n = np.asarray(normal, dtype=float)
    t = perp(n)
    p = np.asarray(push_hat, dtype=float)
    # Moments of unit forces about the CM, per unit |c|: c_hat x f_hat (no under- or
    # overflow of |c| for tiny or huge parts).
    cn = math.hypot(float(c[0]), float(c[1]))
    c_hat = c / cn if cn > 0.0 else c

    def moment(f: np.ndarray) -> float:
        f = f / math.hypot(float(f[0]), float(f[1]))
        return float(c_hat[0] * f[1] - c_hat[1] * f[0])

    edges = [moment(n + mu_c * t), moment(n - mu_c * t)]
    eps = max(float(translation_rel), 64.0 * float(np.finfo(float).eps))
    if all(abs(m) <= eps for m in edges):  # every force through the CM
        decisive = 0.0
    elif all(m >= -eps for m in edges):
        decisive = 1.0
    elif all(m <= eps for m in edges):
        decisive = -1.0
    else:  # the cone straddles the CM: the line of motion decides
        mp = moment(p)
        decisive = 0.0 if abs(mp) <= eps else mp
    if decisive > 0.0:
        return "ccw"
    if decisive < 0.0:
        return "cw"
    return "none"
