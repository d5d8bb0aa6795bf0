"""The exact sticking locus (solver/sticking.py; book 4.1.4, 4.1.2, 3.3.11.1, 6.3) against
independent checks: forward minimum-power solves with pusher friction (4.1; their sticking
CORs and contact forces), a brute-force sweep of force angles over the analytic frictionless
disk loci (the book's own definition of the sticking locus, 4.1.4), frictionless membership
(mu_c -> 0), dense 2-D grids of the footprint (the reduction to the outline), and the
geometry of the book's sticking-locus experiment (6.3)."""

from __future__ import annotations

import dataclasses
import math
import warnings

import cvxpy as cp
import numpy as np
import pytest

from models.locus import cor_disk as cd
from models.errors import InvalidInput
from models.footprint import Footprint
from models.mpp import perp
from models.scene import PushScene
from models.support import random_balanced_tripods
from solver.core.tolerances import SOLVER_DEFAULT
from solver.locus import sticking as st
from solver.motion.forward import solve_forward_batch
from solver.locus.membership import membership
from solver.locus.sticking import sticking_feasibility, sticking_point
from solver.locus.sticking_locus import sticking_locus, sticking_search_range
from tests.scenes import SEED, point_in_polygon, scene_for_mu
from solver.core.budget import Budget
from tests.budgets import checks_budget
from solver.locus import sticking_locus as stl

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


# --- the derivation (4.1.2, 4.1.4, ch. 2) --------------------------------------------------


@pytest.mark.parametrize("name", ["near_translation", "oblique_b"])
def test_forward_sticking_solves_satisfy_the_sticking_conditions(name):
    """Book 4.1.4 via ch. 2: every sticking forward solve (mu_c large) of random tripods
    satisfies (i) F = sigma J sum P d, (ii) zero friction moment about c, (iii) F in the
    cone, with sigma = sign(p . J(c - r))."""
    sc, _ = near_scene(name)
    rng = np.random.default_rng(SEED)
    pts, wts = random_balanced_tripods(rng, 300, 1.0, sc.center_of_mass)
    b = solve_forward_batch(sc, pts, wts, mu_c=2.0)
    stick = np.nonzero((b.mode == 1) & b.converged)[0]
    assert stick.size > 50
    e2 = perp(sc.push_hat)
    for i in stick:
        r = b.cor[i] - sc.center_of_mass
        c = sc.contact_rel
        assert abs((r - c) @ sc.push_hat) <= 1e-12 * (1 + np.linalg.norm(r))  # on the sticking line
        sigma = np.sign(sc.push_hat @ perp(c - r))
        assert sigma == np.sign((r - c) @ e2)
        w = pts[i] - sc.center_of_mass
        rho = np.linalg.norm(w - r, axis=1)
        if rho.min() < 1e-9:
            continue  # COR on a support point: a subgradient, checked by the witnesses below
        d = (w - r) / rho[:, None]
        force = sigma * perp(wts[i] @ d / wts[i].sum())
        assert np.linalg.norm(force - b.contact_force[i]) <= 1e-8
        assert abs(wts[i] @ np.einsum("ij,ij->i", w - c, d)) <= 1e-8
        assert abs(force @ sc.alpha_hat) <= 2.0 * (force @ sc.normal) + 1e-12


def test_direct_power_minimisation_finds_the_forward_sticking_cor():
    """The witnesses' fallback check (a direct 1-D minimisation of the power over sticking
    twists, used where the forward solver's mode test is ambiguous) agrees with the forward
    solver's sticking CORs (3.7, 4.1) on random tripods."""
    sc, _ = near_scene("oblique_a")
    geo = st.sticking_geometry(sc, None, 2.0, TOL)
    rng = np.random.default_rng(SEED + 7)
    pts, wts = random_balanced_tripods(rng, 200, 1.0, sc.center_of_mass)
    b = solve_forward_batch(sc, pts, wts, mu_c=2.0)
    stick = np.nonzero((b.mode == 1) & b.converged)[0]
    assert stick.size > 50
    for i in stick:
        s_fwd = positions(sc, b.cor[i][None])[0]
        s_1d = st.sticking_motion_position(geo.outline.to_local(pts[i]), wts[i], geo.c, s_fwd * 1.3)
        assert abs(s_1d - s_fwd) <= 1e-8 * max(1.0, abs(s_fwd))


