"""The COR locus of a pushed disk with a frictionless pusher (book chapter 3, 3.3.4-3.3.12).

Everything here is first computed in the dimensionless *locus frame*: lengths in units of
the disk radius a, the CM at the origin, x along the symmetry axis alpha' = sign(m) alpha_hat
and y = z x alpha'. The only shape parameter is mu = |alpha . c| / a (3.3.12). A boundary
point is given by its polar distance rho = r/a and the book's relative angle eta (3.24):
its position is rho (-cos eta, sin eta), so eta = 0 points at the tip (epsilon = pi + alpha)
and eta = pi at the r_min end (epsilon = alpha).

The book's boundary has three kinds of pieces (all re-derived and checked numerically in
tests/models/locus/test_cor_disk.py against a direct solution of the membership problem):

* inner: r < a, equation (3.30), from r_min (3.31) at eta = pi out to the disk at
  eta_a (3.32);
* outer: r > a, the diametral dipods of figure 3-12, equations (3.21), (3.34), (3.35),
  from the tip (omega = pi/2) down to the disk;
* perimeter arcs (not in the book): the boundary runs along the disk itself where the outer
  dipod family meets the disk before eta_a. The outer family reaches r = a at finite omega
  with cos(eta) = mu, so this happens for mu >= 1/sqrt(2) (arcs from eta = arccos(mu) to
  eta_a); for mu >= 1 there is no outer piece at all and the farthest COR is on the disk,
  at distance a rather than the book's a^2 / (alpha . c) (3.37), which is then inside it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, Iterable, Sequence

import numpy as np

from models.core.arrays import Real
from models.core.errors import InvalidInput, ModelError
from models.core.scene import PushScene
from models.core.tolerances import DEFAULT, Tolerances

SQRT_HALF = math.sqrt(0.5)

OUTPUTS = ("tip", "tip_line", "r_min", "curvatures", "disk_crossings", "boundary")
"""The parts of a locus a caller can ask for; each is computed only when asked."""


class BoundaryNotConverged(ModelError):
    """The outer-boundary root solve missed its tolerance (a bug or an extreme input)."""


# ---------------------------------------------------------------------------------------
# Closed forms (dimensionless: a = 1, mu = |alpha . c| / a > 0)
# ---------------------------------------------------------------------------------------


def tip_distance_book(mu: Real) -> Real:
    """r_tip / a = a / (alpha . c), equation (3.37): the distance of the tip of the outer
    dipod boundary, the farthest COR when it lies outside the disk (mu < 1)."""
    return 1.0 / np.asarray(mu, dtype=float)


def tip_distance(mu: Real) -> Real:
    """Farthest distance of the COR locus from the CM, / a.

    (3.37) for mu < 1; for mu >= 1 the book's tip a^2/(alpha . c) falls inside the disk and
    the locus reaches the disk itself (perimeter arc through the axis), so the answer is a.
    """
    return 1.0 / np.minimum(np.asarray(mu, dtype=float), 1.0)


def tip_radius_of_curvature(mu: Real) -> Real:
    """Radius of curvature of the boundary at the tip, / a.

    The book prints (3.38) as s = r_tip / (1/2 + r_tip^4 / a^4), which the OCR may have
    garbled; the boundary computed from (3.21)/(3.35) has s = a^4 / (2 r_tip^3) =
    (alpha . c)^3 / (2 a^2) (checked by finite differences in the tests). For mu >= 1 the
    tip lies on a perimeter arc of radius a.
    """
    mu = np.asarray(mu, dtype=float)
    return np.where(mu < 1.0, 0.5 * np.minimum(mu, 1.0) ** 3, 1.0)


def tip_radius_of_curvature_book_printed(mu: Real) -> Real:
    """(3.38) exactly as printed in the book's text, for comparison: r_tip/(1/2 + r_tip^4)."""
    rt = tip_distance_book(mu)
    return rt / (0.5 + rt**4)


def r_min(mu: Real) -> Real:
    """r_min / a = (alpha . c) / (2a + alpha . c), equation (3.31): the boundary's nearest
    point to the CM, on the axis at epsilon = alpha (eta = pi)."""
    mu = np.asarray(mu, dtype=float)
    return mu / (2.0 + mu)


