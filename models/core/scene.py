"""The geometry of one push: workpiece disk, centre of mass, contact, edge and push line.

Frames and signs (book 3.1.9-3.1.10, 3.3.1; see docs/mechanics.md):

* World frame: right-handed, x right, y up; angles in radians, counter-clockwise (CCW)
  positive. Every public input and output of the project is in this frame.
* ``normal`` n: unit direction of the pusher's force on the workpiece, normal to the edge and
  pointing into the workpiece, chosen so that n . p > 0 (the pusher advances into the part).
* ``alpha_hat``: the book's edge vector (cos alpha, sin alpha), here z x n (n turned 90 deg CCW).
  With this choice the book's alpha is the angle from the push direction p to alpha_hat and
  lies in (0, pi), so n . p = sin(alpha) > 0, as in equation (3.3).
* ``moment_arm`` m = alpha_hat . c, with c the contact point relative to the centre of mass:
  the signed distance from the CM to the line of force. m > 0 means clockwise rotation
  (book 3.3.1); m < 0 is the mirror case, counter-clockwise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from models.core.errors import InvalidInput
from models.core.mpp import perp
from models.core.tolerances import DEFAULT, Tolerances

Sense = str  # "cw" | "ccw" | "none"


def _finite_point(name: str, value: ArrayLike) -> np.ndarray:
    arr = np.asarray(value, dtype=float)
    if arr.shape != (2,):
        raise InvalidInput(name, f"must be a point [x, y], got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InvalidInput(name, "must be finite numbers")
    return arr


def _finite_scalar(name: str, value: float) -> float:
    x = float(value)
    if not math.isfinite(x):
        raise InvalidInput(name, "must be a finite number")
    return x


def unit(angle: float) -> np.ndarray:
    """The unit vector at ``angle`` (rad, CCW from +x): the book's arrow notation (3.1.10)."""
    return np.array([math.cos(angle), math.sin(angle)])


