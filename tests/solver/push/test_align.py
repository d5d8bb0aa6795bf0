"""Fence alignment in one call (solver/push/align.py; book 3.4, 4.3): the stages are the
fence geometry's, each stage's numbers are the closed forms ((3.41), the composite of 4.3)
and exact bounds of models/gross, the totals are the sums over the stages, the cost model
refuses before any work, and a budget that runs out raises TimeLimitReached carrying the
stages done. Budgets tick per reading (tests/budgets.py), independent of the machine."""

from __future__ import annotations

import math

import pytest

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.push import fence_geometry as fg
from models.push import gross_bounds as gb
from models.push import gross_motion as gm
from models.push import quasistatic as qs
from solver.core.budget import Budget
from solver.core.errors import TimeLimitReached
from solver.core.outcome import Outcome
from solver.push.align import AlignProblem, align, slip_direction
from solver.push.bounds import SKETCH_COST, QuasiStaticQuery, SketchCost
from tests.budgets import TickingClock, checks_budget

IRREGULAR = [[0.0, 0.0], [4.0, 0.0], [4.5, 1.0], [1.0, 2.5], [-0.5, 1.0]]
TWO_STAGES = dict(orientation=math.pi + math.radians(15.0), fence_angle=0.5 * math.pi, push_direction=0.0)
"""The fence turns this part in two stages, both contacts above the line of motion."""
SQUARE_30 = dict(orientation=math.radians(30.0), fence_angle=0.5 * math.pi, push_direction=0.0)
SQUARE = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
FAST = dict(n_nodes=4, n_points=16)


def problem(outline=IRREGULAR, **kw) -> AlignProblem:
    geometry = TWO_STAGES if outline is IRREGULAR else SQUARE_30
    return AlignProblem(Footprint.create(outline), **{**geometry, **FAST, **kw})


def test_stage_totals_are_the_sums_of_the_stages_3_41():
    """mu_c = 0: per stage (3.41) and the r_min push, exact (the closed forms are exact)
    and the slip over the frictionless locus; every total is the sum over the stages."""
    res = align(problem())
    assert isinstance(res, Outcome) and res.complete and res.status == "aligned"
    assert len(res.stages) == 2 and res.predicted_time_s == 0.0  # nothing to predict without friction
    al = res.alignment
    for s in res.stages:
        st = s.stage
        want = fg.frictionless_push_bounds(al.disk_radius, st.contact_distance, al.alpha, st.beta_initial, st.beta_final)
        assert (s.longest.closed_form, s.shortest.closed_form) == want
        assert (s.longest.exact, s.shortest.exact) == want and s.longest.quadrature_error == 0.0
        assert s.longest.equation == "(3.41)" and [p.equation for p in s.longest.pieces] == ["(3.41)"]
        slip = gb.fence_bounds_exact(al.disk_radius, st.contact_distance, al.alpha, st.beta_initial,
                                     st.beta_final, 0.0, which=gb.FENCE_BOUNDS[2:], **FAST)
        assert s.slip.most_positive == slip["slip_max"].value and s.slip.most_negative == slip["slip_min"].value
    for which in ("longest", "shortest"):
        for field in ("exact", "quadrature_error", "closed_form"):
            assert getattr(getattr(res, which), field) == sum(getattr(getattr(s, which), field) for s in res.stages)
    assert res.longest.difference == res.longest.exact - res.longest.closed_form
    assert res.slip.most_positive == sum(s.slip.most_positive for s in res.stages)
    assert res.slip.most_negative == sum(s.slip.most_negative for s in res.stages)
    assert res.slip.direction == slip_direction(al, 0.0)


