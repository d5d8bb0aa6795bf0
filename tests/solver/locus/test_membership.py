"""Certified membership "can r be a COR?" (solver/locus/membership.py) against independent checks:
the analytic disk locus (3.30)/(3.35), forward minimum-power solves (3.7), the membership
equations recomputed with models.core.mpp (3.8)-(3.10), and brute-force dense sampling of the
dual functional over the 2-D footprint (which also tests the reduction to the outline)."""

from __future__ import annotations

import dataclasses
import math

import cvxpy as cp
import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.mpp import lever, membership_columns
from models.core.scene import PushScene
from models.core.support import Support, random_balanced_tripods
from models.locus import cor_disk as cd
from solver.certify.colgen import decide
from solver.core.budget import UNLIMITED, Budget
from solver.core.errors import SolverError
from solver.locus import membership as mm
from solver.locus.membership import MembershipProblem, decide_membership, membership
from solver.motion.forward import solve_forward
from tests.scenes import SEED, point_in_polygon, scene_for_mu
from tests.solver.locus.membership_checks import (
    FRAME,
    L_SHAPE,
    SQUARE,
    TOL,
    check_dual,
    check_witness,
    disk_samples,
    polygon_samples,
)

# --- the reduction behind the pricing problem ----------------------------------------------








# --- the disk against the analytic boundary ------------------------------------------------


@pytest.mark.parametrize("mu", [0.1, 0.3, 0.9, 1.5])
def test_points_just_inside_and_outside_the_analytic_boundary(mu):
    """(3.30)/(3.35) and the perimeter arcs: points 1e-3 a inside the analytic boundary have
    a witness support (re-verified by the forward Newton solve of (3.7)); points 1e-3 a
    outside have a dual certificate, checked by dense sampling of the disk."""
    sc = scene_for_mu(mu, **FRAME)
    a = sc.disk_radius
    ring = cd.disk_cor_locus(sc, n_points=64).boundary
    tangent = np.roll(ring, -1, axis=0) - np.roll(ring, 1, axis=0)
    normal = np.column_stack([tangent[:, 1], -tangent[:, 0]]) / np.linalg.norm(tangent, axis=1)[:, None]
    samples = disk_samples(sc)
    for k in range(0, 64, 8):
        inside = membership(sc, ring[k] - 1e-3 * a * normal[k])
        check_witness(sc, inside, a)
        assert inside.witness_forward_cor_error <= TOL.witness_cor_rel
        outside = membership(sc, ring[k] + 1e-3 * a * normal[k])
        check_dual(sc, outside, samples, a)


def test_the_cm_is_a_cor_by_a_point_mass_there():
    """With weight concentrated at the CM, rotation about the CM dissipates no power (3.6),
    so the CM is a COR (the locus contains it: r_min > 0 of (3.31) is the boundary's nearest
    distance). The witness uses a point mass at r with subgradient term -s z (3.8)."""
    for mu in (0.05, 0.3, 1.5):
        sc = scene_for_mu(mu, **FRAME)
        res = membership(sc, sc.center_of_mass)
        check_witness(sc, res, sc.disk_radius)
        assert res.point_mass_at_cor > 0.0
        ring = cd.disk_cor_locus(sc, n_points=256).boundary
        assert point_in_polygon(sc.center_of_mass[None], ring)[0]


def test_points_on_the_line_of_force_are_not_cors():
    """s = alpha . (c - r) = 0: (3.3) allows no advance of the pusher, and (3.8) reduces to
    sum P |w - r| alpha = 0, impossible: certified outside."""
    samples = None
    for mu in (0.3, 1.5):
        sc = scene_for_mu(mu, **FRAME)
        samples = disk_samples(sc)
        for t in (-3.0, -0.4, 0.25, 2.0):
            r = sc.contact_point + t * sc.disk_radius * sc.normal
            res = membership(sc, r)
            assert abs(lever(sc.contact_rel, sc.alpha_hat, res.cor - sc.center_of_mass)) < 1e-12
            check_dual(sc, res, samples, sc.disk_radius)


