"""The feeder workflows (solver/feeder/workflow.py) under a budget: past the deadline they
answer what was finished, marked incomplete; a clock that is told when to run out makes
the tests independent of the machine's speed."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.feeder.fence import Fence
from solver import Budget, FeederMapProblem, FeederSimProblem, PartBoundSettings, feeder_map, feeder_simulate
from tests.feeder_cases import Clock, CountingClock, part, random_support


def test_map_of_a_sequence_and_an_expired_budget():
    pent = part("pentagon")
    fences = (Fence.create(math.radians(40), 0.25), Fence.create(math.radians(-50), (0.1, 0.2)))
    clock = Clock()
    done = feeder_map(FeederMapProblem(pent, fences, resolution=90), Budget.of(5.0, clock=clock))
    assert done.complete and len(done.maps) == 2 and done.matrix.shape == (90, 90)
    assert done.product.code_sets is not None
    budget = Budget.of(5.0, clock=clock)
    clock.run_out = True
    cut = feeder_map(FeederMapProblem(pent, fences, resolution=90), budget)
    assert cut.status == "time_limit" and not cut.complete and cut.maps == () and cut.product is None
    assert "0 of 2" in cut.message


def test_a_map_with_the_parts_own_bound_says_so_and_what_it_cost_and_stops_at_the_deadline():
    """bound "part": the maps say which bound made them, each fence's cost is reported
    (loci, dipods, rays), and a deadline met during the search of the part's loci stops
    the request with what was finished; an unknown bound is refused."""
    tri = part("right triangle")
    fences = (Fence.create(math.radians(40), 0.25),)
    settings = PartBoundSettings(contacts=3, turns=1, refine_levels=0, max_rays_per_aim=2)
    done = feeder_map(FeederMapProblem(tri, fences, bound="part", part_bound=settings))
    assert done.complete and done.bound == "part" and done.maps[0].bound == "part"
    assert "own loci" in done.message and len(done.part_bound_costs) == 1
    cost = done.part_bound_costs[0]
    assert cost.loci > 0 and cost.dipods == 360 * cost.loci and cost.rays >= cost.loci and cost.seconds > 0.0
    cut = feeder_map(FeederMapProblem(tri, fences, bound="part", part_bound=settings),
                     Budget.of(5.0, clock=CountingClock(4)))
    assert cut.status == "time_limit" and cut.maps == () and "own locus" in cut.message
    assert len(cut.part_bound_costs) == 1 and cut.part_bound_costs[0].loci < cost.loci
    with pytest.raises(InvalidInput) as err:
        FeederMapProblem(tri, fences, bound="square")
    assert err.value.field == "bound"


def test_simulation_through_fences_and_an_expired_budget():
    sq = part("square")
    body, w = random_support(np.random.default_rng(3), "square")
    fences = ((Fence.create(0.7, 0.25), 0.25), (Fence.create(-0.8, 0.2), 0.2))
    clock = Clock()
    res = feeder_simulate(FeederSimProblem(sq, fences, body, w, 0.3), Budget.of(5.0, clock=clock))
    assert res.complete and res.status == "left" and res.in_map == (True, True)
    assert res.runs[1].theta_initial == res.runs[0].theta_final and res.theta_final == res.runs[1].theta_final
    budget = Budget.of(5.0, clock=clock)
    clock.run_out = True
    cut = feeder_simulate(FeederSimProblem(sq, fences, body, w, 0.3), budget)
    assert cut.status == "time_limit" and not cut.complete and cut.theta_final is None
    assert len(cut.runs) == 1 and cut.in_map == (None,) and cut.runs[0].counts.solves == 0