def test_columns_are_affine_along_rays_from_r():
    """The boundary reduction: on a ray from r, (w - c) . d and the cone rows are affine in
    the distance (in the solver's scaled columns too)."""
    sc, mu_c = near_scene("near_translation")
    geo = st.sticking_geometry(sc, None, mu_c, TOL)
    for s in (-0.4, -3.0, -40.0):
        r = geo.point(s)
        q = st.StickingRows(geo, r, False, bool(np.hypot(*r) <= 1.0))
        for ang in (0.3, 2.0, 4.0):
            u = np.array([math.cos(ang), math.sin(ang)])
            rho = np.array([0.1, 0.55, 1.0])
            w = r + rho[:, None] * u
            g, h = q.columns(w, np.tile(u, (3, 1)), rho)
            for mat in (g, h):
                mid = 0.5 * (mat[:, 0] + mat[:, 2])
                lam = (rho[1] - rho[0]) / (rho[2] - rho[0])
                interp = (1 - lam) * mat[:, 0] + lam * mat[:, 2]
                assert np.allclose(mat[:, 1], interp, atol=1e-12 * (1 + abs(s))), (mid, interp)


# --- the locus against the book's definition (4.1.4) ----------------------------------------


@pytest.mark.parametrize("name", sorted(NEAR_SCENES))
def test_ends_agree_with_a_brute_force_sweep_of_force_angles(name):
    """Book 4.1.4: the sticking locus is the union over |phi| <= nu of {COR}_phi intersected
    with the sticking line. The sweep (801 angles, 2048-point analytic boundaries) is an
    inner approximation: it must lie within our interval, and reach our ends to its
    resolution."""
    sc, mu_c = near_scene(name)
    loc = sticking_locus(sc, mu_c, scan_points=64, seed_tripods=128, seed=SEED)
    sweep = sweep_union(sc, mu_c)
    assert loc.status == "found" and not loc.multiple_intervals and len(sweep) == 1
    lo, hi = loc.lower, loc.upper
    for end in (lo, hi):
        assert end.status == "bracketed" and end.certified
        assert end.width <= TOL.boundary_bracket * loc.length_scale * (1 + 1e-9)
        check_witness(sc, end.feasible, mu_c)
        assert end.infeasible.lower_bound_method == "branch_and_bound" and end.infeasible.dual_margin > 0
    (s_lo, s_hi), = sweep
    assert lo.feasible_position - 1e-4 <= s_lo <= lo.feasible_position + 2e-3
    assert hi.feasible_position - 2e-3 <= s_hi <= hi.feasible_position + 1e-4


def test_witness_force_angle_is_a_frictionless_cor_of_the_turned_edge():
    """Book 4.1.4 and the sign convention of the sweep: a witness with force angle phi makes
    its COR a frictionless COR (membership) of the scene whose edge is turned by +phi."""
    for name in ("near_translation", "oblique_d"):
        sc, mu_c = near_scene(name)
        loc = sticking_locus(sc, mu_c, scan_points=48, seed_tripods=64, seed=SEED)
        for s in np.linspace(loc.lower.feasible_position, loc.upper.feasible_position, 5):
            res = sticking_feasibility(sc, sticking_point(sc, s), mu_c)
            check_witness(sc, res, mu_c)
            turned = PushScene.create(1.0, sc.contact_point, sc.edge_angle + res.force_angle, sc.push_direction)
            assert membership(turned, res.cor, verify_witness=False).status == "inside"


@pytest.mark.parametrize("mu_c", [0.5, 1e6])
def test_every_sticking_forward_cor_lies_in_the_locus(mu_c):
    """Book 7.7 / figure 7-2 as a check: random tripods solved forward with pusher friction
    mu_c; each one in sticking mode has its COR inside the exact sticking locus."""
    for name in ("near_translation", "oblique_c"):
        sc, _ = near_scene(name)
        loc = sticking_locus(sc, mu_c, scan_points=48, seed_tripods=64, seed=SEED)
        rng = np.random.default_rng(SEED + 1)
        pts, wts = random_balanced_tripods(rng, 2000, 1.0, sc.center_of_mass)
        b = solve_forward_batch(sc, pts, wts, mu_c=mu_c)
        stick = (b.mode == 1) & b.converged & np.all(np.isfinite(b.cor), axis=1)
        assert stick.sum() > 100
        s = positions(sc, b.cor[stick])
        slack = 1e-9
        assert all(inside_some_interval(loc, x, slack) for x in s)
        # the tripods come near both ends (they are not the extremes: 3.3.3)
        assert s.min() - loc.lower.position < 1.0 and loc.upper.position - s.max() < 1.0


