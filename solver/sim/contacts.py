"""Contacts of a simulated push: keeping a contact while stepping, finding where a pusher
first meets a part, and locating the events that end a step (book 4.2-4.5).

* Re-imposing a contact after a step removes the O(h^2) drift of the integration without
  changing the motion to first order: a vertex put back on a fence line along the line's
  normal (:func:`onto_line`, 3.4/4.3), a disk put back at its radius from a pusher point
  along the line of centres (:func:`at_distance`, 4.4).
* :func:`first_dip` finds the first parameter at which a pusher moving on a path P(u)
  enters a disk deeper than a graze depth, without missing grazing contacts (rigorous
  interval bounds, then Brent's method).
* :func:`regula_falsi` re-solves a step's length so that an event function is zero at
  its end (the Illinois variant); :func:`crossing_fraction` places a monotone quantity's
  crossing of a level inside a step by linear interpolation.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Protocol, TypeVar

import numpy as np
from scipy.optimize import brentq

from solver.core.errors import NotConverged

T = TypeVar("T")


def onto_line(cm: np.ndarray, point: np.ndarray, normal: np.ndarray, level: float) -> np.ndarray:
    """The CM moved along the unit ``normal`` so that ``point`` (a point of the part) lies
    on the line normal . P = level (a vertex kept on a fence)."""
    return cm + (level - float(normal @ point)) * normal


def at_distance(cm: np.ndarray, centre: np.ndarray, distance: float) -> np.ndarray:
    """The CM moved along the line from ``centre`` so that it lies ``distance`` from it (a
    disk kept touching a pusher point)."""
    d = cm - centre
    return centre + distance * d / float(np.hypot(d[0], d[1]))


def crossing_fraction(before: float, after: float, level: float) -> float:
    """Where in a step a quantity going from ``before`` to ``after`` reaches ``level``, as a
    fraction of the step (linear interpolation)."""
    return (level - before) / (after - before)


class Path(Protocol):
    """A pusher path P(u): position, bounds of |P'| and |P''| on an interval inside one
    smooth piece, the parameters where P' jumps (``breakpoints``) and the end."""

    u_end: float
    breakpoints: np.ndarray

    def position(self, u: float | np.ndarray) -> np.ndarray: ...

    def speed_bound(self, u0: float, u1: float) -> float | np.ndarray: ...

    def accel_bound(self, u0: float, u1: float) -> float | np.ndarray: ...


def gap_to_disk(path: Path, cm: np.ndarray, a: float, u: float | np.ndarray) -> np.ndarray:
    """|P(u) - CM| - a: negative while the pusher is inside the disk."""
    d = path.position(u) - cm
    return np.asarray(np.hypot(d[..., 0], d[..., 1]) - a)


def sample_grid(path: Path, u0: float, u1: float, ds: float) -> np.ndarray:
    """Points from u0 to u1 about ds apart in travel, with every breakpoint inside (so no
    interval straddles a jump of P')."""
    bp = path.breakpoints
    inner = bp[(bp > u0) & (bp < u1)]
    knots = np.concatenate([[u0], inner, [u1]])
    parts = []
    for lo, hi in zip(knots[:-1], knots[1:]):
        speed = float(path.speed_bound(lo, hi))
        n = max(1, int(math.ceil((hi - lo) * speed / ds)))
        parts.append(np.linspace(lo, hi, n + 1)[:-1])
    parts.append(np.array([u1]))
    return np.concatenate(parts)