@pytest.mark.parametrize("mu", [0.05, 0.6, 1.5])
def test_cors_of_random_tripods_are_inside(mu):
    """3.3.3 / figure 3-5: the COR of a tripod (forward Newton solve of (3.7)) is a COR, so
    membership must find a witness; the witness's own COR re-verifies."""
    rng = np.random.default_rng(SEED + int(1000 * mu))
    sc = scene_for_mu(mu, **FRAME)
    pts, wts = random_balanced_tripods(rng, 12, sc.disk_radius, sc.center_of_mass)
    for w, p in zip(pts, wts):
        fwd = solve_forward(sc, Support.create(w, p, sc.center_of_mass))
        if fwd.cor is None:
            continue
        res = membership(sc, fwd.cor)
        check_witness(sc, res, sc.disk_radius)
        assert res.witness_forward_cor_error <= TOL.witness_cor_rel


def test_cor_on_its_own_support_point():
    """Figure 3-11 / (3.15): a dipod with weight a/(r+a) at r (inside the disk) and the rest
    on the disk opposite turns about r itself, its support point, for r just inside the
    inner boundary (3.30). Membership of that r is proven, and the forward solve puts the
    COR on the support point."""
    mu = 0.3
    sc = scene_for_mu(mu)
    rho_min = float(cd.r_min(mu))
    for rho in (rho_min + 0.2 * (1 - rho_min), 0.8):
        eta = math.acos(float(cd.inner_boundary_cos_eta(rho, mu)))
        r_loc = 0.999 * rho * np.array([-math.cos(eta), math.sin(eta)])
        pts = sc.to_world(np.vstack([-r_loc / np.linalg.norm(r_loc), r_loc]))
        rr = np.linalg.norm(r_loc)
        fwd = solve_forward(sc, Support.create(pts, [rr / (1 + rr), 1 / (1 + rr)], sc.center_of_mass))
        assert fwd.cor_on_support is not None
        res = membership(sc, sc.to_world(r_loc))
        check_witness(sc, res, sc.disk_radius)
        assert res.in_footprint


def test_point_mass_exists_only_inside_the_footprint():
    """3.3.13 boundary pieces on the disk (perimeter arcs, models/locus/cor_disk.py): for
    |alpha . c| >= a the tip is on the circle. On the circle r is in F, so a point mass at r
    with the full subgradient disk is allowed and r is inside; 1e-6 a beyond the circle only
    supports near r remain, whose directions cover half the subgradient disk, and r is
    certified outside by a wide margin: membership is discontinuous across dF."""
    sc = scene_for_mu(1.5, **FRAME)
    a = sc.disk_radius
    tip = sc.center_of_mass - a * sc.axis
    on = membership(sc, tip)
    check_witness(sc, on, a)
    assert on.in_footprint and on.point_mass_at_cor > 0.0
    assert membership(sc, sc.center_of_mass + (1 - 1e-6) * (tip - sc.center_of_mass)).status == "inside"
    out = membership(sc, sc.center_of_mass + (1 + 1e-6) * (tip - sc.center_of_mass))
    assert not out.in_footprint
    assert check_dual(sc, out, disk_samples(sc), a) > 0.05


def test_candidate_within_rounding_of_the_outline_is_moved_onto_it():
    """A candidate within ON_BOUNDARY_REL L of dF is decided on dF, where (3.8)'s direction
    (w - r)/|w - r| has closed-form one-sided limits; 1e-6 a away it is not moved."""
    sc = scene_for_mu(0.9, **FRAME)
    a = sc.disk_radius
    direction = np.array([math.cos(0.7), math.sin(0.7)])
    res = membership(sc, sc.center_of_mass + a * (1 + 1e-12) * direction)
    assert res.in_footprint
    assert np.linalg.norm(res.cor - sc.center_of_mass) == pytest.approx(a, rel=1e-15)
    far = membership(sc, sc.center_of_mass + a * (1 + 1e-6) * direction)
    assert not far.in_footprint


