"""Spiral localization of a disk (book 4.5): the recursion (4.26) over a safe envelope
(:mod:`models.spiral.critical`), the pusher path and the power-law fit of figure 4-21.

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
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from models.core.arrays import Real
from models.core.errors import InvalidInput
from models.core.tolerances import SPIRAL_DEFAULT, SpiralTolerances
from models.spiral.critical import CriticalEnvelope, checked_disk_radius, collision_parameter, tip_line_next_radius

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
    a = checked_disk_radius(a)
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
    a = checked_disk_radius(a)
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
