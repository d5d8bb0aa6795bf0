"""Spiral localization, the pure part (models/spiral.py; book 4.5): (4.24), (4.25), the
tip-line closed forms, the safe envelope d*(b), the exact recursion (4.26) and the
optimality of greedy schedules, the path length and polyline, the power-law fit of
figure 4-21. Synthetic tables stand in for r*(beta) (the solver tests use real ones)."""

from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np
import pytest

from models.errors import InvalidInput
from models.gross.gross_bounds import encounter_scene
from models.locus.cor_sketch import tip_line_estimate
from models.spiral import (
    arc_costs,
    collision_parameter,
    critical_envelope,
    distance_from_grazing,
    fastest_spiral,
    greedy_on_graph,
    limiting_radius,
    power_law_fit,
    revolution_length,
    revolution_length_closed_form,
    schedule_graph,
    schedule_grid,
    shortest_path_potentials,
    spiral_path_length,
    spiral_polyline,
    tip_line_critical_distance,
    tip_line_critical_radius,
    tip_line_envelope,
    tip_line_next_radius,
    tip_line_spiral,
)
from models.tolerances import SPIRAL_DEFAULT, SpiralTolerances
from tests.scenes import SEED

HALF_PI = 0.5 * math.pi


def synthetic_r_star(beta, mu=0.25):
    """A stand-in for r*(beta) with the real one's shape (solver tests): ~2/beta near 0,
    b_inf = 1 + mu at pi/2, decreasing."""
    beta = np.asarray(beta, dtype=float)
    return 2.0 / np.sin(beta) - (1.0 - mu) * np.sin(beta) ** 8


def synthetic_envelope(n=60, mu=0.25, a=1.0):
    betas = np.unique(np.concatenate([np.geomspace(0.015, 0.5, n // 3), np.linspace(0.5, HALF_PI - 0.1, n // 3),
                                      HALF_PI - np.geomspace(0.1, 1e-6, n // 3)]))
    return critical_envelope(betas, a * synthetic_r_star(betas, mu), a)


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
    so r*_tip = a sin b - y_COR = 2a/sin b; the same as models.locus.cor_sketch.tip_line_estimate
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
    """The claim of models/spiral.py: if every table value bounds r* on its cell
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
    """Greedy optimality (models/spiral.py): every safe schedule, here random ones that
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


# ------------------------------------------------------------------ grid schedules


def test_schedule_graph_arcs_are_exactly_the_safe_steps():
    """Brute force on a small grid: an arc i -> j iff x_i - x_j <= D(x_j) and >= min_step
    (up to one ulp towards safety)."""
    env = synthetic_envelope()
    x = schedule_grid(env, 8.0, 2.0, spacing=0.07)
    for ms, cap in ((None, None), (0.2, None), (None, 0.3), (0.1, 0.5)):
        g = schedule_graph(env, x, min_step=ms, max_step=cap)
        arcs = set(zip(g.tails.tolist(), g.heads.tolist()))
        D = env.d_star(x, cap)
        for i, j in itertools.product(range(x.size), repeat=2):
            if j >= i:
                continue
            step = x[i] - x[j]
            ok = step <= D[j] and (ms is None or step >= ms)
            if abs(step - D[j]) < 1e-12 or (ms is not None and abs(step - ms) < 1e-12):
                continue  # within rounding of the boundary
            assert ((i, j) in arcs) == ok


def test_greedy_on_a_grid_is_the_shortest_path():
    """Without a minimum step greedy is optimal on any grid, for revolutions and for path
    length (models/spiral.py): compared with the exact DAG shortest path (integer costs)
    over random tables and grids; the potentials certify it (reduced costs >= 0)."""
    rng = np.random.default_rng(SEED)
    base = synthetic_envelope()
    for trial in range(6):
        noisy = base.radii * (1.0 + 0.05 * rng.uniform(size=base.radii.size))
        env = critical_envelope(base.betas, noisy, 1.0)
        cap = None if trial % 2 == 0 else 0.35
        x = schedule_grid(env, 25.0, 2.6, resolution=int(rng.integers(2, 9)), max_step=cap)
        g = schedule_graph(env, x, max_step=cap)
        path = greedy_on_graph(g)
        assert path is not None
        for obj in ("revolutions", "length"):
            unit = 1.0 if obj == "revolutions" else 1e-7
            c = arc_costs(g, obj, unit)
            pot = shortest_path_potentials(g, c)
            rc = c + pot[g.tails] - pot[g.heads]
            assert rc[pot[g.tails] >= 0].min() >= 0
            if obj == "revolutions":
                assert pot[0] == path.size - 1
            else:
                L = sum(revolution_length(x[i], x[j])[0] for i, j in zip(path[:-1], path[1:]))
                assert abs(L / unit - pot[0]) <= 0.5 * (path.size - 1) + 1


def test_minimum_step_can_defeat_greedy():
    """With a minimum step greedy may get stuck (its last step would be too short) while
    another schedule reaches the target: why solver/spiral/schedule.py solves the shortest path."""
    env = synthetic_envelope()
    found = False
    for target in np.linspace(5.0, 8.0, 61):
        x = schedule_grid(env, 12.0, float(target), spacing=0.05)
        g = schedule_graph(env, x, min_step=0.5)
        pot = shortest_path_potentials(g, arc_costs(g, "revolutions", 1.0))
        if greedy_on_graph(g) is None and pot[0] >= 0:
            found = True
            break
    assert found


def test_tolerance_presets():
    assert SpiralTolerances.default() is SPIRAL_DEFAULT
    assert SpiralTolerances.fast().max_revolutions < SPIRAL_DEFAULT.max_revolutions
    assert SpiralTolerances.high_accuracy().grazing_delta < SPIRAL_DEFAULT.grazing_delta
    with pytest.raises(dataclasses.FrozenInstanceError):
        SPIRAL_DEFAULT.grazing_delta = 1.0  # type: ignore[misc]


def test_unsafe_revolutions_needs_a_witness_collision_parameter():
    """4.5.1/4.5.3: a step Delta b allows every beta' >= beta_Delta (4.24); the step is
    unsafe exactly when some tabulated r*(beta_k), beta_k >= beta_Delta, exceeds the new
    radius. A table with r* = 3 up to beta = 0.9 and 1.5 beyond: from 4 to 3.2 the step
    0.8 a reaches beta_Delta = asin(0.2) = 0.20 (r* = 3 < 3.2: safe); from 3.2 to 2.9 the
    step 0.3 a reaches beta = asin(0.7) = 0.775 < 0.9, where r* = 3 > 2.9: unsafe; a step
    of 0.01 a from 2.9 only meets beta >= 1.43 (r* = 1.5): safe."""
    from models.spiral import unsafe_revolutions

    betas = np.array([0.1, 0.5, 0.9, 1.0, 1.2, 1.5])
    r_star = np.array([3.0, 3.0, 3.0, 1.5, 1.5, 1.5])
    flags = unsafe_revolutions([4.0, 3.2, 2.9, 2.89], betas, r_star, 1.0)
    assert flags.tolist() == [False, True, False]
    # NaN table entries are ignored, not taken as witnesses
    flags = unsafe_revolutions([4.0, 3.2, 2.9], betas, np.where(betas < 0.95, np.nan, r_star), 1.0)
    assert flags.tolist() == [False, False]