# --- polygons (7.5) --------------------------------------------------------------------------


def test_square_locus_is_smaller_than_its_disk():
    """7.5 / figure 3-6: the square's locus lies in its circumscribing disk's. A point 10% in
    from the disk locus's tip (3.37) is a COR for the disk but certified not one for the
    square (dual checked on a dense grid of the square)."""
    sc = scene_for_mu(0.3, a=SQUARE.circumradius)
    tip = cd.disk_cor_locus(sc, outputs=["tip"]).tip.point
    r = sc.center_of_mass + 0.9 * (tip - sc.center_of_mass)
    check_witness(sc, membership(sc, r), sc.disk_radius)
    res = membership(sc, r, SQUARE)
    check_dual(sc, res, polygon_samples(SQUARE), SQUARE.circumradius)


def test_square_vertex_and_edge_points():
    """r on the outline: a vertex of the square is a COR with a point mass at it (the
    locus reaches the vertex, where the boundary meets the footprint); 1e-7 outside the
    square next to it no point mass is allowed and r is certified outside."""
    sc = scene_for_mu(0.9, a=SQUARE.circumradius)
    ell = SQUARE.circumradius
    vertex = SQUARE.vertices[0]
    res = membership(sc, vertex, SQUARE)
    check_witness(sc, res, ell)
    assert res.in_footprint and res.point_mass_at_cor > 0.0
    out = membership(sc, vertex - [0.0, 1e-7], SQUARE)
    assert not out.in_footprint
    check_dual(sc, out, polygon_samples(SQUARE), ell)
    edge_point = membership(sc, np.array([-0.5, 0.1]), SQUARE)
    assert edge_point.in_footprint
    check_dual(sc, edge_point, polygon_samples(SQUARE), ell)


def test_l_shape_locus():
    """A non-convex footprint: CORs of random tripods on the L are inside, and a point inside
    the circumscribing disk's locus is certified outside the L's (7.5)."""
    rng = np.random.default_rng(SEED + 3)
    cm = L_SHAPE.center_of_mass
    probe = PushScene.create(L_SHAPE.circumradius, cm, math.pi / 2, 0.0, cm)
    contact = cm + 0.4 * L_SHAPE.circumradius * probe.alpha_hat + 0.3 * probe.normal
    sc = PushScene.create(L_SHAPE.circumradius, contact, math.pi / 2, 0.0, cm)
    pts, wts = random_balanced_tripods(rng, 6, L_SHAPE.circumradius, footprint=L_SHAPE)
    for w, p in zip(pts, wts):
        fwd = solve_forward(sc, Support.create(w, p, cm))
        check_witness(sc, membership(sc, fwd.cor, L_SHAPE), L_SHAPE.circumradius)
    tip = cd.disk_cor_locus(sc, outputs=["tip"]).tip.point
    r = cm + 0.85 * (tip - cm)
    check_witness(sc, membership(sc, r), sc.disk_radius)
    check_dual(sc, membership(sc, r, L_SHAPE), polygon_samples(L_SHAPE), L_SHAPE.circumradius)


def test_footprint_with_another_centre_of_mass_is_refused():
    """3.1.5: the pressure's centroid is the CM, so a footprint whose CM is not the scene's
    describes another problem."""
    sc = scene_for_mu(0.3, cm=(0.1, 0.0))
    with pytest.raises(InvalidInput) as err:
        membership(sc, [0.0, 0.0], SQUARE)
    assert err.value.field == "center_of_mass"


# --- invariances (3.3.12) --------------------------------------------------------------------


