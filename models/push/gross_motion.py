"""Closed forms of gross motions of pushed parts (book 3.4, 4.2-4.4) and integrators of
their equations of motion.

Book 4.2: to bound a gross motion x while a parameter beta runs from beta_initial to
beta_final, write an *equation of motion* dx = g(r, beta) dbeta for a COR r, pick in every
COR sketch the COR that makes dx/dbeta largest (or smallest) and integrate. This module
holds the closed forms the book derives that way, each re-derived (the OCR garbles
several, and some look wrong in the book itself; every finding is in the docstring of its
function and pinned by tests/models/push/test_gross_motion.py), and a small adaptive
Gauss-Kronrod quadrature (numpy only) that integrates the same equations of motion for
any COR callback.

Summary of the findings: (4.6) as printed is not the integral of (4.5) (it needs
alpha_hat . c, not (alpha +- nu)_hat . c, and a factor cos nu on the log); (4.3)'s side
rule is reversed in the text; the 4.3 example's slipping stretch uses the '+' tip, not
the printed '-'; (4.15) is 2a dbeta / sin beta; (4.18) is pi/2 - beta_initial; (4.19)
holds only for sticking, and the rotation rate is -a cos beta / x_COR, not (4.22). The
tip-line approximations are not upper bounds: tests/solver/push/test_simulate.py finds
supports whose CORs dip below the tip line and exceed (4.16) and the composite bound of
4.3 by 1-3 % when mu_c is large.

Frames (the book's, figures 3-20, 4-7 and 4-11; all angles in radians):

* **Fence frame** (3.4, 4.3): origin at the centre of mass (CM), the fence moves along +x,
  y up. The fence face has the book's edge angle alpha in (0, pi): its direction is
  alpha_hat = (cos alpha, sin alpha) and the workpiece lies on the side of the inward normal
  n = (sin alpha, -cos alpha) (n . x_hat = sin alpha > 0, as in ``models.core.scene``). The
  contact vertex is at c = c (-cos beta, sin beta) from the CM: beta is the angle between
  the line of motion and the line from the contact to the CM, which runs down and to the
  right at angle -beta. The workpiece turns clockwise and beta grows by the angle it turns
  (4.3). The moment arm alpha_hat . c = -c cos(alpha + beta) is positive exactly when
  alpha + beta > pi/2 (clockwise with mu_c = 0). The sticking line is the vertical
  x = -c cos beta through the contact.
* **Disk-encounter frame** (4.4): origin at the CM of the pushed disk (radius a), the
  pusher point moves along +x on the line y = a sin beta, so it touches the disk at
  c = a (-cos beta, sin beta): the same frame as the fence with c = a and the edge (the
  disk's tangent) at alpha = pi/2 - beta, so alpha_hat . c = 0 (the line of force of a
  frictionless push passes through the CM). The disk is pushed down and to the right;
  beta runs from beta_initial up to pi/2, where the disk is left tangent to the path.

A COR callback ``cor_of_beta(beta) -> (x_COR, y_COR)`` returns the COR in the frame of its
problem, relative to the CM.

The tip approximations the book makes (the tip of {COR}_phi instead of the exact slowest
point of that locus; the intersection of the tip line with the sticking line instead of
the exact lower end of the sticking locus) are kept here as the book states them; the
integrators take a callback so that exact slowest/fastest CORs can replace them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np
from numpy.typing import ArrayLike

from models.core.arrays import Real
from models.core.errors import InvalidInput

HALF_PI = 0.5 * math.pi

# ---------------------------------------------------------------------------------------
# Adaptive Gauss-Kronrod quadrature (G7/K15, QUADPACK's qk15 nodes), numpy only
# ---------------------------------------------------------------------------------------

_XGK = np.array([
    0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
    0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
    0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
    0.207784955007898467600689403773245, 0.0,
])
_WGK = np.array([
    0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
    0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
    0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
    0.204432940075298892414161999234649, 0.209482141084727828012999174891714,
])
_WG = np.array([
    0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
    0.381830050505118944950369775488975, 0.417959183673469387755102040816327,
])
# 15 nodes on [-1, 1], and the weights of both rules on them (Gauss: every other node).
KRONROD_NODES = np.concatenate([-_XGK[:-1], _XGK[::-1]])
KRONROD_WEIGHTS = np.concatenate([_WGK[:-1], _WGK[::-1]])
GAUSS_WEIGHTS_ON_KRONROD = np.zeros(15)
GAUSS_WEIGHTS_ON_KRONROD[1:7:2] = _WG[:3]
GAUSS_WEIGHTS_ON_KRONROD[7] = _WG[3]
GAUSS_WEIGHTS_ON_KRONROD[9:15:2] = _WG[2::-1]


@dataclass(frozen=True)
class QuadResult:
    """An integral with its error estimate: ``error`` is the sum over the final
    sub-intervals of |K15 - G7| (pessimistic for smooth integrands, where K15 is far more
    accurate than G7). ``converged`` is False when ``max_intervals`` ran out first."""

    value: float
    error: float
    evaluations: int
    intervals: int
    converged: bool


CorOfBeta = Callable[[Any], ArrayLike]
"""A COR callback r(beta) = (x, y): of one float, or (vectorised) of an array of betas
giving (n, 2)."""

RateOfCor = Callable[[np.ndarray, np.ndarray, np.ndarray, float], Real]
"""rate(beta, x_COR, y_COR, a) over arrays."""


def _kronrod(f: Callable[[np.ndarray], ArrayLike], lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """K15 and G7 on many intervals at once; ``f`` takes an array of points."""
    mid = 0.5 * (lo + hi)
    half = 0.5 * (hi - lo)
    x = mid[:, None] + half[:, None] * KRONROD_NODES[None, :]
    y = np.asarray(f(x.reshape(-1)), dtype=float).reshape(x.shape)
    if not np.all(np.isfinite(y)):
        raise InvalidInput("cor_of_beta", "the integrand is not finite on the interval")
    k = half * (y @ KRONROD_WEIGHTS)
    g = half * (y @ GAUSS_WEIGHTS_ON_KRONROD)
    return k, np.abs(k - g)


def adaptive_quadrature(
    f: Callable[..., Real],
    lo: float,
    hi: float,
    rtol: float = 1e-10,
    atol: float = 1e-13,
    max_intervals: int = 4000,
    vectorized: bool = True,
) -> QuadResult:
    """Integral of ``f`` over [lo, hi] by globally adaptive G7/K15 quadrature.

    The interval with the largest error estimate is bisected (in batches: every interval
    whose error exceeds its share of the tolerance) until the summed estimate is at most
    max(atol, rtol |I|). ``f`` must accept a numpy array of points unless ``vectorized`` is
    False, when it is called once per point. Endpoints are never evaluated, so integrable
    end-point singularities are handled (slowly). Non-finite values raise InvalidInput.
    """
    lo, hi = float(lo), float(hi)
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise InvalidInput("beta", "integration limits must be finite")
    if lo == hi:
        return QuadResult(0.0, 0.0, 0, 0, True)
    sign = 1.0
    if hi < lo:
        lo, hi, sign = hi, lo, -1.0
    func = f if vectorized else (lambda xs: np.array([float(f(float(t))) for t in xs]))
    a_ = np.array([lo])
    b_ = np.array([hi])
    vals, errs = _kronrod(func, a_, b_)
    evals = 15
    converged = False
    while True:
        if not (np.all(np.isfinite(vals)) and np.all(np.isfinite(errs))):
            raise InvalidInput("cor_of_beta", "the integrand is not finite on the interval")
        total = float(vals.sum())
        err = float(errs.sum())
        if err <= max(atol, rtol * abs(total)):
            converged = True
            break
        if a_.size >= max_intervals:
            break
        budget = max(atol, rtol * abs(total))
        # Bisect the intervals whose error exceeds their length share of the budget, and at
        # least the worst one.
        share = budget * (b_ - a_) / (hi - lo)
        split = errs > share
        split[int(np.argmax(errs))] = True
        room = max_intervals - a_.size
        idx = np.nonzero(split)[0]
        if idx.size > room:
            idx = idx[np.argsort(errs[idx])[::-1][:room]]
            split = np.zeros_like(split)
            split[idx] = True
        m = 0.5 * (a_[split] + b_[split])
        new_a = np.concatenate([a_[split], m])
        new_b = np.concatenate([m, b_[split]])
        nv, ne = _kronrod(func, new_a, new_b)
        evals += 15 * new_a.size
        keep = ~split
        a_ = np.concatenate([a_[keep], new_a])
        b_ = np.concatenate([b_[keep], new_b])
        vals = np.concatenate([vals[keep], nv])
        errs = np.concatenate([errs[keep], ne])
    return QuadResult(sign * total, err, evals, int(a_.size), converged)


# ---------------------------------------------------------------------------------------
# Input checks
# ---------------------------------------------------------------------------------------


def _positive(name: str, value: float) -> float:
    v = float(value)
    if not (math.isfinite(v) and v > 0.0):
        raise InvalidInput(name, "must be a positive finite number")
    return v


def _angle(name: str, value: float, lo: float, hi: float) -> float:
    v = float(value)
    if not (math.isfinite(v) and lo < v < hi):
        raise InvalidInput(name, f"must lie strictly between {lo:g} and {hi:g} rad")
    return v


def _mu(mu_c: float) -> float:
    v = float(mu_c)
    if not (math.isfinite(v) and v >= 0.0):
        raise InvalidInput("mu_c", "must be a finite number >= 0")
    return v


def _fence_inputs(a: float, c: float, alpha: float) -> tuple[float, float, float]:
    a = _positive("disk_radius", a)
    c = _positive("contact_distance", c)
    if c > a * (1.0 + 1e-12):
        raise InvalidInput(
            "contact_distance",
            "must not exceed the disk radius: the contact vertex belongs to the workpiece, "
            "which the disk of radius a circumscribes about the CM (3.4)",
        )
    alpha = _angle("alpha", alpha, 0.0, math.pi)
    return a, c, alpha


def _log_tan_quarter(u: Real) -> Real:
    """ln|tan(u/2 + pi/4)| = ln|sec u + tan u| = (1/2) ln|(1 + sin u)/(1 - sin u)|, an
    antiderivative of sec u, without the cancellation of 1 - sin u near u = pi/2."""
    return np.log(np.abs(np.tan(0.5 * np.asarray(u, dtype=float) + 0.25 * math.pi)))


def _log_tan_half(beta: Real) -> Real:
    """ln|tan(beta/2)| = (1/2) ln|(1 - cos beta)/(1 + cos beta)|, an antiderivative of
    1/sin beta."""
    return np.log(np.abs(np.tan(0.5 * np.asarray(beta, dtype=float))))


# ---------------------------------------------------------------------------------------
# Aligning a workpiece with a fence, mu_c = 0 (book 3.4)
# ---------------------------------------------------------------------------------------


def fence_contact(beta: Real, c: Real) -> np.ndarray:
    """Contact vertex relative to the CM in the fence frame: c (-cos beta, sin beta)."""
    beta = np.asarray(beta, dtype=float)
    return np.stack([-c * np.cos(beta), c * np.sin(beta)], axis=-1)


def fence_moment_arm(beta: Real, c: Real, alpha: Real) -> Real:
    """alpha_hat . c = -c cos(alpha + beta): the signed distance from the CM to the line of
    force of a frictionless fence (3.3); > 0 turns the part clockwise."""
    return -c * np.cos(alpha + np.asarray(beta, dtype=float))


def fence_final_beta(alpha: float, vertex_edge_angle: float) -> float:
    """beta at which the edge leaving the contact vertex lies flush with the fence.

    ``vertex_edge_angle`` psi is the angle at the contact vertex from the ray towards the
    CM to that edge, turning clockwise (the edge is met first as the part turns clockwise).
    The edge points along -alpha_hat when flush: -beta - psi = alpha - pi, so
    beta_final = pi - alpha - psi (figures 3-20, 3-21).
    """
    return math.pi - float(alpha) - float(vertex_edge_angle)


def fence_rate_frictionless(beta: Real, a: Real, c: Real, alpha: Real) -> Real:
    """dx/dbeta with the COR at the tip of {COR}_alpha, equation (3.40):
    alpha_hat . (c - r_tip) / sin alpha = (m + a^2/m) / sin alpha, m = -c cos(alpha+beta),
    r_tip = a^2/m along -alpha_hat (3.37). The tip is the farthest point of the locus along
    -alpha_hat (it is on the symmetry axis and farthest from the CM), so this is the slowest
    rotation exactly; valid while m < a (always here, as c <= a)."""
    m = fence_moment_arm(beta, c, alpha)
    return (m + a * a / m) / math.sin(alpha)


def fence_push_frictionless_indefinite(beta: Real, a: Real, c: Real, alpha: Real) -> Real:
    """Equation (3.41): x(beta) = [-c sin(alpha+beta)
    - (a^2/2c) log|(1 + sin(alpha+beta))/(1 - sin(alpha+beta))|] / sin alpha,
    the antiderivative of (3.40) (confirmed; the log is evaluated as
    2 log|tan((alpha+beta)/2 + pi/4)| to avoid cancellation)."""
    u = alpha + np.asarray(beta, dtype=float)
    return (-c * np.sin(u) - (a * a / c) * _log_tan_quarter(u)) / math.sin(alpha)


def _check_fence_range(beta_initial: float, beta_final: float, alpha: float,
                       margin_angle: float = 0.0) -> tuple[float, float]:
    bi = _angle("beta_initial", beta_initial, 0.0, math.pi)
    bf = _angle("beta_final", beta_final, 0.0, math.pi)
    if bf < bi:
        raise InvalidInput("beta_final", "must not be smaller than beta_initial (the part turns clockwise)")
    if not bf < math.pi - alpha:
        raise InvalidInput(
            "beta_final",
            "must be below pi - alpha: there the CM would reach the fence line",
        )
    if not alpha + margin_angle + bi > HALF_PI:
        raise InvalidInput(
            "beta_initial",
            "alpha (+ nu) + beta must exceed pi/2: otherwise the line of force does not pass "
            "on the clockwise side of the CM and the COR may go to infinity (3.3.11.1, 4.1.5)",
        )
    return bi, bf


def fence_push_frictionless(a: float, c: float, alpha: float, beta_initial: float, beta_final: float) -> float:
    """Longest push of a frictionless fence that turns the part from beta_initial to
    beta_final: (3.41) at beta_final minus (3.41) at beta_initial (3.4)."""
    a, c, alpha = _fence_inputs(a, c, alpha)
    bi, bf = _check_fence_range(beta_initial, beta_final, alpha)
    f = fence_push_frictionless_indefinite
    return float(f(bf, a, c, alpha) - f(bi, a, c, alpha))


def fence_rate_least_frictionless(beta: Real, a: Real, c: Real, alpha: Real) -> Real:
    """Not in the book: dx/dbeta with the COR at r_min (3.31), the locus point farthest
    along +alpha_hat (checked against the boundary in the tests), i.e. the fastest
    rotation: (m - a m/(2a + m)) / sin alpha = m (a + m) / ((2a + m) sin alpha)."""
    m = fence_moment_arm(beta, c, alpha)
    return m * (a + m) / ((2.0 * a + m) * math.sin(alpha))


def fence_push_least_frictionless_indefinite(beta: Real, a: Real, c: Real, alpha: Real) -> Real:
    """Antiderivative of :func:`fence_rate_least_frictionless` (not in the book).

    m (a + m)/(2a + m) = m - a + 2a^2/(2a + m) with m = -c cos u, u = alpha + beta, and
    int du/(2a - c cos u) = (2/sqrt(4a^2 - c^2)) atan(sqrt((2a + c)/(2a - c)) tan(u/2)),
    continuous for u in (0, pi) (c <= a < 2a)."""
    beta = np.asarray(beta, dtype=float)
    u = alpha + beta
    root = math.sqrt(4.0 * a * a - c * c)
    at = np.arctan(math.sqrt((2.0 * a + c) / (2.0 * a - c)) * np.tan(0.5 * u))
    at = np.where(u > math.pi, at + math.pi, at)  # branch continuity past u = pi
    return (-c * np.sin(u) - a * beta + (4.0 * a * a / root) * at) / math.sin(alpha)


def fence_push_least_frictionless(a: float, c: float, alpha: float, beta_initial: float, beta_final: float) -> float:
    """Not in the book: the shortest push that can turn the part from beta_initial to
    beta_final with a frictionless fence (every COR at r_min, (3.31)); a lower bound
    that any support must respect."""
    a, c, alpha = _fence_inputs(a, c, alpha)
    bi, bf = _check_fence_range(beta_initial, beta_final, alpha)
    f = fence_push_least_frictionless_indefinite
    return float(f(bf, a, c, alpha) - f(bi, a, c, alpha))


# ---------------------------------------------------------------------------------------
# Aligning a workpiece with a fence, mu_c > 0 (book 4.3)
# ---------------------------------------------------------------------------------------


def fence_rate(beta: Real, c: Real, alpha: Real, cor: Real) -> Real:
    """Equation (4.2) = (3.39): dx/dbeta = alpha_hat . (c - r) / sin alpha for a COR r
    (fence frame, relative to the CM). It is the contact condition n . v(c) = n . p with
    the part turning clockwise by dbeta; it holds for every mode (the pusher's normal
    velocity is imposed whether the contact sticks or slips)."""
    beta = np.asarray(beta, dtype=float)
    r = np.asarray(cor, dtype=float)
    cvec = fence_contact(beta, c)
    d = cvec - r
    return (math.cos(alpha) * d[..., 0] + math.sin(alpha) * d[..., 1]) / math.sin(alpha)


def fence_tip(beta: Real, a: Real, c: Real, phi: Real) -> Real:
    """Tip of {COR}_phi, the frictionless locus for force angle phi - pi/2 (3.37):
    -(a^2/k) (cos phi, sin phi) with k = phi_hat . c = -c cos(phi + beta). NaN where
    k <= 0 (the locus is "wrapped", 4.1.5: the line of force passes through or on the
    counter-clockwise side of the CM)."""
    beta = np.asarray(beta, dtype=float)
    k = -c * np.cos(phi + beta)
    with np.errstate(divide="ignore", invalid="ignore"):
        rt = np.where(k > 0.0, a * a / k, np.nan)
    return np.stack([-rt * math.cos(phi), -rt * math.sin(phi)], axis=-1)


def fence_tip_side(beta: Real, a: Real, c: Real, phi: Real) -> Real:
    """E(beta) = a^2 cos phi + c^2 cos beta cos(phi + beta) (derived here): the tip of
    {COR}_phi lies right of the sticking line (x_tip > -c cos beta) when E < 0 and left of
    it when E > 0, for a locus that is not wrapped (x_tip + c cos beta = -E / k).

    Dividing by cos beta cos(phi + beta) gives the book's (4.3),
    a^2 + c^2 = -a^2 tan beta tan(phi + beta). The book says the tip is on the CM's side
    when the left side of (4.3) is *less* than the right; with beta < pi/2 (sticking line
    left of the CM) and phi + beta in (pi/2, pi), it is on the CM's side when the left side
    is *greater* (e.g. alpha = pi/2, beta = pi/4, a = c: the tip is straight below the CM,
    right of the sticking line, and 2a^2 > a^2)."""
    beta = np.asarray(beta, dtype=float)
    return a * a * math.cos(phi) + c * c * np.cos(beta) * np.cos(phi + beta)


def fence_tip_condition_4_3(beta: Real, a: Real, c: Real, phi: Real) -> Real:
    """(4.3) as a residual: (a^2 + c^2) + a^2 tan beta tan(phi + beta), left side minus
    right side; zero where the tip of {COR}_phi crosses the sticking line."""
    beta = np.asarray(beta, dtype=float)
    return a * a + c * c + a * a * np.tan(beta) * np.tan(phi + beta)


def fence_transition_tan_4_4(a: float, c: float, phi: float) -> tuple[float, float]:
    """Both roots of (4.4) as printed: tan beta = [c^2 tan phi -+ (c^4 tan^2 phi
    - 4a^2 (a^2 + c^2))^(1/2)] / 2a^2 (confirmed: (4.3) is the quadratic
    a^2 t^2 - c^2 tan(phi) t + (a^2 + c^2) = 0 in t = tan beta). Returns (t_minus, t_plus),
    NaN when the discriminant is negative (no crossing)."""
    tp = math.tan(phi)
    disc = c**4 * tp * tp - 4.0 * a * a * (a * a + c * c)
    if disc < 0.0:
        return (math.nan, math.nan)
    s = math.sqrt(disc)
    return ((c * c * tp - s) / (2.0 * a * a), (c * c * tp + s) / (2.0 * a * a))


def fence_transition_betas(a: float, c: float, phi: float, lo: float = 0.0, hi: float = math.pi) -> np.ndarray:
    """Angles beta in (lo, hi) where the tip of {COR}_phi crosses the sticking line, on the
    range where that locus is not wrapped (phi + beta in (pi/2, 3pi/2)).

    Closed form (equivalent to (4.4), without its division by cos beta):
    E = (a^2 + c^2/2) cos phi + (c^2/2) cos(phi + 2 beta), so E = 0 at
    phi + 2 beta = +-arccos(-(2a^2 + c^2) cos phi / c^2) + 2 pi n. Real roots exist iff
    (2a^2 + c^2) |cos phi| <= c^2, the same condition as (4.4)'s discriminant.

    Which root applies (phi in (0, pi/2), beta < pi/2): the tip is right of the sticking
    line (same side as the CM) between the two roots atan(t_minus) < atan(t_plus) of (4.4)
    and left of it outside them; as beta grows the tip enters the CM's side at the smaller
    root and leaves it at the larger one. For phi >= pi/2 and beta < pi/2 there is no root:
    the tip stays on the CM's side.
    """
    q = -(2.0 * a * a + c * c) * math.cos(phi) / (c * c)
    if abs(q) > 1.0:
        return np.array([])
    g = math.acos(q)
    out = []
    for base in (g - phi, -g - phi):
        for n in range(-3, 4):
            b = 0.5 * base + math.pi * n
            if lo < b < hi and math.cos(phi + b) < 0.0:
                out.append(b)
    return np.unique(np.round(np.array(out), 15))


def fence_rate_slipping(beta: Real, a: Real, c: Real, alpha: Real, mu_c: Real, sign: int) -> Real:
    """Equation (4.5), dx/dbeta with the COR at the tip of {COR}_(alpha + sign nu),
    nu = atan(mu_c) (4.1):

        alpha_hat . (c - r_tip) / sin alpha = (m + a^2 cos nu / k) / sin alpha,

    m = -c cos(alpha + beta), k = -c cos(alpha + sign nu + beta): the tip lies at a^2/k
    along -(alpha +- nu)_hat, whose component along alpha_hat is cos nu. Note that the dot
    product and sin alpha keep the fence's own alpha (the contact condition (4.2) is about
    the real normal); only the tip uses alpha +- nu."""
    nu = math.atan(mu_c)
    beta = np.asarray(beta, dtype=float)
    m = -c * np.cos(alpha + beta)
    k = -c * np.cos(alpha + sign * nu + beta)
    return (m + a * a * math.cos(nu) / k) / math.sin(alpha)


def fence_push_slipping_indefinite(beta: Real, a: Real, c: Real, alpha: Real, mu_c: Real, sign: int) -> Real:
    """Antiderivative of (4.5), re-derived (corrects the printed (4.6)):

        x = [-c sin(alpha + beta)
             - (a^2 cos nu / 2c) log|(1 + sin(alpha +- nu + beta)) / (1 - sin(alpha +- nu + beta))|]
            / sin alpha.

    The book prints (4.6) as (3.41) with alpha replaced by alpha +- nu everywhere except in
    sin alpha: -c sin(alpha +- nu + beta) in the first term and no cos nu in the second. The
    first term comes from alpha_hat . c, which does not change with nu, and the tip's
    component along alpha_hat carries cos nu. Both agree at nu = 0 with (3.41)."""
    nu = math.atan(mu_c)
    u = alpha + np.asarray(beta, dtype=float)
    return (-c * np.sin(u) - (a * a * math.cos(nu) / c) * _log_tan_quarter(u + sign * nu)) / math.sin(alpha)


def fence_push_slipping_indefinite_book_printed(beta: Real, a: Real, c: Real, alpha: Real, mu_c: Real, sign: int) -> Real:
    """(4.6) exactly as printed, for comparison: [-c sin(alpha +- nu + beta)
    - (a^2/2c) log|(1 + sin(alpha +- nu + beta))/(1 - sin(alpha +- nu + beta))|] / sin alpha.
    Its derivative is not (4.5); see :func:`fence_push_slipping_indefinite`."""
    nu = math.atan(mu_c)
    u = alpha + sign * nu + np.asarray(beta, dtype=float)
    return (-c * np.sin(u) - (a * a / c) * _log_tan_quarter(u)) / math.sin(alpha)


def fence_sticking_cor(beta: Real, a: Real, c: Real) -> Real:
    """Point B of figure 4-7: the tip line (perpendicular to c at distance a^2/c beyond the
    CM, 3.3.11.1) meets the sticking line x = -c cos beta:
    B = (-c cos beta, -(a^2 + c^2 cos^2 beta) / (c sin beta)). The book's approximation of
    the lower end of the sticking locus (4.1.4)."""
    beta = np.asarray(beta, dtype=float)
    return np.stack([-c * np.cos(beta), -(a * a + c * c * np.cos(beta) ** 2) / (c * np.sin(beta))], axis=-1)


def fence_rate_sticking(beta: Real, a: Real, c: Real) -> Real:
    """(4.5) with (4.7): |c - B| = (c^2 + a^2)/(c sin beta) (confirmed; c - B is vertical,
    so alpha_hat . (c - B) = sin alpha |c - B| and sin alpha cancels):
    dx/dbeta = (a^2 + c^2)/(c sin beta), independent of alpha and of mu_c."""
    return (a * a + c * c) / (c * np.sin(np.asarray(beta, dtype=float)))


def fence_push_sticking_indefinite(beta: Real, a: Real, c: Real) -> Real:
    """Equation (4.8), confirmed: x = ((c^2 + a^2)/2c) log|(1 - cos beta)/(1 + cos beta)|
    = ((c^2 + a^2)/c) log|tan(beta/2)|."""
    return ((a * a + c * c) / c) * _log_tan_half(beta)


REGIMES = ("frictionless", "sticking", "slipping_down", "slipping_up")
"""Slowest-COR regimes of 4.3: the tip of {COR}_alpha (mu_c = 0); the lower end of the
sticking locus, B ("sticking-slowest", sketches d, e, g, h); the tip of {COR}_(alpha+nu) in
the down-slipping zone (sketch i: both tips left of the sticking line, the "+" sign); the
tip of {COR}_(alpha-nu) in the up-slipping zone (sketches a, b, c: both tips right, the
"-" sign)."""


def fence_slowest(beta: Real, a: float, c: float, alpha: float,
                  mu_c: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Slowest COR of the COR sketch by the book's rules (4.3, figure 4-6), pointwise.

    The tip of {COR}_(alpha+nu) belongs to the sketch when it lies left of (or on) the
    sticking line (down-slipping locus); the tip of {COR}_(alpha-nu) when it is not wrapped
    and lies right of it (up-slipping locus). With neither in the sketch the tips straddle
    the sticking line and the slowest COR is B (sticking-slowest). With mu_c = 0 it is the
    tip of {COR}_alpha. Returns (regime index into REGIMES, lever alpha_hat . (c - r),
    dx/dbeta) arrays.
    """
    beta = np.atleast_1d(np.asarray(beta, dtype=float))
    sin_a = math.sin(alpha)
    m = -c * np.cos(alpha + beta)
    if mu_c == 0.0:
        lever = m + a * a / m
        return np.zeros(beta.shape, dtype=int), lever, lever / sin_a
    nu = math.atan(mu_c)
    k_p = -c * np.cos(alpha + nu + beta)
    k_m = -c * np.cos(alpha - nu + beta)
    e_p = fence_tip_side(beta, a, c, alpha + nu)
    e_m = fence_tip_side(beta, a, c, alpha - nu)
    with np.errstate(divide="ignore", invalid="ignore"):
        lev_p = np.where(k_p > 0.0, m + a * a * math.cos(nu) / k_p, -np.inf)
        lev_m = np.where(k_m > 0.0, m + a * a * math.cos(nu) / k_m, -np.inf)
    adm_p = (k_p > 0.0) & (e_p >= 0.0)
    adm_m = (k_m > 0.0) & (e_m <= 0.0)
    lev_b = sin_a * fence_rate_sticking(beta, a, c)
    lever = np.where(adm_p | adm_m, np.maximum(np.where(adm_p, lev_p, -np.inf), np.where(adm_m, lev_m, -np.inf)), lev_b)
    regime = np.where(adm_p & (~adm_m | (lev_p >= lev_m)), 2, np.where(adm_m, 3, 1))
    return regime, lever, lever / sin_a


