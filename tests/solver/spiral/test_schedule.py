"""The fastest guaranteed spiral of spiral localization (solver/spiral/schedule.py; book
4.5.5): the OR-Tools optimum against the recursion (4.26), robot limits, the CP-SAT back
end and the exponent of figure 4-21. Tables: tests/solver/spiral/conftest.py; the one-call
plan: tests/solver/spiral/test_plan.py."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.tolerances import SpiralTolerances
from models.spiral.path import fastest_spiral, power_law_fit
from solver.core.budget import Budget
from solver.spiral.critical_radius import critical_radius, critical_radius_table
from solver.spiral.schedule import spiral_schedule

HALF_PI = 0.5 * math.pi


@pytest.mark.slow
def test_or_tools_optimum_equals_the_recursion_up_to_the_grid(dense_sweep_025):
    """Without robot limits greedy is optimal (models/spiral/path.py), so OR-Tools' optimum on
    a uniform grid of spacing h equals the greedy on that grid, for revolutions and for
    path length, and is certified by potentials. Against the continuous recursion (4.26):
    N_rec(d*) <= N_grid <= N_rec(d* - h) (a grid schedule loses < h per revolution)."""
    env = dense_sweep_025.envelope
    h = 0.01
    b1, target = 20.0, 1.6
    sched = spiral_schedule(env, b1, target, spacing=h, speed=0.1)
    assert sched.solver_status == "OPTIMAL" and sched.certificate.certified and not sched.stopped_early
    assert sched.revolutions == sched.greedy_revolutions
    # the tie-break on length picks the greedy (the shortest of the fewest), to its unit
    assert sched.certificate.revolution_weight is not None
    assert sched.path_length == pytest.approx(sched.greedy_path_length, abs=sched.revolutions * 1e-4)
    assert sched.max_step_excess <= 0.0 and sched.radii[0] == b1 and sched.radii[-1] == target
    assert np.all(sched.steps <= env.d_star(sched.radii[1:]))
    assert sched.time_s == pytest.approx(sched.path_length / 0.1)
    rec = fastest_spiral(env, b1, target)
    shrunk = dataclasses.replace(env, distances=np.maximum(env.distances - h, 0.0))
    rec_h = fastest_spiral(shrunk, b1, target)
    assert rec.revolutions == sched.recursion.revolutions
    assert rec.revolutions <= sched.revolutions <= rec_h.revolutions
    n = min(rec.revolutions, sched.revolutions)
    assert np.all(sched.radii[:n] >= rec.radii[:n] - 1e-12)
    by_length = spiral_schedule(env, b1, target, objective="length", spacing=h)
    assert by_length.solver_status == "OPTIMAL" and by_length.certificate.certified
    assert by_length.path_length == pytest.approx(sched.greedy_path_length, abs=by_length.revolutions * 1e-7)
    assert by_length.revolutions == sched.revolutions


@pytest.mark.slow
def test_robot_limits(dense_sweep_025):
    """A maximum step keeps greedy optimal; a minimum step can strand greedy short of the
    target, and the shortest path still finds a safe schedule with every step >= it."""
    env = dense_sweep_025.envelope
    capped = spiral_schedule(env, 30.0, 2.0, max_step=0.5, resolution=8)
    assert capped.solver_status == "OPTIMAL" and capped.certificate.certified
    assert capped.revolutions == capped.greedy_revolutions and np.all(capped.steps <= 0.5 + 1e-12)
    hit = None
    for target in np.linspace(5.0, 9.0, 41):
        s = spiral_schedule(env, 30.0, float(target), min_step=0.6, spacing=0.05)
        if s.solver_status == "OPTIMAL" and s.greedy_revolutions is None:
            hit = s
            break
    assert hit is not None, "no target where greedy gets stuck"
    assert hit.certificate.certified and np.all(hit.steps >= 0.6 - 1e-12) and hit.max_step_excess <= 0.0
    assert hit.revolutions >= hit.recursion.revolutions  # the recursion ignores the minimum step


@pytest.mark.slow
def test_cp_sat_backend_agrees(dense_sweep_025):
    env = dense_sweep_025.envelope
    mcf = spiral_schedule(env, 10.0, 2.5, resolution=3)
    cps = spiral_schedule(env, 10.0, 2.5, resolution=3, backend="cp_sat", budget=Budget.of(120.0))  # far above its time on any machine
    assert cps.solver_status == "OPTIMAL" and cps.certificate.certified
    assert cps.revolutions == mcf.revolutions


def test_exponent_of_figure_4_21(dense_sweep_025):
    """4.5.5, figure 4-21 (mu_c = 0.25, b_1 = 100 a): far out the radius drops by almost a
    per revolution; near b_inf, b_n - b_inf falls like n^-k with the book's k ~ 1.6. The
    fitted k depends on the range of n: ~1.8 over n = 100..1000 (the transition from the
    linear phase, ~110 revolutions, still shows), ~1.15 over 1000..5000, tending to 1
    (r* - b_inf is linear in pi/2 - beta, d ~ (pi/2 - beta)^2 / 2, so e_n ~ 2 c^2 / n)."""
    env = dense_sweep_025.envelope
    rec = fastest_spiral(env, 100.0, tol=SpiralTolerances(max_revolutions=5000))
    assert rec.steps[0] > 0.97
    early = power_law_fit(rec.radii, 1.25, 100, 1000)
    late = power_law_fit(rec.radii, 1.25, 1000, 5000)
    assert 1.5 < early.exponent < 2.1, early
    assert 1.0 < late.exponent < 1.3, late
    assert late.exponent < early.exponent


def test_inputs():
    table = critical_radius_table(1.0, 0.5, "tip_line", r_max=12.0)
    with pytest.raises(InvalidInput):
        spiral_schedule(table, 12.0, 1.8)  # below the table's floor (the tip line's 2a)
    with pytest.raises(InvalidInput):
        critical_radius(1.0, HALF_PI, 0.5)  # grazing
    with pytest.raises(InvalidInput):
        critical_radius(1.0, 0.0, 0.5)
    with pytest.raises(InvalidInput):
        critical_radius(1.0, 1.0, 0.0)
    with pytest.raises(InvalidInput):
        critical_radius(1.0, 1.0, 0.5, method="guess")


@pytest.mark.slow
@pytest.mark.parametrize("b1, target", [(20.0, 1.6), (20.0, 3.0), (60.0, 1.7), (5.0, 1.65)])
@pytest.mark.parametrize("spacing", [None, 0.05])
def test_the_grid_optimum_is_never_worse_than_the_recursion(dense_sweep_025, b1, target, spacing):
    """(4.26) The recursion's schedule is the least (4.5.5); the grid holds its radii, so
    OR-Tools' optimum on the grid needs exactly as many revolutions (the grid of the
    default resolution once needed 47 where the recursion needed fewer on the same table:
    its steps, exactly at d*, failed the graph's rounding-proof test by one ulp)."""
    env = dense_sweep_025.envelope
    sched = spiral_schedule(env, b1, target, spacing=spacing)
    rec = fastest_spiral(env, b1, target)
    assert sched.certificate.certified and sched.revolutions == rec.revolutions
    # every step of the recursion (its last radius moved up to the target) is safe in the graph's test
    path = np.append(rec.radii[:-1], target)
    assert all(env.step_is_safe(y, x) for y, x in zip(path[:-1], path[1:]))