def test_mu_c_to_zero_is_frictionless_membership_on_the_line():
    """mu_c -> 0: the cone collapses onto n and sticking feasibility is frictionless
    membership (3.3) at the same point of the sticking line; the locus ends converge."""
    for mu in (0.05, 0.3, 0.9):
        sc = scene_for_mu(mu)
        lo, hi, _ = sticking_search_range(sc, 0.0)
        for s in np.linspace(max(lo, -4.0), min(hi, 1.0), 23):
            if s == 0.0:
                continue
            r = sticking_point(sc, s)
            a = sticking_feasibility(sc, r, 0.0, verify_witness=False)
            b = membership(sc, r, verify_witness=False)
            assert a.status == b.status, (mu, s)
            if a.status == "inside":
                assert abs(a.force_angle) <= 1e-9
        loc0 = sticking_locus(sc, 0.0, scan_points=48, seed_tripods=64, seed=SEED)
        loc_small = sticking_locus(sc, 1e-7, scan_points=48, seed_tripods=64, seed=SEED)
        assert loc0.status == loc_small.status == "found"
        assert abs(loc_small.lower.position - loc0.lower.position) < 1e-4
        assert abs(loc_small.upper.position - loc0.upper.position) < 1e-4
        assert loc_small.lower.position <= loc0.lower.position + 2e-6
        assert loc_small.upper.position >= loc0.upper.position - 2e-6


def test_mu_c_huge_and_infinite():
    """mu_c huge: only F . n >= 0 is left; mu_c = inf gives the same locus as 1e9, which
    contains the locus at mu_c = 0.5 (the cone only grows)."""
    sc, _ = near_scene("oblique_d")
    loc_inf = sticking_locus(sc, math.inf, scan_points=48, seed_tripods=64, seed=SEED)
    loc_big = sticking_locus(sc, 1e9, scan_points=48, seed_tripods=64, seed=SEED)
    loc_half = sticking_locus(sc, 0.5, scan_points=48, seed_tripods=64, seed=SEED)
    assert loc_inf.friction_angle == math.pi / 2
    for a, b in ((loc_inf.lower, loc_big.lower), (loc_inf.upper, loc_big.upper)):
        assert abs(a.position - b.position) <= 2e-6
    assert loc_inf.lower.position <= loc_half.lower.position + 1e-6
    assert loc_inf.upper.position >= loc_half.upper.position - 1e-6
    check_witness(sc, loc_inf.lower.feasible, 1e300)


# --- invariance ---------------------------------------------------------------------------


def transformed(scene: PushScene, scale=1.0, turn=0.0, shift=(0.0, 0.0), mirror=False):
    rot = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
    m = np.diag([1.0, -1.0]) if mirror else np.eye(2)
    t = lambda x: rot @ (m @ np.asarray(x)) * scale + np.asarray(shift)  # noqa: E731
    sgn = -1.0 if mirror else 1.0
    return PushScene.create(
        scene.disk_radius * scale, t(scene.contact_point), sgn * scene.edge_angle + turn,
        sgn * scene.push_direction + turn, t(scene.center_of_mass),
    )


def test_invariance_under_scale_rotation_translation_and_mirror():
    """3.3.12: the locus is invariant under similarities; a mirror image maps s to -s
    (the book's up and down are exchanged, 4.1.6)."""
    sc, mu_c = near_scene("oblique_a")
    base = sticking_locus(sc, mu_c, scan_points=48, seed_tripods=64, seed=SEED)
    k = 3.7
    for kw in (dict(scale=k, turn=1.1, shift=(2.0, -5.0)), dict(mirror=True), dict(scale=0.01, turn=-2.5, mirror=True)):
        other = sticking_locus(transformed(sc, **kw), mu_c, scan_points=48, seed_tripods=64, seed=SEED)
        f = kw.get("scale", 1.0)
        ends = sorted(f * np.array([base.lower.position, base.upper.position]) * (-1 if kw.get("mirror") else 1))
        got = [other.lower.position, other.upper.position]
        assert np.allclose(got, ends, atol=2e-6 * f), (kw, got, ends)
        if base.tip_line.position is not None:
            assert abs(other.tip_line.error * (-1 if kw.get("mirror") else 1) - f * base.tip_line.error) < 2e-6 * f


# --- footprints, the reduction to the outline --------------------------------------------