@dataclass(frozen=True)
class FencePiece:
    """One stretch of constant slowest-COR regime: beta from ``beta_start`` to
    ``beta_end`` needs at most ``push`` of fence travel."""

    beta_start: float
    beta_end: float
    regime: str
    push: float


@dataclass(frozen=True)
class FencePushBound:
    """Longest push of a fence with contact friction mu_c that turns the part from
    beta_initial to beta_final (4.3): the sum of the pieces' closed forms. ``transitions``
    are the betas where the regime changes (tips crossing the sticking line, (4.4))."""

    total: float
    pieces: tuple[FencePiece, ...]
    transitions: tuple[float, ...]


def fence_push_bound(a: float, c: float, alpha: float, beta_initial: float, beta_final: float,
                     mu_c: float) -> FencePushBound:
    """Composite bound of 4.3: split [beta_initial, beta_final] where a tip of
    {COR}_(alpha +- nu) crosses the sticking line (4.4) or {COR}_(alpha - nu) stops being
    wrapped, find the regime of each piece (:func:`fence_slowest` at its midpoint) and add
    the closed forms: (3.41) for mu_c = 0, the corrected (4.6) for a slipping-slowest piece,
    (4.8) for a sticking-slowest one. The regimes' rates agree where they meet (a tip on the
    sticking line is B), so the bound is continuous in its ends.
    """
    a, c, alpha = _fence_inputs(a, c, alpha)
    mu_c = _mu(mu_c)
    nu = math.atan(mu_c)
    bi, bf = _check_fence_range(beta_initial, beta_final, alpha, margin_angle=nu)
    if mu_c == 0.0:
        push = fence_push_frictionless(a, c, alpha, bi, bf)
        return FencePushBound(push, (FencePiece(bi, bf, "frictionless", push),), ())
    cuts: set[float] = set()
    for phi in (alpha + nu, alpha - nu):
        cuts.update(float(b) for b in fence_transition_betas(a, c, phi, bi, bf))
    for n in range(-2, 3):  # {COR}_(alpha - nu) wrapped <-> not: alpha - nu + beta = pi/2 + n pi
        b = HALF_PI - (alpha - nu) + math.pi * n
        if bi < b < bf:
            cuts.add(b)
    edges = [bi] + sorted(cuts) + [bf]
    pieces: list[FencePiece] = []
    for b0, b1 in zip(edges[:-1], edges[1:]):
        if b1 <= b0:
            continue
        reg = int(fence_slowest(0.5 * (b0 + b1), a, c, alpha, mu_c)[0][0])
        if reg == 1:
            push = float(fence_push_sticking_indefinite(b1, a, c) - fence_push_sticking_indefinite(b0, a, c))
        else:
            sg = 1 if reg == 2 else -1
            f = fence_push_slipping_indefinite
            push = float(f(b1, a, c, alpha, mu_c, sg) - f(b0, a, c, alpha, mu_c, sg))
        name = REGIMES[reg]
        if pieces and pieces[-1].regime == name:
            last = pieces.pop()
            pieces.append(FencePiece(last.beta_start, b1, name, last.push + push))
        else:
            pieces.append(FencePiece(b0, b1, name, push))
    transitions = tuple(p.beta_start for p in pieces[1:])
    return FencePushBound(sum(p.push for p in pieces), tuple(pieces), transitions)