@dataclass(frozen=True)
class PushScene:
    """A push of a workpiece bounded by a disk, with a frictionless pusher (book 3.1.9).

    Build it with :meth:`create`, which validates the input and derives the book's
    quantities. Angles are world-frame radians.
    """

    disk_radius: float
    center_of_mass: np.ndarray
    contact_point: np.ndarray
    edge_angle: float
    push_direction: float
    tolerances: Tolerances = DEFAULT
    # Derived in create() (keyword-only, required):
    contact_rel: np.ndarray = field(kw_only=True, repr=False)  # c = contact - CM
    push_hat: np.ndarray = field(kw_only=True, repr=False)  # p
    normal: np.ndarray = field(kw_only=True, repr=False)  # n, n . p > 0
    alpha_hat: np.ndarray = field(kw_only=True, repr=False)  # z x n (book's alpha vector)
    moment_arm: float = field(kw_only=True)  # m = alpha_hat . c, signed
    book_alpha: float = field(kw_only=True)  # angle from p to alpha_hat, in (0, pi)

    @classmethod
    def create(
        cls,
        disk_radius: float,
        contact_point: ArrayLike,
        edge_angle: float,
        push_direction: float = 0.0,
        center_of_mass: ArrayLike = (0.0, 0.0),
        tolerances: Tolerances = DEFAULT,
    ) -> "PushScene":
        a = _finite_scalar("disk_radius", disk_radius)
        if a <= 0.0:
            raise InvalidInput("disk_radius", "must be positive")
        cm = _finite_point("center_of_mass", center_of_mass)
        cp = _finite_point("contact_point", contact_point)
        edge = _finite_scalar("edge_angle", edge_angle)
        push = _finite_scalar("push_direction", push_direction)
        p = unit(push)
        tangent = unit(edge)
        n = perp(tangent)
        sin_alpha = float(n @ p)
        if abs(sin_alpha) <= tolerances.grazing_sin:
            raise InvalidInput(
                "push_direction",
                "is parallel to the edge (edge_angle): the pusher would slide along the "
                "edge and never push the workpiece",
            )
        if sin_alpha < 0.0:
            n = -n
            sin_alpha = -sin_alpha
        alpha_hat = perp(n)
        c = cp - cm
        m = float(alpha_hat @ c)
        if not abs(m) <= tolerances.max_relative_moment_arm * a:
            raise InvalidInput(
                "disk_radius",
                f"is too small for this contact: the line of force passes more than "
                f"{tolerances.max_relative_moment_arm:g} disk radii from the centre of mass",
            )
        book_alpha = math.atan2(p[0] * alpha_hat[1] - p[1] * alpha_hat[0], float(p @ alpha_hat))
        return cls(
            disk_radius=a,
            center_of_mass=cm,
            contact_point=cp,
            edge_angle=edge,
            push_direction=push,
            tolerances=tolerances,
            contact_rel=c,
            push_hat=p,
            normal=n,
            alpha_hat=alpha_hat,
            moment_arm=m,
            book_alpha=book_alpha,
        )

    @property
    def sin_alpha(self) -> float:
        """n . p = sin(alpha) > 0 (3.3)."""
        return float(self.normal @ self.push_hat)

    @property
    def relative_moment_arm(self) -> float:
        """|alpha . c| / a: the only shape parameter of the locus (3.3.12)."""
        return abs(self.moment_arm) / self.disk_radius

    @property
    def is_translation(self) -> bool:
        """True when the line of force passes through the CM: pure translation (3.3.11.1)."""
        return self.relative_moment_arm <= self.tolerances.translation_rel

    @property
    def sense(self) -> Sense:
        """Sense of rotation, Mason's rule with mu_c = 0 (1.6.2): the line of force
        passing on one side of the CM turns the part the corresponding way (3.3.1)."""
        if self.is_translation:
            return "none"
        return "cw" if self.moment_arm > 0.0 else "ccw"

    @property
    def axis(self) -> np.ndarray:
        """Unit vector alpha' = sign(m) alpha_hat: the locus is symmetric about the line
        through the CM along alpha', and its tip lies at -r_tip alpha' (3.3.11.1, 3.3.12)."""
        return self.alpha_hat if self.moment_arm >= 0.0 else -self.alpha_hat

    def to_world(self, local: np.ndarray) -> np.ndarray:
        """Map points (..., 2) from the locus frame (x along alpha', y = z x alpha', origin
        at the CM) into the world frame."""
        e1 = self.axis
        e2 = perp(e1)
        local = np.asarray(local, dtype=float)
        return self.center_of_mass + local[..., :1] * e1 + local[..., 1:2] * e2

    def rotation_per_push(self, cor_world: ArrayLike) -> float:
        """Rotation of the workpiece per unit advance of the pusher, rad per unit length,
        CCW positive, for a COR given in the world frame (equation 3.3).

        From n . v(c) = n . p with v(c) = omega z x (c - r):
        omega = -sin(alpha) / (alpha_hat . (c - r)). A COR on the line of force through c
        admits no push (the contact cannot move along n) and raises InvalidInput.
        """
        r = _finite_point("cor", cor_world) - self.center_of_mass
        s = float(self.alpha_hat @ (self.contact_rel - r))
        scale = max(self.disk_radius, float(np.linalg.norm(self.contact_rel)), float(np.linalg.norm(r)))
        if abs(s) <= self.tolerances.grazing_sin * scale:
            raise InvalidInput("cor", "lies on the line of force: no rotation about it can advance the contact")
        return -self.sin_alpha / s

    def slip_per_push(self, cor_world: ArrayLike) -> float:
        """Slip of the pusher along the edge per unit advance, positive along alpha_hat:
        the book's dx2 term of (3.2)."""
        r = _finite_point("cor", cor_world) - self.center_of_mass
        omega = self.rotation_per_push(cor_world)
        v_contact = omega * perp(self.contact_rel - r)
        return float(self.alpha_hat @ (self.push_hat - v_contact))