def test_dense_2d_grid_never_beats_the_outline():
    """The boundary reduction by brute force: where an LP over a dense 2-D grid of the disk
    (interior and outline points, plus a point mass at r when r is in the disk) is feasible,
    the certified outline model says inside; and the outline-only LP at the same outline
    resolution is never worse than the 2-D grid beyond the discretisation."""
    sc, mu_c = near_scene("contact_inside")
    loc = sticking_locus(sc, mu_c, scan_points=48, seed_tripods=64, seed=SEED)
    full, outline = disk_grid(1.0, 24, 360)
    lo, hi = loc.lower.position, loc.upper.position
    for s in np.concatenate([np.linspace(lo - 0.3, hi + 0.3, 13), [lo - 1e-3, hi + 1e-3, lo + 1e-3, hi - 1e-3]]):
        r = sticking_point(sc, s)
        in_f = bool(np.linalg.norm(r - sc.center_of_mass) <= 1.0)
        res_full = grid_lp(sc, r, mu_c, full, in_f)
        res_outline = grid_lp(sc, r, mu_c, outline, in_f)
        ours = sticking_feasibility(sc, r, mu_c, verify_witness=False)
        if res_full <= 1e-8:
            assert ours.status == "inside", s
        assert res_outline <= res_full + 1e-4, (s, res_outline, res_full)
        if ours.status == "outside":
            assert res_full > 0.0


def test_certified_duals_hold_on_a_dense_2d_grid():
    """An outside certificate's dual functional phi = y . G - lambda . H (reported on the
    unscaled world-aligned columns) stays above its certified lower bound on a dense 2-D grid
    of the footprint, and the margin is lower bound - y0."""
    cases = [(near_scene("near_translation") + (None,)), (u_scene() + (U_SHAPE,))]
    for (sc, mu_c, fp) in cases:
        loc = sticking_locus(sc, mu_c, footprint=fp, scan_points=48, seed_tripods=64, seed=SEED)
        ends = [e.infeasible for iv in loc.intervals for e in (iv.lower, iv.upper) if e.infeasible is not None]
        assert ends
        if fp is None:
            pts, _ = disk_grid(sc.disk_radius, 60, 720)
        else:
            pts, _ = polygon_grid(fp, 0.01)
        for res in ends:
            assert res.status == "outside" and res.certificate_kind == "dual"
            y = res.dual
            ell = res.length_scale
            cm = sc.center_of_mass
            r = res.cor - cm
            w = pts - cm
            rho = np.linalg.norm(w - r, axis=1)
            w = w[rho > 0]
            d = (w - r) / np.linalg.norm(w - r, axis=1)[:, None]
            s = res.position
            sigma = 1.0 if s > 0 else -1.0
            nu = math.atan(mu_c)
            e = np.array([math.sin(nu) * sc.normal + math.cos(nu) * sc.alpha_hat,
                          math.sin(nu) * sc.normal - math.cos(nu) * sc.alpha_hat])
            k = -sigma * perp(e)
            phi = (y[0] + (w / ell) @ y[1:3] + y[3] * np.einsum("ij,ij->i", w - sc.contact_rel, d) / ell
                   - (k @ d.T).T @ y[4:6])
            assert phi.min() >= res.dual_lower_bound - 1e-12
            assert abs(res.dual_margin - (res.dual_lower_bound - y[0])) <= 1e-12
            assert res.dual_margin > TOL.certificate_margin


def test_polygon_loci_lie_inside_their_disks_and_hold_the_tripods():
    """7.5: a footprint's sticking locus lies inside its circumscribing disk's; sticking
    CORs of random tripods on the footprint lie in it."""
    sc = PushScene.create(SQUARE.circumradius, [-0.5, 0.2], math.radians(80), 0.0, (0.0, 0.0))
    mu_c = 0.5
    sq = sticking_locus(sc, mu_c, footprint=SQUARE, scan_points=48, seed_tripods=64, seed=SEED)
    dk = sticking_locus(sc, mu_c, scan_points=48, seed_tripods=64, seed=SEED)
    assert sq.status == dk.status == "found"
    assert dk.lower.position <= sq.lower.position and sq.upper.position <= dk.upper.position
    for end in (sq.lower, sq.upper):
        assert end.status == "bracketed" and end.certified
        check_witness(sc, end.feasible, mu_c)
    rng = np.random.default_rng(SEED)
    pts, wts = random_balanced_tripods(rng, 1500, SQUARE.circumradius, footprint=SQUARE)
    b = solve_forward_batch(sc, pts, wts, mu_c=mu_c)
    stick = (b.mode == 1) & b.converged
    assert stick.sum() > 50
    assert all(inside_some_interval(sq, x, 1e-9) for x in positions(sc, b.cor[stick]))


