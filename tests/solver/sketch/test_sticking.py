"""The sticking feasibility problem (solver/sketch/sticking.py; book 4.1.2, 4.1.4, ch. 2):
the conditions (i)-(iii) against forward minimum-power solves with pusher friction (4.1),
a direct minimisation of the power over sticking twists, the rows' reduction to the
outline (affine along rays; dense 2-D grids never beat it; certified duals hold on them),
sound interval bounds, and the input checks. The locus along the line:
test_sticking_locus.py; shared scenes and checks: sticking_checks.py."""

from __future__ import annotations

import math

import cvxpy as cp
import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.mpp import perp
from models.core.scene import PushScene
from models.core.support import random_balanced_tripods
from solver.motion.forward import solve_forward_batch
from solver.sketch import sticking as st
from solver.sketch.sticking import sticking_feasibility, sticking_point
from solver.sketch.sticking_locus import sticking_locus
from tests.scenes import SEED
from tests.solver.sketch.sticking_checks import (
    TOL,
    U_SHAPE,
    check_witness,
    disk_grid,
    grid_lp,
    near_scene,
    polygon_grid,
    positions,
    u_scene,
)

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












# --- invariance ---------------------------------------------------------------------------






# --- footprints, the reduction to the outline --------------------------------------------


@pytest.mark.slow
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


@pytest.mark.slow
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








# --- far loci, the search range, translation ---------------------------------------------








# --- the book's experiment (6.3) and the tip line (3.3.11.1) ------------------------------






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
