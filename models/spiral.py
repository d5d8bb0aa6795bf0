"""Spiral localization of a disk (book 4.5): the geometry of the fastest guaranteed spiral.

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

The recursion (4.26) and why greedy is optimal
----------------------------------------------
A step from radius y to radius x < y is safe when y - x <= d*(x); with a robot's maximum
step M, y - x <= D(x) = min(d*(x), M). g(x) = x + D(x) is nondecreasing (D is: a larger
radius admits a smaller beta*, hence a larger d*), and right-continuous (the pieces are
closed on the left), so the safe next radii from y are the closed half line {x : g(x) >=
y} and (4.26) takes its least element, b_n = min{x <= b_{n-1} : g(x) >= b_{n-1}}. Since D
is piecewise constant (value D_k on [R_k, next level)), that minimum is exactly

    b_n = min(b_{n-1}, min_k max(R_k, b_{n-1} - D_k)),

computed with one rounding towards the larger (safer) radius. No bisection is needed;
tests check it against a bisection on g.
Greedy is optimal: if any safe schedule b'_1 = b_1, b'_2, ... has b_{n-1} <= b'_{n-1},
then g(b'_n) >= b'_{n-1} >= b_{n-1}, so b'_n is a safe next radius from b_{n-1} too (or
b'_n > b_{n-1} >= b_n), and b_n <= b'_n. By induction the greedy radii are elementwise
least, so greedy reaches any target in the fewest revolutions; the same holds on any grid
of radii (the argument only compares feasible sets). Path length (as defined below) is
shortest too: a revolution's length L(b_n, b_{n+1}) increases in both radii
(:func:`revolution_length`), so with greedy g_1..g_N and any other o_1..o_M (M >= N,
g_n <= o_n) the first N - 1 revolutions compare termwise, and greedy's final circle
2 pi g_N <= 2 pi o_N is covered by the other's remaining length, which is at least
pi (o_N + o_{N+1}) + 2 pi o_M >= 2 pi o_N when M > N (steps are < a <= b_inf <= o_M).
A *minimum* step breaks the argument (the feasible set from a smaller radius is not a
superset) and needs the shortest-path solve of solver/spiral/schedule.py.

The path (a definition, not in the book)
----------------------------------------
The book gives one radius per revolution ("we will not truly specify the spiral
completely", 4.5.5). Here revolution n (1 <= n < N) runs once round, its radius linear in
the angle from b_n to b_{n+1} (an Archimedean piece), and revolution N is the circle of
radius b_N, so N radii are N revolutions and a total angle of 2 pi N. Like the book's
(4.26) ("to excellent approximation") the guarantee is argued per revolution at the radius
b_n; the continuous spiral in between is a drawing of it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from models.arrays import Real
from models.errors import InvalidInput
from models.tolerances import SPIRAL_DEFAULT, SpiralTolerances

# --------------------------------------------------------------------------------------
# Checks


def _radius(a: float) -> float:
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
    a = _radius(a)
    scalar = np.ndim(beta) == 0
    b = np.asarray(beta, dtype=float)
    if not np.all(np.isfinite(b)) or np.any(np.abs(b) > 0.5 * math.pi):
        raise InvalidInput("beta", "the collision parameter must lie in [-pi/2, pi/2]")
    d = 2.0 * a * np.sin(0.5 * (0.5 * math.pi - b)) ** 2
    return _as_out(d, scalar)


def collision_parameter(a: float, d: ArrayLike) -> Real:
    """The inverse of (4.24): beta = pi/2 - 2 asin(sqrt(d / 2a)) for d in [0, 2a] (accurate
    for small d, where asin(1 - d/a) would lose the digits of d)."""
    a = _radius(a)
    scalar = np.ndim(d) == 0
    dd = np.asarray(d, dtype=float)
    if not np.all(np.isfinite(dd)) or np.any(dd < 0.0) or np.any(dd > 2.0 * a):
        raise InvalidInput("d", "the distance from grazing must lie in [0, 2a]")
    beta = 0.5 * math.pi - 2.0 * np.arcsin(np.sqrt(dd / (2.0 * a)))
    return _as_out(beta, scalar)


def limiting_radius(a: float, mu_c: float) -> float:
    """(4.25), 4.5.4: the limiting radius below which localization cannot be guaranteed,
    b_inf = a (1 + mu_c) for mu_c <= 1 and 2a for mu_c >= 1 (b_inf = r*(pi/2))."""
    a = _radius(a)
    mu = _mu(mu_c)
    return a * (1.0 + min(mu, 1.0))


def tip_line_critical_radius(a: float, beta: ArrayLike) -> Real:
    """The book's tip-line approximation of r*(beta) (4.1.4, 4.4.1.1): the sticking
    line meets the tip line at y_COR = a (sin^2 beta - 2) / sin beta ((4.13), figure 4-13),
    so its distance from the pusher line y = a sin beta is 2a / sin beta, independent of
    mu_c. Its grazing limit is 2a for every mu_c, against (4.25)'s a (1 + mu_c) for mu_c < 1."""
    a = _radius(a)
    scalar = np.ndim(beta) == 0
    b = np.asarray(beta, dtype=float)
    if not np.all(np.isfinite(b)) or np.any(b <= 0.0) or np.any(b > 0.5 * math.pi):
        raise InvalidInput("beta", "the collision parameter must lie in (0, pi/2]")
    return _as_out(2.0 * a / np.sin(b), scalar)


