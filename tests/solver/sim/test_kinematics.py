"""Rigid-body kinematics of a pushed part (solver/sim/kinematics.py; book 3.3: a motion per
unit push is a rotation about the COR): the exact step of a twist against an independent
fine integration of the rigid motion, composition, a full turn, and the translation limit."""

from __future__ import annotations

import math

import numpy as np
import pytest

from solver.sim.kinematics import Twist, advance, body_to_world, rotate_batch, rotation
from tests.scenes import SEED


def _integrate(cm, theta, twist, h, n=20_000):
    """The same motion by many small Euler steps of the velocity field v(P) = omega J (P - r)
    (r the COR) applied to the CM, with theta += omega dh."""
    cor = twist.cm_at + np.array([-twist.velocity[1], twist.velocity[0]]) / twist.omega
    p, th = np.array(cm, dtype=float), float(theta)
    dh = h / n
    for _ in range(n):
        mid = p + 0.5 * dh * twist.omega * np.array([-(p - cor)[1], (p - cor)[0]])
        p = p + dh * twist.omega * np.array([-(mid - cor)[1], (mid - cor)[0]])
        th += twist.omega * dh
    return p, th


def test_advance_is_the_rotation_about_the_cor_3_3():
    rng = np.random.default_rng(SEED)
    for _ in range(5):
        cm = rng.normal(size=2)
        tw = Twist(rng.normal(size=2), float(rng.normal()), cm.copy())
        got = advance(cm, 0.3, tw, 0.7)
        ref = _integrate(cm, 0.3, tw, 0.7)
        assert np.allclose(got[0], ref[0], atol=1e-8) and got[1] == pytest.approx(ref[1], abs=1e-12)


def test_two_half_steps_are_one_step_and_a_full_turn_returns():
    cm = np.array([0.4, -0.2])
    tw = Twist(np.array([1.0, 0.5]), -0.8, cm.copy())
    half = advance(*advance(cm, 0.0, tw, 0.5), tw, 0.5)
    full = advance(cm, 0.0, tw, 1.0)
    assert np.allclose(half[0], full[0], atol=1e-14) and half[1] == pytest.approx(full[1])
    around = advance(cm, 0.0, tw, 2.0 * math.pi / abs(tw.omega))
    assert np.allclose(around[0], cm, atol=1e-13)


def test_a_tiny_turn_is_a_translation():
    cm = np.array([1.0, 2.0])
    tw = Twist(np.array([0.3, -0.4]), 1e-16, cm.copy())
    moved, th = advance(cm, 0.0, tw, 2.0)
    assert np.allclose(moved, cm + 2.0 * tw.velocity) and th == pytest.approx(2e-16)
    assert tw.scaled(3.0).omega == pytest.approx(3e-16) and np.allclose(tw.scaled(3.0).velocity, [0.9, -1.2])


def test_rotations_and_body_points():
    assert np.allclose(rotation(math.pi / 2) @ [1.0, 0.0], [0.0, 1.0], atol=1e-16)
    pts = np.array([[[1.0, 0.0], [0.0, 2.0]], [[1.0, 1.0], [-1.0, 0.0]]])
    turned = rotate_batch(pts, np.array([math.pi / 2, math.pi]))
    assert np.allclose(turned, [[[0.0, 1.0], [-2.0, 0.0]], [[-1.0, -1.0], [1.0, 0.0]]], atol=1e-15)
    world = body_to_world(np.array([5.0, 5.0]), math.pi / 2, np.array([[1.0, 0.0]]))
    assert np.allclose(world, [[5.0, 6.0]], atol=1e-15)
