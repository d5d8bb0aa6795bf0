"""Spiral localization of a disk (solver/spiral/critical_radius.py; book 4.5): r*(beta) exact / sweep /
tip line, the limiting radius (4.25), the critical case of 4.5.2 checked on the whole COR
sketch, the kink of figure 4-19, the fastest spiral on OR-Tools against the recursion
(4.26), and the exponent of figure 4-21.

Heavy exact tables live in tests/benchmarks/test_bench_spiral.py; here a module fixture
holds six exact points."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.mpp import perp
from models.push.gross_bounds import encounter_scene
from models.sketch.disk_sketch import disk_cor_sketch
from models.spiral.critical import critical_envelope, tip_line_critical_radius
from solver.core.budget import Budget
from solver.spiral.critical_radius import (
    INVERSE_BETA_TOL,
    CriticalRadiusProblem,
    critical_beta,
    critical_distance,
    critical_radii,
    critical_radius,
    critical_radius_table,
    kink_beta,
    limiting_radius_check,
)
from solver.spiral.schedule import spiral_schedule
from tests.budgets import checks_budget

HALF_PI = 0.5 * math.pi








# ------------------------------------------------------------------ r*(beta)


@pytest.mark.slow
def test_exact_and_sweep_agree(exact_025, sweep_025):
    """The certified lower end of the sticking locus and the book's force-angle sweep
    (4.1.4) agree to ~1e-5 a; every exact point is certified with a bracket <= 1e-6 a."""
    assert exact_025.complete and exact_025.certified.all()
    assert np.all(exact_025.widths <= 1e-6)
    assert np.all(exact_025.radii >= exact_025.midpoints)  # the outside end is the safe one
    assert np.max(np.abs(exact_025.midpoints - sweep_025.radii)) < 1e-4


@pytest.mark.slow
def test_r_star_decreases_with_beta(exact_025, dense_sweep_025):
    """r*(beta) falls monotonically to b_inf (figure 4-19): no increase along either table,
    so point values bound their cells and the envelope loses nothing."""
    assert exact_025.envelope.max_increase < 0.0 and exact_025.envelope.n_violations == 0
    assert dense_sweep_025.envelope.n_violations == 0
    assert np.allclose(exact_025.envelope.envelope, exact_025.radii)


@pytest.mark.slow
def test_limiting_radius_matches_4_25():
    """(4.25): r*(pi/2 - 1e-6), exact, is a(1 + mu_c) for mu_c <= 1 and 2a for mu_c >= 1,
    to ~2e-6 a (r* - b_inf is ~1.3 (pi/2 - beta) a for mu_c < 1), from above (the safe
    outside end). mu_c -> 0 gives b_inf -> a (0.03 here; 0.01 needs a finer scan, see
    the benchmark), large mu_c stays at 2a."""
    for mu in (0.1, 0.25, 0.5, 1.0, 2.0, 5.0, 0.03, 50.0):
        c = limiting_radius_check(1.0, mu, "exact")
        assert c.certified
        assert c.closed_form == (1.0 + mu if mu <= 1.0 else 2.0)
        assert 0.0 <= c.difference < 3e-6, (mu, c.difference)


@pytest.mark.slow
def test_tip_line_error(exact_025):
    """The book's tip-line approximation (4.1.4, 4.4.1.1): 2a/sin(beta), so 2a at grazing
    for every mu_c: for mu_c = 0.25 it overstates b_inf by 0.75 a (safe but slow), and at
    mu_c = 1, beta = 0.8 it understates r* (unsafe); at beta = 0.3 it is 0.3 % low."""
    tip = tip_line_critical_radius(1.0, exact_025.betas)
    err = tip - exact_025.radii
    assert err[-1] == pytest.approx(0.75, abs=1e-5)
    assert -0.03 < err[0] < 0.0
    assert np.all(err[1:] > 0.0)  # mu_c = 0.25: a safe overestimate past beta ~ 0.46 (4.17)
    r1 = critical_radius(1.0, 0.8, 1.0, "exact")
    assert r1.certified and r1.tip_line_radius < r1.radius - 0.05


@pytest.mark.slow
def test_scale_invariance():
    """Results are linear in a (the sticking solver works in units of a)."""
    ref = critical_radius(1.0, 1.0, 0.5, "exact")
    for a in (1e-3, 1e3):
        for method in ("exact", "sweep", "tip_line"):
            r = critical_radius(a, 1.0, 0.5, method)
            base = ref if method == "exact" else critical_radius(1.0, 1.0, 0.5, method)
            assert r.radius / a == pytest.approx(base.radius, rel=1e-9)
            assert r.distance_from_grazing / a == pytest.approx(base.distance_from_grazing, rel=1e-12)


@pytest.mark.slow
def test_critical_case_every_cor_pushes_the_disk_in(exact_025):
    """4.5.2: with PC directly below the contact at distance r = r*(beta) (the safe exact
    value), every COR of the sketch (sticking segment, down- and up-slipping polygons, 2048
    boundary points) moves the CM inside the circle about PC through it: v_CM . (PC - CM)
    >= 0, computed from the rigid motion (omega from (3.3)). Only the sticking locus's
    lower end is needed (the book's claim; the slipping loci's worst point is where they
    meet the sticking line). With PC just above the exact witness end the disk can be
    pushed out: r* is tight."""
    cases = [(0.25, b, r, lo) for b, r, lo in zip(exact_025.betas, exact_025.radii, exact_025.midpoints)
             if b in (0.3, 0.8, 1.15, 1.55)]
    r1 = critical_radius(1.0, 1.4, 1.0, "exact")
    cases.append((1.0, 1.4, r1.radius, r1.lower_bound))
    for mu, beta, r_star, r_in in cases:
        scene = encounter_scene(1.0, beta)
        sk = disk_cor_sketch(scene, mu, n_points=2048, sweep_points=256)
        contact = scene.contact_point
        # the sticking segment from the exact witness end to the sweep's upper end (a
        # 256-point sweep may overshoot the lower end by ~2e-5 a)
        cors = [contact + np.array([0.0, -r_in]), sk.sticking.high]
        for polys in (sk.down_slipping, sk.up_slipping):
            for poly in polys:
                cors.extend(poly)
        for r, sign in ((r_star, 1.0), (r_in - 1e-4, -1.0)):
            pc = contact + np.array([0.0, -r])
            worst = math.inf
            pts = cors if sign > 0 else [contact + np.array([0.0, -r_in])]  # the exact witness end
            for cor in pts:
                omega = scene.rotation_per_push(cor)
                v = omega * perp(scene.center_of_mass - np.asarray(cor))
                worst = min(worst, float(v @ (pc - scene.center_of_mass)) / float(np.linalg.norm(v)))
            if sign > 0:
                assert worst >= -1e-6, (mu, beta, worst)  # polygon chords: ~1e-7 at 2048 points
            else:
                assert worst < 0.0, (mu, beta, worst)


@pytest.mark.slow
def test_kink_of_figure_4_19():
    """4.5.3: 1/r*(beta) has a slope discontinuity where the sticking locus's lower end
    crosses the disk's rim (r* = 2a sin beta); for mu_c = 0.25 near beta = 1.149, where
    the slope of 1/r* jumps from ~0.22 to ~0.55 per radian. mu_c >= 1: no crossing."""
    kb = kink_beta(1.0, 0.25, iterations=8)
    assert kb is not None and abs(kb - 1.149) < 0.01
    h = 0.02
    inv = [1.0 / critical_radius(1.0, b, 0.25, "sweep", sweep_points=512).radius
           for b in (kb - 2 * h, kb - h, kb + h, kb + 2 * h)]
    left, right = (inv[1] - inv[0]) / h, (inv[3] - inv[2]) / h
    assert 0.15 < left < 0.3 and 0.45 < right < 0.65
    assert kink_beta(1.0, 2.0, iterations=1) is None


@pytest.mark.slow
def test_inverse_beta_and_distance(exact_025):
    """beta*(r) and d*(r) (4.5.3, 4.24) of the exact table: the smallest tabulated beta
    whose tail is below r, and a(1 - sin beta*)."""
    env = exact_025.envelope
    for r, k in ((1.3, 4), (1.5, 3), (2.0, 2), (2.4, 1), (7.0, 0)):
        assert critical_beta(exact_025, r) == exact_025.betas[k]
        assert critical_distance(exact_025, r) == pytest.approx(1.0 - math.sin(exact_025.betas[k]), rel=1e-12)
    assert critical_distance(exact_025, 1.2) == 0.0 and math.isnan(critical_beta(env, 1.2))


# ------------------------------------------------------------------ the schedule (4.26) on OR-Tools








@pytest.mark.slow
def test_time_limits_say_where_they_stopped():
    """A table stopped by its time limit keeps the points it finished, from grazing down,
    and says where it stopped; a schedule whose deadline passes before the solve says so."""
    tab = critical_radius_table(1.0, 0.5, "exact", betas=np.linspace(0.4, 1.5, 8), budget=checks_budget(850))  # ~350 checks per exact point
    assert tab.time_limited and not tab.complete and 1 <= tab.n_done < 8
    assert tab.stopped_at_beta == tab.betas[0] and tab.betas[-1] == 1.5
    assert "time limit" in tab.message
    env = critical_envelope(np.linspace(0.05, 1.5, 30), tip_line_critical_radius(1.0, np.linspace(0.05, 1.5, 30)), 1.0)
    late = spiral_schedule(env, 30.0, 2.5, budget=Budget.of(0.0))
    assert late.solver_status == "TIME_LIMIT" and late.stopped_early and late.radii.size == 0






@pytest.mark.slow
def test_cached_tables_scale_with_a_and_carry_their_margin():
    """4.5.3: r* is a length per a, so one table at a = 1 serves every disk (the service's
    cache): the scaled table equals the one computed for that a; the margin moves the
    envelope (and the floor, b_inf + margin) but not the reported radii; a time-limited
    table is not kept."""
    from solver.spiral.critical_radius import cached_critical_radius_table, cached_table_count, scale_table

    a = 3e-4
    direct = critical_radius_table(a, 0.7, "tip_line", r_max=30 * a, margin_rel=2e-3)
    first, hit1 = cached_critical_radius_table(a, 0.7, "tip_line", 25 * a, margin_rel=2e-3)
    again, hit2 = cached_critical_radius_table(5.0, 0.7, "tip_line", 125.0, margin_rel=2e-3)
    assert (hit1, hit2) == (False, True)
    assert np.allclose(first.radii, direct.radii, rtol=1e-12) and np.array_equal(first.betas, direct.betas)
    assert np.allclose(again.radii, first.radii * (5.0 / a), rtol=1e-12)
    assert again.envelope.b_floor == pytest.approx(5.0 * (2.0 + 2e-3), rel=1e-9)  # tip line: 2a, plus the margin
    assert again.margin == pytest.approx(5.0 * 2e-3)
    assert np.allclose(again.envelope.radii, again.radii + again.margin, rtol=1e-12)
    back = scale_table(again, a)
    assert np.allclose(back.envelope.distances, first.envelope.distances, rtol=1e-12)
    n_kept = cached_table_count()
    cut, hit = cached_critical_radius_table(1.0, 0.123, "sweep", 10.0, budget=Budget.of(0.0))
    assert not hit and cut.time_limited and cached_table_count() == n_kept
    assert "before the first collision parameter" in cut.message
    with pytest.raises(InvalidInput):
        critical_radius_table(1.0, 0.7, "tip_line", r_max=10.0, margin_rel=-1.0)


@pytest.mark.slow
def test_critical_radii_in_one_call_4_13_4_24_4_25():
    """At given betas: the table computed for the problem (not cached), the tip line 2a/sin
    beta (4.13) beside it, b_inf numerically against (4.25), and the inverse beta*(r), d*(r)
    (4.24) on the safe envelope."""
    betas = (0.3, 0.8, 1.3, HALF_PI - 1e-6)
    res = critical_radii(CriticalRadiusProblem(1.0, 0.25, "sweep", betas=betas, radii=(0.5, 4.0), sweep_points=256))
    want = critical_radius_table(1.0, 0.25, "sweep", betas=betas, sweep_points=256, find_kink=False)
    np.testing.assert_array_equal(res.table.radii, want.radii)
    np.testing.assert_allclose(res.tip_line_radii, 2.0 / np.sin(np.array(betas)), rtol=1e-15)
    assert res.b_inf_closed_form == 1.25 and res.b_inf_numeric == want.radii[-1]  # the last beta is the limit point
    env = want.envelope
    low, high = res.inverse
    assert math.isnan(low.beta_star) and low.distance_star == 0.0  # below b_inf: no guarantee
    # 4.5.3: bisected between the table's points (not snapped to the next given beta)
    assert high.beta_below < high.beta_star <= float(env.beta_star(4.0))
    assert high.beta_star - high.beta_below <= INVERSE_BETA_TOL and high.steps > 0
    at = critical_radius_table(1.0, 0.25, "sweep", betas=(high.beta_below, high.beta_star), sweep_points=256,
                               find_kink=False).radii
    assert at[1] <= 4.0 < at[0]
    assert high.distance_star == pytest.approx(1.0 - math.sin(high.beta_star), rel=1e-14)
    assert res.complete and res.status == "complete" and not res.from_cache
    with pytest.raises(InvalidInput) as info:
        CriticalRadiusProblem(1.0, 0.25, betas=betas, max_radius=10.0)
    assert info.value.field == "max_radius"


def test_critical_radii_of_the_cached_grid_and_an_empty_table():
    res = critical_radii(CriticalRadiusProblem(1.0, 0.4, "tip_line", max_radius=20.0))
    assert res.table.betas[-1] == pytest.approx(HALF_PI - 1e-6) and res.b_inf_numeric == res.table.radii[-1]
    again = critical_radii(CriticalRadiusProblem(2.0, 0.4, "tip_line", max_radius=40.0))
    assert again.from_cache and np.allclose(again.table.radii, 2.0 * res.table.radii, rtol=1e-12)
    with pytest.raises(InvalidInput) as info:  # nothing decided in no time: nothing to invert
        critical_radii(CriticalRadiusProblem(1.0, 0.4, "sweep", betas=(0.5,), radii=(3.0,)), Budget.of(0.0))
    assert info.value.field == "radii"
    cut = critical_radii(CriticalRadiusProblem(1.0, 0.4, "sweep", betas=(0.5,)), Budget.of(0.0))
    assert cut.status == "time_limited" and cut.b_inf_numeric is None
