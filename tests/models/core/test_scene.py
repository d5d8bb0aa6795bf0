"""The geometry of one push (models/core/scene.py; book 3.1.9-3.1.10, 3.3, 3.3.1): the frames
and signs of docs/mechanics.md, the rotation (3.3) and slip (3.2) per unit push against
small finite motions, Mason's sense of rotation, and input validation naming the field."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.scene import PushScene, unit
from tests.scenes import SEED


def test_frames_and_signs():
    """n is normal to the edge with n . p = sin(alpha) > 0 (3.3); alpha_hat = z x n; the
    book's alpha, the angle from p to alpha_hat, lies in (0, pi); m = alpha_hat . c."""
    rng = np.random.default_rng(SEED)
    for _ in range(200):
        edge, push = rng.uniform(-10, 10, 2)
        if abs(math.sin(push - edge)) < 1e-3:
            continue
        cm = rng.normal(size=2)
        sc = PushScene.create(rng.uniform(0.1, 3.0), cm + rng.normal(size=2), edge, push, cm)
        assert abs(sc.normal @ unit(edge)) < 1e-12 and sc.normal @ sc.push_hat > 0.0
        assert np.allclose(sc.alpha_hat, [-sc.normal[1], sc.normal[0]], atol=0.0)
        assert 0.0 < sc.book_alpha < math.pi
        assert sc.sin_alpha == pytest.approx(math.sin(sc.book_alpha), abs=1e-12)
        assert sc.moment_arm == pytest.approx(sc.alpha_hat @ (sc.contact_point - cm), abs=1e-12)
        assert sc.axis @ sc.alpha_hat == pytest.approx(math.copysign(1.0, sc.moment_arm))
        local = np.array([0.7, -0.2])
        world = sc.to_world(local)
        e1 = sc.axis
        assert world @ e1 - cm @ e1 == pytest.approx(0.7, abs=1e-12)


def test_mason_sense_3_3_1():
    """m > 0 (the line of force passes with the CM on its alpha_hat side) turns the part
    clockwise, m < 0 counter-clockwise, a line through the CM translates it."""
    assert PushScene.create(1.0, [-1.0, 0.5], math.pi / 2).sense == "cw"
    assert PushScene.create(1.0, [-1.0, -0.5], math.pi / 2).sense == "ccw"
    flat = PushScene.create(1.0, [-1.0, 0.0], math.pi / 2)
    assert flat.sense == "none" and flat.is_translation


def test_slip_per_push_3_2_matches_kinematics():
    """The pusher advances dx along p while the contact point of the part moves
    omega z x (c - r) dx; their difference along alpha_hat is the slip (the dx2 of (3.2))."""
    sc = PushScene.create(1.0, [0.2, 0.3], 1.1, 0.4, [0.1, -0.2])
    for cor in ([0.0, -2.0], [0.5, 0.1], [-3.0, 4.0]):
        dx = 1e-7
        dth = sc.rotation_per_push(cor) * dx
        rot = np.array([[math.cos(dth), -math.sin(dth)], [math.sin(dth), math.cos(dth)]])
        moved = np.asarray(cor) + rot @ (sc.contact_point - np.asarray(cor))
        slip = (dx * sc.push_hat - (moved - sc.contact_point)) @ sc.alpha_hat / dx
        assert sc.slip_per_push(cor) == pytest.approx(slip, rel=1e-6, abs=1e-9)


def test_a_cor_on_the_line_of_force_admits_no_push():
    sc = PushScene.create(1.0, [-1.0, 0.5], math.pi / 2)
    with pytest.raises(InvalidInput) as err:
        sc.rotation_per_push(sc.contact_point + 3.0 * sc.normal)
    assert err.value.field == "cor"


@pytest.mark.parametrize("cor", [[0.0, -2.0], [0.5, 0.1], [-3.0, 4.0]])
def test_rotation_per_push_3_3_matches_kinematics(cor):
    """Turn the part by a small angle about the COR and measure how far the contact's
    normal component moved: it must equal the pusher's advance times n . p (3.3)."""
    sc = PushScene.create(1.0, [0.2, 0.3], 1.1, 0.4, [0.1, -0.2])
    w = sc.rotation_per_push(cor)
    dth = 1e-7
    rot = np.array([[math.cos(dth), -math.sin(dth)], [math.sin(dth), math.cos(dth)]])
    moved = np.asarray(cor) + rot @ (sc.contact_point - np.asarray(cor))
    advance = (moved - sc.contact_point) @ sc.normal / sc.sin_alpha
    assert w == pytest.approx(dth / advance, rel=1e-6)
    # Mason/3.3.1: a COR of the locus turns the part the locus' way
    if cor == [0.0, -2.0]:
        assert (w < 0) == (sc.sense == "cw")


def test_scene_validation_names_the_field():
    with pytest.raises(InvalidInput) as err:
        PushScene.create(0.0, [0, 0], 1.0)
    assert err.value.field == "disk_radius"
    with pytest.raises(InvalidInput) as err:
        PushScene.create(1.0, [0, 0], 0.5, 0.5)  # pushing along the edge
    assert err.value.field == "push_direction"
    with pytest.raises(InvalidInput) as err:
        PushScene.create(1.0, [0, float("nan")], 0.5)
    assert err.value.field == "contact_point"
