"""Spiral localization planned in one call (solver/spiral/plan.py; book 4.5.5): the table
(cached or not), the schedule and the recursion (4.26), the tip-line comparison, the fit of
figure 4-21, the path, the simulation check; a table the budget cuts short raises
TimeLimitReached with the table as the partial result."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.tolerances import SPIRAL_DEFAULT
from models.spiral.path import fastest_spiral, tip_line_spiral, unsafe_revolutions
from solver.core.errors import TimeLimitReached
from solver.core.outcome import Outcome
from solver.spiral.critical_radius import critical_radius_table
from solver.spiral.plan import PathQuery, SimulationQuery, SpiralProblem, plan_spiral
from solver.spiral.schedule import spiral_schedule
from tests.budgets import checks_budget

TIP = SpiralProblem(1.0, 0.5, 12.0, 2.1, method="tip_line", cached=False)
"""The tip line's table costs nothing: the plan without waiting for a table."""


def test_plan_of_the_tip_line_4_26():
    plan = plan_spiral(TIP)
    assert plan.schedule.solver_status == "OPTIMAL" and plan.b_inf_closed_form == 1.5
    assert plan.b_floor == pytest.approx(2.0, abs=1e-6)  # the tip line cannot go below 2a
    with pytest.raises(InvalidInput):
        spiral_schedule(plan.table, 12.0, 1.8)  # below the table's floor
    assert isinstance(plan, Outcome) and plan.complete and plan.status == "OPTIMAL"
    table = critical_radius_table(1.0, 0.5, "tip_line", r_max=12.0)
    np.testing.assert_array_equal(plan.table.radii, table.radii)
    env = table.envelope
    np.testing.assert_array_equal(plan.recursion.radii, fastest_spiral(env, 12.0, 2.1).radii)
    np.testing.assert_array_equal(plan.radii, plan.schedule.radii)
    tips = tip_line_spiral(1.0, 12.0, 2.1)
    np.testing.assert_array_equal(plan.tip_line.radii, tips)
    assert plan.tip_line.unsafe_revolutions == int(np.sum(unsafe_revolutions(tips, table.betas, table.radii, 1.0)))
    assert plan.polyline is None and plan.simulation is None and plan.from_cache is False


@pytest.mark.slow
def test_path_and_simulation_on_request():
    plan = plan_spiral(dataclasses.replace(TIP, path=PathQuery(points_per_revolution=16),
                                           simulate=SimulationQuery(n_supports=1, seed=3, kind="dipod")))
    assert len(plan.polyline.points) == plan.radii.size * 16 + 1
    assert plan.simulation.n == 1 and plan.simulation.promised_radius == float(plan.radii[-1])
    capped = plan_spiral(dataclasses.replace(TIP, path=PathQuery(points_per_revolution=64, max_points=40)))
    assert capped.polyline.points_per_revolution == 8  # 40 // revolutions, not below the minimum of 8
    with pytest.raises(InvalidInput) as info:
        plan_spiral(dataclasses.replace(TIP, simulate=SimulationQuery(kind="triangle")))
    assert info.value.field == "simulate.kind"  # the problem's simulate part


def test_too_many_revolutions_name_the_target():
    few = dataclasses.replace(SPIRAL_DEFAULT, max_revolutions=3)
    with pytest.raises(InvalidInput) as info:
        plan_spiral(dataclasses.replace(TIP, spiral_tol=few))
    assert info.value.field == "target" and "more than 3 revolutions" in info.value.reason


def test_a_table_cut_short_raises_with_the_table():
    """The table is built from grazing outwards (one budget check per collision parameter):
    cut short it covers small radii only, and a spiral from a larger start radius cannot be
    planned (the r* of 4.5.3 is unknown there)."""
    with pytest.raises(TimeLimitReached) as info:
        plan_spiral(TIP, checks_budget(0))
    assert info.value.partial.n_done == 0 and "first collision parameter" in info.value.where
    with pytest.raises(TimeLimitReached) as info:
        plan_spiral(TIP, checks_budget(3))
    tab = info.value.partial
    assert tab.time_limited and tab.n_done == 3 and tab.n_planned == plan_spiral(TIP).table.n_done
    assert tab.envelope.envelope[0] < 12.0 and "start_radius 12" in info.value.where