def tip_line_critical_distance(a: float, r: ArrayLike) -> Real:
    """d*(r) of the tip-line approximation: beta*(r) = asin(2a/r) for r >= 2a, so
    d*(r) = a (1 - 2a/r) by (4.24); 0 below 2a."""
    a = _radius(a)
    scalar = np.ndim(r) == 0
    rr = np.asarray(r, dtype=float)
    d = np.where(rr >= 2.0 * a, a * (1.0 - 2.0 * a / np.maximum(rr, 2.0 * a)), 0.0)
    return _as_out(d, scalar)


def tip_line_next_radius(a: float, b_prev: float) -> float:
    """(4.26) with the tip-line d*: b_n = b_{n-1} - a (1 - 2a/b_n) is the positive root of
    b_n^2 - (b_{n-1} - a) b_n - 2 a^2 = 0 (valid while b_n >= 2a; the fixed point is 2a)."""
    a = _radius(a)
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
    a = _radius(a)
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


# --------------------------------------------------------------------------------------
# Arc length of a revolution, path length, polyline


def revolution_length(b_start: ArrayLike, b_end: ArrayLike,
                      nodes: int = SPIRAL_DEFAULT.arc_nodes) -> tuple[Real, Real]:
    """Length of one revolution whose radius runs linearly in the angle from ``b_start`` to
    ``b_end`` (an Archimedean piece rho(theta) = b_start + k theta, k = (b_end -
    b_start) / 2 pi): L = int_0^2pi sqrt(rho^2 + k^2) dtheta
      = pi (b_start + b_end) + int_0^2pi k^2 / (sqrt(rho^2 + k^2) + rho) dtheta,
    the second (small) term by Gauss-Legendre with ``nodes`` nodes (the integrand is
    analytic; its singularities lie >= 2 half-lengths from the interval when |b_end -
    b_start| <= min radius, so 16 nodes reach rounding). Returns (length, error estimate =
    difference to the rule with half the nodes). Vectorized over arrays of radii.

    L is increasing in both radii whenever |k| <= rho (dL/db_end >= pi/sqrt(1 + (k/rho)^2)
    - |k|/rho_min > 0), which the optimality of greedy schedules for length uses."""
    scalar = np.ndim(b_start) == 0 and np.ndim(b_end) == 0
    r0 = np.asarray(b_start, dtype=float)
    r1 = np.asarray(b_end, dtype=float)
    r0, r1 = np.broadcast_arrays(r0, r1)
    if np.any(r0 <= 0.0) or np.any(r1 <= 0.0):
        raise InvalidInput("radii", "revolution radii must be positive")

    def rule(n: int) -> np.ndarray:
        x, w = np.polynomial.legendre.leggauss(n)
        t = 0.5 * (x + 1.0)  # theta / 2 pi in (0, 1)
        rho = r0[..., None] + (r1 - r0)[..., None] * t
        k = ((r1 - r0) / (2.0 * math.pi))[..., None]
        f = k * k / (np.sqrt(rho * rho + k * k) + rho)
        return math.pi * (r0 + r1) + math.pi * (f @ w)

    full = rule(nodes)
    half = rule(max(2, nodes // 2))
    err = np.abs(full - half)
    if scalar:
        return float(full), float(err)
    return full, err


def revolution_length_closed_form(b_start: float, b_end: float) -> float:
    """The same length from the antiderivative of sqrt(rho^2 + k^2) (k != 0):
    L = [rho s + k^2 asinh(rho/|k|)]_{b_start}^{b_end} / (2k), s = sqrt(rho^2 + k^2).
    Loses digits when |k| << rho (cancellation); used to check :func:`revolution_length`."""
    k = (float(b_end) - float(b_start)) / (2.0 * math.pi)
    if k == 0.0:
        return 2.0 * math.pi * float(b_start)

    def anti(rho: float) -> float:
        return rho * math.sqrt(rho * rho + k * k) + k * k * math.asinh(rho / abs(k))

    return (anti(float(b_end)) - anti(float(b_start))) / (2.0 * k)


def spiral_path_length(radii: ArrayLike, final_circle: bool = True, nodes: int = SPIRAL_DEFAULT.arc_nodes) -> tuple[float, float]:
    """Length of the pusher path (module docstring): revolutions b_n -> b_{n+1} for n < N
    plus, with ``final_circle``, the circle of radius b_N. Returns (length, error bound =
    sum of the per-revolution error estimates)."""
    b = np.asarray(radii, dtype=float).ravel()
    if b.size == 0:
        return 0.0, 0.0
    total = 2.0 * math.pi * float(b[-1]) if final_circle else 0.0
    err = 0.0
    if b.size > 1:
        ls, es = revolution_length(b[:-1], b[1:], nodes)
        total += float(np.sum(ls))
        err = float(np.sum(es))
    return total, err


@dataclass(frozen=True)
class SpiralPolyline:
    """The pusher path as a polyline (world frame, centred at ``center``): ``points``
    (M, 2), the angle and radius of each point, ``points_per_revolution``, and
    ``max_chord_deviation``, an upper bound on the distance between the path and its
    chords (kappa_max l^2 / 8 per chord: the interpolation bound of a curve with
    curvature <= kappa_max over arc length l). ``polyline_length`` is the sum of the chords."""

    points: np.ndarray
    angles: np.ndarray
    radii: np.ndarray
    points_per_revolution: int
    max_chord_deviation: float
    polyline_length: float
    clockwise: bool


def spiral_polyline(radii: ArrayLike, points_per_revolution: int = 64, center: ArrayLike = (0.0, 0.0), phase: float = 0.5 * math.pi,
                    clockwise: bool = True, final_circle: bool = True) -> SpiralPolyline:
    """The path of :func:`spiral_path_length` sampled at ``points_per_revolution`` equal
    angles per revolution (plus the closing point). The default starts at the top
    (``phase`` = pi/2) and runs clockwise, i.e. along +x at the top, the book's drawing of
    the pusher's motion (4.5.1, figure 4-17)."""
    b = np.asarray(radii, dtype=float).ravel()
    m = int(points_per_revolution)
    if m < 3:
        raise InvalidInput("points_per_revolution", "must be at least 3")
    if b.size == 0 or np.any(b <= 0.0):
        raise InvalidInput("radii", "need at least one positive radius")
    ends = np.append(b, b[-1]) if final_circle else b
    n_rev = ends.size - 1
    if n_rev < 1:
        raise InvalidInput("radii", "need two radii, or one with final_circle")
    t = np.arange(n_rev * m + 1) / m  # revolutions done
    i = np.minimum(np.floor(t).astype(int), n_rev - 1)
    f = t - i
    rho = ends[i] + (ends[i + 1] - ends[i]) * f
    sgn = -1.0 if clockwise else 1.0
    ang = phase + sgn * 2.0 * math.pi * t
    c = np.asarray(center, dtype=float)
    pts = c + rho[:, None] * np.column_stack([np.cos(ang), np.sin(ang)])
    # deviation bound per chord: curvature of rho = r0 + k theta is
    # (rho^2 + 2k^2)/(rho^2 + k^2)^1.5, decreasing in rho, so largest at the chord's
    # smaller radius; the arc length is at most sqrt(rho_max^2 + k^2) dtheta.
    k = ((ends[i + 1] - ends[i]) / (2.0 * math.pi))[:-1]
    lo = np.minimum(rho[:-1], rho[1:])
    hi = np.maximum(rho[:-1], rho[1:])
    kappa = (lo * lo + 2.0 * k * k) / (lo * lo + k * k) ** 1.5
    ell = np.sqrt(hi * hi + k * k) * (2.0 * math.pi / m)
    dev = float(np.max(kappa * ell * ell / 8.0))
    chords = float(np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=1)))
    return SpiralPolyline(points=pts, angles=ang, radii=rho, points_per_revolution=m, max_chord_deviation=dev,
                          polyline_length=chords, clockwise=clockwise)


