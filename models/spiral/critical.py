"""Spiral localization of a disk (book 4.5): collision parameters, the critical radius and its
safe envelope. The recursion, the path and its fit are in :mod:`models.spiral.path`, the
schedule graph in :mod:`models.spiral.graph`.

A point pusher circles a disk of radius a known to lie within radius b_1, shrinking its
radius by Delta b each revolution (4.5, figure 4-16). The pusher meets the disk at most
Delta b from the disk's edge, i.e. at a collision parameter beta with

    d = a (1 - sin beta) <= Delta b                                            (4.24)

(d: the pusher's distance from grazing; beta = pi/2 is a grazing touch). In the critical
case (4.5.2, figure 4-17) the pusher centre PC lies directly below the contact, at the
pusher circle's radius r; the disk is pushed *into* the circle when every COR of its
sketch lies on the inward side of the critical line through PC and the CM, which holds
once PC lies below the lower end of the sticking locus (figure 4-18). The distance from the
pusher line to that end is the critical radius r*(beta) (4.5.3); r >= r*(beta) is the
guarantee at collision parameter beta. (For every COR left of the contact, x < 0 in the
frame of models/gross_bounds.encounter_scene, moving PC further down only moves the
critical line further from the COR, so the condition is monotone in r.)

This module is pure: it takes a table of (beta_k, r*_k) (solver/spiral/critical_radius.py computes them
exactly, by the book's sweep, or by the tip line) and turns it into the critical distance
from grazing d*(b) (4.5.3), the recursion (4.26), the pusher path and the power-law fit of
figure 4-21. Every formula names its book equation or section.

The safe envelope (why max over the suffix, and when the table is enough)
-------------------------------------------------------------------------
The disk is left tangent to revolution n-1 and revolution n hits it at a distance d from
grazing that can be anything in [0, Delta b], so beta can be anything in
[beta_Delta, pi/2], and while it is pushed beta sweeps on towards pi/2. The guarantee on
revolution n (radius b) therefore needs r*(beta') <= b for EVERY beta' >= beta_Delta, i.e.
R(beta_Delta) <= b with R(beta) = sup_{beta' >= beta} r*(beta'), a nonincreasing function.
From a table beta_0 < ... < beta_K (< pi/2) with values U_k the module uses

    R_k = max_{j >= k} U_j,     beta*(b) = min{beta_k : R_k <= b},
    d*(b) = a (1 - sin beta*(b))                      (4.24 at beta*, 4.5.3)

and d*(b) = 0 when b < R_K (no guarantee at all: no shrinking allowed).
Claim: if every U_k bounds r* on its cell, U_k >= sup {r*(beta) : beta_k <= beta <
beta_{k+1}} (beta_{K+1} = pi/2), then d*(b) is safe: r*(beta') <= b for every beta' >=
beta*(b). Proof: beta' lies in some cell j >= k* (k* the index of beta*(b)), so r*(beta')
<= U_j <= R_{k*} <= b. Between table points nothing is interpolated, so d* can only be
too small (slower), never too large. A point value U_k >= r*(beta_k) bounds its cell when
r* is nonincreasing there, which the tables show (r* falls from ~2a/beta near beta = 0 to
b_inf at pi/2, 4.5.3-4.5.4); :func:`critical_envelope` reports every increase of the table
(``max_increase``) so a violation is visible.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from models.core.arrays import Real
from models.core.errors import InvalidInput
from models.core.tolerances import SPIRAL_DEFAULT, SpiralTolerances

# --------------------------------------------------------------------------------------
# Checks


def checked_disk_radius(a: float) -> float:
    a = float(a)
    if not (math.isfinite(a) and a > 0.0):
        raise InvalidInput("a", "the disk radius must be a positive finite number")
    return a


def _mu(mu_c: float) -> float:
    mu = float(mu_c)
    if not (math.isfinite(mu) and mu >= 0.0):
        raise InvalidInput("mu_c", "must be a finite number >= 0")
    return mu


def _as_out(x: np.ndarray, scalar: bool) -> Real:
    return float(x) if scalar else x


# --------------------------------------------------------------------------------------
# (4.24), (4.25) and the tip line


def distance_from_grazing(a: float, beta: ArrayLike) -> Real:
    """(4.24): the pusher's distance from grazing d = a (1 - sin beta) at collision
    parameter beta (4.5.1, figure 4-16), for beta in [-pi/2, pi/2]. Computed as
    2 a sin^2((pi/2 - beta)/2), which keeps full relative accuracy as beta -> pi/2."""
    a = checked_disk_radius(a)
    scalar = np.ndim(beta) == 0
    b = np.asarray(beta, dtype=float)
    if not np.all(np.isfinite(b)) or np.any(np.abs(b) > 0.5 * math.pi):
        raise InvalidInput("beta", "the collision parameter must lie in [-pi/2, pi/2]")
    d = 2.0 * a * np.sin(0.5 * (0.5 * math.pi - b)) ** 2
    return _as_out(d, scalar)


def collision_parameter(a: float, d: ArrayLike) -> Real:
    """The inverse of (4.24): beta = pi/2 - 2 asin(sqrt(d / 2a)) for d in [0, 2a] (accurate
    for small d, where asin(1 - d/a) would lose the digits of d)."""
    a = checked_disk_radius(a)
    scalar = np.ndim(d) == 0
    dd = np.asarray(d, dtype=float)
    if not np.all(np.isfinite(dd)) or np.any(dd < 0.0) or np.any(dd > 2.0 * a):
        raise InvalidInput("d", "the distance from grazing must lie in [0, 2a]")
    beta = 0.5 * math.pi - 2.0 * np.arcsin(np.sqrt(dd / (2.0 * a)))
    return _as_out(beta, scalar)


def limiting_radius(a: float, mu_c: float) -> float:
    """(4.25), 4.5.4: the limiting radius below which localization cannot be guaranteed,
    b_inf = a (1 + mu_c) for mu_c <= 1 and 2a for mu_c >= 1 (b_inf = r*(pi/2))."""
    a = checked_disk_radius(a)
    mu = _mu(mu_c)
    return a * (1.0 + min(mu, 1.0))


def tip_line_critical_radius(a: float, beta: ArrayLike) -> Real:
    """The book's tip-line approximation of r*(beta) (4.1.4, 4.4.1.1): the sticking
    line meets the tip line at y_COR = a (sin^2 beta - 2) / sin beta ((4.13), figure 4-13),
    so its distance from the pusher line y = a sin beta is 2a / sin beta, independent of
    mu_c. Its grazing limit is 2a for every mu_c, against (4.25)'s a (1 + mu_c) for mu_c < 1."""
    a = checked_disk_radius(a)
    scalar = np.ndim(beta) == 0
    b = np.asarray(beta, dtype=float)
    if not np.all(np.isfinite(b)) or np.any(b <= 0.0) or np.any(b > 0.5 * math.pi):
        raise InvalidInput("beta", "the collision parameter must lie in (0, pi/2]")
    return _as_out(2.0 * a / np.sin(b), scalar)


