"""Scene analysis (solver/scenes; issue 27): each question is answered by the cheapest model
that reaches the accuracy asked for, the answers are those of the models called directly,
and what one answer computed serves the next.

The properties behind the choice of models are checked, not assumed: the circumscribing
disk's locus contains the polygon's certified locus (7.5); the polygon's contact modes are
among the disk's (4.1), so a decisive disk verdict is the polygon's; the closed forms of
the push to align (3.41) are the exact bounds without pusher friction.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.core.scene import PushScene
from models.push.quasistatic import ShapeMoments
from solver import (
    SKETCH_COST,
    AlignProblem,
    FeederDesignProblem,
    LocusProblem,
    QuasiStaticQuery,
    Question,
    SceneProblem,
    SketchProblem,
    align,
    analyze_scene,
    cor_locus,
    cor_sketch,
    feeder_design,
)
from tests.budgets import checks_budget
from tests.scenes import point_in_polygon

PENTAGON = Footprint.create([[0, 0], [3, 0], [3.5, 1.5], [1.5, 2.5], [-0.5, 1.2]], None)
QS = QuasiStaticQuery(0.05, 0.3, 9.81)


def polygon_scene(edge_angle: float = 0.3, contact=(1.0, 0.0), push=math.pi / 2) -> PushScene:
    return PushScene.create(PENTAGON.circumradius, contact, edge_angle, push, PENTAGON.center_of_mass)


def problem(*questions: Question, mu=(0.25, 0.25), footprint=PENTAGON, scene=None, qs=QS) -> SceneProblem:
    return SceneProblem(scene or polygon_scene(), footprint, mu, qs, tuple(questions))


def test_a_disk_locus_is_the_closed_form_at_every_accuracy_3_30():
    scene = PushScene.create(1.0, [0.2, -0.6], 0.0, math.pi / 2)
    answers = analyze_scene(problem(Question("cor_locus", "estimate"), Question("cor_locus", "exact"), scene=scene,
                                    footprint=None)).answers
    direct = cor_locus(LocusProblem(scene))
    for a in answers:
        assert (a.status, a.model, a.accuracy) == ("answered", "closed_form", "exact")
        np.testing.assert_array_equal(a.result.analytic.boundary, direct.analytic.boundary)
    assert answers[1].reused_from == 0 and answers[1].cost_s == 0.0  # the same locus, computed once


def test_the_disk_bound_contains_the_certified_polygon_locus_7_5():
    """'bound' answers the circumscribing disk's locus, 'exact' the certified polygon's;
    every certified boundary point lies inside the disk's locus (7.5)."""
    bound, exact = analyze_scene(problem(Question("cor_locus", "bound"), Question("cor_locus", "exact", n_rays=8))).answers
    assert (bound.model, bound.accuracy) == ("disk_bound", "bound")
    assert (exact.model, exact.accuracy, exact.status) == ("certified", "exact", "answered")
    assert exact.error_bound is not None and exact.error_bound < 1e-4 * PENTAGON.circumradius
    points = exact.result.certified.boundary
    points = points[np.all(np.isfinite(points), axis=1)]
    assert len(points) == 8
    disk = bound.result.analytic.boundary
    # inside, or within the disk locus's sampling chord error of its boundary
    shrunk = PENTAGON.center_of_mass + (points - PENTAGON.center_of_mass) * (1 - 1e-3)
    assert np.all(point_in_polygon(shrunk, disk))


@pytest.mark.slow
def test_a_decisive_disk_verdict_is_the_polygons_4_1():
    """The disk's sketch allows one mode here: 'exact' is reached without certifying, and
    the certified polygon sketch, computed directly, agrees."""
    (a,) = analyze_scene(problem(Question("stick_or_slip", "exact"))).answers
    assert (a.model, a.accuracy, a.tried) == ("disk_bound", "exact", ())
    assert a.result.decisive and a.result.verdict == "slips"
    own = cor_sketch(SketchProblem(polygon_scene(), 0.25, footprint=PENTAGON, method="certified", n_rays=8))
    assert set(own.sketch.allowed_modes) <= set(a.result.modes)


@pytest.mark.slow
def test_an_undecided_disk_verdict_is_certified_when_exact_is_asked_4_1():
    scene = polygon_scene(edge_angle=0.0)
    bound, exact = analyze_scene(problem(Question("stick_or_slip", "bound"),
                                         Question("stick_or_slip", "exact", n_rays=8), scene=scene,
                                         mu=(0.3, 0.3))).answers
    assert (bound.model, bound.accuracy) == ("disk_bound", "bound") and not bound.result.decisive
    assert exact.model == "certified" and exact.accuracy == "exact" and len(exact.tried) == 1
    assert exact.tried[0].model == "disk_bound" and "not decisive" in exact.tried[0].why_not
    assert set(exact.result.modes) <= set(bound.result.modes)  # the polygon's modes are among the disk's


def test_without_friction_the_contact_slips():
    (a,) = analyze_scene(problem(Question("stick_or_slip", "exact"), mu=(0.0, 0.0))).answers
    assert (a.model, a.accuracy, a.result.verdict, a.cost_s) == ("closed_form", "exact", "slips", 0.0)


def direct_align(mu: float, method: str):
    scene = polygon_scene()
    return align(AlignProblem(PENTAGON, 0.0, scene.edge_angle, scene.push_direction, mu_c=mu, method=method,
                              quasi_static=QS, cost=SKETCH_COST))


