"""The one-particle example of book 2.5: where the minimum power principle fails.

A particle is driven at the speed ``v_x`` along +x by a frictionless moving fence (the
fence can push only along x), a constant external force of magnitude ``mg`` acts along -y,
and a dissipative force of magnitude ``eta |v|^n`` opposes the velocity (figure 2-2).
``n = 0`` is Coulomb friction, ``n = 1`` viscous friction. After the transient the motion
is steady and the question is the velocity component along the external force.

Sign convention (re-derived here; the book leaves it implicit). Let ``v_y`` denote the
speed *along the external force*, i.e. the world velocity is ``(v_x, -v_y)``. Then

* the external force does the work ``+mg v_y`` per unit time, so the book's total power
  (2.30) ``P(v_y) = -mg v_y + eta (v_x^2 + v_y^2)^((n+1)/2)`` is "dissipation minus the
  power supplied by the external force", and it is minimised over ``v_y`` with ``v_x``
  held by the constraint (2.31);
* the y component of the dissipative force balances the external one (2.27):
  ``mg = eta |v|^n v_y / |v|``, i.e. (2.29) ``mg / eta = v_y (v_x^2 + v_y^2)^((n-1)/2)``;
* stationarity of (2.30), (2.31)-(2.32): ``mg / eta = (n + 1) v_y (v_x^2 + v_y^2)^((n-1)/2)``.

With this convention both answers are positive (the particle moves along the force).
Writing ``g_n(u) = u (v_x^2 + u^2)^((n-1)/2)``, Newton solves ``g_n(u) = mg/eta`` and the
minimum power principle ``g_n(u) = mg / ((n + 1) eta)``: they agree only for ``n = 0``
(2.5.2, 2.2.4). For ``n = 1`` ``g_1(u) = u``, so the minimum power answer is exactly half
the Newtonian one.

``g_n`` is strictly increasing on ``u >= 0`` for every ``n >= 0``
(``d log g / d log u = (v_x^2 + n u^2) / (v_x^2 + u^2) > 0``); it grows without bound for
``n > 0``, while ``g_0(u) = u / |v| < 1``. Hence every balance has exactly one positive root
for ``n > 0``, and for ``n = 0`` only when ``mg / eta < 1``: with ``eta <= mg`` Coulomb
friction cannot hold the particle against the external force, it accelerates without limit
(the book's "we will assume eta > mg"), and the power (2.30) ``-mg v_y + eta |v|`` is then
unbounded below (or, for eta = mg, has no minimiser), so the n = 0 minimum power problem is
convex and well posed exactly when ``eta > mg``.

Pure numpy; the roots are found by a bracketing Illinois iteration in ``log(v_y / v_x)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from models.core.arrays import Real
from models.core.errors import InvalidInput, ModelError
from models.core.tolerances import DEFAULT, Tolerances


class BalanceNotConverged(ModelError):
    """The 1-D root solve of (2.29)/(2.32) missed its tolerance (a bug or an extreme input)."""


@dataclass(frozen=True)
class ParticleScene:
    """Validated inputs of the book 2.5 example (figure 2-2).

    ``v_x``: fence speed (> 0); ``mg``: magnitude of the constant external force (> 0);
    ``eta``: coefficient of the dissipative force ``eta |v|^n`` (> 0); ``n``: its exponent
    (>= 0). For ``n = 0`` also ``eta > mg`` (module docstring).
    """

    v_x: float
    mg: float
    eta: float
    n: float

    @classmethod
    def create(cls, v_x: float, mg: float, eta: float, n: float) -> "ParticleScene":
        values = {}
        for name, value in (("v_x", v_x), ("mg", mg), ("eta", eta), ("n", n)):
            try:
                x = float(value)
            except (TypeError, ValueError):
                raise InvalidInput(name, "must be a number") from None
            if not math.isfinite(x):
                raise InvalidInput(name, "must be a finite number")
            values[name] = x
        if values["v_x"] <= 0.0:
            raise InvalidInput("v_x", "must be positive: the fence drives the particle along +x")
        if values["mg"] <= 0.0:
            raise InvalidInput(
                "mg",
                "must be positive: it is the magnitude of the external force, whose direction "
                "defines the sign of v_y (with mg = 0 the particle simply follows the fence)",
            )
        if values["eta"] <= 0.0:
            raise InvalidInput("eta", "must be positive: the dissipative force eta v^n opposes the motion")
        if values["n"] < 0.0:
            raise InvalidInput("n", "must be >= 0 (0 is Coulomb friction, 1 viscous friction)")
        if values["n"] == 0.0 and not values["eta"] > values["mg"]:
            raise InvalidInput(
                "eta",
                "must exceed mg when n = 0: Coulomb friction of magnitude eta cannot balance "
                "the external force mg >= eta, so the particle accelerates without limit (no "
                "quasi-static steady state, book 2.5), and the power (2.30) is unbounded below "
                "or has no minimiser",
            )
        return cls(**values)

    @property
    def load(self) -> float:
        """mg / eta, the left-hand side of (2.29) and (2.32)."""
        return self.mg / self.eta


def balance_function(v_y: Real, v_x: float, n: float) -> np.ndarray:
    """g_n(v_y) = v_y (v_x^2 + v_y^2)^((n-1)/2): the right-hand side of (2.29) (vectorised)."""
    u = np.asarray(v_y, dtype=float)
    return u * np.power(v_x * v_x + u * u, 0.5 * (n - 1.0))


def power(v_y: Real, scene: ParticleScene) -> np.ndarray:
    """Total power (2.30): -mg v_y + eta (v_x^2 + v_y^2)^((n+1)/2) (vectorised in v_y)."""
    u = np.asarray(v_y, dtype=float)
    return -scene.mg * u + scene.eta * np.power(scene.v_x**2 + u * u, 0.5 * (scene.n + 1.0))


def power_derivative(v_y: Real, scene: ParticleScene) -> np.ndarray:
    """dP/dv_y of (2.31): -mg + (n + 1) eta v_y (v_x^2 + v_y^2)^((n-1)/2)."""
    return -scene.mg + (scene.n + 1.0) * scene.eta * balance_function(v_y, scene.v_x, scene.n)


def force_balance_residual(v_y: Real, scene: ParticleScene) -> np.ndarray:
    """Newton's y balance (2.27), relative: (eta |v|^n v_y/|v| - mg) / mg. Zero at the
    Newtonian steady state."""
    return (scene.eta * balance_function(v_y, scene.v_x, scene.n) - scene.mg) / scene.mg


def _softplus2(x: float) -> float:
    """log(1 + exp(2x)) without overflow."""
    return 2.0 * x + math.log1p(math.exp(-2.0 * x)) if x > 0.0 else math.log1p(math.exp(2.0 * x))


def _log_inverse_piecewise(log_y: float, n: float) -> float:
    """log of h^-1(y) for h(t) = t (t <= 1), t^n (t >= 1)."""
    return log_y if log_y <= 0.0 else log_y / n


def solve_balance_bracketing(target: float, v_x: float, n: float, tol: Tolerances = DEFAULT) -> float:
    """The positive root u of g_n(u) = target (target > 0, v_x > 0, n > 0, or n = 0 with
    target < 1) by a bracketing Illinois iteration; no closed form is used.

    In t = u / v_x the equation reads t (1 + t^2)^((n-1)/2) = K with K = target / v_x^n.
    Since 1 + t^2 lies between max(1, t)^2 and 2 max(1, t)^2, the left side lies within a
    factor C = 2^(|n-1|/2) of h(t) = t (t <= 1), t^n (t >= 1), which brackets the root in
    [h^-1(K/C), h^-1(K C)] (n > 0). For n = 0, t = K / sqrt(1 - K^2) is bracketed by
    [K, K/sqrt(1 - K^2)] widened by a factor 2. The iteration runs in x = log t, where
    G(x) = x + (n-1)/2 log(1 + e^(2x)) - log K is increasing with slope in (0, max(1, n)].
    It stops when the bracket is narrower than ``tol.root_rtol * max(1, |x|)``: that is the
    relative accuracy of the returned u (the floor set by representing x = log(u / v_x)).
    """
    if not (target > 0.0 and v_x > 0.0 and n >= 0.0):
        raise InvalidInput("target", "the balance needs target > 0, v_x > 0 and n >= 0")
    log_k = math.log(target) - n * math.log(v_x)
    if n == 0.0:
        if not target < 1.0:
            raise InvalidInput("eta", "the n = 0 balance v_y/|v| = mg/eta needs eta > mg")
        x_lo = log_k - math.log(2.0)
        x_hi = log_k - 0.5 * math.log1p(-target) - 0.5 * math.log1p(target) + math.log(2.0)
    else:
        log_c = 0.5 * abs(n - 1.0) * math.log(2.0)
        x_lo = _log_inverse_piecewise(log_k - log_c, n) - 1.0
        x_hi = _log_inverse_piecewise(log_k + log_c, n) + 1.0

    def g(x: float) -> float:
        return x + 0.5 * (n - 1.0) * _softplus2(x) - log_k

    g_lo, g_hi = g(x_lo), g(x_hi)
    if not (g_lo < 0.0 < g_hi):  # pragma: no cover - the bracket is proven above
        raise BalanceNotConverged(f"root of (2.29)/(2.32) not bracketed for n = {n!r}")
    side = 0
    x = 0.5 * (x_lo + x_hi)
    for _ in range(tol.root_max_iter):
        x = x_hi - g_hi * (x_hi - x_lo) / (g_hi - g_lo)
        if not x_lo < x < x_hi:
            x = 0.5 * (x_lo + x_hi)
        gx = g(x)
        if gx == 0.0:
            break
        if gx > 0.0:
            x_hi, g_hi = x, gx
            if side == 1:
                g_lo *= 0.5  # Illinois: the low end was kept twice
            side = 1
        else:
            x_lo, g_lo = x, gx
            if side == -1:
                g_hi *= 0.5
            side = -1
        if x_hi - x_lo <= tol.root_rtol * max(1.0, abs(x)):
            x = x_hi if abs(g_hi) < abs(g_lo) else x_lo
            break
    else:
        raise BalanceNotConverged(
            f"root of (2.29)/(2.32) did not converge in {tol.root_max_iter} iterations for n = {n!r}"
        )
    if x + math.log(v_x) >= math.log(np.finfo(float).max):
        raise InvalidInput("n", "is so close to 0 with eta <= mg that the steady speed overflows")
    return v_x * math.exp(x)


def solve_balance(target: float, v_x: float, n: float, tol: Tolerances = DEFAULT) -> float:
    """The positive root of g_n(u) = target: closed forms for n = 0
    (u = v_x K / sqrt(1 - K^2), K = target) and n = 1 (u = target), else
    :func:`solve_balance_bracketing`."""
    if n == 0.0:
        if not target < 1.0:
            raise InvalidInput("eta", "the n = 0 balance v_y/|v| = mg/eta needs eta > mg")
        return v_x * target / math.sqrt((1.0 - target) * (1.0 + target))
    if n == 1.0:
        return float(target)
    return solve_balance_bracketing(target, v_x, n, tol)


def newton_v_y(v_x: float, mg: float, eta: float, n: float, tol: Tolerances = DEFAULT) -> float:
    """Steady speed along the external force by Newton's law, (2.27)-(2.29):
    mg / eta = v_y (v_x^2 + v_y^2)^((n-1)/2)."""
    sc = ParticleScene.create(v_x, mg, eta, n)
    return solve_balance(sc.load, sc.v_x, sc.n, tol)


def mpp_v_y(v_x: float, mg: float, eta: float, n: float, tol: Tolerances = DEFAULT) -> float:
    """The minimiser of the power (2.30), from its stationarity (2.31)-(2.32):
    mg / eta = (n + 1) v_y (v_x^2 + v_y^2)^((n-1)/2). (2.30) is convex in v_y (a power
    >= 1 of the norm |v| plus a linear term), so the stationary point is the minimum."""
    sc = ParticleScene.create(v_x, mg, eta, n)
    return solve_balance(sc.load / (sc.n + 1.0), sc.v_x, sc.n, tol)