def tip_line_critical_distance(a: float, r: ArrayLike) -> Real:
    """d*(r) of the tip-line approximation: beta*(r) = asin(2a/r) for r >= 2a, so
    d*(r) = a (1 - 2a/r) by (4.24); 0 below 2a."""
    a = checked_disk_radius(a)
    scalar = np.ndim(r) == 0
    rr = np.asarray(r, dtype=float)
    d = np.where(rr >= 2.0 * a, a * (1.0 - 2.0 * a / np.maximum(rr, 2.0 * a)), 0.0)
    return _as_out(d, scalar)


def tip_line_next_radius(a: float, b_prev: float) -> float:
    """(4.26) with the tip-line d*: b_n = b_{n-1} - a (1 - 2a/b_n) is the positive root of
    b_n^2 - (b_{n-1} - a) b_n - 2 a^2 = 0 (valid while b_n >= 2a; the fixed point is 2a)."""
    a = checked_disk_radius(a)
    y = float(b_prev)
    if y <= 2.0 * a:
        return y
    p = y - a
    return 0.5 * (p + math.sqrt(p * p + 8.0 * a * a))


# --------------------------------------------------------------------------------------
# The safe envelope and d*(b)


@dataclass(frozen=True)
class CriticalEnvelope:
    """A table of critical radii made safe (module docstring): ``betas`` ascending in
    (0, pi/2), ``radii`` the table values U_k (upper bounds of r* on each cell),
    ``envelope`` R_k = max_{j >= k} U_j (nonincreasing), ``distances`` d_k = a (1 - sin
    beta_k) (4.24). ``max_increase`` = max_k (U_{k+1} - U_k), > 0 when r* is not monotone
    on the grid; ``n_violations`` counts the increases above monotone_rel. ``b_floor`` =
    R_K: the smallest radius with any guaranteed progress (the table's b_inf)."""

    a: float
    betas: np.ndarray
    radii: np.ndarray
    envelope: np.ndarray
    distances: np.ndarray
    max_increase: float
    n_violations: int
    b_floor: float = field(default=0.0)

    def index(self, r: ArrayLike) -> np.ndarray:
        """Index k* of beta*(r) (the smallest k with R_k <= r); len(betas) when none."""
        return np.searchsorted(-self.envelope, -np.asarray(r, dtype=float), side="left")

    def beta_star(self, r: ArrayLike) -> Real:
        """beta*(r) (4.5.3): the smallest tabulated collision parameter whose whole tail
        beta' >= beta_k has r*(beta') <= r; nan below ``b_floor`` (no guarantee)."""
        scalar = np.ndim(r) == 0
        k = self.index(r)
        ext = np.append(self.betas, np.nan)
        return _as_out(ext[k], scalar)

    def d_star(self, r: ArrayLike, max_step: float | None = None) -> Real:
        """d*(r) (4.5.3, via 4.24): the largest distance from grazing with a guarantee at
        pusher radius r; 0 below ``b_floor``. With ``max_step`` the robot's cap min(d*, M)."""
        scalar = np.ndim(r) == 0
        k = self.index(r)
        ext = np.append(self.distances, 0.0)
        d = ext[k]
        if max_step is not None:
            d = np.minimum(d, float(max_step))
        return _as_out(d, scalar)

    def step_is_safe(self, b_prev: float, x: float, max_step: float | None = None) -> bool:
        """b_prev - x <= D(x) in the rounding-proof form the schedule graph uses
        (:func:`schedule_graph`): b_prev <= fl(x + D(x)) less one ulp."""
        return float(b_prev) <= float(safe_reach(float(x), float(self.d_star(float(x), max_step))))

    def next_radius(self, b_prev: float, max_step: float | None = None) -> float:
        """One step of (4.26), exactly (module docstring): the least x <= b_prev with
        b_prev - x <= D(x), D = d* (capped at ``max_step``). Rounded towards the larger x."""
        y = float(b_prev)
        dk = self.distances if max_step is None else np.minimum(self.distances, float(max_step))
        # max(R_k, y - D_k), with y - D_k rounded up so that y - x <= D_k holds exactly
        cand = np.maximum(self.envelope, np.nextafter(y - dk, np.inf))
        best = float(np.min(cand)) if cand.size else y
        return min(y, best)