def integrate_fence_push(
    cor_of_beta: CorOfBeta,
    c: float,
    alpha: float,
    beta_initial: float,
    beta_final: float,
    rtol: float = 1e-10,
    atol: float = 1e-13,
    vectorized: bool = False,
) -> QuadResult:
    """Integrate (4.2), dx = dbeta alpha_hat . (c - r(beta)) / sin alpha, for any COR
    callback r(beta) = (x, y) in the fence frame (relative to the CM). With
    ``vectorized`` the callback takes an array of betas and returns (n, 2)."""
    if vectorized:
        def f(b: np.ndarray) -> Real:
            return fence_rate(b, c, alpha, np.asarray(cor_of_beta(b), dtype=float).reshape(-1, 2))
    else:
        def f(b: np.ndarray) -> Real:
            r = np.array([np.asarray(cor_of_beta(float(t)), dtype=float) for t in b]).reshape(-1, 2)
            return fence_rate(b, c, alpha, r)
    return adaptive_quadrature(f, beta_initial, beta_final, rtol, atol)


# ---------------------------------------------------------------------------------------
# A disk pushed aside by a point moving in a line (book 4.4)
# ---------------------------------------------------------------------------------------


def encounter_contact(beta: Real, a: Real) -> Real:
    """The pusher point relative to the disk's CM: a (-cos beta, sin beta)."""
    return fence_contact(beta, a)