def first_dip(
    path: Path, cm: np.ndarray, a: float, u0: float, sample: float, graze_depth: float, root_tol: float,
    max_bisections: int, chunk_samples: int = 256,
) -> tuple[float | None, int]:
    """The first u >= u0 where the pusher enters the disk (centre ``cm``, radius a) deeper
    than ``graze_depth`` a, refined to where it crosses the circle |P - CM| = a; None if it
    never does. Also the number of intervals refined to ``root_tol`` a without a decision
    (they can hold a dip at most root_tol a deeper than the graze depth: touches).

    f(u) = |P(u) - CM| - a is sampled every ``sample`` a of travel and every interval is
    excluded by a rigorous lower bound or bisected: Lipschitz, f >= (f_0 + f_1 - S w)/2
    with S >= |P'|; once |P - CM| >= a/2 on the interval, the quadratic bound
    f >= min(f_0, f_1) - M w^2/8 with M = 2 S^2/a + |P''| >= |f''|."""
    delta = graze_depth * a
    chunk = chunk_samples * sample * a
    touches = 0
    bisections = 0
    lo = u0
    while lo < path.u_end:
        speed = float(path.speed_bound(lo, lo))
        hi = min(path.u_end, lo + chunk / max(speed, 1e-300))
        grid = sample_grid(path, lo, hi, sample * a)
        f = gap_to_disk(path, cm, a, grid)
        if f[0] < -delta:
            return lo, touches
        stack = [(grid[i], grid[i + 1], f[i], f[i + 1]) for i in range(grid.size - 2, -1, -1)]
        while stack:
            ua, ub, fa, fb = stack.pop()
            if fb < -delta:
                return contact_start(path, cm, a, ua, ub, fa, graze_depth, root_tol), touches
            w = ub - ua
            sp = float(path.speed_bound(ua, ub))
            if 0.5 * (fa + fb - sp * w) >= -delta:
                continue
            if sp * w <= 0.25 * a and min(fa, fb) >= -delta:
                m2 = 2.0 * sp * sp / a + float(path.accel_bound(ua, ub))
                if min(fa, fb) - 0.125 * m2 * w * w >= -delta:
                    continue
            if sp * w <= root_tol * a:
                touches += 1
                continue
            bisections += 1
            if bisections > max_bisections:
                raise NotConverged("the contact search did not settle (bisection cap reached)")
            um = 0.5 * (ua + ub)
            fm = float(gap_to_disk(path, cm, a, um))
            stack.append((um, ub, fm, fb))
            stack.append((ua, um, fa, fm))
        lo = hi
    return None, touches


def contact_start(
    path: Path, cm: np.ndarray, a: float, ua: float, ub: float, fa: float, graze_depth: float, root_tol: float,
) -> float:
    """The crossing of |P - CM| = a in [ua, ub] (f(ua) >= -graze depth > f(ub)) by Brent's
    method; if already f(ua) < 0 (inside a touch), the crossing of f = -graze depth a."""
    sp = float(path.speed_bound(ua, ub))
    level = 0.0 if fa >= 0.0 else -graze_depth * a
    return float(brentq(lambda u: float(gap_to_disk(path, cm, a, u)) - level, ua, ub,
                        xtol=root_tol * a / max(sp, 1e-300)))


def regula_falsi(
    trial: Callable[[float], tuple[float, T]], lo: float, g_lo: float, hi: float, g_hi: float, tol: float,
    max_iter: int,
) -> tuple[float, T | None]:
    """The length h in [lo, hi] (event g(lo) > 0 > g(hi)) where g(h) = 0, by Illinois
    regula falsi on ``trial(h) -> (g, payload)``, until |g| <= ``tol`` or ``max_iter``
    trials; returns (h, payload) of the last trial (None before any)."""
    kept = 0
    out: tuple[float, T | None] = (hi, None)
    for _ in range(max_iter):
        h = (lo * g_hi - hi * g_lo) / (g_hi - g_lo)
        g, payload = trial(h)
        out = (h, payload)
        if abs(g) <= tol:
            break
        if g < 0.0:
            hi, g_hi = h, g
            if kept == -1:
                g_lo *= 0.5
            kept = -1
        else:
            lo, g_lo = h, g
            if kept == 1:
                g_hi *= 0.5
            kept = 1
    return out