def r_min_radius_of_curvature(mu: Real) -> Real:
    """Radius of curvature of the boundary at r_min, / a, equation (3.33)."""
    mu = np.asarray(mu, dtype=float)
    return mu * (mu + 2.0) ** 2 / (mu**3 + 4.0 * mu**2 + 8.0 * mu + 4.0)


def disk_crossing_cos_eta(mu: Real) -> Real:
    """cos(eta) where the inner boundary (3.30) meets the disk, equation (3.32):
    ((alpha . c)^2 + 4a^2)^(1/2) - alpha . c) / 2a, written without cancellation."""
    mu = np.asarray(mu, dtype=float)
    return 2.0 / (np.sqrt(mu * mu + 4.0) + mu)


def inner_boundary_cos_eta(rho: Real, mu: Real) -> Real:
    """cos(eta) of the inner boundary at distance rho = r/a < 1, equation (3.30).

    (3.30): cos eta = (r ((r+a)^2 + (alpha.c)^2)^(1/2) - a alpha.c) / (r (r + a)),
    rewritten as [rho^2 (rho+1) + mu^2 (rho-1)] / [rho (rho X^(1/2) + mu)],
    X = (rho+1)^2 + mu^2, to avoid the cancellation of the printed form when mu >> 1.
    """
    rho = np.asarray(rho, dtype=float)
    mu = np.asarray(mu, dtype=float)
    x = (rho + 1.0) ** 2 + mu * mu
    return (rho * rho * (rho + 1.0) + mu * mu * (rho - 1.0)) / (rho * (rho * np.sqrt(x) + mu))


def inner_boundary_residual(rho: Real, eta: Real, mu: Real) -> Real:
    """Residual of (3.26)/(3.28) at (rho, eta): how far the required quotient moment
    q = r^2 / (alpha . (c - r)) alpha (3.23) is from the circle of radius b (3.20) about
    -(r - b) r_hat (3.19), relative to b. Zero on the inner boundary, < 0 inside."""
    rho = np.asarray(rho, dtype=float)
    b = rho / (rho + 1.0)
    s = mu + rho * np.cos(eta)
    q = rho * rho / s
    lhs = (q - (rho - b) * np.cos(eta)) ** 2 + ((rho - b) * np.sin(eta)) ** 2
    return (np.sqrt(lhs) - b) / b


def dipod_quotient(rho: Real, omega: Real) -> tuple[np.ndarray, np.ndarray]:
    """Moments of the diametral dipod of figure 3-12 at a COR distance rho > 1, (3.21).

    Returns (mu, eta): the moment arm alpha . c / a that makes this dipod's quotient
    moment satisfy (3.35), and its direction eta (3.34). From (3.23) with q = r^2 v/d:
    alpha . c = d/|v| - r cos(eta) = (d - r v_y) / |v|.

    The printed (3.21) loses every digit when r >> a (d - r v_y is a difference of nearly
    equal numbers); the algebra below is exact and cancellation-free:
    d - r v_y = 2 rho^2 sin^2(omega) (Q + D) / ((D + rho^2 - 1) S D),
    v_x = -2 rho sin(omega) cos(omega) / (D S), with d_+- from (3.21), D = d+ d-,
    S = d+ + d-, Q = rho^2 + 1.
    """
    rho = np.asarray(rho, dtype=float)
    sa = np.sin(omega)
    ca = np.cos(omega)
    mu, vx, vy = _dipod_terms(rho, sa, ca)
    eta = np.arctan2(-vx, vy)
    return mu, eta


