"""Radius of gyration and the impact-limit COR (book 7.4, equation (7.1)).

In the impact limit (inertia dominates friction, 7.4) with a frictionless pusher
(mu_c = 0) or a plastic contact (e = 0) the COR of the instantaneous motion lies on the
symmetry axis of the quasi-static locus, at the distance (7.1)

    r_impact = rho^2 / (alpha . c)

from the CM, rho the polar radius of gyration about the CM. Derivation (re-done here, it
fixes the side): an impulse J n at the contact c (CM frame) gives the CM the velocity
J n / M and the body the rotation rate J (c x n) / (M rho^2). The COR of that motion,
r = z x v / omega (3.1.4), is r = rho^2 (z x n) / (c x n) = -rho^2 alpha_hat / (alpha_hat . c)
since c x n = -(alpha_hat . c) with alpha_hat = z x n (models/core/scene.py). In the locus frame
(x along alpha' = sign(m) alpha_hat, models/locus/cor_disk.py) that is the point
(-rho^2 / |alpha . c|, 0): the same side and axis as the tip of the quasi-static locus,
(-a^2 / |alpha . c|, 0) by (3.37). So (7.1) with rho = a (a thin ring, all mass on the
bounding circle) is the tip, and every other body inside the disk has rho < a, so its
impact COR lies between the CM and the tip, inside the quasi-static locus.

Pure numpy.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.core.scene import PushScene
from models.core.tolerances import SUPPORT_DEFAULT


def _positive_length(name: str, value: float) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InvalidInput(name, "must be a number") from None
    if not (math.isfinite(x) and x > 0.0):
        raise InvalidInput(name, "must be a positive finite length")
    return x


def disk_radius_of_gyration(radius: float) -> float:
    """Uniform disk of radius a about its centre: rho^2 = a^2 / 2."""
    return _positive_length("disk_radius", radius) * math.sqrt(0.5)


def ring_radius_of_gyration(radius: float) -> float:
    """Thin ring (circular rim) of radius a about its centre: rho = a (7.4)."""
    return _positive_length("disk_radius", radius)


def polygon_second_moments(vertices: ArrayLike, about: ArrayLike) -> tuple[float, float]:
    """Signed area A and polar second moment J = integral |x - about|^2 dA of a simple
    polygon of uniform density, from its vertices (Green's theorem, the shoelace pattern):

        A = 1/2  sum_i k_i,   J = 1/12 sum_i k_i (x_i^2 + x_i x_j + x_j^2 + y_i^2 + y_i y_j + y_j^2)

    with j = i + 1 (cyclic), coordinates relative to ``about`` and k_i = x_i y_j - x_j y_i.
    Both are negative for a clockwise polygon; their ratio is not. Working relative to
    ``about`` keeps the digits when the polygon is far from the origin."""
    v = np.asarray(vertices, dtype=float) - np.asarray(about, dtype=float)
    x, y = v[:, 0], v[:, 1]
    xj, yj = np.roll(x, -1), np.roll(y, -1)
    k = x * yj - xj * y
    area = 0.5 * float(np.sum(k))
    polar = float(np.sum(k * (x * x + x * xj + xj * xj + y * y + y * yj + yj * yj))) / 12.0
    return area, polar


def polygon_mean_distance(vertices: ArrayLike, about: ArrayLike) -> float:
    """rbar = (1/A) integral |x - about| dA over a simple polygon, exactly.

    Green / triangle fan from ``about``: the triangle (about, p_i, p_j) contributes the
    polar integral of R(phi)^3 / 3, R = h / cos(psi) along its edge (h the signed distance
    from ``about`` to the edge line, t the coordinate along the edge, r = |p|). With
    integral sec^3 = (sec tan + ln(sec + tan)) / 2 this is

        (1/6) [h r t + h^3 ln(r + t)] from p_i to p_j,

    summed over the edges (signs from h carry the orientation; edges whose line passes
    through ``about`` contribute nothing). r + t is evaluated as h^2 / (r - t) for t < 0,
    without cancellation. Computed in units of the largest |p - about|, so any size keeps
    its digits."""
    v = np.asarray(vertices, dtype=float) - np.asarray(about, dtype=float)
    scale = float(np.max(np.linalg.norm(v, axis=1)))
    if not (math.isfinite(scale) and scale > 0.0):
        raise InvalidInput("footprint", "must have vertices away from the centre of mass")
    v = v / scale
    p, q = v, np.roll(v, -1, axis=0)
    e = q - p
    length = np.linalg.norm(e, axis=1)
    e = e / length[:, None]
    h = p[:, 0] * e[:, 1] - p[:, 1] * e[:, 0]  # signed distance of `about` to the edge line

    def primitive(x: np.ndarray) -> np.ndarray:
        r = np.linalg.norm(x, axis=1)
        t = np.einsum("ij,ij->i", x, e)
        with np.errstate(divide="ignore", invalid="ignore"):
            s = np.where(t >= 0.0, r + t, h * h / (r - t))
            log_term = np.where(s > 0.0, h**3 * np.log(np.where(s > 0.0, s, 1.0)), 0.0)
        return h * r * t + log_term

    integral = float(np.sum(primitive(q) - primitive(p))) / 6.0
    x, y = v[:, 0], v[:, 1]
    area = 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
    return scale * integral / area


def polygon_radius_of_gyration(footprint: Footprint, about: ArrayLike | None = None) -> float:
    """Polar radius of gyration of a uniform lamina with the footprint's shape, about
    ``about`` (default: the footprint's centre of mass): rho^2 = J_about / A.

    For a uniform density the CM is the area centroid c0 and this is the radius of
    gyration of (7.1). A footprint built with another centre of mass describes a
    non-uniform body whose inertia its outline does not determine; the value returned is
    then the uniform lamina's second moment about that CM, rho_c0^2 + |c0 - CM|^2 by the
    parallel-axis theorem (about the CM directly, so no subtraction is involved). It is
    still below the footprint's circumradius, as every point of the lamina is."""
    point = footprint.center_of_mass if about is None else np.asarray(about, dtype=float)
    if point.shape != (2,) or not np.all(np.isfinite(point)):
        raise InvalidInput("center_of_mass", "must be a finite point [x, y]")
    area, polar = polygon_second_moments(footprint.vertices, point)
    return math.sqrt(polar / area)


def support_radius_of_gyration(points: ArrayLike, weights: ArrayLike, center_of_mass: ArrayLike | None = None,
                               centroid_rel: float = SUPPORT_DEFAULT.centroid_rel) -> float:
    """Radius of gyration of point masses: rho^2 = sum_i P_i |w_i - CM|^2, P normalised.

    The CM of point masses is their weighted centroid; a given ``center_of_mass`` must be
    it to within ``centroid_rel`` of the support's size (book 3.1.5), else InvalidInput."""
    w = np.asarray(points, dtype=float)
    if w.ndim != 2 or w.shape[1] != 2 or w.shape[0] < 1 or not np.all(np.isfinite(w)):
        raise InvalidInput("points", "must be a non-empty list of finite [x, y] points")
    p = np.asarray(weights, dtype=float).reshape(-1)
    if p.shape[0] != w.shape[0] or not np.all(np.isfinite(p)) or np.any(p < 0.0) or not p.sum() > 0.0:
        raise InvalidInput("weights", "need one finite non-negative weight per point, not all zero")
    p = p / p.sum()
    centroid = p @ w
    if center_of_mass is None:
        cm = centroid
    else:
        cm = np.asarray(center_of_mass, dtype=float)
        if cm.shape != (2,) or not np.all(np.isfinite(cm)):
            raise InvalidInput("center_of_mass", "must be a finite point [x, y]")
        size = max(float(np.max(np.linalg.norm(w - cm, axis=1))), np.finfo(float).tiny)
        if np.linalg.norm(centroid - cm) > centroid_rel * size:
            raise InvalidInput("center_of_mass", "is not the weighted centroid of the point masses")
    return math.sqrt(float(p @ np.sum((w - cm) ** 2, axis=1)))


def impact_cor_distance(scene: PushScene, radius_of_gyration: float) -> float | None:
    """r_impact = rho^2 / |alpha . c| (7.1); None for a pure translation (alpha . c = 0)."""
    rho = _positive_length("radius_of_gyration", radius_of_gyration)
    if rho > scene.disk_radius:
        raise InvalidInput(
            "radius_of_gyration",
            "exceeds the disk radius: a body inside the disk of radius a has rho <= a "
            "(rho = a only for a thin ring on the circle)",
        )
    if scene.is_translation:
        return None
    return rho * rho / abs(scene.moment_arm)


def impact_cor(scene: PushScene, radius_of_gyration: float) -> np.ndarray | None:
    """World-frame COR of the impact limit (7.1): the locus-frame point
    (-rho^2 / |alpha . c|, 0), on the symmetry axis on the side of the quasi-static tip
    (3.37) (module docstring). None for a pure translation (the COR is at infinity)."""
    dist = impact_cor_distance(scene, radius_of_gyration)
    if dist is None:
        return None
    return scene.to_world(np.array([-dist, 0.0]))