def _transformed(sc: PushScene, scale=1.0, angle=0.0, mirror=False, shift=(0.0, 0.0)):
    """The scene mapped by x -> R (M x) * scale + shift (M the mirror y -> -y)."""
    m = np.diag([1.0, -1.0]) if mirror else np.eye(2)
    rot = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
    f = lambda p: scale * (rot @ (m @ np.asarray(p, float))) + shift
    sign = -1.0 if mirror else 1.0
    new = PushScene.create(sc.disk_radius * scale, f(sc.contact_point), sign * sc.edge_angle + angle,
                           sign * sc.push_direction + angle, f(sc.center_of_mass))
    return new, f


@pytest.mark.parametrize("kind", ["scale_1e-6", "scale_1e6", "rotate", "mirror"])
def test_invariance_under_similarity(kind):
    """3.3.12: the locus scales with a and c, turns with the scene, and mirrors (the sense of
    rotation flips, (3.3)); statuses and dimensionless margins do not change."""
    sc = scene_for_mu(0.3, **FRAME)
    args = {"scale_1e-6": dict(scale=1e-6), "scale_1e6": dict(scale=1e6),
            "rotate": dict(angle=1.1, shift=(5.0, -3.0)), "mirror": dict(mirror=True, shift=(0.2, 0.1))}[kind]
    new, f = _transformed(sc, **args)
    ring = cd.disk_cor_locus(sc, n_points=16).boundary
    cm = sc.center_of_mass
    for b in ring[::4]:
        for factor in (0.98, 1.02):
            r = cm + factor * (b - cm)
            base = membership(sc, r, verify_witness=False)
            other = membership(new, f(r), verify_witness=False)
            assert base.status == other.status != "undecided"
            if base.status == "outside":
                assert other.dual_margin == pytest.approx(base.dual_margin, rel=1e-6, abs=1e-9)


# --- modes and errors ------------------------------------------------------------------------


def test_grid_mode_is_not_a_certificate_and_time_limit_gives_undecided():
    """A point far beyond the tip (3.37) is outside; without the branch and bound the dual of
    (3.8) is only checked on a grid and the result says it is no certificate."""
    sc = scene_for_mu(0.3)
    far = sc.center_of_mass + 5.0 * sc.axis
    grid = membership(sc, far, certify=False)
    assert grid.status == "outside" and grid.lower_bound_method == "grid" and grid.certificate_kind == "none"
    cert = membership(sc, far)
    assert cert.lower_bound_method == "branch_and_bound" and cert.certificate_kind == "dual"
    late = membership(sc, far, budget=Budget.of(0.0))
    assert late.status == "undecided" and "time limit" in late.message


def test_a_loose_residual_tolerance_admits_points_just_beyond_the_tip():
    """Why the default membership_residual is strict (1e-12): at the tip (3.37) for
    |alpha . c| = 0.05 a, 5e-7 a beyond it, a residual tolerance of 1e-8 accepts a witness
    whose residual is ~1e-9 and whose own forward COR is visibly not r; the default
    certifies the point outside, and the point 5e-7 a inside still has an exact witness."""
    sc = scene_for_mu(0.05)
    a = sc.disk_radius
    ring = cd.disk_cor_locus(sc, n_points=64).boundary
    tangent = ring[1] - ring[-1]
    nu = np.array([tangent[1], -tangent[0]]) / np.linalg.norm(tangent)
    beyond = ring[0] + 5e-7 * a * nu
    loose = membership(sc, beyond, tol=dataclasses.replace(TOL, membership_residual=1e-8))
    assert loose.status == "inside"
    assert 1e-12 < loose.witness_residual <= 1e-8
    assert loose.witness_forward_cor_error > 1e-7
    assert TOL.membership_residual <= 1e-12
    check_dual(sc, membership(sc, beyond), disk_samples(sc), a)
    inner = membership(sc, ring[0] - 5e-7 * a * nu)
    assert inner.status == "inside" and inner.witness_residual <= 1e-12
    assert inner.witness_forward_cor_error <= 1e-9


