"""The feeder design workflow (solver/feeder/design.py; book 5.3, 5.4, 1.8.6): a design
found, proven and validated by simulation; under a budget, what was established."""

from __future__ import annotations

import math

from models.feeder.fence import feeder_part
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


def test_on_a_belt_the_design_is_validated_through_its_placed_fences_1_8_6():
    """With a belt, the validation parts enter in the layout's lane and meet the placed
    fences one after the other (world frame), not each fence in its own frame: the
    rectangle's alternating design brings all of them into its band; the pentagon's
    shortest design (fences on one side, not alternating) lets every part pass a fence
    placed beside the previous one's end untouched (reach 0: ``may_miss``), which the
    validation counts as missed, never as in the band."""
    radius = feeder_part(*PARTS["rectangle"]).circumradius
    res = feeder_design(problem("rectangle", validation_parts=12, seed=5, belt=BeltSpec(width=12.0 * radius)))
    v = res.validation
    assert v is not None and v.on_belt and v.parts == 12
    assert v.in_band == 12 and v.missed == v.outside == v.unflushed == v.unfinished == 0
    assert len(v.examples) == 3 and all(len(r.runs) == 2 for r in v.examples)
    assert not any(c.may_miss for c in res.placed)
    radius = feeder_part(*PARTS["pentagon"]).circumradius
    res = feeder_design(problem("pentagon", alternate=False, validation_parts=6, seed=5,
                                belt=BeltSpec(width=12.0 * radius)))
    v = res.validation
    assert res.design is not None and any(c.may_miss for c in res.placed)
    assert v is not None and v.on_belt and v.missed + v.unfinished == 6 and v.in_band == 0


def test_an_expired_budget_answers_what_was_established():
    clock = Clock()
    budget = Budget.of(5.0, clock=clock)
    clock.run_out = True
    res = feeder_design(problem("pentagon"), budget)
    assert res.status == "time_limit" and not res.complete and res.maps == () and res.search is None
    assert res.design is None and "stopped after 0 candidate maps" in res.message
    # a budget that runs out during the maps keeps the maps made
    res = feeder_design(problem("pentagon"), Budget.of(5.0, clock=CountingClock(20)))
    assert res.status == "time_limit" and 0 < len(res.maps) < 12 and res.search is None
