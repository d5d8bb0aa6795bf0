"""The feeder workflows (solver/feeder/workflow.py) under a budget: past the deadline they
answer what was finished, marked incomplete; a clock that is told when to run out makes
the tests independent of the machine's speed."""

from __future__ import annotations

import math

import numpy as np

from models.feeder.fence import Fence
from solver import Budget, FeederMapProblem, FeederSimProblem, feeder_map, feeder_simulate
from tests.feeder_cases import Clock, part, random_support


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
