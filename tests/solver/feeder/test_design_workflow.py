"""The feeder design workflow (solver/feeder/design.py; book 5.3, 5.4, 1.8.6): a design
found, proven and validated by simulation; under a budget, what was established."""

from __future__ import annotations

import math

import pytest

from models.feeder.fence import feeder_part
from models.feeder.gate import GateSpec
from models.feeder.placed import PlacedDesign
from models.feeder.pushplan import plan_pushes
from solver import Budget, FeederDesignProblem, feeder_design
from solver.feeder.design import BeltSpec
from tests.feeder_cases import PARTS, Clock, CountingClock


def problem(name: str, **kw) -> FeederDesignProblem:
    v, cm = PARTS[name]
    base = dict(part=feeder_part(v, cm), angle_min=math.radians(20), angle_max=math.radians(70),
                angle_step=math.radians(10), mu_c=(0.25, 0.25))
    base.update(kw)
    return FeederDesignProblem(**base)


def test_a_rectangle_design_is_validated_by_simulated_parts_over_a_mu_c_interval():
    """Two fences leave a rectangle in one band up to its half-turn symmetry; simulated parts
    with mu_c drawn over the interval all end in it (seeded)."""
    res = feeder_design(problem("rectangle", mu_c=(0.2, 0.3), validation_parts=20, seed=4, prove_with_cp_sat=True))
    assert res.complete and res.design is not None and len(res.design.fences) == 2
    assert res.cp_sat is not None and res.cp_sat.depth_proven == 1
    v = res.validation
    assert v is not None and v.parts == 20 and v.outside == 0 and v.in_band >= 18
    assert len(res.final_set.arcs) == 2  # two bands half a turn apart
    s, w = res.final_set.arcs[0]
    assert abs((res.final_set.arcs[1][0] - s) % (2 * math.pi) - math.pi) < 1e-9


def test_on_a_belt_the_design_is_searched_as_placed_and_validated_there_1_8_6():
    """With a belt, the right triangle's design uses same-side runs (no alternating design
    exists, issue 13) and every placed fence has the reach its arriving orientations need;
    the parts simulated on the placed belt (entering across the lane) all end in the band;
    the product of the placed maps leaves unaligned exactly the first fence's loss."""
    radius = feeder_part(*PARTS["right triangle"]).circumradius
    res = feeder_design(problem("right triangle", alternate=False, validation_parts=12, seed=5,
                                belt=BeltSpec(width=20.0 * radius, entry_spread=0.5 * radius)))
    d, pl, v = res.design, res.placement, res.validation
    assert isinstance(d, PlacedDesign) and d.gate is None and d.guaranteed_yield >= 0.995
    assert pl is not None and len(pl.fences) == len(d.fences)
    assert any(f.side == g.side for f, g in zip(pl.fences, pl.fences[1:]))  # a same-side run
    assert all(f.reach >= f.reach_needed - 1e-9 * radius for f in pl.fences)
    assert res.product is not None and res.product.unaligned == d.lost
    assert v is not None and v.on_belt and v.parts == 12 and v.in_band == 12 and v.failed == 0


@pytest.mark.slow
def test_the_alternating_layout_of_issue_13_fails_on_the_belt_and_the_placed_search_knows_why():
    """The pentagon's shortest sequence without a belt (non-alternating, issue 13) is placed
    by nobody now: on a belt 20 radii wide the fences-only search is exhausted (every
    same-side run needs more width than the belt has); with a gate allowed the design
    accepts only the accepted band and rejects the rest in simulation."""
    part = feeder_part(*PARTS["pentagon"])
    belt = BeltSpec(width=20.0 * part.circumradius)
    res = feeder_design(problem("pentagon", alternate=False, belt=belt, max_depth=6))
    assert res.design is None and res.placed_search is not None and res.placed_search.exhausted
    assert res.placed_search.refused["width"] > 0
    res = feeder_design(problem("pentagon", alternate=False, belt=belt, max_depth=6, gate=GateSpec(),
                                validation_parts=10, seed=7))
    d, v = res.design, res.validation
    assert isinstance(d, PlacedDesign) and d.gate is not None and res.fences_only_exhausted
    assert v is not None and v.outside == 0 and v.in_band + v.rejected == 10 and v.failed == 0