def encounter_rate(beta: Real, x_cor: Real, y_cor: Real, a: Real) -> Real:
    """Equation (4.12), confirmed: dx/dbeta = a (sin beta + cos beta / tan theta) with
    tan theta = x_COR / y_COR (4.13), theta the angle below the horizontal of the CM's
    motion. From a sin beta = y_pusher - y_CM (4.10) and x_pusher = x_CM - a cos beta (the
    pusher stays on the disk); it is geometry only and holds for any COR with x_COR != 0."""
    beta = np.asarray(beta, dtype=float)
    return a * (np.sin(beta) + np.cos(beta) * np.asarray(y_cor, dtype=float) / np.asarray(x_cor, dtype=float))


def encounter_tip_line_cor(beta: Real, a: Real) -> Real:
    """(4.13): the tip line meets the sticking line at x_COR = -a cos beta,
    y_COR = a (sin^2 beta - 2)/sin beta (confirmed: point B of 4.3 with c = a)."""
    return fence_sticking_cor(beta, a, a)


def encounter_tan_theta_min(beta: Real) -> Real:
    """(4.14), confirmed: tan theta = cos beta sin beta / (1 + cos^2 beta) at the COR of
    (4.13): the smallest theta, hence the largest dx/dbeta, for sketches g and h."""
    beta = np.asarray(beta, dtype=float)
    return np.cos(beta) * np.sin(beta) / (1.0 + np.cos(beta) ** 2)