# --------------------------------------------------------------------------------------
# The recursion (4.26)


@dataclass(frozen=True)
class SpiralRecursion:
    """The fastest guaranteed spiral by the recursion (4.26), 4.5.5.

    ``radii`` b_1, b_2, ..., b_N (N = ``revolutions``; the last is the final circle);
    ``steps`` b_{n-1} - b_n (each <= d*(b_n), ``max_step_excess`` = max(step - d*(b_n)) <=
    0); ``stop_reason``: "target" (b_N <= target), "stalled" (the next step would be at
    most stall_step_rel * a: the radius is at the table's floor, near b_inf),
    "max_revolutions". ``path_length`` (module docstring) with its quadrature error bound;
    ``time_s`` = path_length / ``speed`` when a pusher speed is given."""

    radii: np.ndarray
    steps: np.ndarray
    revolutions: int
    stop_reason: str
    reached_target: bool
    target: float | None
    b_floor: float
    path_length: float
    path_length_error: float
    speed: float | None
    time_s: float | None
    max_step_excess: float


def fastest_spiral(envelope: CriticalEnvelope, b_1: float, target: float | None = None,
                   max_step: float | None = None, speed: float | None = None,
                   tol: SpiralTolerances = SPIRAL_DEFAULT) -> SpiralRecursion:
    """(4.26): b_n = b_{n-1} - d*(b_n), each step the exact least safe radius
    (:meth:`CriticalEnvelope.next_radius`), from ``b_1`` until b_n <= ``target`` (or, with
    no target, until it stalls near the table's floor), at most tol.max_revolutions
    revolutions. ``max_step`` caps each step (a robot limit; greedy stays optimal)."""
    a = envelope.a
    y = float(b_1)
    if not (math.isfinite(y) and y > 0.0):
        raise InvalidInput("b_1", "must be a positive finite radius")
    if target is not None:
        target = float(target)
        if not (math.isfinite(target) and target > 0.0):
            raise InvalidInput("target", "must be a positive finite radius")
    if max_step is not None and not (math.isfinite(float(max_step)) and float(max_step) > 0.0):
        raise InvalidInput("max_step", "must be a positive finite length")
    if speed is not None and not (math.isfinite(float(speed)) and float(speed) > 0.0):
        raise InvalidInput("speed", "must be a positive finite speed")
    radii = [y]
    stop = "max_revolutions"
    stall = tol.stall_step_rel * a
    if target is not None and y <= target:
        stop = "target"
    else:
        while len(radii) < tol.max_revolutions:
            x = envelope.next_radius(y, max_step)
            # up by ulps until the step is safe in the graph's rounding-proof form too, so
            # that a grid holding these radii holds the recursion's path (solver.spiral);
            # the two forms differ by rounding only, a few ulps at most
            for _ in range(tol.graph_safe_ulps):
                if x >= y or envelope.step_is_safe(y, x, max_step):
                    break
                x = float(np.nextafter(x, np.inf))
            if y - x <= stall:
                stop = "stalled"
                break
            radii.append(x)
            y = x
            if target is not None and x <= target:
                stop = "target"
                break
    b = np.asarray(radii, dtype=float)
    steps = -np.diff(b)
    excess = float(np.max(steps - envelope.d_star(b[1:], max_step))) if steps.size else 0.0
    length, err = spiral_path_length(b, final_circle=True, nodes=tol.arc_nodes)
    return SpiralRecursion(
        radii=b, steps=steps, revolutions=int(b.size), stop_reason=stop,
        reached_target=stop == "target", target=target, b_floor=envelope.b_floor,
        path_length=length, path_length_error=err, speed=None if speed is None else float(speed),
        time_s=None if speed is None else length / float(speed), max_step_excess=excess,
    )


