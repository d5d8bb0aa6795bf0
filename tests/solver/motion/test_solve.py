"""Motions for known pressure distributions in one call (solver/motion/solve.py): a support,
a batch (one Newton batch per support size, or one solve after the other), a uniform
pressure (figure 7-1), each the forward solver's answer (3.2-3.3.3, 4.1), and the
impact-limit COR (7.1) of a single body."""

from __future__ import annotations

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.core.inertia import impact_cor_distance, polygon_radius_of_gyration, support_radius_of_gyration
from models.core.support import Support
from solver.core.outcome import Outcome
from solver.motion.forward import solve_forward, solve_forward_batch
from solver.motion.solve import MotionProblem, UniformPressure, solve_motion
from solver.motion.statistics import uniform_pressure_cor
from tests.scenes import scene_for_mu

SCENE = scene_for_mu(0.3)
TRIPOD = Support.create([[0.6, 0.0], [-0.3, 0.5], [-0.3, -0.5]], [1.0, 1.0, 1.0], (0.0, 0.0))
DIPOD = Support.create([[0.5, 0.0], [-0.5, 0.0]], [1.0, 1.0], (0.0, 0.0))
OTHER_TRIPOD = Support.create([[0.0, 0.8], [0.4, -0.4], [-0.4, -0.4]], [1.0, 1.0, 1.0], (0.0, 0.0))


def test_one_support_is_the_forward_solve_with_its_impact_7_1():
    res = solve_motion(MotionProblem(SCENE, support=TRIPOD, mu_c=0.2))
    want = solve_forward(SCENE, TRIPOD, mu_c=0.2)
    np.testing.assert_array_equal(res.motion.cor, want.cor)
    assert res.motion.omega == want.omega and res.motion.mode == want.mode
    rho = support_radius_of_gyration(TRIPOD.points, TRIPOD.weights)
    assert res.impact.source == "support" and res.impact.radius_of_gyration == rho
    assert res.impact.distance == impact_cor_distance(SCENE, rho)
    assert isinstance(res, Outcome) and res.status == "optimal" and res.complete and res.n_motions == 1


def test_newton_batch_is_one_batch_per_support_size():
    res = solve_motion(MotionProblem(SCENE, supports=(TRIPOD, DIPOD, OTHER_TRIPOD)))
    assert sorted(g.indices for g in res.groups) == [(0, 2), (1,)]
    for g in res.groups:
        pts = np.stack([res.problem.supports[i].points for i in g.indices])
        wts = np.stack([res.problem.supports[i].weights for i in g.indices])
        want = solve_forward_batch(SCENE, pts, wts, check_centroid=False)
        np.testing.assert_array_equal(g.result.cor, want.cor)
    assert res.impact is None and res.n_motions == 3 and res.status == "optimal"


def test_slow_batch_one_by_one_and_a_bad_member_is_named():
    res = solve_motion(MotionProblem(SCENE, supports=(TRIPOD, DIPOD), method="cvxpy"))
    assert res.groups is None and len(res.motions) == 2
    np.testing.assert_allclose(res.motions[1].cor, solve_forward(SCENE, DIPOD).cor, rtol=0, atol=1e-8)
    shifted = Support.create([[1.6, 1.0], [0.7, 1.5], [0.7, 0.5]], [1.0, 1.0, 1.0], (1.0, 1.0))
    with pytest.raises(InvalidInput) as info:
        solve_motion(MotionProblem(SCENE, supports=(TRIPOD, shifted), method="cvxpy"))
    assert info.value.field == "supports.1"  # the problem's supports[1]


def test_uniform_pressure_figure_7_1():
    fp = Footprint.create([[-1.0, -0.5], [1.0, -0.5], [1.0, 0.5], [-1.0, 0.5]])
    scene = scene_for_mu(0.3, a=fp.circumradius)
    res = solve_motion(MotionProblem(scene, pressure=UniformPressure(fp, 4)))
    want = uniform_pressure_cor(scene, fp, resolution=4)
    np.testing.assert_array_equal(res.motion.cor, want.cor)
    assert res.impact.source == "uniform_polygon"
    assert res.impact.radius_of_gyration == min(polygon_radius_of_gyration(fp), scene.disk_radius)
    disk = solve_motion(MotionProblem(SCENE, pressure=UniformPressure(None, 4)))
    assert disk.impact.source == "uniform_disk"


def test_exactly_one_input_and_a_known_method():
    with pytest.raises(InvalidInput):
        MotionProblem(SCENE)
    with pytest.raises(InvalidInput):
        MotionProblem(SCENE, support=TRIPOD, supports=(DIPOD,))
    with pytest.raises(InvalidInput) as info:
        MotionProblem(SCENE, support=TRIPOD, method="simplex")
    assert info.value.field == "method"
