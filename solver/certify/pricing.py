"""Pricing over the outline: local minima of a dual functional refined by golden section,
and a sound branch and bound of its minimum (:mod:`solver.certify.functional`).

Both work on the pieces of :mod:`solver.certify.outline` and are vectorised over all
brackets or intervals at once.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from solver.certify.functional import DualFunctional
from solver.certify.outline import Pieces
from solver.core.budget import Budget

GOLDEN_ITERATIONS = 48
"""Golden-section steps of the local pricing refinement (the bracket shrinks by 0.618 each)."""

COLUMNS_PER_ROUND = 4
"""Most new columns added per column-generation round (local minima, and points the
branch and bound finds below its target)."""

MIN_INTERVAL = 1e-13
"""Branch-and-bound intervals shorter than this (parameter units, ~ L) are not split
further; their (valid, possibly weak) bound is kept."""

_GOLD = 0.5 * (math.sqrt(5.0) - 1.0)


def golden(
    fn: DualFunctional, pieces: Pieces, piece: np.ndarray, lo: np.ndarray, hi: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Vectorised golden-section minimisation of phi on [lo, hi] of each ``piece``; the
    best of the final bracket's points and the given ends is returned as (t, phi)."""
    a, b = np.asarray(lo, dtype=float).copy(), np.asarray(hi, dtype=float).copy()
    for _ in range(GOLDEN_ITERATIONS):
        c = b - _GOLD * (b - a)
        d = a + _GOLD * (b - a)
        f = fn.values(pieces, np.concatenate([piece, piece]), np.concatenate([c, d]))
        left = f[: len(c)] < f[len(c):]
        b = np.where(left, d, b)
        a = np.where(left, a, c)
    n = len(a)
    cand = np.concatenate([lo, hi, a, b, 0.5 * (a + b)])
    fv = fn.values(pieces, np.concatenate([piece] * 5), cand).reshape(5, n)
    best = np.argmin(fv, axis=0)
    return cand.reshape(5, n)[best, np.arange(n)], fv[best, np.arange(n)]


def local_minima(
    fn: DualFunctional, pieces: Pieces, gt: np.ndarray, gf: np.ndarray, limit: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Refine the grid's local minima (per piece; grid values ``gf`` at parameters ``gt``)
    by golden section; the ``limit`` lowest as (piece, t, value)."""
    idx_lo, idx_hi, idx_piece = [], [], []
    start = 0
    for k, n in enumerate(pieces.grid_counts):
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
    # keep the most promising brackets (lowest grid value inside the bracket)
    centre_val = np.minimum(gf[np.array(idx_lo)], gf[np.array(idx_hi)])
    order = np.argsort(centre_val)[: 4 * limit]
    t, f = golden(fn, pieces, piece[order], lo[order], hi[order])
    best = np.argsort(f)[:limit]
    return piece[order][best], t[best], f[best]


@dataclass(frozen=True)
class BnBResult:
    """``lower_bound``: a sound lower bound of phi over the outline (when ``certified``:
    every interval's bound reached the target). ``violators``: (piece, lo, hi) of
    intervals whose midpoint lies below the target (empty when none was found);
    ``intervals``: intervals examined."""

    lower_bound: float
    certified: bool
    violators: tuple[np.ndarray, np.ndarray, np.ndarray] | tuple[()]
    intervals: int


def branch_and_bound(
    fn: DualFunctional, pieces: Pieces, gp: np.ndarray, gt: np.ndarray, target: float,
    max_intervals: int, budget: Budget,
) -> BnBResult:
    """Sound lower bound of phi over the outline, or points below ``target``.

    Breadth-first bisection of the grid intervals (grid ``gp``, ``gt``); an interval is
    discarded once its lower bound reaches ``target`` (its bound enters the certified
    minimum) and split otherwise. Stops at the first level that samples phi below
    ``target``, at ``max_intervals`` or when the budget has expired.
    """
    f_all, e_all = fn.evaluate(pieces, gp, gt)
    last = np.ones(len(gp), dtype=bool)
    last[:-1] = gp[:-1] != gp[1:]
    i0 = np.nonzero(~last)[0]
    i1 = i0 + 1
    piece, t0, t1 = gp[i0], gt[i0], gt[i1]
    f0, f1, e0, e1 = f_all[i0], f_all[i1], e_all[i0], e_all[i1]
    certified_min = math.inf
    total = len(piece)
    while True:
        lb = fn.lower_bounds(pieces, piece, t0, t1, f0, f1, e0, e1)
        small = (t1 - t0) <= MIN_INTERVAL
        done = (lb >= target) | small
        if np.any(done):
            certified_min = min(certified_min, float(np.min(lb[done])))
        keep = ~done
        if not np.any(keep):
            return BnBResult(certified_min, certified_min >= target, (), total)
        piece, t0, t1, f0, f1, e0, e1, lb = (arr[keep] for arr in (piece, t0, t1, f0, f1, e0, e1, lb))
        if total + len(piece) > max_intervals or budget.expired():
            return BnBResult(min(certified_min, float(np.min(lb))), False, (), total)
        tm = 0.5 * (t0 + t1)
        fm, em = fn.evaluate(pieces, piece, tm)
        total += len(piece)
        below = fm < target
        if np.any(below):
            order = np.argsort(fm[below])[:COLUMNS_PER_ROUND]
            return BnBResult(
                min(certified_min, float(np.min(lb))), False,
                (piece[below][order], t0[below][order], t1[below][order]), total,
            )
        piece = np.concatenate([piece, piece])
        t0, t1 = np.concatenate([t0, tm]), np.concatenate([tm, t1])
        f0, f1 = np.concatenate([f0, fm]), np.concatenate([fm, f1])
        e0, e1 = np.concatenate([e0, em]), np.concatenate([em, e1])