def tip_line_spiral(a: float, b_1: float, target: float | None = None, max_revolutions: int = 100_000) -> np.ndarray:
    """The recursion (4.26) with the tip-line d* in closed form (:func:`tip_line_next_radius`):
    radii until b_n <= target or the step drops below rounding (fixed point 2a)."""
    a = _radius(a)
    out = [float(b_1)]
    while len(out) < max_revolutions:
        x = tip_line_next_radius(a, out[-1])
        if out[-1] - x <= 4.0 * np.finfo(float).eps * out[-1]:
            break
        out.append(x)
        if target is not None and x <= target:
            break
    return np.asarray(out)


def unsafe_revolutions(radii: ArrayLike, betas: ArrayLike, r_star: ArrayLike, a: float) -> np.ndarray:
    """Which steps of a schedule are provably unsafe against a table of critical radii
    (4.5.1, 4.5.3): revolution n (radius b_n after a step Delta b = b_{n-1} - b_n) can meet
    the disk at any beta' >= beta_Delta (4.24, d = Delta b), and it is unsafe when some
    tabulated beta_k >= beta_Delta has r*(beta_k) > b_n -- a witness collision parameter.
    ``r_star`` are the table's values without any margin (for "exact" the outside ends, so
    a step flagged here may be safe by up to the bracket width). Returns a boolean per step
    (length len(radii) - 1). Steps of d >= 2a meet the disk anywhere (beta_Delta <= -pi/2)."""
    a = _radius(a)
    b = np.asarray(radii, dtype=float).ravel()
    bt = np.asarray(betas, dtype=float).ravel()
    r = np.asarray(r_star, dtype=float).ravel()
    ok = np.isfinite(r)
    bt, r = bt[ok], r[ok]
    order = np.argsort(bt)
    bt, r = bt[order], r[order]
    tail_max = np.maximum.accumulate(r[::-1])[::-1] if r.size else r  # max_{j >= k} r_j
    steps = b[:-1] - b[1:]
    out = np.zeros(steps.size, dtype=bool)
    for n, (step, b_n) in enumerate(zip(steps, b[1:])):
        beta_d = float(collision_parameter(a, min(max(step, 0.0), 2.0 * a)))
        k = int(np.searchsorted(bt, beta_d, side="left"))
        out[n] = k < bt.size and bool(tail_max[k] > b_n)
    return out


