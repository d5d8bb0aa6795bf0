"""Spiral localization, the pure part (models/spiral/path.py; book 4.5): the exact recursion
(4.26) and the optimality of greedy schedules, the path length and polyline, the power-law
fit of figure 4-21, and which revolutions a table shows unsafe."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.tolerances import SpiralTolerances
from models.spiral.critical import (
    critical_envelope,
    tip_line_envelope,
)
from models.spiral.path import (
    fastest_spiral,
    power_law_fit,
    revolution_length,
    revolution_length_closed_form,
    spiral_path_length,
    spiral_polyline,
    tip_line_spiral,
)
from tests.models.spiral.synthetic import HALF_PI, synthetic_envelope
from tests.scenes import SEED

# ------------------------------------------------------------------ recursion (4.26)


def _bisection_next(env, y, max_step=None):
    """The least x with y - x <= D(x), by bisection on the nondecreasing g = x + D(x)."""
    def D(x):
        return env.d_star(x, max_step)

    if D(y) == 0.0:
        return y
    lo, hi = 0.0, y
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid + D(mid) >= y:
            hi = mid
        else:
            lo = mid
    return hi


@pytest.mark.slow
def test_exact_step_equals_bisection_and_g_is_nondecreasing():
    """The closed-form step of (4.26) is the least safe radius: it equals a bisection on
    g(x) = x + d*(x) (nondecreasing, checked) to rounding, and it is itself safe."""
    rng = np.random.default_rng(SEED)
    env = synthetic_envelope()
    xs = np.sort(rng.uniform(1.0, 120.0, 20_000))
    g = xs + env.d_star(xs)
    assert np.all(np.diff(g) > 0.0)
    for y in rng.uniform(env.b_floor, 110.0, 300):
        for cap in (None, 0.3):
            x = env.next_radius(y, cap)
            assert y - x <= env.d_star(x, cap)
            assert x == pytest.approx(_bisection_next(env, y, cap), abs=1e-12 * y)
    assert env.next_radius(env.b_floor * 0.999) == env.b_floor * 0.999  # below the floor: no step


def test_recursion_is_safe_and_stops_for_a_reason():
    env = synthetic_envelope()
    rec = fastest_spiral(env, 100.0, target=1.5, speed=2.0)
    assert rec.stop_reason == "target" and rec.reached_target and rec.radii[-1] <= 1.5 < rec.radii[-2]
    assert rec.max_step_excess <= 0.0
    assert np.all(rec.steps <= env.d_star(rec.radii[1:]))
    assert rec.revolutions == rec.radii.size
    assert rec.time_s == pytest.approx(rec.path_length / 2.0)
    stalled = fastest_spiral(env, 100.0, target=None)
    assert stalled.stop_reason == "stalled" and stalled.radii[-1] >= env.b_floor
    capped = fastest_spiral(env, 100.0, target=1.5, tol=SpiralTolerances(max_revolutions=50))
    assert capped.stop_reason == "max_revolutions" and capped.revolutions == 50
    below = fastest_spiral(env, env.b_floor * 0.99, target=1.0)
    assert below.stop_reason == "stalled" and below.revolutions == 1


def test_greedy_radii_are_elementwise_least():
    """Greedy optimality (models/spiral/path.py): every safe schedule, here random ones that
    take a random fraction of the safe step, stays elementwise above the recursion (4.26);
    with a maximum step as well."""
    rng = np.random.default_rng(SEED)
    env = synthetic_envelope()
    for cap in (None, 0.4):
        greedy = fastest_spiral(env, 60.0, target=1.4, max_step=cap).radii
        for _ in range(20):
            b = [60.0]
            while len(b) < greedy.size:
                x_min = env.next_radius(b[-1], cap)
                b.append(b[-1] - rng.uniform(0.0, 1.0) * (b[-1] - x_min))
            assert np.all(np.asarray(b) >= greedy - 1e-12)


def test_tip_line_table_recursion_is_safe_against_the_closed_form():
    """The envelope recursion on a tip-line table never steps beyond the closed-form
    tip-line recursion (it only rounds towards safety) and comes close on a dense table."""
    betas = np.unique(np.concatenate([np.geomspace(0.01, 1.0, 400), HALF_PI - np.geomspace(0.57, 1e-6, 400)]))
    env = tip_line_envelope(1.0, betas)
    rec = fastest_spiral(env, 100.0, target=2.5)
    closed = tip_line_spiral(1.0, 100.0, target=2.5)
    n = min(rec.revolutions, closed.size)
    assert np.all(rec.radii[:n] >= closed[:n] - 1e-12)
    assert rec.revolutions >= closed.size
    assert rec.revolutions <= 1.03 * closed.size


def test_scale_invariance_of_the_recursion():
    """Everything is linear in a: radii scale, revolutions do not."""
    base = synthetic_envelope(a=1.0)
    ref = fastest_spiral(base, 80.0, target=1.4)
    for a in (1e-3, 1e3):
        env = critical_envelope(base.betas, a * base.radii, a)
        rec = fastest_spiral(env, 80.0 * a, target=1.4 * a)
        assert rec.revolutions == ref.revolutions
        assert np.allclose(rec.radii / a, ref.radii, rtol=1e-12)
        assert rec.path_length / a == pytest.approx(ref.path_length, rel=1e-12)


# ------------------------------------------------------------------ path length, polyline


def test_revolution_length_against_closed_form_and_circles():
    """The stable quadrature of one Archimedean revolution against the antiderivative
    (where the latter is well conditioned), the circle 2 pi b, and a dense trapezoid."""
    for b0, b1 in ((10.0, 9.0), (3.0, 2.2), (100.0, 99.02), (1.3, 1.25)):
        L, err = revolution_length(b0, b1)
        assert L == pytest.approx(revolution_length_closed_form(b0, b1), rel=1e-11)
        assert err < 1e-12 * L
        th = np.linspace(0.0, 2 * math.pi, 400_001)
        rho = b0 + (b1 - b0) * th / (2 * math.pi)
        k = (b1 - b0) / (2 * math.pi)
        trap = np.trapezoid(np.sqrt(rho ** 2 + k ** 2), th)
        assert L == pytest.approx(trap, rel=1e-10)
    assert revolution_length(5.0, 5.0)[0] == pytest.approx(10.0 * math.pi, rel=1e-15)
    # tiny steps: the closed form cancels, the quadrature does not
    L, _ = revolution_length(1.25, 1.25 - 1e-12)
    assert L == pytest.approx(math.pi * (2.5 - 1e-12), rel=1e-15)


def test_revolution_length_increases_with_both_radii():
    """Used for the optimality of greedy for path length: L(b0, b1) grows in each radius
    for steps up to the radius (finite differences over random revolutions)."""
    rng = np.random.default_rng(SEED)
    b1 = rng.uniform(1.0, 100.0, 2000)
    b0 = b1 + rng.uniform(0.0, 1.0, 2000) * b1
    h = 1e-6 * b1
    L = revolution_length(b0, b1)[0]
    assert np.all(revolution_length(b0 + h, b1)[0] > L)
    assert np.all(revolution_length(b0, b1 + h)[0] > L)


def test_polyline_chord_deviation_bound_holds():
    """The reported chord deviation bounds the true distance between path and polyline
    (dense sampling), is close to the sagitta b(1 - cos(pi/m)) for a circle, and the
    polyline length tends to the path length."""
    radii = np.array([10.0, 9.2, 8.5, 8.0, 7.9])
    for m in (16, 64):
        pl = spiral_polyline(radii, points_per_revolution=m)
        assert pl.points.shape == ((radii.size) * m + 1, 2)
        assert np.allclose(pl.points[0], [0.0, 10.0])
        assert pl.points[1][0] > 0.0  # clockwise from the top: along +x
        dense = spiral_polyline(radii, points_per_revolution=m * 64)
        worst = 0.0
        for p, q, seg in zip(pl.points[:-1], pl.points[1:], np.split(dense.points[:-1], pl.points.shape[0] - 1)):
            d = q - p
            t = np.clip((seg - p) @ d / (d @ d), 0.0, 1.0)
            worst = max(worst, float(np.max(np.linalg.norm(seg - p - t[:, None] * d, axis=1))))
        assert worst <= pl.max_chord_deviation
        assert pl.max_chord_deviation <= 1.1 * worst + 1e-12
        circle = spiral_polyline([5.0], points_per_revolution=m)
        assert circle.max_chord_deviation == pytest.approx(5.0 * (1 - math.cos(math.pi / m)), rel=0.01)
    fine = spiral_polyline(radii, points_per_revolution=4096)
    assert fine.polyline_length == pytest.approx(spiral_path_length(radii)[0], rel=1e-6)


# ------------------------------------------------------------------ power-law fit


def test_power_law_fit_recovers_a_known_exponent():
    n = np.arange(1, 2001)
    b = 1.25 + 3.0 * n ** -1.6
    fit = power_law_fit(b, 1.25, 10, 1000)
    assert fit.exponent == pytest.approx(1.6, abs=1e-10)
    assert fit.coefficient == pytest.approx(3.0, rel=1e-9)
    assert (fit.n_min, fit.n_max, fit.n_points) == (10, 1000, 991)
    with pytest.raises(InvalidInput):
        power_law_fit(b[:2], 1.25)




def test_unsafe_revolutions_needs_a_witness_collision_parameter():
    """4.5.1/4.5.3: a step Delta b allows every beta' >= beta_Delta (4.24); the step is
    unsafe exactly when some tabulated r*(beta_k), beta_k >= beta_Delta, exceeds the new
    radius. A table with r* = 3 up to beta = 0.9 and 1.5 beyond: from 4 to 3.2 the step
    0.8 a reaches beta_Delta = asin(0.2) = 0.20 (r* = 3 < 3.2: safe); from 3.2 to 2.9 the
    step 0.3 a reaches beta = asin(0.7) = 0.775 < 0.9, where r* = 3 > 2.9: unsafe; a step
    of 0.01 a from 2.9 only meets beta >= 1.43 (r* = 1.5): safe."""
    from models.spiral.path import unsafe_revolutions

    betas = np.array([0.1, 0.5, 0.9, 1.0, 1.2, 1.5])
    r_star = np.array([3.0, 3.0, 3.0, 1.5, 1.5, 1.5])
    flags = unsafe_revolutions([4.0, 3.2, 2.9, 2.89], betas, r_star, 1.0)
    assert flags.tolist() == [False, True, False]
    # NaN table entries are ignored, not taken as witnesses
    flags = unsafe_revolutions([4.0, 3.2, 2.9], betas, np.where(betas < 0.95, np.nan, r_star), 1.0)
    assert flags.tolist() == [False, False]