def test_a_u_shape_has_a_sticking_locus_of_two_intervals():
    """A non-convex footprint: the scan finds two intervals, each end certified, the gap
    certified outside in its middle and the 2-D grid LP agrees that the gap is infeasible."""
    sc, mu_c = u_scene()
    loc = sticking_locus(sc, mu_c, footprint=U_SHAPE, seed=SEED)
    assert loc.status == "found" and loc.multiple_intervals and len(loc.intervals) == 2
    for iv in loc.intervals:
        for end in (iv.lower, iv.upper):
            assert end.status == "bracketed" and end.certified
            check_witness(sc, end.feasible, mu_c)
    gap = 0.5 * (loc.intervals[0].upper.position + loc.intervals[1].lower.position)
    res = sticking_feasibility(sc, sticking_point(sc, gap), mu_c, footprint=U_SHAPE)
    assert res.status == "outside" and res.certificate_kind == "dual"
    pts, _ = polygon_grid(U_SHAPE, 0.05)
    r = sticking_point(sc, gap)
    in_f = bool(point_in_polygon(r[None], U_SHAPE.vertices)[0])
    assert grid_lp(sc, r, mu_c, pts, in_f) > 1e-6


def test_l_shape_locus_and_footprint_with_another_cm():
    sc = PushScene.create(L_SHAPE.circumradius, [0.5, 0.0], 0.0, math.pi / 2 + 0.3, L_SHAPE.center_of_mass)
    loc = sticking_locus(sc, 0.6, footprint=L_SHAPE, scan_points=48, seed_tripods=64, seed=SEED)
    assert loc.status == "found"
    for end in (loc.lower, loc.upper):
        assert end.status == "bracketed" and end.certified
        check_witness(sc, end.feasible, 0.6)
    other = PushScene.create(L_SHAPE.circumradius, [0.5, 0.0], 0.0, math.pi / 2, (1.0, 1.0))
    with pytest.raises(InvalidInput):
        sticking_feasibility(other, sticking_point(other, -1.0), 0.6, footprint=L_SHAPE)


# --- far loci, the search range, translation ---------------------------------------------


def test_a_far_sticking_locus():
    """A cone holding a line of force close to the CM puts the locus ~65-185 L away (the
    book's tip distance a^2/|alpha . c| grows without bound): ends bracketed ("wide" when
    the certifiable margin at |s| ~ 185 L needs a wider bracket), witnesses re-verified by
    forward solves, and each witness's force angle a frictionless COR of the turned edge."""
    sc = PushScene.create(1.0, [-0.26447305, -0.69623092], 6.224765398562094, 1.2190980200659878)
    mu_c = 0.5
    loc = sticking_locus(sc, mu_c, scan_points=64, seed_tripods=64, seed=SEED)
    assert loc.status == "found" and len(loc.intervals) == 1
    assert -186 < loc.lower.position < -183 and -67 < loc.upper.position < -65
    for end in (loc.lower, loc.upper):
        assert end.status in ("bracketed", "wide") and end.certified
        assert end.width <= 2 ** stl.MAX_WIDENINGS * TOL.boundary_bracket
        check_witness(sc, end.feasible, mu_c)
        turned = PushScene.create(1.0, sc.contact_point, sc.edge_angle + end.feasible.force_angle, sc.push_direction)
        # 4.1.4: the sticking locus is the union of {COR}_phi over the cone cut by the line, so
        # the witness's point is a frictionless COR of its turned edge and a point past the
        # end is none; membership decides both (|s| ~ 65-185 L, where its plain rows alone
        # left them undecided)
        inside = membership(turned, end.feasible.cor, verify_witness=False)
        assert inside.status == "inside"
        past = end.feasible.cor + 20.0 * (end.infeasible.cor - end.feasible.cor)  # 20 brackets past the end
        beyond = membership(turned, past, verify_witness=False)
        assert beyond.status == "outside" and beyond.certificate_kind == "dual"


def test_the_search_range_is_an_outer_bound():
    """Points just beyond the sound search range (moment bound and disk-loci bound) are
    certified outside, for a scene where each bound is the tighter one."""
    for name in ("near_translation", "oblique_c"):
        sc, mu_c = near_scene(name)
        lo, hi, how = sticking_search_range(sc, mu_c)
        assert "moment" in how
        for s in (lo * 1.001, hi * 1.001):
            res = sticking_feasibility(sc, sticking_point(sc, s), mu_c)
            assert res.status == "outside" and res.certificate_kind == "dual"