def test_conic_solver_failure_is_a_solver_error(monkeypatch):
    """A failure of the restricted master's conic solve becomes the project's SolverError."""

    import clarabel

    def broken(*args, **kwargs):
        raise cp.error.SolverError("boom")

    def broken_direct(*args, **kwargs):
        raise ValueError("boom")

    monkeypatch.setattr(cp.Problem, "solve", broken)  # the compiled master
    monkeypatch.setattr(clarabel, "DefaultSolver", broken_direct)  # the direct one
    with pytest.raises(SolverError):
        membership(scene_for_mu(0.3), [0.5, 0.5])


def test_far_candidates_are_decided_on_the_conditioned_rows():
    """A locus tip ~185 L away (|alpha . c| = 0.0054 a, tip a^2/|alpha . c|, (3.37)): 2e-6 a
    beyond it the plain rows (3.8)-(3.10) separate by a margin of order delta/s^2, below
    certificate_margin, and stay undecided; membership decides the point on the
    conditioned rows (moment about the contact, module docstring) with a dual that holds on
    dense samples of the whole disk, converted back to the columns of
    models.core.mpp.membership_columns. The point 2e-6 a inside has a witness."""
    sc = scene_for_mu(0.0054)
    a = sc.disk_radius
    tip = cd.disk_cor_locus(sc, outputs=("tip",)).tip
    assert 184 < tip.distance / a < 186
    u = (tip.point - sc.center_of_mass) / tip.distance
    beyond, inside = tip.point + 2e-6 * a * u, tip.point - 2e-6 * a * u
    outline = mm.outline_of(sc, None)
    r = outline.to_local(beyond)
    alpha = outline.vector_to_local(sc.alpha_hat)
    c = outline.vector_to_local(sc.contact_rel) / outline.length
    plain = decide(mm.PlainRows(outline, r, False, False, alpha, float(alpha @ (c - r))), TOL, UNLIMITED, mm.MESSAGES)
    assert plain.status == "undecided"
    res = membership(sc, beyond)
    assert res.status == "outside" and res.certificate_kind == "dual" and res.rows == "far"
    assert res.dual_margin > TOL.certificate_margin
    y = res.dual
    w = disk_samples(sc) - sc.center_of_mass
    vals = y @ membership_columns(res.cor - sc.center_of_mass, w, sc.contact_rel, sc.alpha_hat, a)
    assert vals.min() >= res.dual_lower_bound - 1e-11 * np.max(np.abs(y))
    assert res.dual_lower_bound - y[0] == pytest.approx(res.dual_margin, abs=1e-12)
    inner = membership(sc, inside)
    check_witness(sc, inner, a)


def test_decide_membership_is_membership_of_the_problem_3_8():
    """The one-call form answers as membership() (3.8): inside with a witness beyond the
    disk, outside beyond the tip (3.37), undecided when the budget is already spent."""
    sc = scene_for_mu(0.3)
    tip = cd.disk_cor_locus(sc, outputs=["tip"]).tip
    inside = decide_membership(MembershipProblem(sc, 0.9 * tip.point))
    assert inside.status == "inside" == membership(sc, 0.9 * tip.point).status and inside.complete
    assert decide_membership(MembershipProblem(sc, 1.1 * tip.point)).status == "outside"
    spent = decide_membership(MembershipProblem(sc, 0.9 * tip.point), Budget.of(0.0))
    assert spent.status == "undecided" and not spent.complete


@pytest.mark.parametrize("radius", [5e-324, 1e-300, 1e-13])
def test_a_candidate_beyond_the_resolved_distance_is_refused_by_name(radius):
    """|r - CM| / L above SolverTolerances.max_cor_distance_rel (a disk of 5e-324 and a
    candidate 6.5 away: 1.3e324 L, an overflow) is refused naming `cor`, not a solver
    failure deep in the master (found by the live contract test)."""
    scene = PushScene.create(radius, [0.0, 0.0], 1e-93, -989690.7470272449)
    with pytest.raises(InvalidInput) as err:
        membership(scene, [6.472574030457316, 2.00001])
    assert err.value.field == "cor"