# --------------------------------------------------------------------------------------
# Power-law fit (figure 4-21)


@dataclass(frozen=True)
class PowerLawFit:
    """Least squares of log(b_n - b_inf) = log C - k log n over n_min <= n <= n_max
    (figure 4-21: the book reads k ~ 1.6 for mu_c = 0.25, b_1 = 100 a). ``rms_residual``
    in natural log units; ``local_exponents`` -d log e / d log n between consecutive points
    of the range (how far from a straight line the data are)."""

    exponent: float
    coefficient: float
    n_min: int
    n_max: int
    n_points: int
    rms_residual: float
    b_inf: float
    local_exponent_range: tuple[float, float]


def power_law_fit(radii: ArrayLike, b_inf: float, n_min: int = 1, n_max: int | None = None) -> PowerLawFit:
    """Fit (b_n - b_inf) ~ C n^-k (figure 4-21) with n counted from 1 at b_1; points with
    b_n <= b_inf are left out."""
    b = np.asarray(radii, dtype=float).ravel()
    n = np.arange(1, b.size + 1)
    hi = b.size if n_max is None else min(int(n_max), b.size)
    sel = (n >= int(n_min)) & (n <= hi) & (b - b_inf > 0.0)
    if int(sel.sum()) < 3:
        raise InvalidInput("n_min", "fewer than 3 revolutions above b_inf in the fit range")
    x = np.log(n[sel].astype(float))
    y = np.log(b[sel] - b_inf)
    A = np.column_stack([np.ones_like(x), -x])
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    res = y - A @ coef
    loc = -np.diff(y) / np.diff(x)
    return PowerLawFit(exponent=float(coef[1]), coefficient=float(math.exp(coef[0])), n_min=int(n[sel][0]),
                       n_max=int(n[sel][-1]), n_points=int(sel.sum()), rms_residual=float(np.sqrt(np.mean(res ** 2))),
                       b_inf=float(b_inf), local_exponent_range=(float(loc.min()), float(loc.max())))


