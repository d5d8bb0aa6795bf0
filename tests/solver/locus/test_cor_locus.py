"""The COR locus in one call (solver/locus/cor_locus.py): method "analytic" is the closed forms
of book 3.3 ((3.30)-(3.37)) unchanged; method "certified" adds certified brackets of the
boundary (3.3.13, 7.5), stops when the budget runs out and says how far it got."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.core.scene import PushScene
from models.locus.cor_disk import disk_cor_locus
from solver.core.outcome import Outcome
from solver.locus.certified_locus import certified_disk_boundary
from solver.locus.cor_locus import LocusProblem, cor_locus
from tests.budgets import checks_budget
from tests.scenes import scene_for_mu

SCENE = scene_for_mu(0.3)


def test_analytic_is_the_closed_forms_3_30_to_3_37():
    res = cor_locus(LocusProblem(SCENE, n_points=64))
    want = disk_cor_locus(SCENE, n_points=64)
    np.testing.assert_array_equal(res.analytic.boundary, want.boundary)
    assert res.analytic.tip.distance == want.tip.distance and res.analytic.r_min.distance == want.r_min.distance
    assert res.certified is None and res.notes == ()
    assert isinstance(res, Outcome) and res.status == "analytic" and res.complete
    only_tip = cor_locus(LocusProblem(SCENE, outputs=("tip",)))
    assert only_tip.analytic.tip is not None and only_tip.analytic.boundary is None


@pytest.mark.slow
def test_certified_disk_is_the_bracketed_analytic_boundary():
    res = cor_locus(LocusProblem(SCENE, method="certified", n_certified=8))
    want = certified_disk_boundary(SCENE, n_points=8)
    assert res.status == "certified" and res.complete and res.n_requested == res.n_done == len(want.boundary)
    assert [p.verdict for p in res.certified.pairs] == [p.verdict for p in want.pairs]
    assert res.certified.n_certified == res.n_done


def test_certified_stops_at_the_budget_and_says_so():
    res = cor_locus(LocusProblem(SCENE, method="certified", n_certified=16), checks_budget(1))
    assert res.status == "time_limited" and not res.complete
    assert 1 <= res.n_done < res.n_requested == 16  # at least one point is always examined
    assert res.notes == (f"method certified: time limit 1 s reached after {res.n_done} of 16 points",)


def test_certified_polygon_traces_rays():
    fp = Footprint.create([[-1.0, -0.5], [1.0, -0.5], [1.0, 0.5], [-1.0, 0.5]])
    scene = PushScene.create(fp.circumradius, [-1.0, -0.3], 0.5 * math.pi, 0.0, fp.center_of_mass)
    res = cor_locus(LocusProblem(scene, fp, method="certified", n_certified=4))
    assert res.n_requested == 4 and res.n_done == len(res.certified.rays) == 4
    assert res.complete and len(res.certified.rays) == 4


def test_a_translation_has_nothing_to_certify():
    scene = PushScene.create(1.0, [-1.0, 0.0], 0.5 * math.pi, 0.0)
    res = cor_locus(LocusProblem(scene, method="certified"))
    assert res.analytic.kind == "translation" and res.certified is None and res.complete
    assert "nothing to certify" in res.notes[0]


def test_unknown_method_names_the_field():
    with pytest.raises(InvalidInput) as info:
        LocusProblem(SCENE, method="guess")
    assert info.value.field == "method"