def test_an_expired_budget_answers_what_was_established(monkeypatch):
    import solver.feeder.design as design

    clock = Clock()
    budget = Budget.of(5.0, clock=clock)
    clock.run_out = True
    res = feeder_design(problem("pentagon"), budget)
    assert res.status == "time_limit" and not res.complete and res.maps == () and res.search is None
    assert res.design is None and "stopped after 0 candidate maps" in res.message
    # a budget that runs out during the maps keeps the maps made (the push-plan baseline
    # before them reads the clock once for its share and once per class of turns; the maps
    # are made in groups, the deadline read before each group and before its extremes)
    monkeypatch.setattr(design, "MAPS_AT_ONCE", 4)
    baseline = Tally()
    plan_pushes(problem("pentagon").part, problem("pentagon").max_depth, expired=lambda: baseline() > 0.0)
    res = feeder_design(problem("pentagon"), Budget.of(5.0, clock=CountingClock(1 + baseline.calls + 3)))
    assert res.status == "time_limit" and len(res.maps) in (4, 8) and res.search is None


class Tally:
    """A clock that never runs out and counts its readings."""

    def __init__(self) -> None:
        self.calls = 0

    def __call__(self) -> float:
        self.calls += 1
        return 0.0


@pytest.mark.slow
def test_a_placed_search_cut_by_its_time_limit_answers_what_it_established():
    """A budget that runs out a few readings before the end (machine-independent: counted
    readings) stops the placed search: the answer is incomplete, keeps every map and reach
    profile made, and reports the nodes searched and the depth proven so far."""
    part = feeder_part(*PARTS["pentagon"])
    kw = dict(alternate=False, belt=BeltSpec(width=20.0 * part.circumradius), max_depth=6, gate=GateSpec())
    tally = Tally()
    full = feeder_design(problem("pentagon", **kw), Budget.of(5.0, clock=tally))
    assert full.complete and full.design is not None
    res = feeder_design(problem("pentagon", **kw), Budget.of(5.0, clock=CountingClock(tally.calls - 3)))
    assert res.status == "time_limit" and not res.complete and res.design is None
    assert len(res.maps) == len(full.maps) and "reach_profiles" in res.timings
    assert res.progress is not None and res.progress.nodes > 0 and res.progress.depth_proven >= 1
    assert "no design shorter than" in res.message


class Ticking:
    """A clock that moves 1 ms forward at every reading: a work limit the machine's speed
    cannot change."""

    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        self.now += 1e-3
        return self.now


def test_the_push_plan_baseline_is_cut_first_and_never_sinks_the_design():
    """Issue 25: the regular 64-gon with its centre of mass at (0.01, 0), whose push plan
    needs over a minute: the baseline stops at its tenth of the budget, says it was cut,
    and the design goes on to its answer."""
    part = feeder_part([(math.cos(2 * math.pi * i / 64), math.sin(2 * math.pi * i / 64)) for i in range(64)],
                       (0.01, 0.0))
    prob = FeederDesignProblem(part, math.radians(20), math.radians(70), math.radians(10), (0.25, 0.25), max_depth=8)
    clock = Ticking()
    res = feeder_design(prob, Budget.of(30.0, clock=clock))
    assert res.baseline is not None and not res.baseline.complete and res.baseline.alphas is None
    assert res.status == "ok" and res.complete and len(res.maps) == 12
    assert clock.now < 30.0


def test_validation_cut_by_the_time_limit_is_no_outcome_and_no_complete_design(monkeypatch):
    """Issue 35, point 11: a design whose simulated parts were all stopped by the time limit
    answered 'ok, complete' with every part 'unfinished'. Parts the limit stops are `cut`:
    no outcome, the design is not complete, and its message says how many."""
    from solver.feeder import design as design_module

    clock = Clock()
    real = design_module.validate_in_own_frames

    def late(*args, **kwargs):
        clock.run_out = True  # the limit passes as the validation starts
        return real(*args, **kwargs)

    monkeypatch.setattr(design_module, "validate_in_own_frames", late)
    res = feeder_design(problem("rectangle", validation_parts=20, seed=4), Budget.of(60.0, clock=clock))
    v = res.validation
    assert res.design is not None and v is not None
    assert (v.parts, v.cut, v.simulated, v.unfinished, v.in_band) == (20, 20, 0, 0, 0)
    assert res.status == "time_limit" and not res.complete
    assert "stopped 20 of the 20 simulated parts" in res.message