@pytest.mark.slow
def test_friction_stage_is_the_composite_of_4_3_and_the_exact_sketch():
    res = align(problem(SQUARE, mu_c=0.3))
    (s,) = res.stages
    al, st = res.alignment, s.stage
    book = gm.fence_push_bound(al.disk_radius, st.contact_distance, al.alpha, st.beta_initial, st.beta_final, 0.3)
    exact = gb.fence_bounds_exact(al.disk_radius, st.contact_distance, al.alpha, st.beta_initial, st.beta_final,
                                  0.3, **FAST)
    assert s.longest.closed_form == book.total and s.longest.transitions == book.transitions
    assert [(p.beta_start, p.beta_end, p.regime, p.push) for p in s.longest.pieces] == [
        (p.beta_start, p.beta_end, p.regime, p.push) for p in book.pieces]
    assert s.longest.exact == exact["push_max"].value and s.shortest.exact == exact["push_min"].value
    assert s.longest.exact_sources == tuple(sorted(set(exact["push_max"].sources)))
    assert s.shortest.closed_form is None and res.shortest.closed_form is None  # no closed form with friction
    assert res.predicted_time_s == SKETCH_COST.bounds_s(1, 4, 16)


@pytest.mark.slow
def test_methods_leave_out_what_they_do_not_compute():
    closed = align(problem(SQUARE, mu_c=0.3, method="closed_form"))
    assert closed.longest.exact is None and closed.slip is None and closed.predicted_time_s == 0.0
    exact = align(problem(SQUARE, mu_c=0.3, method="exact"))
    assert exact.longest.closed_form is None and exact.longest.equation is None and exact.slip is not None
    with pytest.raises(InvalidInput) as info:
        problem(method="fast")
    assert info.value.field == "method"


@pytest.mark.slow
def test_refused_before_any_work_when_predicted_over_the_budget():
    clock = TickingClock()
    budget = Budget.of(1.0, clock=clock)
    with pytest.raises(InvalidInput) as info:
        align(problem(SQUARE, mu_c=0.3, n_nodes=16), budget)
    assert info.value.field == "time_limit_s" and "predicted" in info.value.reason
    assert clock.readings == 1  # the budget's creation: no checkpoint was reached
    free = SketchCost(fixed_s=0.0, per_point_s=0.0)
    assert align(problem(SQUARE, mu_c=0.3, cost=free), checks_budget(1000)).complete


def summary(stage):
    """A stage's numbers (not its timings)."""
    return (stage.stage.contact_index, stage.stage.flush_index, stage.longest.exact, stage.shortest.exact,
            stage.slip.most_positive, stage.slip.most_negative)


def test_running_out_carries_the_stages_done():
    """With a budget of n clock readings the alignment stops at a checkpoint; what it
    carries is exactly the stages finished, each equal to the full run's."""
    full = align(problem(method="exact"))
    seen = set()
    for n in range(0, 40):
        try:
            align(problem(method="exact"), checks_budget(n))
        except TimeLimitReached as exc:
            done = exc.partial
            assert [summary(s) for s in done] == [summary(s) for s in full.stages[: len(done)]]
            assert ("stage" in exc.where) or ("the sketch at beta" in exc.where)
            seen.add(len(done))
        else:
            break
    else:
        pytest.fail("the alignment never finished")
    assert seen == {0, 1}


def test_mirror_image_pushes_the_same():
    """A part turning counter-clockwise is reflected onto the book's clockwise case (3.4):
    the mirror image gives the same pushes."""
    mirrored = [[-x, y] for x, y in IRREGULAR]
    a = align(problem(method="closed_form"))
    b = align(AlignProblem(Footprint.create(mirrored), orientation=-TWO_STAGES["orientation"],
                           fence_angle=0.5 * math.pi, push_direction=math.pi, method="closed_form", **FAST))
    assert b.alignment.mirrored != a.alignment.mirrored
    assert b.longest.closed_form == pytest.approx(a.longest.closed_form, rel=1e-12)
    assert b.shortest.closed_form == pytest.approx(a.shortest.closed_form, rel=1e-12)


def test_quasi_static_check_6_7():
    q = QuasiStaticQuery(speed=5.0, mu_s=0.3, g=981.0)
    res = align(problem(SQUARE, method="closed_form", quasi_static=q))
    want = qs.assess(5.0, 0.3, 981.0, qs.ShapeMoments.polygon(Footprint.create(SQUARE)))
    assert res.quasi_static == want
    assert align(problem(SQUARE, method="closed_form")).quasi_static is None