def encounter_rate_max(beta: Real, a: Real) -> Real:
    """(4.15) re-derived: (4.12) with (4.14) is
    dx = a dbeta [sin beta + (1 + cos^2 beta)/sin beta] = 2a dbeta / sin beta.
    The OCR prints "a dbeta (sin beta) + (1 + cos^2 beta)/sin beta": the bracket closes too
    early, leaving the second term without its factor a dbeta."""
    return 2.0 * a / np.sin(np.asarray(beta, dtype=float))


def encounter_rate_max_book_printed(beta: Real, a: Real) -> Real:
    """(4.15) as the OCR prints it, read as dx/dbeta = a sin beta + (1 + cos^2 beta)/sin beta
    (not even dimensionally consistent unless a = 1); kept for the test that shows it."""
    beta = np.asarray(beta, dtype=float)
    return a * np.sin(beta) + (1.0 + np.cos(beta) ** 2) / np.sin(beta)


def encounter_length_max_indefinite(beta: Real, a: Real) -> Real:
    """(4.16), confirmed: x = a ln((1 - cos beta)/(1 + cos beta)) = 2a ln tan(beta/2), the
    antiderivative of 2a / sin beta; zero at beta = pi/2."""
    return 2.0 * a * _log_tan_half(beta)


def encounter_length_max(beta_initial: float, a: float, beta_final: float = HALF_PI) -> float:
    """Greatest length of the encounter (4.4.1.1): (4.16) at beta_final (pi/2: zero) minus
    its value at beta_initial, = a ln((1 + cos beta_i)/(1 - cos beta_i)) for beta_final =
    pi/2. Neglects the dip of the sticking locus below the tip line (underestimates) and uses
    the tip line also in sketch i (overestimates), as the book says (4.4.1.2)."""
    a = _positive("disk_radius", a)
    bi = _angle("beta_initial", beta_initial, 0.0, HALF_PI + 1e-15)
    bf = _angle("beta_final", beta_final, 0.0, HALF_PI + 1e-15)
    return float(encounter_length_max_indefinite(bf, a) - encounter_length_max_indefinite(bi, a))