def test_a_translation_along_the_push_sticks_and_is_reported():
    """CM on the push line through c and p in the cone: a pure translation sticks (COR at
    infinity); the finite sticking locus is empty here (every {COR}_phi reaches the line
    x = c_x only at the contact point)."""
    sc = PushScene.create(1.0, [-1.0, 0.0], math.pi / 2 + 0.2, 0.0)
    loc = sticking_locus(sc, 0.5, scan_points=32, seed_tripods=64, seed=SEED)
    assert loc.translation_sticks and loc.search_bound.startswith("cap")
    assert loc.status == "empty" and "translation" in loc.message
    assert not sticking_locus(sc, 0.1, scan_points=16, seed_tripods=0).translation_sticks


# --- the book's experiment (6.3) and the tip line (3.3.11.1) ------------------------------


def test_book_6_3_sticking_locus_experiment():
    """Book 6.3 (figure 6-1): a brass disk of radius 1.25 in pushed by a fence at
    alpha = 70 degrees, mu_c about 0.5. "The COR should not fall below the tip line, which
    intersects the sticking line at y = -5.51a." The tip line is a^2/|c| = a from the CM on
    the far side (the disk's far tangent, contact on the rim); its crossing is at
    y = -a (1 + sin^2 70)/cos 70 = -5.506 a. The exact lower end dips below it, to -5.528 a;
    the upper end is at -2.481 a (the book has no method for it)."""
    a = 1.25
    al = math.radians(70)
    sc = PushScene.create(a, [-a * math.sin(al), a * math.cos(al)], al, 0.0)
    assert sc.is_translation  # the fence's normal passes through the CM: rolling (sticking)
    loc = sticking_locus(sc, 0.5, seed=SEED)
    assert loc.status == "found" and len(loc.intervals) == 1
    y_tip = loc.tip_line.point[1] / a
    assert abs(y_tip - (-5.51)) < 0.005
    assert abs(y_tip + (1 + math.sin(al) ** 2) / math.cos(al)) < 1e-12
    y_lo = loc.lower.point[1] / a
    y_hi = loc.upper.point[1] / a
    assert loc.tip_line.end == "lower" and loc.tip_line.beyond
    assert -5.53 < y_lo < -5.52 and -2.49 < y_hi < -2.47
    assert abs(loc.tip_line.error / a - (y_lo - y_tip)) < 1e-9
    for end in (loc.lower, loc.upper):
        assert end.status == "bracketed" and end.certified
        check_witness(sc, end.feasible, 0.5)
    # brute force: the sweep of force angles reaches the same ends
    (s_lo, s_hi), = sweep_union(sc, 0.5, n_phi=801)
    assert abs(s_lo - loc.lower.position) < 3e-3 * a and abs(s_hi - loc.upper.position) < 3e-3 * a
    # sticking CORs of uniform random tripods all fall in it (figure 6-2 shows rolling only)
    rng = np.random.default_rng(SEED)
    pts, wts = random_balanced_tripods(rng, 2000, a, sc.center_of_mass)
    b = solve_forward_batch(sc, pts, wts, mu_c=0.5)
    stick = (b.mode == 1) & b.converged
    assert stick.mean() > 0.9
    assert all(inside_some_interval(loc, x, 1e-9) for x in positions(sc, b.cor[stick]))


def test_tip_line_error_against_the_exact_lower_end():
    """3.3.11.1 / 4.1.4: the tip line's crossing approximates the lower end; each {COR}_phi
    dips slightly below the tip line, so for a scene of sketch type g/h the exact end lies
    just beyond it (here 0.019 a), while the square's locus (7.5) ends well above it."""
    sc, mu_c = near_scene("near_translation")
    loc = sticking_locus(sc, mu_c, scan_points=48, seed_tripods=64, seed=SEED)
    s_tip = -(1.0 + 0.9**2 + 0.3**2) / 0.3
    assert abs(loc.tip_line.position - s_tip) < 1e-12
    assert loc.tip_line.beyond and -0.02 < loc.tip_line.error < -0.019
    tl = cd.disk_cor_locus(sc, outputs=("tip_line",)).tip_line
    assert abs((loc.tip_line.point - tl.point) @ perp(tl.direction)) < 1e-12


# --- API behaviour -------------------------------------------------------------------------


