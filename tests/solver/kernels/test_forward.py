"""The compiled forward solve (solver/kernels/forward.py) against its reference, the vectorised
Newton solver (solver/motion/newton.py) through the same mode logic (4.1), on seeded cases:
tripods at several mu and mu_c (0, -> 0, moderate, large), supports of 2 to 40 points (the
Newton-first path beyond 16), the COR on a support point (3.3), translations (3.3.11.1),
sticking on a support point (4.1.2) and extreme scales. The two must give the same motion
(to 1e-9 of the normalised twist), the same mode and the same support point, each within
the KKT tolerance."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.scene import PushScene
from models.core.support import random_balanced_tripods
from solver.motion.forward import solve_forward_batch, solve_forward_scenes
from tests.scenes import SEED, scene_for_mu

AGREE = 1e-9
"""Largest difference of the normalised twists (v, omega L) and contact forces (/ mu_s W) of
the two paths; their KKT tolerance is 1e-10."""


def _agree(scene_or_scenes, points, weights, mu_c):
    solve = solve_forward_scenes if isinstance(scene_or_scenes, list) else solve_forward_batch
    got = solve(scene_or_scenes, points, weights, mu_c=mu_c, check_centroid=False)
    ref = solve(scene_or_scenes, points, weights, mu_c=mu_c, check_centroid=False, compiled=False)
    assert got.reference_rows == 0, got.message
    ell = np.max(np.linalg.norm(points - np.mean(points, axis=1, keepdims=True), axis=2), axis=1) * 2.0
    assert np.all(ref.converged) and np.all(got.converged)
    assert np.array_equal(got.mode, ref.mode)
    assert np.array_equal(got.cor_on_support, ref.cor_on_support)
    assert np.max(np.abs(got.velocity_cm - ref.velocity_cm)) <= AGREE
    assert np.max(np.abs((got.omega - ref.omega) * ell)) <= AGREE
    assert np.max(np.abs(got.contact_force - ref.contact_force)) <= AGREE
    return got


def random_supports(rng, b, k, spread=1.0):
    """b random supports of k points with their weighted centroid at the origin."""
    w = rng.uniform(-spread, spread, (b, k, 2))
    p = rng.uniform(0.05, 1.0, (b, k))
    p /= p.sum(axis=1, keepdims=True)
    return w - np.einsum("bk,bki->bi", p, w)[:, None, :], p


@pytest.mark.parametrize("mu", (0.05, 0.3, 0.9, 1.5))
@pytest.mark.parametrize("mu_c", (0.0, 1e-9, 0.4, 50.0))
def test_tripods_agree_with_the_reference(mu, mu_c):
    """Figure 3-5's tripods (3.2): every mode of 4.1 met, the same motions."""
    scene = scene_for_mu(mu)
    rng = np.random.default_rng([SEED, int(100 * mu), int(1e3 * mu_c)])
    pts, wts = random_balanced_tripods(rng, 400, scene.disk_radius, scene.center_of_mass, None)
    got = _agree(scene, pts, wts, mu_c)
    if mu_c == 0.4 and mu >= 0.3:
        assert len(set(got.mode.tolist())) >= 2  # sticking and slipping both met (all stick at mu 0.05)


@pytest.mark.parametrize("k", (2, 5, 16, 17, 40))
@pytest.mark.parametrize("mu_c", (0.0, 0.3))
def test_supports_of_many_sizes_agree(k, mu_c):
    """The vertex-first path (k <= 16) and the Newton-first path with its nearest-point tests
    and kink escapes (k > 16)."""
    scene = PushScene.create(1.0, (-0.9, -0.3), math.pi / 2, 0.0)
    rng = np.random.default_rng([SEED, k, int(10 * mu_c)])
    w, p = random_supports(rng, 200, k, 0.8)
    _agree(scene, w, p, mu_c)


def test_a_cor_on_a_support_point_agrees():
    """A heavy point on the sticking line pins the part (3.3): the COR on it, found exactly
    by both paths, without friction and sticking with a large mu_c (the force chosen deepest
    in the cone, 4.1.2)."""
    base = PushScene.create(1.0, (-0.9, 0.2), math.radians(80.0), 0.0)
    c, jp = base.contact_point, np.array([-base.push_hat[1], base.push_hat[0]])
    rng = np.random.default_rng(SEED + 5)
    scenes, pts, wts = [], [], []
    for _ in range(100):
        heavy = c + rng.uniform(0.3, 1.2) * jp * rng.choice([-1.0, 1.0])
        w = np.vstack([heavy, rng.uniform(-0.8, 0.8, (3, 2))])
        p = np.r_[0.85, rng.uniform(0.02, 0.08, 3)]
        p /= p.sum()
        shift = p @ w
        scenes.append(PushScene.create(1.0, c - shift, base.edge_angle, 0.0))
        pts.append(w - shift)
        wts.append(p)
    for mu_c in (0.0, 1e6):
        got = _agree(scenes, np.array(pts), np.array(wts), mu_c)
        assert np.count_nonzero(got.cor_on_support >= 0) >= 10