def encounter_length_frictionless(beta_initial: float, a: float, beta_final: float = HALF_PI) -> float:
    """Length of the encounter with mu_c = 0: the force passes through the CM, the disk
    translates along the contact normal (4.4.2.1, [42]), theta = beta, and (4.12) gives
    dx = a dbeta / sin beta: x = a ln tan(beta_f/2) - a ln tan(beta_i/2), half of the
    greatest length (4.16)."""
    a = _positive("disk_radius", a)
    bi = _angle("beta_initial", beta_initial, 0.0, HALF_PI + 1e-15)
    bf = _angle("beta_final", beta_final, 0.0, HALF_PI + 1e-15)
    return float(a * (_log_tan_half(bf) - _log_tan_half(bi)))


def sketch_i(beta: Real, mu_c: Real) -> Real:
    """(4.17), confirmed: the COR sketch is of type i (the tip of {COR}_(alpha+nu) left of
    the sticking line) when tan beta > 2 tan nu = 2 mu_c. From E of
    :func:`fence_tip_side` with c = a, phi = pi/2 - beta + nu:
    E = a^2 (sin beta cos nu - 2 cos beta sin nu)."""
    return np.tan(np.asarray(beta, dtype=float)) > 2.0 * mu_c


def sketch_i_onset(mu_c: float) -> float:
    """beta above which the sketch is of type i: atan(2 mu_c) (4.17)."""
    return math.atan(2.0 * _mu(mu_c))