def test_input_checks_contact_point_and_grid_mode():
    sc, mu_c = near_scene("near_translation")
    with pytest.raises(InvalidInput):
        sticking_feasibility(sc, sticking_point(sc, -3.0) + 1e-6 * sc.push_hat, mu_c)
    with pytest.raises(InvalidInput):
        sticking_feasibility(sc, sticking_point(sc, -3.0), -0.1)
    with pytest.raises(InvalidInput):
        sticking_locus(sc, math.nan)
    res = sticking_feasibility(sc, sc.contact_point, mu_c)
    assert res.status == "outside" and res.certificate_kind == "contact"
    res = sticking_feasibility(sc, sticking_point(sc, -8.0), mu_c, certify=False)
    assert res.status == "outside" and res.certificate_kind == "none" and res.lower_bound_method == "grid"
    res = sticking_feasibility(sc, sticking_point(sc, -8.0), mu_c)
    assert res.certificate_kind == "dual" and res.lower_bound_method == "branch_and_bound"


def test_time_limit_stops_the_locus():
    sc, mu_c = near_scene("near_translation")
    budget = checks_budget(20)
    loc = sticking_locus(sc, mu_c, budget=budget, seed_tripods=0)
    assert loc.time_limited and not loc.complete and loc.status in ("incomplete", "found", "empty")
    assert loc.n_queries < 20  # one budget check (at least) per query
    res = sticking_feasibility(sc, sticking_point(sc, -3.0), mu_c, budget=Budget.of(0.0))
    assert res.status == "undecided"


def test_cm_on_the_sticking_line_is_a_degenerate_cor():
    """All weight at the CM turns the part about it at no cost (3.6): with the CM on the
    sticking line it is a sticking COR (that support has F = 0; the witness found may be
    another)."""
    sc = PushScene.create(1.0, [0.0, -0.5], 0.3, 0.0)
    res = sticking_feasibility(sc, sc.center_of_mass, 0.3)
    check_witness(sc, res, 0.3)
    geo = st.sticking_geometry(sc, None, 0.3, TOL)
    q = st.StickingRows(geo, np.zeros(2), False, True)
    pg, ph = q.point_mass_columns()
    assert np.allclose(pg @ [1.0, 0.0, 0.0], q.b) and np.all(ph @ [1.0, 0.0, 0.0] >= 0.0)


def test_conic_solver_failure_is_a_solver_error(monkeypatch):
    from solver.core.errors import SolverError

    sc, mu_c = near_scene("near_translation")

    def boom(*args, **kwargs):
        raise cp.error.SolverError("boom")

    monkeypatch.setattr(cp.Problem, "solve", boom)
    with pytest.raises(SolverError):
        sticking_feasibility(sc, sticking_point(sc, -3.0), mu_c)


def test_wrongly_graded_scan_probes_do_not_split_or_shorten_the_locus(monkeypatch):
    """Grid pricing ("outside" without a certificate) can be wrong: a probe graded outside
    (or undecided) in the middle of the locus splits the scan's run; the certified brackets
    step past it and the pieces are merged into the one true interval."""
    sc, mu_c = near_scene("oblique_a")
    ref = sticking_locus(sc, mu_c, scan_points=48, seed_tripods=0)
    lo, hi = ref.lower.position, ref.upper.position
    window = (lo + 0.4 * (hi - lo), lo + 0.6 * (hi - lo))
    real = stl.decide_on_line

    def lying(geo, r_local, tol, budget, warm, verify, certify):
        res = real(geo, r_local, tol, budget, warm, verify, certify)
        s = res.position
        if not certify and window[0] <= s <= window[1]:
            return dataclasses.replace(res, status="outside" if s < 0.5 * sum(window) else "undecided")
        return res

    monkeypatch.setattr(stl, "decide_on_line", lying)
    loc = sticking_locus(sc, mu_c, scan_points=48, seed_tripods=0)
    assert len(loc.intervals) == 1 and loc.status == "found"
    assert abs(loc.lower.position - lo) < 1e-6 and abs(loc.upper.position - hi) < 1e-6


