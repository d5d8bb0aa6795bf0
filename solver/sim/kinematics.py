"""Planar rigid-body kinematics of a pushed part (book 3.1.9-3.3: a motion per unit push is
a rotation about the COR): poses, rotations, and the exact rigid motion of a twist held for
a push.

A pose is the world position of the part's centre of mass (CM) and its orientation theta
(radians, counter-clockwise). A twist per unit push (v, omega) -- the CM's velocity and
the rotation rate per unit of pusher travel, as :func:`solver.motion.forward.solve_forward`
returns them -- is a rotation about the COR r = CM + J v / omega (J = +90 degrees), or a
translation when omega = 0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from models.core.mpp import perp

TRANSLATION_TURN = 1e-14
"""A step whose turn |omega h| is at most this (radians) is taken as the translation v h
(the COR is then too far away to rotate about without losing digits)."""


@dataclass(frozen=True)
class Twist:
    """The motion per unit push found with the CM at ``cm_at``: the CM's velocity
    ``velocity`` (2,) and the rotation rate ``omega`` (CCW positive)."""

    velocity: np.ndarray
    omega: float
    cm_at: np.ndarray

    def scaled(self, factor: float) -> Twist:
        """The same motion per unit of another parameter (e.g. a path's u with speed
        ``factor`` of pusher travel per unit u)."""
        return Twist(self.velocity * factor, self.omega * factor, self.cm_at)


def rotation(theta: float) -> np.ndarray:
    """The 2 x 2 matrix of a counter-clockwise rotation by theta."""
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s], [s, c]])


def rotate_batch(points: np.ndarray, theta: float | np.ndarray) -> np.ndarray:
    """Rotate points (B, k, 2) by angles theta (B,) or one angle, CCW positive."""
    th = np.broadcast_to(np.asarray(theta, dtype=float), points.shape[:1])
    c, s = np.cos(th)[:, None], np.sin(th)[:, None]
    x, y = points[..., 0], points[..., 1]
    return np.stack([c * x - s * y, s * x + c * y], axis=-1)


def body_to_world(cm: np.ndarray, theta: float, body_points: np.ndarray) -> np.ndarray:
    """Points (k, 2) given relative to the CM in the body frame, in the world at the pose."""
    return cm + body_points @ rotation(theta).T


def advance(cm: np.ndarray, theta: float, twist: Twist, h: float) -> tuple[np.ndarray, float]:
    """The pose (cm, theta) moved by ``twist`` held for a push h: a rotation by omega h
    about the twist's COR, the world point cm_at + J v / omega (3.3), or the translation
    v h when the turn is at most TRANSLATION_TURN.

    The COR is fixed in the world where the twist was found, not relative to the moved
    pose: for a midpoint twist, rotating about a point relative to the pose would shift the
    COR by O(h) and make the midpoint scheme first order."""
    turn = twist.omega * h
    if abs(turn) <= TRANSLATION_TURN:
        return cm + twist.velocity * h, theta + turn
    cor = twist.cm_at + perp(twist.velocity) / twist.omega
    return cor + rotation(turn) @ (cm - cor), theta + turn