def rotation_max(beta_initial: float, beta_final: float = HALF_PI) -> float:
    """(4.18) re-derived: with the COR on the sticking line the pusher rolls on the disk
    without slipping, so the disk turns by exactly the change of beta:
    xi_encounter = pi/2 - beta_initial (radians; the arc rolled is a xi). The OCR prints
    "xi = a pi/(2 - beta_initial)". Every possible COR is on or left of the sticking line
    (only sketches g, h, i occur), where dxi/dbeta <= 1 (:func:`rotation_rate`), so this is
    an exact upper bound."""
    bi = _angle("beta_initial", beta_initial, 0.0, HALF_PI + 1e-15)
    return float(beta_final) - bi


def rotation_rate(beta: Real, x_cor: Real, y_cor: Real, a: Real) -> Real:
    """dxi/dbeta re-derived: -a cos beta / x_COR (clockwise rotation xi of the disk).

    The disk turns at omega = -sin(alpha)/(alpha_hat . (c - r)) per unit push (3.3), with
    alpha = pi/2 - beta: -omega = -cos beta / (x sin beta + y cos beta); times (4.12),
    dx/dbeta = a (x sin beta + y cos beta)/x, the bracket cancels. So the contours of
    constant dxi/dbeta are vertical lines, and the least rotation is at the leftmost COR
    of the sketch. On the sticking line (x = -a cos beta) the rate is 1.

    The book's (4.19) dx = l sin xi dxi takes the pusher's advance to be the horizontal
    travel of the disk's material point at the contact, true only when it sticks; its
    (4.22) (:func:`rotation_rate_book_printed`) agrees with this one only on the sticking
    line (checked against the forward solver in tests/solver/push/test_simulate.py).
    """
    beta = np.asarray(beta, dtype=float)
    return -a * np.cos(beta) / np.asarray(x_cor, dtype=float)


