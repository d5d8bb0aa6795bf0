"""Shared scenes and independent checks of the sticking-locus tests (book 4.1.2, 4.1.4):
disk scenes whose locus lies within a few radii, a U shape with two intervals, a brute-force
sweep of force angles over the analytic frictionless loci, the sticking conditions (i)-(iii)
recomputed from a witness, and an independent grid LP."""

from __future__ import annotations

import math
import warnings

import cvxpy as cp
import numpy as np

from models.core.footprint import Footprint
from models.core.mpp import perp
from models.core.scene import PushScene
from models.locus import cor_disk as cd
from solver.core.tolerances import SOLVER_DEFAULT
from tests.scenes import point_in_polygon

TOL = SOLVER_DEFAULT

# Disk scenes whose sticking locus lies within a few radii (seeded draws, kept explicit):
# (contact, edge_angle, push_direction, mu_c).
NEAR_SCENES = {
    "near_translation": ([-0.9, 0.3], math.radians(70), 0.0, 0.5),
    "oblique_a": ([-0.7433, 0.669], 4.3539, 6.278, 0.2),
    "oblique_b": ([-0.8147, 0.273], 4.5251, 5.0258, 0.2),
    "oblique_c": ([0.6351, -0.268], 8.6705, 4.2373, 0.2),
    "oblique_d": ([-0.2064, -0.8692], 5.5226, 3.0127, 0.5),
    "contact_inside": ([-0.3215, 0.1109], 4.0725, 2.1468, 0.2),
}
SQUARE = Footprint.create([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]])
L_SHAPE = Footprint.create([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]])
U_SHAPE = Footprint.create([[0, 0], [3, 0], [3, 2], [2, 2], [2, 0.6], [1, 0.6], [1, 2], [0, 2]])


def near_scene(name: str, a: float = 1.0):
    contact, edge, push, mu_c = NEAR_SCENES[name]
    return PushScene.create(a, np.asarray(contact) * a, edge, push, (0.0, 0.0)), mu_c


def u_scene():
    """A seeded U-shape push whose sticking locus is two intervals (found by a scan of 60
    random scenes; the part is pulled: n points out of the U's left side)."""
    return PushScene.create(
        U_SHAPE.circumradius, [0.0, 0.29439040855770426], -math.pi / 2, 2.1405943745008185, U_SHAPE.center_of_mass
    ), 0.3


# --- independent checks ----------------------------------------------------------------


def sweep_union(scene: PushScene, mu_c: float, n_phi: int = 801, n_points: int = 2048):
    """Book 4.1.4 by brute force: for force angles phi in [-nu, nu] the frictionless disk
    locus of the scene whose edge is turned by phi (its force direction is n turned by phi
    CCW, as the witness's force angle), intersected with the sticking line; the union of the
    intersections as merged intervals of positions s (world lengths along J p)."""
    nu = math.atan(mu_c)
    p = scene.push_hat
    e2 = perp(p)
    c = scene.contact_point
    pieces = []
    for phi in np.linspace(-nu, nu, n_phi):
        turned = PushScene.create(
            scene.disk_radius, c, scene.edge_angle + phi, scene.push_direction, scene.center_of_mass
        )
        # its force direction is n turned by +phi (CCW)
        turn = math.atan2(float(perp(scene.normal) @ turned.normal), float(scene.normal @ turned.normal))
        assert abs(turn - phi) < 1e-12
        loc = cd.disk_cor_locus(turned, outputs=("boundary",), n_points=n_points)
        if loc.boundary is None:
            continue
        b = loc.boundary - c
        x, y = b @ p, b @ e2
        x2, y2 = np.roll(x, -1), np.roll(y, -1)
        cross = (x > 0) != (x2 > 0)
        t = x[cross] / (x[cross] - x2[cross])
        ss = np.sort(y[cross] + t * (y2[cross] - y[cross]))
        pieces += [(ss[k], ss[k + 1]) for k in range(0, len(ss) - 1, 2)]
    pieces.sort()
    merged: list[list[float]] = []
    for lo, hi in pieces:
        if merged and lo <= merged[-1][1]:
            merged[-1][1] = max(merged[-1][1], hi)
        else:
            merged.append([lo, hi])
    return merged


def sticking_equations(scene: PushScene, res, mu_c: float):
    """(i)-(iii) of the module docstring recomputed from a witness with unscaled columns:
    (L1 residual of weight, centroid and moment rows, |F - reported F|, force angle)."""
    cm = scene.center_of_mass
    c = scene.contact_rel
    r = res.cor - cm
    w = res.witness_points - cm
    s = float((res.cor - scene.contact_point) @ perp(scene.push_hat))
    sigma = 1.0 if s > 0 else -1.0
    d = (w - r) / np.linalg.norm(w - r, axis=1)[:, None]
    pw, p0, z = res.witness_weights, res.point_mass_at_cor, res.point_mass_subgradient
    assert np.hypot(*z) <= p0 * (1 + 1e-12) + 1e-300
    ell = res.length_scale
    rows = np.array([
        pw.sum() + p0 - 1.0,
        (pw @ w[:, 0] + p0 * r[0]) / ell,
        (pw @ w[:, 1] + p0 * r[1]) / ell,
        (pw @ np.einsum("ij,ij->i", w - c, d) + (r - c) @ z) / ell,
    ])
    force = sigma * perp(pw @ d + z)
    angle = math.atan2(float(force @ scene.alpha_hat), float(force @ scene.normal))
    return float(np.sum(np.abs(rows))), float(np.linalg.norm(force - res.contact_force)), angle


