"""Closed forms of the frictionless disk COR locus (book chapter 3), each checked against an
independent computation. Equation numbers are the book's."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.scene import PushScene
from models.core.tolerances import DEFAULT, HIGH_ACCURACY
from models.locus import cor_disk as cd
from tests.scenes import ALL_MU, MU_ON_DISK, MU_OUTER_INNER, MU_WITH_ARC, circle_radius, scene_for_mu


def moments(r: np.ndarray, points: np.ndarray, weights: np.ndarray):
    """d_r (3.9) and v_r (3.10) straight from their definitions."""
    diff = points - r
    dist = np.linalg.norm(diff, axis=1)
    return float(weights @ dist), weights @ (diff / dist[:, None])


# --- the quotient locus (3.15)-(3.21) from the dipod definitions --------------------------


@pytest.mark.parametrize("rho", [0.1, 0.5, 0.9])
def test_fig_3_8_dipod_weights_and_moments_3_15_to_3_17(rho):
    """(3.15): P1 = r/(r+a), P2 = a/(r+a) centre the dipod of figure 3-8; (3.16)-(3.17)."""
    a = 1.0
    r = np.array([rho, 0.0])
    w1, w2 = np.array([-a, 0.0]), r + np.array([1e-9, 0.0])
    p1, p2 = rho / (rho + a), a / (rho + a)
    assert np.allclose(p1 * w1 + p2 * r, 0.0, atol=1e-15)
    d, v = moments(r, np.vstack([w1, w2]), np.array([p1, p2]))
    assert d == pytest.approx(rho, rel=1e-8)  # (3.17)
    assert np.linalg.norm(v) == pytest.approx((a - rho) / (a + rho), rel=1e-8)  # (3.16)


@pytest.mark.parametrize("rho", [0.2, 0.6, 0.95])
@pytest.mark.parametrize("omega", [0.0, 1.0, 2.5, 4.0])
def test_fig_3_11_dipods_trace_the_circle_3_19_3_20(rho, omega):
    """q_r of the figure 3-11 dipods lies on the circle of radius b = ar/(r+a) (3.20) about
    -(r - b) r_hat. (The printed (3.19) has r^2/a where a belongs; (3.20) is right.)"""
    r = rho * np.array([math.cos(0.3), math.sin(0.3)])
    w1 = -r / rho  # on the disk, opposite the COR
    p1, p2 = rho / (1 + rho), 1 / (1 + rho)
    z = np.array([math.cos(omega), math.sin(omega)])
    v = p1 * (w1 - r) / np.linalg.norm(w1 - r) + p2 * z  # the point mass at r contributes z
    d = p1 * np.linalg.norm(w1 - r)
    q = rho**2 * v / d
    b = rho / (rho + 1)
    assert np.linalg.norm(q + (rho - b) * r / rho) == pytest.approx(b, rel=1e-12)


@pytest.mark.parametrize("rho", [1.01, 1.5, 3.0, 20.0])
@pytest.mark.parametrize("omega", [0.05, 0.7, 1.2, math.pi / 2])
def test_dipod_quotient_matches_definitions_3_21_3_34_3_35(rho, omega):
    """The cancellation-free form of (3.21)/(3.34)/(3.35) equals both the printed formulas
    and the moments computed from the two support points of figure 3-12."""
    mu, eta = cd.dipod_quotient(rho, omega)
    mu_p, eta_p = cd.dipod_quotient_printed(rho, omega)
    assert mu == pytest.approx(mu_p, rel=1e-9)
    assert eta == pytest.approx(eta_p, abs=1e-10)
    # Local frame of (3.21): y from the COR towards the CM, x = y turned clockwise.
    r = np.array([0.0, -rho])
    u = np.array([math.sin(omega), math.cos(omega)])
    d, v = moments(r, np.vstack([u, -u]), np.array([0.5, 0.5]))
    assert math.atan2(-v[0], v[1]) == pytest.approx(eta, abs=1e-12)  # (3.34)
    q = rho**2 * np.linalg.norm(v) / d
    assert rho**2 == pytest.approx(q * (mu + rho * math.cos(eta)), rel=1e-12)  # (3.35)


def test_dipod_quotient_keeps_digits_far_outside():
    """At r = 1e9 a the printed (3.21) has lost all digits; the rewritten form has not:
    at omega = pi/2 it must give alpha . c = a^2 / r exactly (3.36)-(3.37)."""
    for rho in [1e3, 1e6, 1e9, 1e12]:
        mu, eta = cd.dipod_quotient(rho, math.pi / 2)
        assert mu == pytest.approx(1 / rho, rel=1e-13)
        assert abs(eta) < 1e-15


# --- closed forms ---------------------------------------------------------------------------


@pytest.mark.parametrize("mu", ALL_MU)
def test_r_min_3_31_solves_3_29_at_eta_pi(mu):
    """(3.29) with cos(eta) = -1 at r = r_min (3.31), and (3.30) gives eta = pi there."""
    r = cd.r_min(mu)
    s = mu - r
    lhs = r * r * (1 + r) + (r - 1) * s * s - 2 * r * r * s * (-1.0)
    assert abs(lhs) < 1e-14
    assert cd.inner_boundary_cos_eta(r, mu) == pytest.approx(-1.0, abs=1e-12)


@pytest.mark.parametrize("mu", ALL_MU)
def test_inner_boundary_3_30_solves_3_28(mu):
    """Points from (3.30) put the required quotient moment on the circle (3.26)-(3.28)."""
    rho = np.linspace(cd.r_min(mu) * 1.001, 0.999, 50)
    eta = np.arccos(cd.inner_boundary_cos_eta(rho, mu))
    assert np.max(np.abs(cd.inner_boundary_residual(rho, eta, mu))) < 1e-10
    # the printed form of (3.30) agrees where it has no cancellation
    printed = (rho * np.sqrt((rho + 1) ** 2 + mu * mu) - mu) / (rho * (rho + 1))
    assert np.allclose(np.cos(eta), printed, atol=1e-10 * max(1.0, mu))


@pytest.mark.parametrize("mu", ALL_MU)
def test_disk_crossing_3_32_is_3_30_at_r_equal_a(mu):
    assert cd.disk_crossing_cos_eta(mu) == pytest.approx(cd.inner_boundary_cos_eta(1.0, mu), rel=1e-13)
    printed = (math.sqrt(mu * mu + 4) - mu) / 2
    assert cd.disk_crossing_cos_eta(mu) == pytest.approx(printed, rel=1e-12)


@pytest.mark.parametrize("mu", MU_OUTER_INNER + MU_WITH_ARC)
def test_tip_3_37_is_where_the_omega_pi_2_dipod_satisfies_3_35(mu):
    """(3.36)-(3.37): the dipod at omega = pi/2 sits on the boundary at r = a^2/(alpha . c)."""
    m, eta = cd.dipod_quotient(cd.tip_distance_book(mu), math.pi / 2)
    assert m == pytest.approx(mu, rel=1e-13)
    assert abs(eta) < 1e-15
    assert cd.tip_distance(mu) == pytest.approx(1 / mu)


@pytest.mark.parametrize("mu", MU_ON_DISK)
def test_tip_is_on_the_disk_when_moment_arm_reaches_a(mu):
    """For alpha . c >= a the book's tip a^2/(alpha . c) lies inside the disk and the
    farthest COR is on the disk: every point of the axis up to r = a satisfies the inner
    membership condition (3.25) (residual <= 0)."""
    assert cd.tip_distance(mu) == 1.0
    rho = np.linspace(0.5, 0.999999, 20)
    assert np.all(cd.inner_boundary_residual(rho, 0.0, mu) <= 1e-12)


@pytest.mark.parametrize("mu", [0.02, 0.1, 0.3, 0.5, 0.7, 0.9])
def test_tip_radius_of_curvature_3_38(mu):
    """Finite-difference curvature of the solved outer boundary (3.35) at the tip.

    Finding: it is a^4/(2 r_tip^3) = (alpha . c)^3 / (2 a^2); (3.38) as printed in the text,
    r_tip / (1/2 + r_tip^4/a^4), is about twice that for r_tip >> a (OCR or typo)."""
    h = 1e-5  # the error is O(h^2) until round-off takes over near h = 1e-6
    omega = np.array([math.pi / 2 - h])
    rho, eta, _ = cd.outer_boundary(omega, mu, HIGH_ACCURACY)
    pts = [np.array([-r * math.cos(e), s * r * math.sin(e)]) for r, e, s in ((rho[0], eta[0], -1), (cd.tip_distance(mu), 0.0, 1), (rho[0], eta[0], 1))]
    measured = circle_radius(*pts)
    assert measured == pytest.approx(float(cd.tip_radius_of_curvature(mu)), rel=2e-3)
    if mu <= 0.3:
        printed = float(cd.tip_radius_of_curvature_book_printed(mu))
        assert printed / measured == pytest.approx(2.0, rel=0.1)


@pytest.mark.parametrize("mu", ALL_MU)
def test_r_min_radius_of_curvature_3_33(mu):
    """Finite-difference curvature of (3.30) at r_min against (3.33)."""
    r0 = float(cd.r_min(mu))
    r1 = r0 * (1 + 1e-7)
    e1 = math.acos(float(cd.inner_boundary_cos_eta(r1, mu)))
    pts = [np.array([-r1 * math.cos(e1), -r1 * math.sin(e1)]), np.array([r0, 0.0]), np.array([-r1 * math.cos(e1), r1 * math.sin(e1)])]
    assert circle_radius(*pts) == pytest.approx(float(cd.r_min_radius_of_curvature(mu)), rel=1e-4)


# --- the outer family and how the pieces join ----------------------------------------------


@pytest.mark.parametrize("mu", MU_OUTER_INNER + MU_WITH_ARC)
def test_dipod_moment_arm_decreases_along_each_ray(mu):
    """The root of (3.35) in r is unique on [a, r_tip] (what the bracketing solver needs)."""
    omega = np.linspace(cd.outer_corner_omega(mu) + 1e-4, math.pi / 2, 40)[:, None]
    rho = np.exp(np.linspace(1e-6, math.log(1 / mu), 400))[None, :]
    m, _ = cd.dipod_quotient(rho, omega)
    assert np.all(np.diff(m, axis=1) < 0)


@pytest.mark.parametrize("mu", [0.05, 0.3, 0.6, 0.7])
def test_outer_piece_runs_into_the_inner_one_at_eta_a(mu):
    """mu < 1/sqrt 2: as omega -> 0 the outer boundary reaches the disk at eta_a (3.32)."""
    rho, eta, _ = cd.outer_boundary(np.array([1e-6]), mu)
    assert rho[0] == pytest.approx(1.0, abs=1e-4)
    assert math.cos(eta[0]) == pytest.approx(cd.disk_crossing_cos_eta(mu), abs=1e-4)


@pytest.mark.parametrize("mu", MU_WITH_ARC)
def test_outer_piece_meets_the_disk_at_arccos_mu(mu):
    """1/sqrt 2 <= mu < 1: the outer family reaches r = a at eta_c = arccos(mu), before eta_a."""
    omega_c = cd.outer_corner_omega(mu)
    m, eta = cd.dipod_quotient(1.0, omega_c)
    assert m == pytest.approx(mu, rel=1e-12)
    assert eta == pytest.approx(math.acos(mu), abs=1e-12)
    assert eta < math.acos(cd.disk_crossing_cos_eta(mu))


# --- the assembled locus ------------------------------------------------------------------------


@pytest.mark.parametrize("mu", ALL_MU + (1e-12, 1e-8, 1e6))
def test_boundary_is_a_closed_simple_ring_with_small_residual(mu):
    sc = scene_for_mu(mu)
    loc = cd.disk_cor_locus(sc, n_points=256)
    b = loc.boundary
    assert b.shape == (256, 2)
    assert np.all(np.isfinite(b))
    assert loc.boundary_residual <= DEFAULT.boundary_residual_rel
    # counter-clockwise and starting at the tip
    x, y = b[:, 0], b[:, 1]
    assert 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) > 0
    assert np.allclose(b[0], loc.tip.point, rtol=0, atol=1e-12 * max(1.0, loc.tip.distance))
    # farthest point is the tip; nearest boundary point on the axis is r_min
    dist = np.linalg.norm(b - sc.center_of_mass, axis=1)
    assert dist.max() == pytest.approx(loc.tip.distance, rel=1e-12)
    assert dist.min() == pytest.approx(loc.r_min.distance, rel=1e-9)


@pytest.mark.parametrize("n_points", [8, 9, 64, 1001])
def test_n_points_is_respected_up_to_even(n_points):
    loc = cd.disk_cor_locus(scene_for_mu(0.4), n_points=n_points)
    assert len(loc.boundary) == n_points + (n_points % 2)


def test_only_requested_outputs_are_computed():
    loc = cd.disk_cor_locus(scene_for_mu(0.4), outputs=["tip"])
    assert loc.tip is not None
    assert loc.boundary is None and loc.r_min is None and loc.curvatures is None
    with pytest.raises(InvalidInput) as err:
        cd.disk_cor_locus(scene_for_mu(0.4), outputs=["tip", "everything"])
    assert err.value.field == "outputs"


@pytest.mark.parametrize("mu", MU_WITH_ARC + MU_ON_DISK)
def test_perimeter_arcs_lie_on_the_boundary(mu):
    loc = cd.disk_cor_locus(scene_for_mu(mu), n_points=512)
    on_disk = np.abs(np.linalg.norm(loc.boundary, axis=1) - 1.0) < 1e-12
    assert on_disk.sum() >= 4
    arcs = loc.disk_crossings.arcs
    assert len(arcs) == (1 if mu >= 1 else 2)
    angles = np.arctan2(loc.boundary[on_disk, 1], loc.boundary[on_disk, 0])
    for arc in arcs:
        span = (arc.end_angle - arc.start_angle) % (2 * math.pi)
        assert span < math.pi
        assert np.allclose(np.linalg.norm(arc.start), 1.0) and np.allclose(np.linalg.norm(arc.end), 1.0)
    inside_some = np.zeros(angles.shape, bool)
    for arc in arcs:
        inside_some |= (angles - arc.start_angle) % (2 * math.pi) <= (arc.end_angle - arc.start_angle) % (2 * math.pi) + 1e-12
    assert np.all(inside_some)


def test_translation_is_a_first_class_answer():
    sc = scene_for_mu(0.0)
    loc = cd.disk_cor_locus(sc)
    assert loc.kind == "translation" and loc.sense == "none"
    assert loc.tip is None and loc.boundary is None
    assert np.allclose(loc.translation_direction, sc.normal)
    # Tip line still exists: c is not zero (it lies on the line of force).
    assert loc.tip_line is not None


@pytest.mark.parametrize("mu", [1e-12, 1e-9, 1e-6])
def test_tiny_moment_arm_is_bounded_and_finite(mu):
    loc = cd.disk_cor_locus(scene_for_mu(mu, along=0.0))
    assert loc.kind == "bounded"
    assert loc.tip.distance == pytest.approx(1 / mu, rel=1e-9)
    assert np.all(np.isfinite(loc.boundary))


# --- symmetries (3.3.12) --------------------------------------------------------------------


@pytest.mark.parametrize("scale", [1e-6, 1e-3, 1e3, 1e6])
def test_scaling_a_and_c_scales_the_locus(scale):
    """3.3.12: scaling a and c by gamma scales the locus by gamma."""
    base = cd.disk_cor_locus(scene_for_mu(0.35, along=0.1), n_points=128)
    big = cd.disk_cor_locus(scene_for_mu(0.35, a=scale, along=0.1), n_points=128)
    assert np.allclose(big.boundary, scale * base.boundary, rtol=0, atol=1e-12 * scale * base.tip.distance)
    assert big.tip.distance == pytest.approx(scale * base.tip.distance, rel=1e-13)


@pytest.mark.parametrize("angle", [0.3, 1.9, -2.4])
def test_rotating_the_scene_rotates_the_locus(angle):
    rot = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
    cm = np.array([0.7, -1.1])
    sc = PushScene.create(1.3, cm + [0.4, 0.5], 1.2, 0.1, cm)
    sc_r = PushScene.create(1.3, rot @ (cm + [0.4, 0.5]), 1.2 + angle, 0.1 + angle, rot @ cm)
    a, b = cd.disk_cor_locus(sc, n_points=96), cd.disk_cor_locus(sc_r, n_points=96)
    assert np.allclose(b.boundary, a.boundary @ rot.T, atol=1e-12)
    assert np.allclose(b.tip_line.point, rot @ a.tip_line.point, atol=1e-12)
    assert a.sense == b.sense


def test_locus_is_mirror_symmetric_about_its_axis():
    loc = cd.disk_cor_locus(scene_for_mu(0.45), n_points=200)
    axis = loc.axis
    b = loc.boundary
    mirrored = 2 * np.outer(b @ axis, axis) - b
    # every mirrored vertex is a vertex of the ring
    d = np.min(np.linalg.norm(mirrored[:, None] - b[None], axis=2), axis=1)
    assert d.max() < 1e-12


def test_mirror_scene_turns_the_other_way_with_the_mirrored_locus():
    """Reflecting the scene in the x axis swaps CW and CCW and reflects the locus (3.3.1:
    the book assumes alpha . (c - r) > 0; the mirror case is handled by symmetry)."""
    sc = PushScene.create(1.0, [0.1, 0.35], 1.3, 0.2)
    mi = PushScene.create(1.0, [0.1, -0.35], -1.3, -0.2)
    a, b = cd.disk_cor_locus(sc), cd.disk_cor_locus(mi)
    assert {a.sense, b.sense} == {"cw", "ccw"}
    flip = np.array([1.0, -1.0])
    d = np.min(np.linalg.norm((a.boundary * flip)[:, None] - b.boundary[None], axis=2), axis=1)
    assert d.max() < 1e-12


@pytest.mark.parametrize("shift", [-0.8, 0.3, 5.0])
def test_sliding_the_contact_along_the_line_of_force_changes_nothing(shift):
    """3.3.12: displacing c along the applied force changes neither force nor torque."""
    a = cd.disk_cor_locus(scene_for_mu(0.4, along=0.0), n_points=64)
    b = cd.disk_cor_locus(scene_for_mu(0.4, along=shift), n_points=64)
    assert np.allclose(a.boundary, b.boundary, atol=1e-12)


def test_edge_angle_and_reversed_push_give_the_same_locus():
    """The edge angle is a line: edge_angle + pi is the same edge; the push direction
    enters only through the sign of n . p, not the locus."""
    a = cd.disk_cor_locus(PushScene.create(1.0, [0.2, 0.3], 1.0, 0.0), n_points=64)
    b = cd.disk_cor_locus(PushScene.create(1.0, [0.2, 0.3], 1.0 + math.pi, 0.4), n_points=64)
    assert np.allclose(a.boundary, b.boundary, atol=1e-12)


# --- tip line (3.3.11.1) ------------------------------------------------------------------------


def test_tips_for_all_edge_angles_lie_on_the_tip_line():
    c = np.array([0.3, 0.4])
    line = None
    for edge in np.linspace(0.1, 3.0, 25):
        sc = PushScene.create(1.0, c, edge, 0.0)
        if sc.relative_moment_arm >= 1 or sc.is_translation:
            continue
        loc = cd.disk_cor_locus(sc, outputs=["tip", "tip_line"])
        line = loc.tip_line
        off = loc.tip.point - line.point
        assert abs(off @ np.array([-line.direction[1], line.direction[0]])) < 1e-12 * loc.tip.distance
    assert line.distance == pytest.approx(1 / 0.5)


# --- rotation per unit push (3.3) ------------------------------------------------------------






def test_absurd_moment_arm_is_an_input_error_not_an_overflow():
    """A disk 1e-200 wide pushed 0.3 away: the ratio would overflow (3.33); refuse it."""
    with pytest.raises(InvalidInput) as err:
        PushScene.create(1e-200, [-0.5, -0.3], math.pi / 2)
    assert err.value.field == "disk_radius"
    loc = cd.disk_cor_locus(PushScene.create(1e-12, [0.0, 0.9999], math.pi / 2))
    assert np.all(np.isfinite(loc.boundary)) and loc.tip.on_disk


SQRT_HALF_PROBE = 0.7071067811865476  # the outer piece meets the disk from here (outer_corner_omega)


def test_boundaries_solved_together_are_each_boundary_3_35():
    """Issue 26: the boundaries of many loci solved at once (boundary_locals: the outer
    pieces (3.35) of every mu in one root-finding) are, point for point, the boundary of
    each alone, across the outer/arc/inner regimes (mu < 1/sqrt 2, up to 1, above 1)."""
    from models.locus.cor_disk import boundary_local, boundary_locals

    rng = np.random.default_rng(20261127)
    mus = [float(m) for m in rng.uniform(1e-3, 3.0, 60)] + [1e-6, 0.5, SQRT_HALF_PROBE, 1.0, 1.0 - 1e-9, 50.0]
    together = boundary_locals(mus, 64)
    for mu, (ring, residual, _) in zip(mus, together):
        alone, alone_residual, _ = boundary_local(mu, 64)
        assert np.array_equal(ring, alone), mu
        assert residual == alone_residual

