"""Witnesses: the residual of a support in a problem's rows, and the exact polish that
turns the restricted master's approximate support into a small one satisfying the rows
to rounding.

A problem's rows are equalities G P + PG pm = b and inequalities H P + PH pm >= 0, with
the point mass pm = (P0, z), |z| <= P0 (:mod:`solver.certify.master`). The residual of a
support is the L1 norm of the equality violation plus the total violation of the
inequalities.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import nnls

POLISH_BELOW = 1e-6
"""The exact polish is tried once the master's residual is below this (the master alone
reaches only the conic solver's accuracy, about 1e-10)."""

EXACT_RESIDUAL = 1e-14
"""A polished support with a residual at or below this is final (rounding level)."""

DENSE_WEIGHT_REL = 1e-12
"""Weights below this fraction of the largest are dropped from the master's support
before it is polished as a whole."""

MAX_POLISH_DROPS = 8
"""Times the least-norm correction may drop weights that turn negative and retry."""


def violations(
    b: np.ndarray, g: np.ndarray, h: np.ndarray, weights: np.ndarray,
    pg: np.ndarray | None, ph: np.ndarray | None, pm: np.ndarray,
) -> tuple[float, float, np.ndarray]:
    """(L1 residual of the equalities, total violation of the inequalities, the inequality
    rows' values) of the support (weights, pm)."""
    lhs = g @ weights
    rows = h @ weights
    if pg is not None:
        lhs = lhs + pg @ pm
        if ph is not None:
            rows = rows + ph @ pm
    return float(np.sum(np.abs(lhs - b))), float(np.sum(np.maximum(-rows, 0.0))), rows


def residual(
    b: np.ndarray, g: np.ndarray, h: np.ndarray, weights: np.ndarray,
    pg: np.ndarray | None, ph: np.ndarray | None, pm: np.ndarray,
) -> float:
    eq, ineq, _ = violations(b, g, h, weights, pg, ph, pm)
    return eq + ineq


def _cone_direction(pm: np.ndarray) -> np.ndarray:
    zn = math.hypot(pm[1], pm[2])
    return pm[1:] / zn if zn > 0.0 else np.array([1.0, 0.0])


def _pm_basis(pg: np.ndarray, ph: np.ndarray, pm: np.ndarray, variant: str) -> tuple[np.ndarray, np.ndarray]:
    """The point mass as extra columns (rows of [G; H]) and coordinates: "free" (P0, z) with
    |z| <= P0, or "cone" (P0 alone, z = P0 zhat on the cone's boundary, zhat from ``pm``)."""
    full = np.vstack([pg, ph])
    if variant == "free":
        return full, pm.copy()
    zhat = _cone_direction(pm)
    e = np.array([1.0, zhat[0], zhat[1]])
    return (full @ e)[:, None], np.array([pm[0]])


def _pm_back(pm: np.ndarray, coords: np.ndarray, variant: str) -> np.ndarray:
    if variant == "free":
        return coords
    zhat = _cone_direction(pm)
    return np.array([coords[0], coords[0] * zhat[0], coords[0] * zhat[1]])


def _pm_feasible(coords: np.ndarray, variant: str) -> bool:
    if variant == "free":
        return bool(coords[0] >= 0.0 and math.hypot(coords[1], coords[2]) <= coords[0])
    return bool(coords[0] >= 0.0)


def _polish_once(
    m: np.ndarray, target: np.ndarray, weights: np.ndarray, pm_cols: np.ndarray | None,
    pm_coords: np.ndarray, variant: str,
) -> tuple[np.ndarray, np.ndarray] | None:
    """Least-norm correction of the positive weights (and the point mass) so that
    m x = target to rounding; drops weights that turn negative and retries.
    (weights, point-mass coordinates) or None."""
    active = np.nonzero(weights > 0.0)[0]
    for _ in range(MAX_POLISH_DROPS):
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


def exact_witness(
    b: np.ndarray, g: np.ndarray, h: np.ndarray, weights: np.ndarray, pm: np.ndarray,
    pg: np.ndarray | None, ph: np.ndarray | None, accept: float,
) -> tuple[np.ndarray, np.ndarray, float]:
    """Turn the master's approximate support (weights, pm) into an exact small one.

    The inequality rows become equalities with slack columns, [G 0; H -I] (P, t) = (b, 0)
    with P, t >= 0. With the point mass held at the master's value, non-negative least
    squares (Lawson and Hanson's active set, ending on at most as many independent columns
    as rows) picks a basic support; a least-norm correction of those weights, slacks and
    the point mass (free, on its cone's boundary, or absent) makes the rows hold to
    rounding. The master's whole support is tried the same way. Returns
    (weights, pm, residual): the best polished support if its residual is at most
    ``accept`` or below the given one, else the given support."""
    n = g.shape[1]
    n_eq, n_ineq = g.shape[0], h.shape[0]
    given = (weights, pm, residual(b, g, h, weights, pg, ph, pm))
    best = (weights, pm, math.inf)
    m = np.block([[g, np.zeros((n_eq, n_ineq))], [h, -np.eye(n_ineq)]])
    tgt = np.concatenate([b, np.zeros(n_ineq)])
    _, _, rows = violations(b, g, h, weights, pg, ph, pm)
    dense = np.where(weights > DENSE_WEIGHT_REL * float(np.max(weights, initial=0.0)), weights, 0.0)
    dense = np.concatenate([dense, np.maximum(rows, 0.0)])
    variants = ("free", "cone", "none") if pg is not None else ("none",)
    ph_full = ph if ph is not None else np.zeros((n_ineq, 3))
    for variant in variants:
        pm_cols: np.ndarray | None
        if variant == "none" or pg is None:
            pm_cols, coords, target = None, np.zeros(0), tgt
        else:
            pm_cols, coords = _pm_basis(pg, ph_full, pm, variant)
            target = tgt - pm_cols @ coords
        basic = nnls(m, target)[0]
        for start in (basic, dense):
            out = _polish_once(m, tgt, start, pm_cols, coords, variant)
            if out is None:
                continue
            x1, c1 = out
            w1 = x1[:n]
            pm1 = _pm_back(pm, c1, variant) if pm_cols is not None else np.zeros(3)
            res1 = residual(b, g, h, w1, pg, ph, pm1)
            if res1 < best[2]:
                best = (w1, pm1, res1)
            if best[2] <= EXACT_RESIDUAL:
                return best
    return best if best[2] <= accept or best[2] <= given[2] else given


def heaviest_points(points: np.ndarray, weights: np.ndarray, k: int) -> np.ndarray:
    """The ``k`` support points of largest weight, heaviest first (warm starts of the
    next query)."""
    order = np.argsort(weights)[::-1][:k]
    return np.asarray(points)[order]
