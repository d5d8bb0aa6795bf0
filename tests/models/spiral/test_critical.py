"""Spiral localization, the pure part (models/spiral/critical.py; book 4.5): (4.24), (4.25), the
tip-line closed forms and the safe envelope d*(b) of a table of critical radii (synthetic
tables stand in for r*(beta): tests/models/spiral/synthetic.py)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.tolerances import SPIRAL_DEFAULT, SpiralTolerances
from models.push.gross_bounds import encounter_scene
from models.sketch.disk_sketch import tip_line_estimate
from models.spiral.critical import (
    collision_parameter,
    critical_envelope,
    distance_from_grazing,
    limiting_radius,
    tip_line_critical_distance,
    tip_line_critical_radius,
    tip_line_next_radius,
)
from models.spiral.path import (
    tip_line_spiral,
)
from tests.models.spiral.synthetic import HALF_PI, synthetic_envelope, synthetic_r_star
from tests.scenes import SEED

# ------------------------------------------------------------------ (4.24), (4.25), tip line


def test_distance_from_grazing_round_trip():
    """(4.24) d = a(1 - sin beta) and its inverse, to rounding, also for d ~ 1e-14 a where
    asin(1 - d/a) would lose every digit of d."""
    rng = np.random.default_rng(SEED)
    for a in (1e-3, 1.0, 1e3):
        beta = rng.uniform(-HALF_PI, HALF_PI, 200)
        d = distance_from_grazing(a, beta)
        assert np.allclose(d, a * (1.0 - np.sin(beta)), rtol=1e-12, atol=1e-15 * a)
        assert np.allclose(collision_parameter(a, d), beta, atol=1e-12)
        tiny = a * np.geomspace(1e-14, 1e-6, 9)
        back = distance_from_grazing(a, collision_parameter(a, tiny))
        assert np.allclose(back, tiny, rtol=1e-9)
    assert distance_from_grazing(1.0, HALF_PI) == 0.0
    assert distance_from_grazing(2.0, 0.0) == pytest.approx(2.0)
    with pytest.raises(InvalidInput):
        collision_parameter(1.0, 2.5)
    with pytest.raises(InvalidInput):
        distance_from_grazing(1.0, 2.0)


def test_limiting_radius_closed_form():
    """(4.25): a(1 + mu_c) up to mu_c = 1, then 2a; continuous at 1; a at mu_c = 0 (4.5.4:
    'only at mu_c = 0 can a disk be localized completely')."""
    assert limiting_radius(1.0, 0.25) == 1.25
    assert limiting_radius(2.0, 0.5) == 3.0
    assert limiting_radius(1.0, 1.0) == 2.0
    assert limiting_radius(1.0, 5.0) == 2.0
    assert limiting_radius(3.0, 0.0) == 3.0
    with pytest.raises(InvalidInput):
        limiting_radius(1.0, -0.1)


def test_tip_line_radius_is_the_books_construction():
    """4.4.1.1, (4.13): the tip line meets the sticking line at y_COR = a(sin^2 b - 2)/sin b,
    so r*_tip = a sin b - y_COR = 2a/sin b; the same as models.sketch.disk_sketch.tip_line_estimate
    on the encounter scene. Its grazing limit is 2a (for every mu_c)."""
    for a in (1e-3, 1.0, 1e3):
        for beta in (0.05, 0.4, 1.0, 1.5, HALF_PI - 1e-6):
            y_cor = a * (math.sin(beta) ** 2 - 2.0) / math.sin(beta)
            r = tip_line_critical_radius(a, beta)
            assert r == pytest.approx(a * math.sin(beta) - y_cor, rel=1e-12)
            assert r == pytest.approx(-tip_line_estimate(encounter_scene(a, beta)), rel=1e-12)
    assert tip_line_critical_radius(1.0, HALF_PI - 1e-6) == pytest.approx(2.0, abs=1e-11)


def test_tip_line_recursion_closed_form():
    """(4.26) with the tip-line d*(r) = a(1 - 2a/r) solved in closed form; each step
    satisfies b_{n-1} - b_n = d*(b_n) exactly; the radii fall to 2a geometrically."""
    a = 1.0
    b = tip_line_spiral(a, 100.0, target=2.0 + 1e-9)
    steps = -np.diff(b)
    assert np.allclose(steps, tip_line_critical_distance(a, b[1:]), rtol=1e-12, atol=1e-14)
    assert b[-1] <= 2.0 + 1e-9 and b[-1] > 2.0
    e = b - 2.0
    tail = e[-20:] / e[-21:-1]
    assert np.allclose(tail, 2.0 / 3.0, atol=1e-3)  # d* ~ (r - 2a)/2 near 2a: e_n = e_{n-1}/(3/2)
    assert tip_line_next_radius(a, 1.5) == 1.5


# ------------------------------------------------------------------ the safe envelope


def test_envelope_is_safe_when_table_values_bound_their_cells():
    """The claim of models/spiral/critical.py: if every table value bounds r* on its cell
    [beta_k, beta_{k+1}), then r*(beta') <= b for every beta' >= beta*(b). Checked on a
    NON-monotone r* (a bump between grid points) with cell maxima as table values; with
    mere point values the same bump breaks it (the monotonicity the real tables show is
    what makes point values enough)."""
    rng = np.random.default_rng(SEED)
    grid = np.linspace(0.2, HALF_PI - 1e-3, 25)
    bump_at = 0.5 * (grid[14] + grid[15])  # between two grid points: point values miss it

    def bumpy(beta):
        return synthetic_r_star(beta) + 0.3 * np.exp(-((beta - bump_at) / 0.004) ** 2)

    fine = np.linspace(0.2, HALF_PI - 1e-9, 400_001)
    vals = bumpy(fine)
    tail_max = np.maximum.accumulate(vals[::-1])[::-1]  # sup of r* over beta' >= fine[i]
    cell = np.searchsorted(grid, fine, side="right") - 1
    upper = np.array([vals[cell == k].max() for k in range(grid.size)]) * (1 + 1e-12)
    env = critical_envelope(grid, upper, 1.0)
    point = critical_envelope(grid, bumpy(grid), 1.0)
    assert env.n_violations > 0 and env.max_increase > 0.0  # the bump shows up in the table
    b = rng.uniform(env.b_floor, env.envelope[0], 2000)
    k = env.index(b)
    assert np.all(tail_max[np.searchsorted(fine, env.betas[k])] <= b)
    kp = point.index(b)
    ok = kp < grid.size
    unsafe = tail_max[np.searchsorted(fine, point.betas[kp[ok]])] > b[ok]
    assert unsafe.any()
    # d* and beta* agree with (4.24)
    assert np.allclose(env.d_star(b), distance_from_grazing(1.0, env.beta_star(b)), atol=1e-15)
    # below the floor there is no guarantee
    assert env.d_star(env.b_floor * (1 - 1e-12)) == 0.0 and math.isnan(env.beta_star(env.b_floor * (1 - 1e-12)))


def test_d_star_is_nondecreasing_and_never_interpolates():
    """d*(b) is a nondecreasing step function whose values are table distances; with a
    monotone table it is the largest tabulated d whose r*_k <= b (no interpolation)."""
    env = synthetic_envelope()
    b = np.linspace(env.b_floor * 0.99, 150.0, 20_001)
    d = env.d_star(b)
    assert np.all(np.diff(d) >= 0.0)
    assert set(np.unique(d)) <= set(env.distances) | {0.0}
    for bb in (1.3, 2.0, 5.0, 40.0):
        ok = env.radii <= bb
        assert env.d_star(bb) == env.distances[ok].max()
    assert env.max_increase <= 0.0 and env.n_violations == 0




def test_tolerance_presets():
    assert SpiralTolerances.default() is SPIRAL_DEFAULT
    assert SpiralTolerances.fast().max_revolutions < SPIRAL_DEFAULT.max_revolutions
    assert SpiralTolerances.high_accuracy().grazing_delta < SPIRAL_DEFAULT.grazing_delta
    with pytest.raises(dataclasses.FrozenInstanceError):
        SPIRAL_DEFAULT.grazing_delta = 1.0  # type: ignore[misc]