# --------------------------------------------------------------------------------------
# Schedules on a grid of radii (the graph that solver/spiral/schedule.py hands to OR-Tools)


@dataclass(frozen=True)
class ScheduleGraph:
    """The DAG of safe revolutions between grid radii ``x`` (ascending, x[0] = target,
    x[-1] = b_1): an arc i -> j (i > j, from radius x_i to the next revolution's x_j) when
    x_i - x_j <= D(x_j) (the step is safe at the new radius, 4.26; D = d* capped by
    max_step) and x_i - x_j >= min_step, both in exact arithmetic (one ulp of slack towards
    safety). Incoming arcs of node j come from the contiguous range lo[j] <= i <= hi[j]
    (empty when lo > hi). ``tails``/``heads`` list every arc."""

    x: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    tails: np.ndarray
    heads: np.ndarray
    min_step: float | None
    max_step: float | None

    @property
    def n_arcs(self) -> int:
        return int(self.tails.size)


def schedule_grid(envelope: CriticalEnvelope, b_1: float, target: float, spacing: float | None = None,
                  resolution: int = 16, max_nodes: int = 200_000, max_step: float | None = None) -> np.ndarray:
    """Radii from ``target`` to ``b_1`` (both included). Uniform with ``spacing``, else
    adaptive: each next radius is x + D(x) / ``resolution`` (D = d* capped by max_step),
    i.e. about ``resolution`` grid points per safe step, so the grid is fine where the
    safe steps are short (near b_inf) and coarse where they are ~a. Every grid point is a
    real radius, so a schedule on it is exactly as safe as its arcs. More than
    ``max_nodes`` radii is refused (InvalidInput), as is an adaptive grid from a target
    below the envelope's floor (D = 0 there)."""
    b_1 = float(b_1)
    target = float(target)
    if not (math.isfinite(b_1) and math.isfinite(target) and 0.0 < target < b_1):
        raise InvalidInput("target", "need 0 < target < b_1")
    if spacing is not None:
        h = float(spacing)
        if not (math.isfinite(h) and h > 0.0):
            raise InvalidInput("spacing", "must be a positive length")
        n = int(math.ceil((b_1 - target) / h))
        if n + 1 > max_nodes:
            raise InvalidInput("spacing", f"gives {n + 1} grid radii, more than max_nodes = {max_nodes}")
        grid = target + h * np.arange(n + 1)
        grid[-1] = b_1
        return grid
    if resolution < 1:
        raise InvalidInput("resolution", "must be at least 1")
    out = [target]
    x = target
    while True:
        d = float(envelope.d_star(x, max_step))
        if d <= 0.0:
            raise InvalidInput("target", f"no safe step at radius {x:.9g}: below the table's floor {envelope.b_floor:.9g}")
        x = max(x + d / resolution, float(np.nextafter(x, np.inf)))
        if x >= b_1:
            break
        out.append(x)
        if len(out) + 1 > max_nodes:
            raise InvalidInput(
                "resolution",
                f"the adaptive grid needs more than max_nodes = {max_nodes} radii (the safe steps near the target "
                "are short): lower the resolution, raise the target or max_nodes",
            )
    out.append(b_1)
    return np.asarray(out)


def safe_reach(x: Real, d: Real) -> Real:
    """The largest radius from which a revolution to ``x`` is safe with the safe step ``d``
    (4.26), proof against rounding: y - x <= d holds for every y <= fl(x + d) less one ulp
    (fl is within half an ulp). The schedule graph and the recursion both use it."""
    return np.nextafter(np.asarray(x, dtype=float) + d, -np.inf)


