"""Shared scenes and independent checks of the membership tests (book 3.8-3.10): the
membership equations recomputed from a witness with models.core.mpp, dense 2-D samples of the
disk and of polygons, and the dual certificate checked on them."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.footprint import Footprint
from models.core.mpp import lever, membership_columns, stationarity_residual
from models.core.scene import PushScene
from solver.core.tolerances import SOLVER_DEFAULT
from tests.scenes import point_in_polygon

TOL = SOLVER_DEFAULT
# Scenes away from the book's standard frame (CM off the origin, tilted edge, oblique push).
FRAME = dict(a=2.0, cm=(0.4, -1.1), edge_angle=2.0, push_direction=0.3)
SQUARE = Footprint.create([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]])
L_SHAPE = Footprint.create([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]])


# --- independent checks ------------------------------------------------------------------


def equations_residual(sc: PushScene, res, length: float) -> float:
    """L1 residual of sum P G(w) + point mass = (1, 0, 0, 0, 0), recomputed from the reported
    witness with models.core.mpp.membership_columns: total weight, centroid at the CM (3.1.5) and
    (3.8) with the point mass's subgradient term -s z (|z| <= P0)."""
    cm = sc.center_of_mass
    r = res.cor - cm
    cols = membership_columns(r, res.witness_points - cm, sc.contact_rel, sc.alpha_hat, length)
    lhs = cols @ res.witness_weights
    p0, z = res.point_mass_at_cor, res.point_mass_subgradient
    assert np.hypot(*z) <= p0 * (1 + 1e-12) + 1e-300
    s = lever(sc.contact_rel, sc.alpha_hat, r)
    lhs = lhs + np.array([p0, p0 * r[0] / length, p0 * r[1] / length, -s * z[0] / length, -s * z[1] / length])
    return float(np.sum(np.abs(lhs - [1.0, 0.0, 0.0, 0.0, 0.0])))


def check_witness(sc, res, length):
    assert res.status == "inside" and res.certificate_kind == "witness"
    assert np.all(res.witness_weights >= 0.0) and res.point_mass_at_cor >= 0.0
    assert equations_residual(sc, res, length) <= 10 * TOL.membership_residual
    if res.point_mass_at_cor == 0.0:
        # the book's own form of (3.8): d_r alpha - s v_r = 0, relative to the weights' sum
        st = stationarity_residual(res.cor - sc.center_of_mass, res.witness_points - sc.center_of_mass,
                                   res.witness_weights, sc.contact_rel, sc.alpha_hat)
        assert np.linalg.norm(st) <= 10 * TOL.membership_residual * length


def disk_samples(sc: PushScene, n_rings=160, n_rim=1440) -> np.ndarray:
    """Dense 2-D samples of the disk (world), rim included."""
    pts = [np.zeros((1, 2))]
    for k, rad in enumerate(np.sqrt(np.linspace(0, 1, n_rings + 1)[1:])):
        th = np.linspace(0, 2 * math.pi, max(12, int(n_rim * rad)), endpoint=False) + 0.61 * k
        pts.append(rad * np.column_stack([np.cos(th), np.sin(th)]))
    return sc.center_of_mass + sc.disk_radius * np.vstack(pts)


def polygon_samples(fp: Footprint, n=400) -> np.ndarray:
    """Dense 2-D grid over the polygon (world) plus dense points on its edges."""
    lo, hi = fp.vertices.min(axis=0), fp.vertices.max(axis=0)
    gx, gy = np.meshgrid(np.linspace(lo[0], hi[0], n), np.linspace(lo[1], hi[1], n))
    grid = np.column_stack([gx.ravel(), gy.ravel()])
    grid = grid[point_in_polygon(grid, fp.vertices)]
    t = np.linspace(0, 1, 2000, endpoint=False)[:, None]
    edges = [a + t * (b - a) for a, b in zip(fp.vertices, np.roll(fp.vertices, -1, axis=0))]
    return np.vstack([grid] + edges)


def check_dual(sc, res, samples, length):
    """The dual certificate, independently: y . G(w) >= the certified lower bound at every
    sampled point of the 2-D footprint (3.8)-(3.10), and at the point-mass set if r is in
    it; the bound exceeds y . b. Interior samples test the reduction to the outline."""
    assert res.status == "outside" and res.certificate_kind == "dual"
    assert res.lower_bound_method == "branch_and_bound"
    y = res.dual
    # |y|_inf <= 1 in the locus frame where it was computed (rotations keep the 2-norms)
    assert abs(y[0]) <= 1 + 1e-12 and max(np.hypot(*y[1:3]), np.hypot(*y[3:5])) <= math.sqrt(2) + 1e-12
    cm = sc.center_of_mass
    r = res.cor - cm
    w = samples - cm
    w = w[np.hypot(*(w - r).T) > 1e-12 * length]
    vals = y @ membership_columns(r, w, sc.contact_rel, sc.alpha_hat, length)
    assert vals.min() >= res.dual_lower_bound - 1e-12, (vals.min(), res.dual_lower_bound)
    if res.in_footprint:
        s = lever(sc.contact_rel, sc.alpha_hat, r)
        pm = y[0] + y[1:3] @ r / length - abs(s) / length * np.hypot(y[3], y[4])
        assert pm >= res.dual_lower_bound - 1e-12
    assert res.dual_margin == pytest.approx(res.dual_lower_bound - y[0], abs=1e-15)
    assert res.dual_margin > TOL.certificate_margin
    return float(vals.min() - y[0])
