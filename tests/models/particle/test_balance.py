"""The particle of book 2.5 (figure 2-2): Newton (2.27)-(2.29) against the minimum power
principle (2.30)-(2.32), each answer checked by an independent computation.

Convention (models/particle/balance.py): v_y is the speed along the external force, so the world
velocity is (v_x, -v_y) and both answers are positive."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.tolerances import DEFAULT
from models.particle import balance as mp


def newton_closed_form_n0(v_x, k):
    """n = 0: the dissipative force has magnitude eta, its y part eta v_y/|v| = mg, so
    sin(theta) = k with theta the angle of the velocity below the x axis."""
    return v_x * math.tan(math.asin(k))


def quartic_root(v_x, k, n):
    """Independent closed forms of g_n(u) = k for n = 2 and n = 1/2 (quadratics in u^2):
    n = 2:   u^2 (v_x^2 + u^2) = k^2         -> u^2 = 2 k^2 / (v_x^2 + sqrt(v_x^4 + 4 k^2))
    n = 1/2: u^4 = k^4 (v_x^2 + u^2)         -> u^2 = (k^4 + sqrt(k^8 + 4 k^4 v_x^2)) / 2"""
    if n == 2.0:
        return math.sqrt(2.0 * k * k / (v_x**2 + math.sqrt(v_x**4 + 4.0 * k * k)))
    if n == 0.5:
        return math.sqrt(0.5 * (k**4 + math.sqrt(k**8 + 4.0 * k**4 * v_x**2)))
    raise AssertionError(n)


def y_force_balance(v_y, v_x, mg, eta, n):
    """Sum of the y forces on the particle at world velocity (v_x, -v_y), from the vectors:
    external (0, -mg) plus dissipative -eta |v|^n v/|v|. Zero at a steady state (2.27)."""
    v = np.array([v_x, -v_y])
    speed = float(np.linalg.norm(v))
    dissipative = -eta * speed**n * v / speed
    return float(dissipative[1] - mg)


def golden_min(f, lo, hi, iters=200):
    """Golden-section minimum of a unimodal f on [lo, hi] (no derivatives, no roots)."""
    g = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = lo, hi
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = f(c), f(d)
    for _ in range(iters):
        if fc < fd:
            b, d, fd = d, c, fc
            c = b - g * (b - a)
            fc = f(c)
        else:
            a, c, fc = c, d, fd
            d = a + g * (b - a)
            fd = f(d)
    return 0.5 * (a + b)


CASES = [  # (v_x, mg, eta)
    (1.0, 1.0, 2.0),
    (0.3, 2.0, 5.0),
    (7.0, 0.2, 0.9),
    (1e-3, 1.0, 1.5),
]


@pytest.mark.parametrize("v_x,mg,eta", CASES)
def test_coulomb_n0_newton_and_mpp_agree(v_x, mg, eta):
    """2.5.2: for n = 0 (Coulomb friction) (2.32) is (2.29): the two answers agree."""
    newton = mp.newton_v_y(v_x, mg, eta, 0.0)
    mpp = mp.mpp_v_y(v_x, mg, eta, 0.0)
    assert mpp == pytest.approx(newton, rel=1e-10)
    assert newton == pytest.approx(newton_closed_form_n0(v_x, mg / eta), rel=1e-12)
    assert abs(y_force_balance(newton, v_x, mg, eta, 0.0)) <= 1e-12 * mg


@pytest.mark.parametrize("v_x,mg,eta", CASES)
def test_viscous_n1_mpp_is_half_of_newton(v_x, mg, eta):
    """n = 1: (2.29) gives v_y = mg/eta, (2.32) gives mg/(2 eta): half the correct speed."""
    newton = mp.newton_v_y(v_x, mg, eta, 1.0)
    mpp = mp.mpp_v_y(v_x, mg, eta, 1.0)
    assert newton == pytest.approx(mg / eta, rel=1e-14)
    assert mpp / newton == pytest.approx(0.5, rel=1e-14)
    assert abs(y_force_balance(newton, v_x, mg, eta, 1.0)) <= 1e-12 * mg
    # the minimum power answer violates Newton's balance by exactly half the load
    assert y_force_balance(mpp, v_x, mg, eta, 1.0) == pytest.approx(-0.5 * mg, rel=1e-12)


@pytest.mark.parametrize("n", [2.0, 0.5])
@pytest.mark.parametrize("v_x,mg,eta", CASES)
def test_n2_and_n_half_match_independent_closed_forms(n, v_x, mg, eta):
    """Newton is the root of g_n(u) = mg/eta, the MPP the root of g_n(u) = mg/((n+1) eta):
    the disagreement is exactly the ratio of the two closed-form roots."""
    k = mg / eta
    newton = mp.newton_v_y(v_x, mg, eta, n)
    mpp = mp.mpp_v_y(v_x, mg, eta, n)
    assert newton == pytest.approx(quartic_root(v_x, k, n), rel=1e-12)
    assert mpp == pytest.approx(quartic_root(v_x, k / (n + 1.0), n), rel=1e-12)
    predicted = quartic_root(v_x, k / (n + 1.0), n) / quartic_root(v_x, k, n)
    assert mpp / newton == pytest.approx(predicted, rel=1e-12)
    assert mpp < newton  # g_n is increasing and the MPP's load is smaller
    assert abs(y_force_balance(newton, v_x, mg, eta, n)) <= 1e-12 * mg


@pytest.mark.parametrize("n", [0.5, 2.0, 3.0])
def test_disagreement_limits(n):
    """g_n(u) ~ u v_x^(n-1) for u << v_x and ~ u^n for u >> v_x, so mpp/newton tends to
    1/(n+1) for a light load and to (n+1)^(-1/n) for a heavy one."""
    # (u / v_x)^2 and (v_x / u)^2, the relative corrections, are below 1e-9 here
    light = mp.mpp_v_y(1e10, 1.0, 1.0, n) / mp.newton_v_y(1e10, 1.0, 1.0, n)
    heavy = mp.mpp_v_y(1e-10, 1.0, 1.0, n) / mp.newton_v_y(1e-10, 1.0, 1.0, n)
    assert light == pytest.approx(1.0 / (n + 1.0), rel=1e-6)
    assert heavy == pytest.approx((n + 1.0) ** (-1.0 / n), rel=1e-6)


@pytest.mark.parametrize("n", [0.0, 0.5, 1.0, 2.0, 4.5])
def test_mpp_is_the_minimum_of_the_power_2_30(n):
    """A derivative-free minimisation of (2.30) lands on the MPP answer, and for n > 0 the
    Newtonian (true) motion dissipates more: the principle prefers the wrong motion."""
    sc = mp.ParticleScene.create(0.8, 1.0, 1.7, n)
    mpp = mp.mpp_v_y(sc.v_x, sc.mg, sc.eta, n)
    newton = mp.newton_v_y(sc.v_x, sc.mg, sc.eta, n)
    brute = golden_min(lambda u: float(mp.power(u, sc)), -10.0, 10.0)
    assert brute == pytest.approx(mpp, rel=1e-6)  # golden section: sqrt(eps) accuracy
    assert abs(float(mp.power_derivative(mpp, sc))) <= 1e-12
    if n > 0:
        assert float(mp.power(mpp, sc)) < float(mp.power(newton, sc))
    # convexity of (2.30) on a grid: non-negative second differences
    u = np.linspace(-5.0, 5.0, 2001)
    assert np.all(np.diff(mp.power(u, sc), 2) >= -1e-12)


@pytest.mark.parametrize("n", [0.0, 0.5, 1.0, 2.0])
def test_terminal_velocity_of_the_dynamics_is_newtons(n):
    """Integrating m du/dt = mg - eta |v|^(n-1) u (RK4) from rest reaches the Newtonian
    speed (2.29), not the minimum power one (book 2.5: the steady state after the transient)."""
    v_x, m, mg, eta = 1.0, 1.0, 1.0, 2.0

    def rate(u):
        return (mg - eta * (v_x * v_x + u * u) ** (0.5 * (n - 1.0)) * u) / m

    u, dt = 0.0, 0.01
    for _ in range(6000):
        k1 = rate(u)
        k2 = rate(u + 0.5 * dt * k1)
        k3 = rate(u + 0.5 * dt * k2)
        k4 = rate(u + dt * k3)
        u += dt * (k1 + 2 * k2 + 2 * k3 + k4) / 6.0
    assert u == pytest.approx(mp.newton_v_y(v_x, mg, eta, n), rel=1e-9)
    if n > 0:
        assert abs(u - mp.mpp_v_y(v_x, mg, eta, n)) > 0.1 * u


@pytest.mark.parametrize("n", [0.0, 1.0])
def test_bracketing_root_agrees_with_the_closed_forms(n):
    """The bracketing iteration (used for every n but 0 and 1) reproduces the closed forms
    over eleven decades of the load."""
    rng = np.random.default_rng(7)
    for _ in range(40):
        v_x = 10.0 ** rng.uniform(-4, 4)
        k = 10.0 ** rng.uniform(-6, 5) if n else rng.uniform(1e-6, 0.999)
        assert mp.solve_balance_bracketing(k, v_x, n) == pytest.approx(mp.solve_balance(k, v_x, n), rel=1e-13)


@pytest.mark.parametrize("n", [1e-3, 0.3, 1.7, 6.0, 60.0])
def test_bracketing_root_residual_over_wide_ranges(n):
    rng = np.random.default_rng(11)
    for _ in range(40):
        v_x = 10.0 ** rng.uniform(-4, 4)
        k = 10.0 ** rng.uniform(-6, 0.5 if n > 0.1 else 0.0)  # k > 1, n -> 0: u overflows
        u = mp.solve_balance_bracketing(k, v_x, n)
        # documented accuracy of u: root_rtol max(1, |log(u/v_x)|); g amplifies it by
        # d log g / d log u <= max(1, n), and evaluating g costs a few n eps more.
        rel_u = DEFAULT.root_rtol * max(1.0, abs(math.log(u / v_x)))
        bound = max(1.0, n) * (rel_u + 8.0 * np.finfo(float).eps)
        assert abs(float(mp.balance_function(u, v_x, n)) / k - 1.0) <= bound


@pytest.mark.parametrize(
    "kwargs,field",
    [
        (dict(v_x=1.0, mg=1.0, eta=0.0, n=1.0), "eta"),
        (dict(v_x=1.0, mg=1.0, eta=-2.0, n=1.0), "eta"),
        (dict(v_x=1.0, mg=1.0, eta=2.0, n=-0.5), "n"),
        (dict(v_x=0.0, mg=1.0, eta=2.0, n=1.0), "v_x"),
        (dict(v_x=-1.0, mg=1.0, eta=2.0, n=1.0), "v_x"),
        (dict(v_x=1.0, mg=0.0, eta=2.0, n=1.0), "mg"),
        (dict(v_x=1.0, mg=1.0, eta=2.0, n=float("nan")), "n"),
        (dict(v_x=float("inf"), mg=1.0, eta=2.0, n=1.0), "v_x"),
        (dict(v_x=1.0, mg="heavy", eta=2.0, n=1.0), "mg"),
        # Coulomb friction no stronger than the load: no quasi-static steady state
        (dict(v_x=1.0, mg=1.0, eta=1.0, n=0.0), "eta"),
        (dict(v_x=1.0, mg=3.0, eta=2.0, n=0.0), "eta"),
    ],
)
def test_invalid_inputs_raise(kwargs, field):
    for fn in (mp.newton_v_y, mp.mpp_v_y, mp.ParticleScene.create):
        with pytest.raises(InvalidInput) as err:
            fn(**kwargs)
        assert err.value.field == field


def test_eta_below_mg_is_fine_for_velocity_dependent_friction():
    """For n > 0 the dissipative force grows with speed, so any eta > 0 has a steady state."""
    u = mp.newton_v_y(1.0, 3.0, 2.0, 1.0)
    assert u == pytest.approx(1.5, rel=1e-14)


def test_steady_speed_overflow_is_an_input_error():
    with pytest.raises(InvalidInput) as err:
        mp.newton_v_y(1.0, 3.0, 1.0, 1e-3)  # (mg/eta)^(1/n) = 3^1000
    assert err.value.field == "n"