def rotation_rate_book_printed(beta: Real, x_cor: Real, y_cor: Real, a: Real) -> Real:
    """(4.22) as printed: a (y cos beta + x sin beta) / (x (a sin beta - y)); see
    :func:`rotation_rate`."""
    beta = np.asarray(beta, dtype=float)
    x = np.asarray(x_cor, dtype=float)
    y = np.asarray(y_cor, dtype=float)
    return a * (y * np.cos(beta) + x * np.sin(beta)) / (x * (a * np.sin(beta) - y))


def _cor_integrand(cor_of_beta: CorOfBeta, vectorized: bool, rate: RateOfCor,
                   a: float) -> Callable[[np.ndarray], Real]:
    """The integrand rate(beta, x_COR, y_COR, a) for a COR callback; a COR that makes it
    infinite (x_COR = 0) is reported by the quadrature as InvalidInput."""

    def f(b: np.ndarray) -> Real:
        if vectorized:
            r = np.asarray(cor_of_beta(b), dtype=float).reshape(-1, 2)
        else:
            r = np.array([np.asarray(cor_of_beta(float(t)), dtype=float) for t in b]).reshape(-1, 2)
        with np.errstate(divide="ignore", invalid="ignore"):
            return rate(b, r[:, 0], r[:, 1], a)

    return f


def integrate_encounter_length(
    cor_of_beta: CorOfBeta,
    a: float,
    beta_initial: float,
    beta_final: float = HALF_PI,
    rtol: float = 1e-10,
    atol: float = 1e-13,
    vectorized: bool = False,
) -> QuadResult:
    """Integrate the equation of motion (4.12) over [beta_initial, beta_final] for a COR
    callback r(beta) = (x_COR, y_COR) in the disk-encounter frame (CM at the origin, pusher
    moving along +x on the line y = a sin beta; module docstring). This is how the book
    means (4.12) to be used with the numerically found ends of the sticking locus
    (4.4.1.3): the lower end gives the greatest length, the upper end the least."""
    a = _positive("disk_radius", a)
    return adaptive_quadrature(_cor_integrand(cor_of_beta, vectorized, encounter_rate, a), beta_initial, beta_final, rtol, atol)


def integrate_rotation(
    cor_of_beta: CorOfBeta,
    a: float,
    beta_initial: float,
    beta_final: float = HALF_PI,
    rtol: float = 1e-10,
    atol: float = 1e-13,
    vectorized: bool = False,
    book_printed: bool = False,
) -> QuadResult:
    """Integrate the rotation's equation of motion, (4.23) with (4.22), for a COR callback
    (as :func:`integrate_encounter_length`): the disk's clockwise rotation xi. The default
    uses the re-derived rate -a cos beta / x_COR; ``book_printed`` uses (4.22) as printed.
    The least rotation (4.4.2.2) is this integral with the sketch's leftmost COR."""
    a = _positive("disk_radius", a)
    rate = rotation_rate_book_printed if book_printed else rotation_rate
    return adaptive_quadrature(_cor_integrand(cor_of_beta, vectorized, rate, a), beta_initial, beta_final, rtol, atol)
