"""The world-frame answer of a certified query (solver/certify/answer.py): a decision made
in the dimensionless locus frame comes back in the world frame of the scene. Checked on a
scene that is translated, rotated and scaled (3.3.12), so the frame matters: the world
witness must have the candidate as its COR by an independent forward solve (3.7), an
outside answer carries its certificate, and an undecided one is not complete."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.scene import PushScene
from models.core.support import Support
from models.locus.cor_disk import disk_cor_locus
from solver.certify.answer import CertifiedPoint, answer_fields
from solver.certify.colgen import Messages, decide
from solver.core.budget import UNLIMITED
from solver.core.tolerances import SOLVER_DEFAULT
from solver.locus.membership import PlainRows, outline_of
from solver.motion.forward import solve_forward
from tests.budgets import checks_budget

TOL = SOLVER_DEFAULT
MESSAGES = Messages(inside="in", outside="out")
# mu = |alpha . c| / a = 0.3, then moved to (7, -3), turned by 2 rad and scaled by 40
_T = 2.0
_ROT = np.array([[math.cos(_T), -math.sin(_T)], [math.sin(_T), math.cos(_T)]])
_CM = np.array([7.0, -3.0])
SCENE = PushScene.create(40.0, _CM + 40.0 * _ROT @ np.array([0.3, -0.8]), _T + 0.0, _T + 1.9, _CM)


def _answer(point_world, budget=UNLIMITED) -> CertifiedPoint:
    outline = outline_of(SCENE, None)
    r, on = outline.snap(outline.to_local(point_world))
    alpha = outline.vector_to_local(SCENE.alpha_hat)
    c = outline.vector_to_local(SCENE.contact_rel) / outline.length
    rows = PlainRows(outline, r, on, outline.contains(r, on), alpha, float(alpha @ (c - r)))
    dec = decide(rows, TOL, budget, MESSAGES)
    return CertifiedPoint(**answer_fields(dec, outline, r, rows.in_footprint, dec.y, None, 0.0))


def _boundary_pair(k, offset):
    ring = disk_cor_locus(SCENE, n_points=32).boundary
    tangent = ring[(k + 1) % 32] - ring[k - 1]
    nu = np.array([tangent[1], -tangent[0]]) / np.hypot(*tangent)
    return ring[k] - offset * nu, ring[k] + offset * nu


@pytest.mark.parametrize("k", [3, 11, 20])
def test_the_world_witness_has_the_candidate_as_its_cor(k):
    inside, _ = _boundary_pair(k, 1e-3 * SCENE.disk_radius)
    ans = _answer(inside)
    assert ans.status == "inside" and ans.complete and ans.certificate_kind == "witness"
    assert np.allclose(ans.cor, inside, rtol=0.0, atol=1e-12 * SCENE.disk_radius)
    assert ans.length_scale == pytest.approx(SCENE.disk_radius, rel=1e-15)
    pts = ans.witness_points
    assert np.all(np.hypot(*(pts - SCENE.center_of_mass).T) <= SCENE.disk_radius * (1 + 1e-12))
    weights = ans.witness_weights
    if ans.point_mass_at_cor > 0.0:  # the point mass at the COR joins the support there
        pts, weights = np.vstack([pts, ans.cor]), np.append(weights, ans.point_mass_at_cor)
    support = Support.create(pts, weights, SCENE.center_of_mass, TOL)
    cor = solve_forward(SCENE, support, mu_c=0.0, method="newton", tol=TOL).cor
    assert np.linalg.norm(cor - inside) <= 1e-6 * SCENE.disk_radius
    assert np.linalg.norm(ans.point_mass_subgradient) <= ans.point_mass_at_cor * (1 + 1e-9) + 1e-15


def test_an_outside_answer_carries_its_certificate():
    _, outside = _boundary_pair(7, 1e-3 * SCENE.disk_radius)
    ans = _answer(outside)
    assert ans.status == "outside" and ans.complete and ans.certificate_kind == "dual"
    assert ans.lower_bound_method == "branch_and_bound" and ans.dual_margin > 0.0
    assert ans.dual is not None and ans.message == "out"


def test_an_expired_budget_leaves_the_answer_incomplete():
    inside, _ = _boundary_pair(7, 1e-3 * SCENE.disk_radius)
    ans = _answer(inside, checks_budget(0))
    assert ans.status == "undecided" and not ans.complete