@pytest.mark.parametrize("mu,accuracy,model,level", [
    (0.0, "bound", "closed_form", "bound"),
    (0.25, "estimate", "closed_form", "estimate"),
    (0.25, "bound", "exact_bounds", "bound"),
])
def test_the_push_to_align_takes_the_closed_form_where_it_is_enough_3_41_4_3(mu, accuracy, model, level):
    (a,) = analyze_scene(problem(Question("push_to_align", accuracy), mu=(mu, mu))).answers
    assert (a.model, a.accuracy) == (model, level)
    want = direct_align(mu, "closed_form" if model == "closed_form" else "both")
    assert a.result.longest == want.longest and a.result.shortest == want.shortest
    if mu == 0.0:
        assert a.error_bound == 0.0
        exact = direct_align(0.0, "exact")  # without friction the closed form is the exact bound (3.41)
        assert a.result.longest.closed_form == pytest.approx(exact.longest.exact, rel=1e-6)
    elif model == "closed_form":
        assert a.error_bound is None  # the closed forms with friction approximate; no bound is claimed


def test_the_quasi_static_verdict_is_reused_from_the_push_to_align_6_8():
    analysis = analyze_scene(problem(Question("quasi_static"), Question("push_to_align")))
    qs, push = analysis.answers
    assert push.reused_from is None and qs.reused_from == 1 and qs.cost_s == 0.0
    assert qs.result == QS.assess(ShapeMoments.polygon(PENTAGON))
    (alone,) = analyze_scene(problem(Question("quasi_static"))).answers
    assert alone.reused_from is None and alone.result == qs.result


def test_the_aligning_fence_is_read_from_the_design_5_3():
    """A design is the fewest fences: its answer says whether one fence orients the part, the
    same as a search one fence deep."""
    design_q = Question("feeder_design", alternate=False, max_depth=8)
    fence, design = analyze_scene(problem(Question("aligning_fence"), design_q)).answers
    assert design.status == "answered" and design.result.design is not None
    assert fence.reused_from == 1 and fence.cost_s == 0.0
    (alone,) = analyze_scene(problem(Question("aligning_fence"))).answers
    assert alone.reused_from is None and alone.result.search.depth_proven >= 1
    single = alone.result.design is not None and len(alone.result.design.fences) == 1
    assert single == (len(design.result.design.fences) == 1)
    direct = feeder_design(FeederDesignProblem(PENTAGON.centred(), design_q.angle_min, design_q.angle_max,
                                               design_q.angle_step, (0.25, 0.25), max_depth=8, alternate=False))
    assert direct.design == design.result.design


@pytest.mark.slow
def test_exact_design_is_checked_by_simulated_parts():
    (a,) = analyze_scene(problem(Question("feeder_design", "exact", alternate=False, max_depth=8,
                                          validation_parts=6, seed=3))).answers
    assert a.model == "design_search+simulation" and a.result.validation.parts == 6
    assert "no design is certified" in a.note and a.accuracy == "bound"


def test_nothing_is_reported_done_that_was_not():
    """With a budget that expires after a fixed number of clock readings (any machine), the
    questions reached late are 'not_run', and none of them claims a result."""
    analysis = analyze_scene(problem(Question("cor_locus"), Question("cor_locus", "exact", n_rays=64),
                                     Question("stick_or_slip")), checks_budget(6))
    statuses = [a.status for a in analysis.answers]
    assert statuses[0] == "answered" and "answered" != statuses[1]
    assert not analysis.complete and analysis.status == "incomplete"
    for a in analysis.answers:
        if a.status == "not_run":
            assert a.result is None and a.model is None and a.accuracy is None
        if a.status == "time_limited":  # what it finished, bounded by the disk's answer at best
            assert a.accuracy in (None, "bound")
    cut = analysis.answers[1]
    if cut.status == "time_limited":  # the certified locus cut short: the disk's locus answers, and says so
        assert (cut.model, cut.accuracy, cut.tried[0].model) == ("disk_bound", "bound", "certified")
        assert "rays certified" in cut.tried[0].why_not


@pytest.mark.parametrize("questions,mu,footprint,field", [
    ((Question("push_to_align"),), (0.2, 0.2), None, "questions.0.ask"),
    ((Question("cor_locus"), Question("feeder_design"),), (0.2, 0.2), None, "questions.1.ask"),
    ((Question("stick_or_slip"),), (0.1, 0.3), PENTAGON, "questions.0.ask"),
    ((Question("cor_locus"),), (0.3, 0.1), PENTAGON, "mu_c"),
])
def test_questions_the_scene_cannot_answer_are_refused(questions, mu, footprint, field):
    with pytest.raises(InvalidInput) as err:
        SceneProblem(polygon_scene(), footprint, mu, QS, questions)
    assert err.value.field == field
    with pytest.raises(InvalidInput):
        SceneProblem(polygon_scene(), PENTAGON, (0.2, 0.2), None, (Question("quasi_static"),))
    with pytest.raises(InvalidInput):
        Question("where_is_it")


@pytest.mark.parametrize("checks", [6, 40])
def test_the_answers_do_not_depend_on_the_order_of_the_questions(checks):
    """Issue 35, point 7: [the exact locus, its bound] under a limit that the certified
    locus uses up answered the bound 'not_run', the reverse order both; the cheap question is
    answered first whatever the order, and the two orders give the same answers."""
    asked = (Question("cor_locus", "exact", n_rays=256), Question("cor_locus"))
    forward = analyze_scene(problem(*asked), checks_budget(checks)).answers
    backward = analyze_scene(problem(*reversed(asked)), checks_budget(checks)).answers[::-1]
    assert forward[1].status == "answered" and forward[1].model == "disk_bound"
    assert [(a.status, a.model, a.accuracy) for a in forward] == [(a.status, a.model, a.accuracy) for a in backward]
