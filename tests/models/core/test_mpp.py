"""The minimum-power formulation in twists (models/core/mpp.py; book 2, 3.5-3.10): the power
(3.6)-(3.7) is convex and positively homogeneous, the membership columns of (3.8)-(3.10)
are affine along rays from r, the stationarity residual vanishes at a forward solve's COR,
and Mason's rule (1.6.2) with friction."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.mpp import (
    contact_generalized_force,
    lever,
    mason_sense,
    membership_columns,
    point_velocities,
    power,
    stationarity_residual,
)
from models.core.scene import PushScene
from models.core.support import Support
from tests.scenes import SEED


def test_power_3_7_is_convex_and_positively_homogeneous():
    """f(x) = sum P_i |v + omega J w_i| (3.6)-(3.7): f(t x) = t f(x) for t > 0 and
    f((x + y)/2) <= (f(x) + f(y))/2."""
    rng = np.random.default_rng(SEED)
    w = rng.normal(size=(7, 2))
    p = rng.uniform(0.1, 1.0, 7)
    for _ in range(100):
        x, y = rng.normal(size=3), rng.normal(size=3)
        assert power(2.5 * x, w, p) == pytest.approx(2.5 * power(x, w, p), rel=1e-13)
        assert power(0.5 * (x + y), w, p) <= 0.5 * (power(x, w, p) + power(y, w, p)) + 1e-13
    v = point_velocities(np.array([1.0, 2.0, 3.0]), w)
    assert np.allclose(v, np.array([1.0, 2.0]) + 3.0 * np.column_stack([-w[:, 1], w[:, 0]]))


def test_contact_force_is_the_covector_of_the_work_rate():
    """(F, F . J c) applied to a twist (v, omega) is the work rate F . (v + omega J c) (ch. 2)."""
    rng = np.random.default_rng(SEED + 1)
    for _ in range(20):
        f, c, x = rng.normal(size=2), rng.normal(size=2), rng.normal(size=3)
        vel = x[:2] + x[2] * np.array([-c[1], c[0]])
        assert contact_generalized_force(f, c) @ x == pytest.approx(f @ vel, abs=1e-12)


def test_stationarity_3_8_vanishes_at_the_cor_of_a_forward_solve():
    """The book's (3.8), d_r alpha - s v_r = 0, holds at the COR the minimum-power solver
    finds for a support none of whose points is the COR."""
    from solver.motion.forward import solve_forward

    sc = PushScene.create(1.0, [-0.6, 0.5], math.pi / 2)
    rng = np.random.default_rng(SEED + 2)
    pts = rng.uniform(-0.6, 0.6, size=(9, 2))
    pts -= pts.mean(axis=0)
    sup = Support.create(pts, np.ones(9), [0.0, 0.0])
    res = solve_forward(sc, sup)
    r = res.cor - sc.center_of_mass
    assert np.min(np.hypot(*(sup.points - res.cor).T)) > 1e-6
    st = stationarity_residual(r, sup.points - sc.center_of_mass, sup.weights, sc.contact_rel, sc.alpha_hat)
    assert np.linalg.norm(st) < 1e-9
    assert lever(sc.contact_rel, sc.alpha_hat, r) == pytest.approx(sc.alpha_hat @ (sc.contact_rel - r))


def test_mason_sense_with_friction_1_6_2():
    """Mason's rules: both edges of the friction cone passing on one side of the CM fix the
    sense whatever the push; edges straddling the CM leave it to the line of motion."""
    n = np.array([1.0, 0.0])
    c = np.array([-1.0, 0.05])
    up, down = np.array([1.0, 0.2]) / math.hypot(1.0, 0.2), np.array([1.0, -0.2]) / math.hypot(1.0, 0.2)
    assert mason_sense(c, n, up, 0.0) == mason_sense(c, n, down, 0.0) == "cw"
    assert mason_sense(c, n, down, 0.01) == "cw"  # narrow cone: both edges on one side
    assert mason_sense(c, n, up, 1.0) == "cw" and mason_sense(c, n, down, 1.0) == "ccw"  # wide: the push decides
    assert mason_sense(np.array([-1.0, 0.0]), n, n, 0.5) == "none"


def test_columns_are_affine_along_rays_from_r():
    """Module docstring: on a ray w = r + rho u every component of G(w) = (1, w/L, g_r(w)/L)
    of (3.8) is affine in rho, so y . G is too and its minimum over the footprint lies on the
    outline or at r. Checked with second differences of models.core.mpp.membership_columns."""
    rng = np.random.default_rng(SEED)
    for _ in range(50):
        r, c = rng.normal(size=2), rng.normal(size=2)
        alpha = rng.normal(size=2)
        alpha /= np.linalg.norm(alpha)
        u = rng.normal(size=2)
        u /= np.linalg.norm(u)
        rho = np.sort(rng.uniform(0.01, 5.0, 3))
        g = membership_columns(r, r + rho[:, None] * u, c, alpha, 1.7)
        slope = (g[:, 1] - g[:, 0]) / (rho[1] - rho[0])
        assert np.allclose(g[:, 2], g[:, 0] + slope * (rho[2] - rho[0]), atol=1e-12)
        # and the limit rho -> 0 is the point-mass column with zeta = u
        s = lever(c, alpha, r)
        limit = np.concatenate([[1.0], r / 1.7, -s * u / 1.7])
        assert np.allclose(g[:, 0] - slope * rho[0], limit, atol=1e-12)


@pytest.mark.parametrize("theta", [0.0, 0.7, 2.0, -2.9])
@pytest.mark.parametrize("push_angle", [0.0, 0.4, -1.1])
def test_mason_a_force_through_the_cm_translates_whatever_the_push(theta, push_angle):
    """(1.6.2) With mu_c = 0 the force is the normal; through the CM it cannot turn the
    part, whatever the direction the pusher moves in (the push direction decides only when
    the friction cone straddles the CM). It said 'ccw' when the motion's line missed the CM."""
    rot = np.array([[math.cos(theta), -math.sin(theta)], [math.sin(theta), math.cos(theta)]])
    n = rot @ np.array([1.0, 0.0])
    c = -0.7 * n  # the contact on the line of the normal through the CM
    p = rot @ np.array([math.cos(push_angle), math.sin(push_angle)])
    assert mason_sense(c, n, p, 0.0) == "none"
    assert mason_sense(c + 1e-15 * (rot @ np.array([0.0, 1.0])), n, p, 0.0, translation_rel=1e-12) == "none"
    off = c + 1e-3 * (rot @ np.array([0.0, 1.0]))  # off the line: it turns, and its mirror image the other way
    mirror = np.array([[1.0, 0.0], [0.0, -1.0]])
    turned = mason_sense(off, n, p, 0.0)
    mirrored = mason_sense(mirror @ off, mirror @ n, mirror @ p, 0.0)
    assert turned in ("cw", "ccw") and {turned, mirrored} == {"cw", "ccw"}


