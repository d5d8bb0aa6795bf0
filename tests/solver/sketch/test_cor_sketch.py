"""The COR sketch in one call (solver/sketch/cor_sketch.py; book 4.1): method "analytic" is
models.sketch.disk_sketch (the disk's loci and the force sweep of 4.1.4); "certified" is
solver.sketch.certified_sketch within the budget; the tip line (3.3.11.1) on request."""

from __future__ import annotations

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.locus.cor_disk import disk_cor_locus
from models.sketch.disk_sketch import disk_cor_sketch
from solver.core.outcome import Outcome
from solver.sketch.cor_sketch import SketchProblem, cor_sketch
from tests.budgets import checks_budget
from tests.scenes import scene_for_mu

SCENE = scene_for_mu(0.3)


@pytest.mark.slow
def test_analytic_is_the_sketch_of_4_1():
    res = cor_sketch(SketchProblem(SCENE, 0.3, n_points=64))
    want = disk_cor_sketch(SCENE, 0.3, n_points=64)
    assert res.sketch.sketch == want.sketch and res.sketch.implication == want.implication
    np.testing.assert_array_equal(res.sketch.plus.boundary, want.plus.boundary)
    assert res.sketch.sticking.t_low == want.sticking.t_low and res.sketch.sticking.t_high == want.sticking.t_high
    assert res.certified is None and res.tip_line is None
    assert isinstance(res, Outcome) and res.status == "analytic" and res.complete


def test_tip_line_on_request_3_3_11_1():
    res = cor_sketch(SketchProblem(SCENE, 0.3, n_points=64, with_tip_line=True))
    want = disk_cor_locus(SCENE, outputs=["tip_line"]).tip_line
    np.testing.assert_array_equal(res.tip_line.point, want.point)
    assert res.tip_line.distance == want.distance


def test_certified_within_the_budget_reports_what_it_certified():
    res = cor_sketch(SketchProblem(SCENE, 0.3, method="certified", n_points=64), checks_budget(3))
    assert res.certified is not None and res.status in ("certified", "incomplete")
    assert res.complete == res.certified.complete
    assert res.certified.time_limited and res.status == "incomplete"  # three clock readings cannot finish it
    with pytest.raises(InvalidInput):
        SketchProblem(SCENE, 0.3, method="guess")