def test_agrees_with_the_cor_sketch_force_angle_sweep():
    """models/cor_sketch.py computes the sticking locus of a disk by the book's construction
    (a sweep of force angles over the analytic loci, refined by golden section): the ends
    agree to its boundary resolution (1024-point polygons). Where the sweep reaches beyond a
    certified end (contact_inside: 3.8e-6 a, a chord across a concave stretch of the locus
    boundary), frictionless membership at the sweep's own force angle certifies the sweep's
    point outside, and a 65536-point boundary moves the crossing back inside the bracket."""
    from models.locus.cor_sketch import force_scene, sticking_locus_sweep

    for name in sorted(NEAR_SCENES):
        sc, mu_c = near_scene(name)
        loc = sticking_locus(sc, mu_c, scan_points=48, seed_tripods=64, seed=SEED)
        sw = sticking_locus_sweep(sc, mu_c)
        assert abs(sw.t_low - loc.lower.position) < 5e-5 and abs(sw.t_high - loc.upper.position) < 5e-5
        if name == "contact_inside":
            assert sw.t_low < loc.lower.infeasible_position  # beyond the certified outside end
            turned, _ = force_scene(sc, sw.phi_low)
            res = membership(turned, sticking_point(sc, sw.t_low))
            assert res.status == "outside" and res.certificate_kind == "dual"
            fine = cd.disk_cor_locus(turned, outputs=("boundary",), n_points=65536).boundary
            b = fine - sc.contact_point
            x, y = b @ sc.push_hat, b @ perp(sc.push_hat)
            x2, y2 = np.roll(x, -1), np.roll(y, -1)
            cross = (x > 0) != (x2 > 0)
            t = x[cross] / (x[cross] - x2[cross])
            s_fine = float(np.min(y[cross] + t * (y2[cross] - y[cross])))
            assert loc.lower.infeasible_position - 1e-8 <= s_fine <= loc.lower.feasible_position + 1e-8


def test_the_tip_line_misses_the_end_when_the_cone_is_narrow():
    """4.1.4's "unstated assumption": the tip line approximates the lower end only when the
    tips of {COR}_(alpha -+ nu) lie on either side of the sticking line. For a narrow cone
    (mu_c = 0.05) no tip reaches the line and the exact lower end is 2.85 a above the tip
    line; from mu_c = 0.2 on the end dips just below it. The brute-force sweep agrees."""
    sc, _ = near_scene("near_translation")
    narrow = sticking_locus(sc, 0.05, scan_points=48, seed_tripods=64, seed=SEED)
    wide = sticking_locus(sc, 0.2, scan_points=48, seed_tripods=64, seed=SEED)
    assert 2.8 < narrow.tip_line.error < 2.9 and not narrow.tip_line.beyond
    assert -0.01 < wide.tip_line.error < 0 and wide.tip_line.beyond
    (s_lo, s_hi), = sweep_union(sc, 0.05, n_phi=801)
    assert abs(s_lo - narrow.lower.position) < 2e-3 and abs(s_hi - narrow.upper.position) < 2e-3


@pytest.mark.parametrize("kind", ["disk", "polygon"])
def test_branch_and_bound_interval_bounds_are_sound(kind):
    """Every interval lower bound (Lipschitz, second-order and zeroth-order, in the near and
    the far form of phi, with the disk's tight |u'| bound) lies below phi sampled densely on
    the interval, for random functionals and candidates near, on and far from the outline."""
    rng = np.random.default_rng(SEED + 3)
    if kind == "disk":
        sc, mu_c = near_scene("near_translation")
        fp = None
    else:
        sc, mu_c = u_scene()
        fp = U_SHAPE
    geo = st.sticking_geometry(sc, fp, mu_c, TOL)
    checked = 0
    for s in (-0.3, -0.9, 0.2, -2.5, -7.0, -60.0, 35.0):
        r = geo.point(s)
        r, on = st.snap_on_line(geo, r)
        in_f = geo.outline.contains(r, on)
        if s == 0.0:
            continue
        q = st.StickingRows(geo, r, on, in_f)
        for _ in range(12):
            y = rng.normal(size=4)
            lam = np.abs(rng.normal(size=2))
            fn = q.functional(y, lam)
            piece = int(rng.integers(len(q.pieces.piece_lo)))
            a, b = q.pieces.piece_lo[piece], q.pieces.piece_hi[piece]
            for _ in range(4):
                t0, t1 = np.sort(rng.uniform(a, b, 2))
                if rng.uniform() < 0.3:
                    t1 = t0 + (t1 - t0) * 1e-3
                pc = np.array([piece])
                f0, e0 = fn.evaluate(q.pieces, pc, np.array([t0]))
                f1, e1 = fn.evaluate(q.pieces, pc, np.array([t1]))
                lb = fn.lower_bounds(q.pieces, pc, np.array([t0]), np.array([t1]), f0, f1, e0, e1)[0]
                ts = np.linspace(t0, t1, 4001)
                vals = fn.evaluate(q.pieces, np.full(ts.size, piece), ts)[0]
                assert vals.min() >= lb - 1e-12 * (1 + abs(vals.min())), (s, piece, t0, t1, vals.min(), lb)
                checked += 1
    assert checked > 200