def test_mason_a_cone_with_one_edge_through_the_cm_turns_with_the_other():
    """(1.6.2) One edge of the friction cone through the CM (contact below it, that edge
    straight up), the other edge with a moment: every allowed force turns the part that
    way or not at all, so that is the sense; the push direction does not enter."""
    mu = 0.3
    phi = math.atan(mu)
    c = np.array([0.0, -1.0])
    n = np.array([math.sin(phi), math.cos(phi)])  # (0, 1) turned clockwise by phi: n + mu J n is vertical
    for push in (np.array([1.0, 0.0]), np.array([-1.0, 0.2])):
        assert mason_sense(c, n, push, mu) == "ccw"  # the other edge leans right of the CM: c x f > 0


def test_perp_is_the_quarter_turn_for_one_vector_and_for_arrays():
    """Issue 26: perp's fast path for one vector and its array path give J v exactly (the
    same numbers as stacking (-y, x)), in the input's shape."""
    from models.core.mpp import perp

    rng = np.random.default_rng(5)
    for v in (rng.normal(size=2), rng.normal(size=(7, 2)), rng.normal(size=(3, 4, 2))):
        want = np.stack([-v[..., 1], v[..., 0]], axis=-1)
        got = perp(v)
        assert got.shape == want.shape and np.array_equal(got, want)
    assert np.array_equal(perp([1, 2]), [-2.0, 1.0])