def _dipod_terms(rho: np.ndarray, sa: Real, ca: Real) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(mu, v_x, v_y) of :func:`dipod_quotient` from sin and cos of omega."""
    dp = np.hypot(rho + ca, sa)
    dm = np.hypot(rho - ca, sa)
    big_d = dp * dm
    big_s = dp + dm
    q = rho * rho + 1.0
    vx = -2.0 * rho * sa * ca / (big_d * big_s)
    vy = 0.5 * ((rho + ca) / dp + (rho - ca) / dm)
    num = 2.0 * rho * rho * sa * sa * (q + big_d) / ((big_d + rho * rho - 1.0) * big_s * big_d)
    return num / np.hypot(vx, vy), vx, vy


def dipod_quotient_printed(rho: Real, omega: Real) -> tuple[np.ndarray, np.ndarray]:
    """(3.21), (3.34), (3.35) evaluated exactly as printed (an independent check of
    :func:`dipod_quotient`; accurate only for moderate rho)."""
    rho = np.asarray(rho, dtype=float)
    d_plus = np.sqrt(rho**2 + 1.0 + 2.0 * rho * np.cos(omega))
    d_minus = np.sqrt(rho**2 + 1.0 - 2.0 * rho * np.cos(omega))
    sg_p = np.sin(omega) / d_plus
    sg_m = np.sin(omega) / d_minus
    cg_p = np.sqrt(1.0 - sg_p**2)
    cg_m = np.sqrt(1.0 - sg_m**2)
    vx = 0.5 * (sg_p - sg_m)
    vy = 0.5 * (cg_p + cg_m)
    d = 0.5 * (d_plus + d_minus)
    q = rho**2 * np.hypot(vx, vy) / d
    eta = np.arctan(-vx / vy)
    mu = rho**2 / q - rho * np.cos(eta)  # (3.35) solved for alpha . c / a
    return mu, eta


def outer_corner_omega(mu: float) -> float:
    """Smallest dipod angle omega of the outer boundary, where it meets the disk.

    On the disk (rho = 1) the dipod moment arm is cos(omega/2 - pi/4) >= 1/sqrt(2), so for
    mu >= 1/sqrt(2) the family reaches the disk at omega_c = pi/2 - 2 arccos(mu), with
    eta_c = arccos(mu); for mu < 1/sqrt(2) it runs into the singular corner omega -> 0,
    rho -> 1, where it joins the inner boundary at eta_a (3.32).
    """
    if mu < SQRT_HALF:
        return 0.0
    return 0.5 * math.pi - 2.0 * math.acos(min(mu, 1.0))


def outer_boundary(omega: np.ndarray, mu: float | np.ndarray, tol: Tolerances = DEFAULT) -> tuple[np.ndarray, np.ndarray, int]:
    """Solve (3.35) for rho at each dipod angle omega (vectorised, no Python loop per point;
    ``mu`` one value or one per point, so the boundaries of many loci are solved at once).

    For fixed omega the dipod moment arm decreases from >= mu at rho = 1 to <= mu at
    rho = r_tip (3.37), so the root is bracketed in x = log(rho) in [0, log(1/mu)]. A
    bracketing Illinois (modified regula falsi) iteration on g(x) = log(mu(x)/mu) runs on
    all points at once. Returns (rho, eta, iterations).
    """
    omega = np.asarray(omega, dtype=float)
    sa, ca = np.sin(omega), np.cos(omega)
    mus = np.broadcast_to(np.asarray(mu, dtype=float), omega.shape)

    def g(x: np.ndarray, k: np.ndarray | slice) -> np.ndarray:
        # log(mu(x)/mu) of dipod_quotient (same operations, without eta, on the points k)
        return np.log(_dipod_terms(np.exp(x), sa[k], ca[k])[0] / mus[k])

    x_lo = np.zeros_like(omega)
    x_hi = np.log(1.0 / mus)
    # rho = 1 is singular only at omega = 0, which callers exclude.
    g_lo = g(x_lo, slice(None))
    g_hi = g(x_hi, slice(None))
    done = g_hi >= 0.0  # the tip itself (omega = pi/2): root at the upper end
    x = np.where(done, x_hi, 0.5 * (x_lo + x_hi))
    side = np.zeros_like(omega)
    active = np.flatnonzero(~done)
    it = 0
    for it in range(1, tol.root_max_iter + 1):
        if active.size == 0:
            break
        # Illinois (modified regula falsi) on the points not yet converged; elementwise
        # the same steps as on the whole array
        xl, xh, gl, gh, sd = x_lo[active], x_hi[active], g_lo[active], g_hi[active], side[active]
        denom = gh - gl
        x_new = np.where(denom != 0.0, xh - gh * (xh - xl) / np.where(denom != 0.0, denom, 1.0), 0.5 * (xl + xh))
        bad = ~((x_new > xl) & (x_new < xh))
        x_new = np.where(bad, 0.5 * (xl + xh), x_new)
        g_new = g(x_new, active)
        upper = g_new < 0.0  # root lies below x_new
        # halve the retained end's value when the same end is kept twice
        gl = np.where(upper & (sd == -1), 0.5 * gl, gl)
        gh = np.where(~upper & (sd == 1), 0.5 * gh, gh)
        x_hi[active] = np.where(upper, x_new, xh)
        g_hi[active] = np.where(upper, g_new, gh)
        x_lo[active] = np.where(upper, xl, x_new)
        g_lo[active] = np.where(upper, gl, g_new)
        side[active] = np.where(upper, -1.0, 1.0)
        x[active] = x_new
        conv = (np.abs(g_new) <= tol.root_rtol) | (x_hi[active] - x_lo[active] <= tol.root_rtol * np.maximum(1.0, np.abs(x_new)))
        done[active] = conv
        active = active[~conv]
    if not np.all(done):
        raise BoundaryNotConverged(
            f"outer COR boundary (3.35) did not converge in {tol.root_max_iter} iterations "
            f"for mu = {mus[~done][0]!r}"
        )
    rho = np.exp(x)
    _, eta = dipod_quotient(rho, omega)
    return rho, eta, it


def outer_boundary_residual(rho: Real, eta: Real, omega: Real, mu: Real) -> Real:
    """Relative residual of (3.35), r^2 = |q_r| (alpha . c + r cos eta), at solved points."""
    m, e = dipod_quotient(rho, omega)
    return np.maximum(np.abs(m - mu) / mu, np.abs(e - eta))


# ---------------------------------------------------------------------------------------
# The whole boundary
# ---------------------------------------------------------------------------------------


def polar_to_local(rho: Real, eta: Real) -> np.ndarray:
    """Locus-frame point(s) (..., 2) at distance rho and relative angle eta (3.24):
    rho (-cos eta, sin eta)."""
    rho = np.asarray(rho, dtype=float)
    eta = np.asarray(eta, dtype=float)
    return np.stack([-rho * np.cos(eta), rho * np.sin(eta)], axis=-1)


@dataclass(frozen=True)
class PolarBoundary:
    """One half of the boundary (eta from 0 to pi), in the dimensionless locus frame.

    ``piece`` labels each point: 0 outer (3.21)/(3.35), 1 perimeter arc, 2 inner (3.30).
    ``residual`` is the largest relative residual of the boundary equations.
    """

    rho: np.ndarray
    eta: np.ndarray
    piece: np.ndarray
    residual: float
    iterations: int


def _allocate(lengths: list[float], total: int, minimum: int) -> list[int]:
    """Split ``total`` points among pieces by length, at least ``minimum`` for each."""
    present = [ell > 0.0 for ell in lengths]
    counts = [minimum if p else 0 for p in present]
    spare = total - sum(counts)
    length_sum = sum(ell for ell in lengths if ell > 0.0)
    if spare > 0 and length_sum > 0.0:
        shares = [spare * ell / length_sum if ell > 0.0 else 0.0 for ell in lengths]
        extra = [int(math.floor(s)) for s in shares]
        remainder = spare - sum(extra)
        order = sorted(range(len(lengths)), key=lambda i: shares[i] - extra[i], reverse=True)
        for i in order[:remainder]:
            extra[i] += 1
        counts = [c + e for c, e in zip(counts, extra)]
    return counts


@dataclass(frozen=True)
class _HalfPlan:
    """The pieces of one half boundary (half_boundary): their ends and point counts."""

    mu: float
    rho_min: float
    eta_a: float
    eta_c: float
    rho_tip: float
    omega_c: float
    has_outer: bool
    n_outer: int
    n_arc: int
    n_inner: int
    length_arc: float

    @classmethod
    def of(cls, mu: float, n_half: int) -> _HalfPlan:
        rho_min = float(r_min(mu))
        cos_a = float(disk_crossing_cos_eta(mu))
        eta_a = math.acos(min(1.0, cos_a))
        has_outer = mu < 1.0
        omega_c = outer_corner_omega(mu) if has_outer else 0.0
        if not has_outer:
            eta_c = 0.0
        elif mu >= SQRT_HALF:
            eta_c = math.acos(mu)
        else:
            eta_c = eta_a
        rho_tip = float(tip_distance(mu))

        cart = polar_to_local
        corner = cart(1.0, eta_c)
        length_outer = float(np.linalg.norm(cart(rho_tip, 0.0) - corner)) if has_outer else 0.0
        length_arc = max(0.0, eta_a - eta_c)
        mid = 0.5 * (1.0 + rho_min)
        mid_pt = cart(mid, math.acos(np.clip(inner_boundary_cos_eta(mid, mu), -1.0, 1.0)))
        length_inner = float(np.linalg.norm(cart(1.0, eta_a) - mid_pt) + np.linalg.norm(mid_pt - cart(rho_min, math.pi)))
        # Pieces share their end points, so each joint adds one to the points to allocate.
        lengths = [length_outer, length_arc, length_inner]
        joints = sum(ell > 0.0 for ell in lengths) - 1
        n_outer, n_arc, n_inner = _allocate(lengths, n_half + joints, 2)
        return cls(mu, rho_min, eta_a, eta_c, rho_tip, omega_c, has_outer, n_outer, n_arc, n_inner, length_arc)

    def outer_omegas(self) -> np.ndarray:
        """The outer piece's interior dipod angles: omega evenly spaced from pi/2 (tip) down
        to the corner, without its ends."""
        t = np.linspace(0.0, 1.0, self.n_outer)
        return (self.omega_c + (0.5 * math.pi - self.omega_c) * (1.0 - t))[1:-1]


def half_boundary(mu: float, n_half: int, tol: Tolerances = DEFAULT) -> PolarBoundary:
    """Points of the boundary from the tip (eta = 0) to r_min (eta = pi), in order.

    ``n_half`` counts both ends. Pieces present depend on mu (module docstring).
    """
    return half_boundaries([mu], n_half, tol)[0]


def half_boundaries(mus: Sequence[float], n_half: int, tol: Tolerances = DEFAULT) -> list[PolarBoundary]:
    """:func:`half_boundary` of each mu, the outer pieces (3.35) of all of them solved at once
    (the same iteration on each point; ``iterations`` is the batch's)."""
    plans = [_HalfPlan.of(float(mu), n_half) for mu in mus]
    omegas = [p.outer_omegas() if p.has_outer else np.empty(0) for p in plans]
    flat_omega = np.concatenate(omegas) if omegas else np.empty(0)
    flat_mu = np.repeat([p.mu for p in plans], [o.size for o in omegas])
    iterations = 0
    flat_rho = flat_eta = flat_res = np.empty(0)
    if flat_omega.size:
        flat_rho, flat_eta, iterations = outer_boundary(flat_omega, flat_mu, tol)
        flat_res = np.asarray(outer_boundary_residual(flat_rho, flat_eta, flat_omega, flat_mu))
    out = []
    start = 0
    for plan, omega in zip(plans, omegas):
        stop = start + omega.size
        out.append(_assemble_half(plan, flat_rho[start:stop], flat_eta[start:stop], flat_res[start:stop], iterations))
        start = stop
    return out


def _assemble_half(plan: _HalfPlan, rho_i: np.ndarray, eta_i: np.ndarray, outer_res: np.ndarray,
                   iterations: int) -> PolarBoundary:
    """One half boundary from its plan and its solved outer interior points."""
    mu = plan.mu
    rhos, etas, pieces = [], [], []
    residual = 0.0
    if plan.has_outer:
        residual = max(residual, float(np.max(outer_res, initial=0.0)))
        rhos += [np.array([plan.rho_tip]), rho_i, np.array([1.0])]
        etas += [np.array([0.0]), eta_i, np.array([plan.eta_c])]
        pieces.append(np.zeros(plan.n_outer, dtype=int))
    else:
        iterations = 0
    if plan.length_arc > 0.0:
        eta_arc = np.linspace(plan.eta_c, plan.eta_a, plan.n_arc)
        if plan.has_outer:
            eta_arc = eta_arc[1:]  # the corner is already the outer piece's last point
        rhos.append(np.ones_like(eta_arc))
        etas.append(eta_arc)
        pieces.append(np.ones(eta_arc.size, dtype=int))
    # Inner piece: rho = rho_min + (1 - rho_min) t^2 resolves the square-root behaviour of
    # eta(rho) at r_min.
    t = np.linspace(1.0, 0.0, plan.n_inner)
    rho_in = plan.rho_min + (1.0 - plan.rho_min) * t * t
    cos_in = np.clip(inner_boundary_cos_eta(rho_in, mu), -1.0, 1.0)
    eta_in = np.arccos(cos_in)
    eta_in[0] = plan.eta_a
    eta_in[-1] = math.pi
    rho_in = rho_in[1:]  # (1, eta_a) closes the arc or the outer piece
    eta_in = eta_in[1:]
    inner_res = inner_boundary_residual(rho_in[:-1], eta_in[:-1], mu)
    residual = max(residual, float(np.max(np.abs(inner_res), initial=0.0)))
    rhos.append(rho_in)
    etas.append(eta_in)
    pieces.append(np.full(rho_in.size, 2, dtype=int))
    return PolarBoundary(
        rho=np.concatenate(rhos),
        eta=np.concatenate(etas),
        piece=np.concatenate(pieces),
        residual=residual,
        iterations=iterations,
    )


def boundary_local(mu: float, n_points: int, tol: Tolerances = DEFAULT) -> tuple[np.ndarray, float, int]:
    """Closed boundary polygon (n_points, 2), counter-clockwise, in the dimensionless
    locus frame, starting at the tip. The boundary is mirror symmetric, so an odd
    ``n_points`` is rounded up to the next even number. Returns (points, residual,
    iterations)."""
    return boundary_locals([mu], n_points, tol)[0]


def boundary_locals(mus: Sequence[float], n_points: int, tol: Tolerances = DEFAULT) -> list[tuple[np.ndarray, float, int]]:
    """:func:`boundary_local` of each mu, solved together (:func:`half_boundaries`)."""
    n_half = (n_points + 1) // 2 + 1
    out = []
    for half in half_boundaries(mus, n_half, tol):
        # The half runs tip -> r_min through y > 0 (clockwise); its mirror image closes it.
        upper = polar_to_local(half.rho, half.eta)
        lower = upper[-2:0:-1] * np.array([1.0, -1.0])
        ring = np.vstack([upper, lower])[::-1]
        ring = np.roll(ring, 1, axis=0)  # start at the tip again
        out.append((ring, half.residual, half.iterations))
    return out


# ---------------------------------------------------------------------------------------
# World-frame result
# ---------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Tip:
    """The farthest point of the locus on its axis (3.37; see :func:`tip_distance`)."""

    point: np.ndarray
    distance: float
    distance_book: float  # a^2 / |alpha . c|, (3.37) as printed
    on_disk: bool  # True when |alpha . c| >= a: the tip is on the disk, not at (3.37)


@dataclass(frozen=True)
class TipLine:
    """Locus of tips as the edge angle varies (3.3.11.1): perpendicular to c, at distance
    a^2/|c| from the CM on the side away from the contact."""

    point: np.ndarray
    direction: np.ndarray
    distance: float


@dataclass(frozen=True)
class RMin:
    point: np.ndarray
    distance: float  # (3.31)


@dataclass(frozen=True)
class Curvatures:
    tip_radius: float  # corrected (3.38); a when the tip is on the disk
    tip_radius_book_printed: float  # (3.38) as printed
    r_min_radius: float  # (3.33)


@dataclass(frozen=True)
class PerimeterArc:
    """A stretch where the boundary runs along the disk, CCW from start to end (world)."""

    start_angle: float
    end_angle: float
    start: np.ndarray
    end: np.ndarray


@dataclass(frozen=True)
class DiskCrossings:
    """Where the boundary meets the disk perimeter.

    ``points``: the two ends of the inner boundary (3.30) on the disk, at eta_a (3.32).
    ``arcs``: perimeter stretches that belong to the boundary (empty for mu < 1/sqrt 2).
    """

    cos_eta: float  # (3.32)
    points: np.ndarray
    arcs: tuple[PerimeterArc, ...]


@dataclass(frozen=True)
class DiskCorLocus:
    """The COR locus of a frictionless push on a disk-bounded workpiece, world frame.

    ``kind`` is "bounded", or "translation" when the line of force passes through the CM:
    then the only COR is at infinity (pure translation along ``translation_direction``)
    and no tip, r_min or boundary exists. Parts not asked for are None.
    """

    kind: str
    sense: str
    moment_arm: float  # |alpha . c|
    relative_moment_arm: float  # |alpha . c| / a
    book_alpha: float
    axis: np.ndarray  # unit vector from the CM towards the tip
    translation_direction: np.ndarray  # unit direction of a pure translation, = normal
    tip: Tip | None
    tip_line: TipLine | None
    r_min: RMin | None
    curvatures: Curvatures | None
    disk_crossings: DiskCrossings | None
    boundary: np.ndarray | None
    boundary_residual: float | None
    boundary_iterations: int | None


def _check_outputs(outputs: Iterable[str]) -> frozenset[str]:
    chosen = frozenset(outputs)
    unknown = chosen - set(OUTPUTS)
    if unknown:
        raise InvalidInput("outputs", f"unknown output(s) {sorted(unknown)}; choose from {list(OUTPUTS)}")
    return chosen


def _disk_crossings(scene: PushScene) -> DiskCrossings:
    """Where the boundary crosses the disk (3.32) and the perimeter arcs between them
    (for mu >= 1/sqrt 2 the outer dipods reach the disk before eta_a)."""
    a, mu, cm = scene.disk_radius, scene.relative_moment_arm, scene.center_of_mass
    cos_a = float(disk_crossing_cos_eta(mu))
    eta_a = math.acos(min(1.0, cos_a))

    def on_disk(eta: float) -> np.ndarray:
        return scene.to_world(a * polar_to_local(1.0, eta))

    def world_angle(eta: float) -> float:
        v = on_disk(eta) - cm
        return math.atan2(v[1], v[0])

    arcs: list[PerimeterArc] = []
    # A boundary point at eta sits at polar angle pi - eta in the locus frame, so
    # growing eta runs clockwise on the y > 0 side and counter-clockwise on its mirror.
    if mu >= 1.0:
        arcs.append(PerimeterArc(world_angle(eta_a), world_angle(-eta_a), on_disk(eta_a), on_disk(-eta_a)))
    elif mu >= SQRT_HALF:
        eta_c = math.acos(mu)
        arcs.append(PerimeterArc(world_angle(eta_a), world_angle(eta_c), on_disk(eta_a), on_disk(eta_c)))
        arcs.append(PerimeterArc(world_angle(-eta_c), world_angle(-eta_a), on_disk(-eta_c), on_disk(-eta_a)))
    return DiskCrossings(cos_eta=cos_a, points=np.vstack([on_disk(eta_a), on_disk(-eta_a)]), arcs=tuple(arcs))


Boundaries = Callable[[Sequence[PushScene], int], list[np.ndarray]]
""":func:`disk_boundaries`'s question, for callers that take it as a parameter (the fence
maps): the solver passes its compiled twin (solver/locus/disk_rings.py), the same points to
rounding."""


def disk_boundaries(scenes: Sequence[PushScene], n_points: int = 256, tol: Tolerances | None = None) -> list[np.ndarray]:
    """The world-frame boundary of each bounded scene's disk locus, as
    ``disk_cor_locus(scene, outputs=["boundary"], n_points).boundary``, with the boundaries
    of all of them solved at once (:func:`boundary_locals`)."""
    if n_points < 8:
        raise InvalidInput("n_points", "must be at least 8")
    if any(s.is_translation for s in scenes):
        raise InvalidInput("scenes", "a translation has no bounded locus")
    tol = tol or (scenes[0].tolerances if scenes else DEFAULT)
    out = []
    for scene, (local, residual, _) in zip(scenes, boundary_locals([s.relative_moment_arm for s in scenes],
                                                                   n_points, tol)):
        out.append(_world_boundary(scene, local, residual, tol))
    return out


def _world_boundary(scene: PushScene, local: np.ndarray, residual: float, tol: Tolerances) -> np.ndarray:
    """The locus-frame boundary ``local`` in the world of ``scene``, once its residual is
    within tolerance (BoundaryNotConverged otherwise)."""
    if not residual <= tol.boundary_residual_rel:  # NaN fails too
        raise BoundaryNotConverged(f"boundary residual {residual:.3g} exceeds {tol.boundary_residual_rel:.3g}")
    return scene.to_world(local * scene.disk_radius)


def disk_cor_locus(
    scene: PushScene,
    outputs: Iterable[str] = OUTPUTS,
    n_points: int = 256,
    tol: Tolerances | None = None,
) -> DiskCorLocus:
    """COR locus for all pressure distributions on the disk of ``scene`` (chapter 3).

    Only the parts named in ``outputs`` are computed (the boundary is the only costly one).
    """
    tol = tol or scene.tolerances
    wanted = _check_outputs(outputs)
    if n_points < 8:
        raise InvalidInput("n_points", "must be at least 8")
    a = scene.disk_radius
    mu = scene.relative_moment_arm
    e1 = scene.axis
    cm = scene.center_of_mass

    tip_line = None
    c_norm = float(np.linalg.norm(scene.contact_rel))
    if "tip_line" in wanted and c_norm > tol.translation_rel * a:
        c_hat = scene.contact_rel / c_norm
        tip_line = TipLine(
            point=cm - (a * a / c_norm) * c_hat,
            direction=np.array([-c_hat[1], c_hat[0]]),
            distance=a * a / c_norm,
        )

    common: dict[str, Any] = dict(
        sense=scene.sense,
        moment_arm=abs(scene.moment_arm),
        relative_moment_arm=mu,
        book_alpha=scene.book_alpha,
        axis=-e1,
        translation_direction=scene.normal.copy(),
        tip_line=tip_line,
    )
    if scene.is_translation:
        return DiskCorLocus(
            kind="translation", tip=None, r_min=None, curvatures=None, disk_crossings=None,
            boundary=None, boundary_residual=None, boundary_iterations=None, **common,
        )

    tip = None
    if "tip" in wanted:
        dist = float(tip_distance(mu)) * a
        tip = Tip(
            point=cm - dist * e1,
            distance=dist,
            distance_book=float(tip_distance_book(mu)) * a,
            on_disk=mu >= 1.0,
        )
    rmin = None
    if "r_min" in wanted:
        d = float(r_min(mu)) * a
        rmin = RMin(point=cm + d * e1, distance=d)
    curv = None
    if "curvatures" in wanted:
        curv = Curvatures(
            tip_radius=float(tip_radius_of_curvature(mu)) * a,
            tip_radius_book_printed=float(tip_radius_of_curvature_book_printed(mu)) * a,
            r_min_radius=float(r_min_radius_of_curvature(mu)) * a,
        )
    crossings = _disk_crossings(scene) if "disk_crossings" in wanted else None
    boundary = residual = iterations = None
    if "boundary" in wanted:
        local, residual, iterations = boundary_local(mu, n_points, tol)
        boundary = _world_boundary(scene, local, residual, tol)
    return DiskCorLocus(
        kind="bounded", tip=tip, r_min=rmin, curvatures=curv, disk_crossings=crossings,
        boundary=boundary, boundary_residual=residual, boundary_iterations=iterations, **common,
    )