def check_witness(scene, res, mu_c):
    assert res.status == "inside" and res.certificate_kind == "witness"
    assert np.all(res.witness_weights >= 0.0) and res.point_mass_at_cor >= 0.0
    resid, ferr, angle = sticking_equations(scene, res, mu_c)
    assert resid <= 1e-10
    assert ferr <= 1e-9
    nu = math.atan(mu_c)
    assert abs(angle - res.force_angle) <= 1e-9
    assert abs(res.force_angle) <= nu + 1e-9
    # re-verified by the forward solve: the minimum-power sticking motion of the witness
    # turns about r; the forward mode is sticking (frictionless for mu_c = 0) unless a point
    # mass sits at r (a kink: the contact force is a set, forward tests one element of it)
    # or F is on the cone's edge (then a slipping answer has zero slip: the same motion)
    if res.witness_forward_mode is not None:
        assert res.witness_forward_cor_error <= TOL.witness_cor_rel
        expected = "sticking" if mu_c > 0 else "frictionless"
        assert res.witness_check == ("forward" if res.witness_forward_mode == expected else "power_1d")
        if res.witness_forward_mode != expected:
            assert res.witness_forward_mode.startswith("slipping")
            on_edge = abs(abs(res.force_angle) - nu) <= 1e-7
            assert res.point_mass_at_cor > 0.0 or (on_edge and abs(res.witness_forward_slip) <= 1e-9)


def grid_lp(scene, r_world, mu_c, points_world, in_footprint):
    """Independent L1-residual LP (cvxpy + Clarabel) of the sticking conditions with the
    unscaled columns (1, w, (w - c) . d) and the cone rows e_+- . F >= 0 on F = sigma J D,
    over the given support points (and a point mass at r with |z| <= P0 when r is in the
    footprint). Returns the optimal residual."""
    cm = scene.center_of_mass
    r = np.asarray(r_world) - cm
    c = scene.contact_rel
    s = float((np.asarray(r_world) - scene.contact_point) @ perp(scene.push_hat))
    sigma = 1.0 if s > 0 else -1.0
    w = np.asarray(points_world) - cm
    rho = np.linalg.norm(w - r, axis=1)
    keep = rho > 1e-7
    w, rho = w[keep], rho[keep]
    d = (w - r) / rho[:, None]
    g = np.vstack([np.ones(len(w)), w.T, np.einsum("ij,ij->i", w - c, d)])
    nu = math.atan(mu_c)
    e = np.array([math.sin(nu) * scene.normal + math.cos(nu) * scene.alpha_hat,
                  math.sin(nu) * scene.normal - math.cos(nu) * scene.alpha_hat])
    p = cp.Variable(len(w), nonneg=True)
    dvec = d.T @ p
    eq = g @ p - np.array([1.0, 0.0, 0.0, 0.0])
    cons = []
    if in_footprint:
        p0, z = cp.Variable(), cp.Variable(2)
        eq = eq + cp.hstack([p0, p0 * r[0], p0 * r[1], (r - c) @ z])
        dvec = dvec + z
        cons.append(cp.SOC(p0, z))
    force = sigma * cp.hstack([-dvec[1], dvec[0]])
    viol = cp.Variable(2, nonneg=True)
    cons.append(e @ force + viol >= 0)
    prob = cp.Problem(cp.Minimize(cp.norm1(eq) + cp.sum(viol)), cons)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        prob.solve(solver=cp.CLARABEL)
    return float(prob.value)


def disk_grid(a, n_radial, n_angular):
    rad = a * np.linspace(0.0, 1.0, n_radial + 1)[1:]
    th = np.linspace(0.0, 2 * math.pi, n_angular, endpoint=False)
    pts = (rad[:, None, None] * np.stack([np.cos(th), np.sin(th)], axis=-1)[None]).reshape(-1, 2)
    return np.vstack([[0.0, 0.0], pts]), a * np.stack([np.cos(th), np.sin(th)], axis=-1)


def polygon_grid(fp: Footprint, h: float):
    lo, hi = fp.vertices.min(axis=0), fp.vertices.max(axis=0)
    xs, ys = np.meshgrid(np.arange(lo[0], hi[0] + h / 2, h), np.arange(lo[1], hi[1] + h / 2, h))
    pts = np.column_stack([xs.ravel(), ys.ravel()])
    inside = pts[point_in_polygon(pts, fp.vertices)]
    v, vn = fp.vertices, np.roll(fp.vertices, -1, axis=0)
    outline = []
    for a, b in zip(v, vn):
        k = max(2, int(math.ceil(np.linalg.norm(b - a) / h)))
        outline.append(a + np.linspace(0.0, 1.0, k, endpoint=False)[:, None] * (b - a))
    outline = np.vstack(outline)
    return np.vstack([inside, outline]), outline


def positions(scene, cors):
    return (np.asarray(cors) - scene.contact_point) @ perp(scene.push_hat)


def inside_some_interval(loc, s, slack):
    return any(iv.lower.position - slack <= s <= iv.upper.position + slack for iv in loc.intervals)


def transformed(scene: PushScene, scale=1.0, turn=0.0, shift=(0.0, 0.0), mirror=False):
    rot = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
    m = np.diag([1.0, -1.0]) if mirror else np.eye(2)
    t = lambda x: rot @ (m @ np.asarray(x)) * scale + np.asarray(shift)
    sgn = -1.0 if mirror else 1.0
    return PushScene.create(
        scene.disk_radius * scale, t(scene.contact_point), sgn * scene.edge_angle + turn,
        sgn * scene.push_direction + turn, t(scene.center_of_mass),
    )
