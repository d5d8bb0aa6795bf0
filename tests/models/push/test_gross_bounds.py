"""Exact bounds on gross motions from the exact COR sketch (book 4.2-4.4), against the
book's closed forms (models/push/gross_motion.py) and against simulated pushes of random
pressure distributions (solver/push/simulate.py): no simulation may beat a bound."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.support import random_balanced_tripods
from models.push import gross_motion as gm
from models.push.gross_bounds import encounter_bounds_exact, fence_push_bound_exact
from solver.push.simulate import simulate_disk_encounter_batch, simulate_fence_alignment_batch
from tests.scenes import SEED

# The book's 4.3 example reconstructed (models/push/gross_motion.py): alpha = 70 deg, mu_c =
# 0.25, c = 0.5746 a, beta from 45 to 80 deg, transition at 69.4 deg.
BOOK = dict(a=1.0, c=0.5746, alpha=math.radians(70.0), beta_initial=math.radians(45.0),
            beta_final=math.radians(80.0))


@pytest.mark.slow
def test_small_friction_gives_the_frictionless_closed_form():
    """mu_c -> 0: the slowest COR is the tip (3.37) and the bound is (3.41)."""
    b = fence_push_bound_exact(mu_c=1e-7, n_nodes=8, n_points=512, **BOOK)
    ref = gm.fence_push_frictionless(BOOK["a"], BOOK["c"], BOOK["alpha"], BOOK["beta_initial"], BOOK["beta_final"])
    assert abs(b.value - ref) < 1e-3 * ref


@pytest.mark.slow
def test_book_example_exact_bound_is_slightly_above_the_closed_form():
    """4.3: the book's tip-line construction neglects the dip of the sticking locus below
    the tip line; the exact bound is above it, but within a percent."""
    b = fence_push_bound_exact(mu_c=0.25, n_nodes=8, **BOOK)
    assert b.book_value is not None
    assert b.book_value < b.value < 1.01 * b.book_value
    assert b.quadrature_error < 3e-3 * b.value
    assert {"sticking"} <= set(b.sources)


@pytest.mark.slow
def test_no_simulated_fence_push_beats_the_exact_bounds():
    """Random tripods and diametral dipods pushed by the fence with friction (mu_c = 1,
    where the book's closed form is beaten by ~1 %): every push lies between the exact
    shortest and longest bounds."""
    geo = dict(a=1.0, c=0.9, alpha=math.radians(60.0), beta_initial=math.radians(35.0), beta_final=math.radians(75.0))
    longest = fence_push_bound_exact(mu_c=1.0, n_nodes=8, n_points=256, **geo)
    shortest = fence_push_bound_exact(mu_c=1.0, n_nodes=8, n_points=256, longest=False, **geo)
    rng = np.random.default_rng(SEED)
    pts, wts = random_balanced_tripods(rng, 60, 1.0)
    ang = rng.uniform(0, math.pi, 40)
    dip = np.stack([np.column_stack([np.cos(ang), np.sin(ang)]), -np.column_stack([np.cos(ang), np.sin(ang)])], axis=1)
    pts = np.concatenate([pts, np.pad(dip, ((0, 0), (0, 1), (0, 0)))])
    wts = np.concatenate([wts, np.tile([0.5, 0.5, 0.0], (40, 1))])
    sim = simulate_fence_alignment_batch(pts, wts, mu_c=1.0, n_steps=64, **geo)
    slack = 2e-3 * longest.value
    assert sim.push.max() <= longest.value + slack
    assert sim.push.min() >= shortest.value - slack
    # and the book's closed form is beaten here (models/push/gross_motion.py findings)
    assert longest.book_value is None or longest.value > longest.book_value


@pytest.mark.slow
@pytest.mark.parametrize("beta_deg", [30.0, 60.0])
def test_disk_encounter_exact_bounds_hold_the_simulations(beta_deg):
    """4.4: length and rotation of the encounter for random supports lie within the exact
    bounds; the greatest rotation is pi/2 - beta_initial exactly (re-derived (4.18)); the
    book's greatest length (4.16) is beaten at mu_c = 5, the exact bound is not."""
    bi = math.radians(beta_deg)
    bounds = encounter_bounds_exact(1.0, bi, 5.0, n_nodes=8, n_points=256)
    assert abs(bounds["rotation_max"].value - (0.5 * math.pi - bi)) < 1e-9
    rng = np.random.default_rng(SEED + 1)
    pts, wts = random_balanced_tripods(rng, 60, 1.0)
    sim = simulate_disk_encounter_batch(pts, wts, 1.0, bi, 5.0, n_steps=48)
    tol = 2e-3
    assert sim.push.max() <= bounds["length_max"].value * (1 + tol)
    assert sim.push.min() >= bounds["length_min"].value * (1 - tol)
    assert sim.rotation.max() <= bounds["rotation_max"].value * (1 + tol)
    assert sim.rotation.min() >= bounds["rotation_min"].value * (1 - tol)
    assert bounds["length_max"].value >= bounds["length_max"].book_value


def test_bad_ranges_are_refused():
    with pytest.raises(InvalidInput):
        encounter_bounds_exact(1.0, 1.7, 0.5)
    with pytest.raises(InvalidInput):
        fence_push_bound_exact(mu_c=0.25, n_nodes=2, **BOOK)


@pytest.mark.slow
@pytest.mark.parametrize("beta_deg", [1e-4, 0.5, 5.0])
def test_small_collision_parameter_is_integrated_accurately(beta_deg):
    """4.4 near beta_i -> 0 the rates grow like 1/sin(beta) ((4.15)); the exact greatest
    length must stay within a few percent of (4.16) (which it may exceed only by the dip of
    the sticking locus) and its quadrature error estimate must be honest."""
    bi = math.radians(beta_deg)
    b = encounter_bounds_exact(1.0, bi, 0.5, n_nodes=8, n_points=128)["length_max"]
    assert b.book_value is not None
    assert 0.9 * b.book_value < b.value < 1.05 * b.book_value
    assert b.quadrature_error < 0.02 * b.value


def test_head_on_push_is_refused_on_beta_initial():
    """beta_i = 5e-324 (a subnormal; ln tan(beta/2) must not underflow to log(0)): the
    push is head-on at the first nodes, the disk only translates and the encounter has no
    end, which is an input error on beta_initial, not a crash."""
    with pytest.raises(InvalidInput) as e:
        encounter_bounds_exact(1.0, 5e-324, 1.0, n_nodes=4, n_points=8)
    assert e.value.field == "beta_initial"


@pytest.mark.slow
def test_fence_slip_bounds_hold_every_simulated_support():
    """How far the pusher slips along the fence: the slip rate of every simulated support's
    COR (forward solves) lies between the sketch's extremes at that beta; the rate formula
    equals the scene's own slip per push times dx/dbeta; sticking CORs do not slip."""
    from models.core.scene import PushScene
    from models.push.gross_bounds import extreme_over_sketch, fence_slip_bounds_exact, fence_slip_rate
    from models.sketch.disk_sketch import disk_cor_sketch

    geo = dict(a=1.0, c=0.9, alpha=math.radians(60.0), beta_initial=math.radians(35.0), beta_final=math.radians(75.0))
    mu_c = 0.3
    hi, lo = fence_slip_bounds_exact(mu_c=mu_c, n_nodes=6, n_points=256, **geo)
    assert hi.value >= lo.value
    rng = np.random.default_rng(SEED + 3)
    pts, wts = random_balanced_tripods(rng, 60, 1.0)
    sim = simulate_fence_alignment_batch(pts, wts, mu_c=mu_c, n_steps=8, **geo)
    c, alpha = geo["c"], geo["alpha"]
    for k in (0, len(sim.beta_nodes) // 2, len(sim.beta_nodes) - 1):
        beta = float(sim.beta_nodes[k])
        scene = PushScene.create(1.0, c * np.array([-math.cos(beta), math.sin(beta)]), alpha, 0.0)
        sk = disk_cor_sketch(scene, mu_c, n_points=1024)
        top = extreme_over_sketch(sk, lambda r: fence_slip_rate(beta, c, alpha, r), True)[0]
        bottom = extreme_over_sketch(sk, lambda r: fence_slip_rate(beta, c, alpha, r), False)[0]
        cors = sim.cor[k][np.all(np.isfinite(sim.cor[k]), axis=1)]
        rates = fence_slip_rate(beta, c, alpha, cors)
        scale = max(1.0, abs(top), abs(bottom))
        assert rates.max() <= top + 2e-3 * scale and rates.min() >= bottom - 2e-3 * scale
        # the formula against the scene: slip per push times dx/dbeta
        r0 = cors[0]
        expect = scene.slip_per_push(r0) * gm.fence_rate(beta, c, alpha, r0[None])[0]
        assert math.isclose(rates[0], expect, rel_tol=1e-9, abs_tol=1e-12)
        stick = sim.mode[k] == 1
        if stick.any():
            assert np.abs(fence_slip_rate(beta, c, alpha, sim.cor[k][stick])).max() < 1e-8


def _simpson(values: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Composite Simpson over equally spaced nodes (odd count) along axis 0."""
    h = (x[-1] - x[0]) / (len(x) - 1)
    w = np.ones(len(x))
    w[1:-1:2], w[2:-1:2] = 4.0, 2.0
    return h / 3.0 * (w @ values)


@pytest.mark.slow
@pytest.mark.parametrize("mu_c", [0.0, 0.3])
def test_fence_slip_over_the_whole_turn_stays_within_the_exact_bounds(mu_c):
    """Issue 4 / 4.3: the total slip of the fence along the part while it turns from
    beta_initial to beta_final, integrated for each simulated support (forward solves at
    every beta node, Simpson), never leaves [slip_min, slip_max] of the exact sketch; the
    push bounds come out of the same sketches. mu_c = 0 uses the frictionless locus, where
    the longest and shortest push are the closed forms (3.41) and the r_min push."""
    from models.push.fence_geometry import frictionless_push_bounds
    from models.push.gross_bounds import fence_bounds_exact, fence_slip_rate

    geo = dict(a=1.0, c=0.9, alpha=math.radians(60.0), beta_initial=math.radians(35.0), beta_final=math.radians(75.0))
    b = fence_bounds_exact(mu_c=mu_c, n_nodes=8, n_points=512, **geo)
    rng = np.random.default_rng(SEED + 11)
    pts, wts = random_balanced_tripods(rng, 80, 1.0)
    sim = simulate_fence_alignment_batch(pts, wts, mu_c=mu_c, n_steps=32, **geo)
    assert sim.converged
    rates = np.stack([fence_slip_rate(float(beta), geo["c"], geo["alpha"], sim.cor[k])
                      for k, beta in enumerate(sim.beta_nodes)])
    total = _simpson(rates, sim.beta_nodes)
    slack = 1e-3 + b["slip_max"].quadrature_error + b["slip_min"].quadrature_error
    assert total.max() <= b["slip_max"].value + slack
    assert total.min() >= b["slip_min"].value - slack
    assert b["slip_min"].value < total.min() and total.max() < b["slip_max"].value + slack  # not vacuous: spread
    assert sim.push.max() <= b["push_max"].value + 1e-3 and sim.push.min() >= b["push_min"].value - 1e-3
    if mu_c == 0.0:
        longest, shortest = frictionless_push_bounds(**geo)
        # Gauss-Legendre with 8 nodes: agreement within the reported quadrature error
        assert abs(b["push_max"].value - longest) <= b["push_max"].quadrature_error
        assert abs(b["push_min"].value - shortest) <= max(b["push_min"].quadrature_error, 1e-9)


@pytest.mark.slow
def test_fence_bounds_share_sketches_and_match_the_single_bounds():
    """One sketch per node serves all four bounds: the values equal the bounds computed
    alone (fence_push_bound_exact, fence_slip_bounds_exact) and an unknown key is refused."""
    from models.push.gross_bounds import fence_bounds_exact, fence_slip_bounds_exact

    allb = fence_bounds_exact(mu_c=0.25, n_nodes=4, n_points=64, **BOOK)
    assert allb["push_max"].value == fence_push_bound_exact(mu_c=0.25, n_nodes=4, n_points=64, **BOOK).value
    assert allb["push_min"].value == fence_push_bound_exact(mu_c=0.25, n_nodes=4, n_points=64, longest=False, **BOOK).value
    hi, lo = fence_slip_bounds_exact(mu_c=0.25, n_nodes=4, n_points=64, **BOOK)
    assert (allb["slip_max"].value, allb["slip_min"].value) == (hi.value, lo.value)
    with pytest.raises(InvalidInput) as e:
        fence_bounds_exact(mu_c=0.25, n_nodes=4, n_points=64, which=("push_mean",), **BOOK)
    assert e.value.field == "which"