def test_a_translation_agrees():
    """The force line through the CM of a symmetric support: a translation (3.3.11.1)."""
    scene = PushScene.create(1.0, (-1.0, 0.0), math.pi / 2, 0.0)
    w = np.array([[[0.0, 0.5], [0.0, -0.5], [0.5, 0.0], [-0.5, 0.0]]])
    got = _agree(scene, w, np.ones((1, 4)) / 4.0, 0.0)
    assert abs(got.omega[0]) <= 1e-12 and np.isnan(got.cor[0, 0])


@pytest.mark.parametrize("scale", (1e-6, 1e6))
def test_the_answers_scale(scale):
    """Lengths scaled by 1e-6 and 1e6: v unchanged, omega divided by the scale (3.2)."""
    scene = scene_for_mu(0.5)
    rng = np.random.default_rng(SEED + 7)
    pts, wts = random_balanced_tripods(rng, 100, scene.disk_radius, scene.center_of_mass, None)
    small = PushScene.create(scene.disk_radius * scale, scene.contact_point * scale, scene.edge_angle,
                             scene.push_direction, scene.center_of_mass * scale)
    base = solve_forward_batch(scene, pts, wts, mu_c=0.3, check_centroid=False)
    got = solve_forward_batch(small, pts * scale, wts, mu_c=0.3, check_centroid=False)
    assert np.max(np.abs(got.velocity_cm - base.velocity_cm)) <= 1e-12
    assert np.max(np.abs(got.omega * scale - base.omega)) <= 1e-12 * np.max(np.abs(base.omega))


def test_a_scene_per_support_agrees():
    """The simulator's batches: a scene (contact, edge, CM) per support."""
    rng = np.random.default_rng(SEED + 11)
    scenes, pts = [], []
    for i in range(60):
        cm = rng.uniform(-2, 2, 2)
        th = rng.uniform(0, 2 * math.pi)
        contact = cm + 0.9 * np.array([math.cos(th), math.sin(th)])
        scenes.append(PushScene.create(1.0, contact, th + math.pi / 2 + rng.uniform(-0.3, 0.3), th + math.pi, cm))
        w, _ = random_supports(rng, 1, 4, 0.7)
        pts.append(w[0] + cm)
    p = np.full((60, 4), 0.25)
    pts = np.array(pts)
    pts -= np.einsum("bk,bki->bi", p, pts)[:, None, :] - np.array([s.center_of_mass for s in scenes])[:, None, :]
    for mu_c in (0.0, 0.25):
        _agree(scenes, pts, p, mu_c)


def test_a_problem_the_kernel_leaves_unsolved_goes_to_the_reference(monkeypatch):
    """A row the kernel flags is solved again on the reference path and counted."""
    from solver.kernels import codes
    from solver.kernels import forward as kernel

    real = kernel.solve_supports

    def flag_first(*args):
        values, ints, bad = real(*args)
        ints[0, codes.I_FAILED] = 1
        return values, ints, bad

    monkeypatch.setattr(kernel, "solve_supports", flag_first)
    scene = scene_for_mu(0.3)
    rng = np.random.default_rng(SEED)
    pts, wts = random_balanced_tripods(rng, 20, scene.disk_radius, scene.center_of_mass, None)
    got = solve_forward_batch(scene, pts, wts, mu_c=0.4, check_centroid=False)
    ref = solve_forward_batch(scene, pts, wts, mu_c=0.4, check_centroid=False, compiled=False)
    assert got.reference_rows == 1 and "1 re-solved on the reference path" in got.message
    assert np.array_equal(got.velocity_cm[0], ref.velocity_cm[0]) and got.omega[0] == ref.omega[0]


@pytest.mark.parametrize("change, field, words", [
    (lambda w, p: w.__setitem__((3, 1, 0), np.nan), "weights", "must be finite"),
    (lambda w, p: p.__setitem__((2, 0), -0.1), "weights", "must be finite"),
    (lambda w, p: p.__setitem__(4, 0.0), "weights", "positive total weight"),
    (lambda w, p: w.__setitem__((5, 0), w[5, 0] + 0.3), "weights", "support 5 does not have its centroid"),
])
def test_bad_supports_are_refused_as_on_the_reference_path(change, field, words):
    """The compiled path's checks say what the reference path's say, naming the same field."""
    from models.core.errors import InvalidInput

    scene = scene_for_mu(0.3)
    rng = np.random.default_rng(SEED + 3)
    pts, wts = random_balanced_tripods(rng, 8, scene.disk_radius, scene.center_of_mass, None)
    change(pts, wts)
    for compiled in (True, False):
        with pytest.raises(InvalidInput) as err:
            solve_forward_batch(scene, pts, wts, mu_c=0.2, compiled=compiled)
        assert err.value.field == field and words in str(err.value)