def schedule_graph(envelope: CriticalEnvelope, x: ArrayLike, min_step: float | None = None,
                   max_step: float | None = None) -> ScheduleGraph:
    """The safe-revolution DAG on the radii ``x`` (see :class:`ScheduleGraph`)."""
    x = np.asarray(x, dtype=float)
    if x.ndim != 1 or x.size < 2 or np.any(np.diff(x) <= 0.0):
        raise InvalidInput("grid", "need at least two strictly increasing radii")
    D = np.asarray(envelope.d_star(x, max_step), dtype=float)
    upper = safe_reach(x, D)
    hi = np.searchsorted(x, upper, side="right") - 1
    idx = np.arange(x.size)
    lo = idx + 1
    if min_step is not None:
        m = float(min_step)
        if not (math.isfinite(m) and m >= 0.0):
            raise InvalidInput("min_step", "must be a finite length >= 0")
        # x_i - x_j >= m  <=  x_i >= fl(x_j + m) + 1 ulp
        lower = np.nextafter(x + m, np.inf)
        lo = np.maximum(lo, np.searchsorted(x, lower, side="left"))
    hi = np.where(D > 0.0, hi, -1)
    cnt = np.maximum(hi - lo + 1, 0)
    heads = np.repeat(idx, cnt)
    start = np.repeat(lo - np.cumsum(np.r_[0, cnt[:-1]]), cnt)
    tails = start + np.arange(int(cnt.sum()))
    return ScheduleGraph(x=x, lo=lo, hi=hi, tails=tails.astype(np.int64), heads=heads.astype(np.int64),
                         min_step=None if min_step is None else float(min_step),
                         max_step=None if max_step is None else float(max_step))


def greedy_on_graph(graph: ScheduleGraph) -> np.ndarray | None:
    """Greedy on the grid: from the current node take the smallest reachable radius. Node
    indices from b_1 (last) down to the target (0), or None when it gets stuck (possible
    only with a minimum step). Optimal without a minimum step (module docstring).
    hi[j] and lo[j] are nondecreasing in j (x_j + D(x_j) and x_j + m are), so the smallest
    j with hi[j] >= i is found by bisection, and if its lo[j] > i no larger j serves."""
    i = graph.x.size - 1
    path = [i]
    while i > 0:
        j = int(np.searchsorted(graph.hi, i, side="left"))
        if j >= i or graph.lo[j] > i:
            return None
        i = j
        path.append(i)
    return np.asarray(path)


def arc_costs(graph: ScheduleGraph, objective: str, unit: float, nodes: int = SPIRAL_DEFAULT.arc_nodes) -> np.ndarray:
    """Integer arc costs: 1 per revolution ("revolutions"), or the revolution's length
    (:func:`revolution_length` from x_tail to x_head) in units of ``unit``, rounded
    ("length")."""
    if objective == "revolutions":
        return np.ones(graph.n_arcs, dtype=np.int64)
    if objective == "length":
        out = np.empty(graph.n_arcs, dtype=np.int64)
        chunk = 200_000
        for s in range(0, graph.n_arcs, chunk):
            ls, _ = revolution_length(graph.x[graph.tails[s:s + chunk]], graph.x[graph.heads[s:s + chunk]], nodes)
            out[s:s + chunk] = np.rint(np.asarray(ls) / unit).astype(np.int64)
        return out
    raise InvalidInput("objective", "must be 'revolutions' or 'length'")


def shortest_path_potentials(graph: ScheduleGraph, costs: np.ndarray) -> np.ndarray:
    """Shortest-path distances from b_1 (the last node) to every node over the DAG, in the
    integer costs (exact; -1 = unreachable). Node j's incoming arcs come from a contiguous
    range of larger nodes, so one pass from the top down is exact. They are the dual
    potentials of the shortest-path LP: every arc's reduced cost c_ij + pi_i - pi_j >= 0,
    so pi_target is a lower bound on every schedule's cost (the certificate)."""
    n = graph.x.size
    INF = np.iinfo(np.int64).max // 4
    dist = np.full(n, INF, dtype=np.int64)
    dist[n - 1] = 0
    # arcs grouped by head j, tails ascending: costs for head j lie in one slice
    cnt = np.maximum(graph.hi - graph.lo + 1, 0)
    off = np.r_[0, np.cumsum(cnt)]
    for j in range(n - 2, -1, -1):
        if cnt[j] == 0:
            continue
        d = dist[graph.lo[j]:graph.hi[j] + 1] + costs[off[j]:off[j + 1]]
        dist[j] = min(int(d.min()), INF)
    dist[dist >= INF] = -1
    return dist