def critical_envelope(betas: ArrayLike, radii: ArrayLike, a: float, tol: SpiralTolerances = SPIRAL_DEFAULT) -> CriticalEnvelope:
    """The safe envelope of a critical-radius table (module docstring): sorts by beta,
    checks 0 < beta < pi/2 and positive finite radii, and takes the suffix maximum."""
    a = checked_disk_radius(a)
    b = np.asarray(betas, dtype=float).ravel()
    r = np.asarray(radii, dtype=float).ravel()
    if b.size == 0 or b.shape != r.shape:
        raise InvalidInput("betas", "need a non-empty table with one radius per beta")
    if not (np.all(np.isfinite(b)) and np.all(b > 0.0) and np.all(b < 0.5 * math.pi)):
        raise InvalidInput("betas", "collision parameters must lie in (0, pi/2)")
    if not (np.all(np.isfinite(r)) and np.all(r > 0.0)):
        raise InvalidInput("radii", "critical radii must be positive finite numbers")
    order = np.argsort(b, kind="stable")
    b, r = b[order], r[order]
    if np.any(np.diff(b) <= 0.0):
        raise InvalidInput("betas", "collision parameters must be distinct")
    env = np.maximum.accumulate(r[::-1])[::-1]
    inc = np.diff(r)
    max_inc = float(inc.max()) if inc.size else 0.0
    n_viol = int(np.sum(inc > tol.monotone_rel * r[:-1])) if inc.size else 0
    d = distance_from_grazing(a, b)
    return CriticalEnvelope(a=a, betas=b, radii=r, envelope=env, distances=np.asarray(d, dtype=float),
                            max_increase=max_inc, n_violations=n_viol, b_floor=float(env[-1]))


def tip_line_envelope(a: float, betas: ArrayLike) -> CriticalEnvelope:
    """The envelope of the tip-line approximation 2a / sin beta on a beta grid."""
    b = np.asarray(betas, dtype=float)
    return critical_envelope(b, tip_line_critical_radius(a, b), a)


def safe_reach(x: Real, d: Real) -> Real:
    """The largest radius from which a revolution to ``x`` is safe with the safe step ``d``
    (4.26), proof against rounding: y - x <= d holds for every y <= fl(x + d) less one ulp
    (fl is within half an ulp). The schedule graph and the recursion both use it."""
    return np.nextafter(np.asarray(x, dtype=float) + d, -np.inf)
