"""Closed forms of gross motions (book 3.4, 4.3, 4.4) in models/push/gross_motion.py.

Every closed form is checked against an adaptive quadrature of its own equation of motion,
and the CORs it relies on (tips, B, the sticking-line side) against models.locus.cor_disk on a
PushScene built in the world frame, which knows nothing of the fence or disk frames used
here. Book text references are line numbers of /work/shared/seed/000_11c73ac4ccaabe12.txt.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.scene import PushScene
from models.locus.cor_disk import disk_cor_locus
from models.push import gross_motion as gm

D = math.radians

# The 4.3 example: the text (lines 1855, 1890, 1906, 1923) gives beta 45 -> 80 degrees,
# the tip of {COR}_(alpha+nu) crossing the sticking line at 69.4 degrees (same-sided split
# before, opposite-sided after), sticking-slowest 45 -> 69.4 and slipping-slowest after.
# It does not give a, c, alpha or mu_c (they are only in figures 4-7 to 4-9, which the
# text does not reproduce). Solving (4.3) for c^2/a^2 = (1 + t^2)/(t tan(alpha+nu) - 1),
# t = tan 69.4 deg, gives the family of scenes that reproduce the text; two members:
# alpha = 70 deg and mu_c = 0.25 (the fence angle of 6.1 and the fence friction measured in
# 6.4), and alpha = 60 deg, mu_c = 0.25.
T_694 = math.tan(D(69.4))


def example_c(alpha: float, mu_c: float, a: float = 1.0) -> float:
    t_phi = math.tan(alpha + math.atan(mu_c))
    return a * math.sqrt((1.0 + T_694**2) / (T_694 * t_phi - 1.0))


EXAMPLES = [(D(70.0), 0.25), (D(60.0), 0.25)]


def world_tip(beta: float, a: float, c: float, phi: float) -> np.ndarray:
    """Tip of {COR}_phi from models.locus.cor_disk: a world-frame scene pushing along +x with
    the edge at angle phi and the contact c (-cos beta, sin beta)."""
    contact = c * np.array([-math.cos(beta), math.sin(beta)])
    scene = PushScene.create(a, contact, phi, 0.0)
    assert scene.book_alpha == pytest.approx(phi)
    return disk_cor_locus(scene, outputs=("tip",)).tip.point


# --- quadrature ------------------------------------------------------------------------


def test_kronrod_rules_integrate_polynomials_exactly():
    """K15 is exact to degree 22, G7 to degree 13 (Legendre nodes from numpy agree)."""
    x = gm.KRONROD_NODES
    for deg in range(23):
        exact = 0.0 if deg % 2 else 2.0 / (deg + 1)
        assert gm.KRONROD_WEIGHTS @ x**deg == pytest.approx(exact, abs=1e-15)
        if deg <= 13:
            assert gm.GAUSS_WEIGHTS_ON_KRONROD @ x**deg == pytest.approx(exact, abs=1e-15)
    nodes, _ = np.polynomial.legendre.leggauss(7)
    assert np.allclose(np.sort(x[1::2]), np.sort(nodes), atol=1e-15)


def test_adaptive_quadrature_with_honest_error_estimate():
    # A log singularity at the end (the shape of (4.16) near beta = 0) and a kink.
    r = gm.adaptive_quadrature(lambda b: 1.0 / np.sin(b), 1e-3, 1.0, rtol=1e-12)
    exact = math.log(math.tan(0.5)) - math.log(math.tan(5e-4))
    assert r.converged and abs(r.value - exact) <= max(r.error, 1e-14 * exact)
    r = gm.adaptive_quadrature(lambda b: np.abs(b - 0.3), 0.0, 1.0, rtol=1e-11)
    assert r.value == pytest.approx(0.045 + 0.245, rel=1e-10)
    r = gm.adaptive_quadrature(math.exp, 1.0, 0.0, vectorized=False)  # reversed limits
    assert r.value == pytest.approx(1.0 - math.e, rel=1e-13)
    with pytest.raises(InvalidInput), np.errstate(divide="ignore"):
        gm.adaptive_quadrature(lambda b: 1.0 / (b - 0.5), 0.0, 1.0)  # a node hits the pole


# --- 3.4, mu_c = 0 ---------------------------------------------------------------------


@pytest.mark.parametrize("alpha,c", [(D(90), 0.7), (D(70), 1.0), (D(110), 0.4)])
def test_3_40_rate_is_the_lever_of_the_cor_disk_tip(alpha, c):
    """(3.40): alpha . (c - r_tip)/sin alpha with the tip of models.locus.cor_disk."""
    a = 1.0
    for beta in np.linspace(HALF_LO(alpha), math.pi - alpha - 0.05, 5):
        tip = world_tip(beta, a, c, alpha)
        assert np.allclose(tip, gm.fence_tip(beta, a, c, alpha), rtol=1e-12, atol=1e-12)
        lever = np.array([math.cos(alpha), math.sin(alpha)]) @ (gm.fence_contact(beta, c) - tip)
        assert gm.fence_rate_frictionless(beta, a, c, alpha) == pytest.approx(lever / math.sin(alpha), rel=1e-12)
        assert gm.fence_rate(beta, c, alpha, tip) == pytest.approx(lever / math.sin(alpha), rel=1e-12)


def HALF_LO(alpha: float) -> float:
    """A beta a little above the wrapping angle pi/2 - alpha (and above 0)."""
    return max(0.05, math.pi / 2 - alpha + 0.05)


@pytest.mark.parametrize("alpha,c", [(D(90), 0.7), (D(70), 1.0), (D(110), 0.4), (D(50), 0.2)])
def test_3_41_against_quadrature_of_3_40(alpha, c):
    a = 1.0
    bi, bf = HALF_LO(alpha), math.pi - alpha - 0.02
    q = gm.adaptive_quadrature(lambda b: gm.fence_rate_frictionless(b, a, c, alpha), bi, bf, rtol=1e-12)
    assert gm.fence_push_frictionless(a, c, alpha, bi, bf) == pytest.approx(q.value, rel=1e-11)
    # (3.41) exactly as printed (with log|(1+s)/(1-s)|) agrees with the stable evaluation.
    s = math.sin(alpha + bi)
    printed = (-c * s - a * a / (2 * c) * math.log(abs((1 + s) / (1 - s)))) / math.sin(alpha)
    assert gm.fence_push_frictionless_indefinite(bi, a, c, alpha) == pytest.approx(printed, rel=1e-12)


def test_3_41_scales_with_the_part_and_diverges_at_wrapping():
    a, c, alpha = 2.0, 1.2, D(80)
    x1 = gm.fence_push_frictionless(a, c, alpha, D(30), D(60))
    assert gm.fence_push_frictionless(2 * a, 2 * c, alpha, D(30), D(60)) == pytest.approx(2 * x1, rel=1e-13)
    near = [gm.fence_push_frictionless(a, c, alpha, math.pi / 2 - alpha + eps, D(60)) for eps in (1e-2, 1e-4, 1e-6)]
    assert near[0] < near[1] < near[2]  # r_tip -> infinity as alpha + beta -> pi/2
    with pytest.raises(InvalidInput):
        gm.fence_push_frictionless(a, c, alpha, D(5), D(60))  # alpha + beta < pi/2
    with pytest.raises(InvalidInput):
        gm.fence_push_frictionless(a, 1.5 * a, alpha, D(30), D(60))  # vertex outside the disk
    with pytest.raises(InvalidInput):
        gm.fence_push_frictionless(a, c, alpha, D(30), D(101))  # CM past the fence line


@pytest.mark.parametrize("alpha,c", [(D(90), 0.7), (D(70), 1.0), (D(110), 0.4)])
def test_least_push_uses_r_min_the_locus_point_farthest_along_alpha(alpha, c):
    """Not in the book: r_min (3.31) is the locus point farthest along +alpha_hat (checked on
    the cor_disk boundary), so it is the fastest COR; its closed form against quadrature."""
    a = 1.0
    beta = HALF_LO(alpha) + 0.1
    contact = c * np.array([-math.cos(beta), math.sin(beta)])
    scene = PushScene.create(a, contact, alpha, 0.0)
    loc = disk_cor_locus(scene, outputs=("boundary", "r_min"), n_points=2000)
    along = loc.boundary @ scene.alpha_hat
    assert along.max() == pytest.approx(scene.alpha_hat @ loc.r_min.point, abs=1e-12)
    lever = scene.alpha_hat @ (contact - loc.r_min.point)
    assert gm.fence_rate_least_frictionless(beta, a, c, alpha) == pytest.approx(lever / math.sin(alpha), rel=1e-12)
    bi, bf = HALF_LO(alpha), math.pi - alpha - 0.02
    q = gm.adaptive_quadrature(lambda b: gm.fence_rate_least_frictionless(b, a, c, alpha), bi, bf, rtol=1e-12)
    least = gm.fence_push_least_frictionless(a, c, alpha, bi, bf)
    assert least == pytest.approx(q.value, rel=1e-11)
    assert 0.0 < least < gm.fence_push_frictionless(a, c, alpha, bi, bf)


def test_least_push_branch_past_u_equal_pi():
    """alpha + beta crosses pi (alpha obtuse): the atan branch is continued."""
    a, c, alpha = 1.0, 0.6, D(150)
    bi, bf = D(10), D(28)
    q = gm.adaptive_quadrature(lambda b: gm.fence_rate_least_frictionless(b, a, c, alpha), bi, bf, rtol=1e-12)
    assert gm.fence_push_least_frictionless(a, c, alpha, bi, bf) == pytest.approx(q.value, rel=1e-11)


# --- 4.3: the transition (4.3)/(4.4) ---------------------------------------------------


@pytest.mark.parametrize("c", [0.3, 0.6, 1.0])
@pytest.mark.parametrize("phi", [D(40), D(75), D(88), D(100), D(130)])
def test_4_3_side_of_the_tip_against_cor_disk(c, phi):
    """E < 0 exactly when the cor_disk tip of {COR}_phi is right of the sticking line;
    the book's (4.3) residual is positive there (the text says 'less than': reversed)."""
    a = 1.0
    for beta in np.linspace(max(0.02, math.pi / 2 - phi + 0.02), min(math.pi - 0.02, 1.5 * math.pi - phi - 0.02), 9):
        if abs(math.cos(beta)) < 1e-3:
            continue
        tip = world_tip(beta, a, c, phi)
        right = tip[0] > -c * math.cos(beta)
        e = float(gm.fence_tip_side(beta, a, c, phi))
        assert (e < 0.0) == right
        assert tip[0] + c * math.cos(beta) == pytest.approx(-e / (-c * math.cos(phi + beta)), rel=1e-9, abs=1e-12)
        if beta < math.pi / 2 and phi + beta < math.pi:
            assert (float(gm.fence_tip_condition_4_3(beta, a, c, phi)) > 0.0) == right


@pytest.mark.parametrize("c", [0.3, 0.6, 1.0])
@pytest.mark.parametrize("phi", [D(40), D(75), D(84), D(88), D(100)])
def test_4_4_roots_are_the_crossings(c, phi):
    a = 1.0
    roots = gm.fence_transition_betas(a, c, phi, 0.0, math.pi / 2)
    t_m, t_p = gm.fence_transition_tan_4_4(a, c, phi)
    expected = [b for b in np.arctan([t_m, t_p]) if 0 < b and math.cos(phi + b) < 0] if not math.isnan(t_m) else []
    if not expected:
        assert roots.size == 0
        # No crossing: for phi < pi/2 the tip stays left of the sticking line (beyond the
        # wrapping angle), for phi > pi/2 right of it.
        b = np.linspace(max(0.01, math.pi / 2 - phi + 0.01), math.pi / 2 - 0.01, 50)
        assert np.all((gm.fence_tip_side(b, a, c, phi) > 0) == (phi < math.pi / 2))
        return
    assert np.allclose(roots, expected, atol=1e-13)
    for b in roots:
        assert gm.fence_tip_condition_4_3(b, a, c, phi) == pytest.approx(0.0, abs=1e-9)
        tip = world_tip(b, a, c, phi)
        assert tip[0] == pytest.approx(-c * math.cos(b), abs=1e-9)
    # Right of the sticking line (the CM's side) between the roots, left outside.
    lo, hi = roots
    assert gm.fence_tip_side(0.5 * (lo + hi), a, c, phi) < 0
    assert gm.fence_tip_side(hi + 1e-3, a, c, phi) > 0
    assert gm.fence_tip_side(lo - 1e-3, a, c, phi) > 0


@pytest.mark.parametrize("alpha,mu_c", EXAMPLES)
def test_book_example_transition_69_4_degrees(alpha, mu_c):
    """Lines 1855, 1890, 1906, 1923: the alpha + nu tip is right of the sticking line (the
    CM's side) at 45 degrees, crosses at 69.4 by (4.4) (the larger root) and is left of it
    up to 80; the alpha - nu tip stays left (or wrapped) throughout. So sticking-slowest
    45 -> 69.4, slipping-slowest 69.4 -> 80."""
    a, c = 1.0, example_c(alpha, mu_c)
    nu = math.atan(mu_c)
    t_m, t_p = gm.fence_transition_tan_4_4(a, c, alpha + nu)
    assert math.degrees(math.atan(t_p)) == pytest.approx(69.4, abs=1e-9)
    assert math.degrees(math.atan(t_m)) < 45.0
    assert gm.fence_transition_betas(a, c, alpha - nu, D(45), D(80)).size == 0
    bound = gm.fence_push_bound(a, c, alpha, D(45), D(80), mu_c)
    assert [p.regime for p in bound.pieces] == ["sticking", "slipping_down"]
    assert math.degrees(bound.transitions[0]) == pytest.approx(69.4, abs=1e-9)
    tip_p = world_tip(D(50), a, c, alpha + nu)
    assert tip_p[0] > -c * math.cos(D(50))
    tip_p = world_tip(D(75), a, c, alpha + nu)
    assert tip_p[0] < -c * math.cos(D(75))
    for b in (D(45), D(60), D(79)):
        tip_m = world_tip(b, a, c, alpha - nu)
        assert tip_m[0] < -c * math.cos(b)


@pytest.mark.parametrize("alpha,mu_c", EXAMPLES)
def test_book_example_slipping_piece_uses_the_plus_tip_not_minus(alpha, mu_c):
    """Line 1906 says the '-' sign of alpha +- nu is used from 69.4 to 80 degrees. After
    the transition both tips are left of the sticking line: the alpha - nu tip is in the
    down-slipping zone, where only {COR}_(alpha+nu) counts (4.1.3), so it is not a
    possible COR. The part of {COR}_(alpha-nu) right of the sticking line (the up-slipping
    locus, from the cor_disk boundary) turns the part faster than the alpha + nu tip, so
    the slowest COR is the '+' tip; the '-' tip gives a larger, unreachable bound."""
    a, c = 1.0, example_c(alpha, mu_c)
    nu = math.atan(mu_c)
    alpha_hat = np.array([math.cos(alpha), math.sin(alpha)])
    for beta in (D(72), D(76), D(79.5)):
        contact = gm.fence_contact(beta, c)
        scene = PushScene.create(a, contact, alpha - nu, 0.0)
        ring = disk_cor_locus(scene, outputs=("boundary",), n_points=4000).boundary
        up = ring[ring[:, 0] >= contact[0]]
        lever_up = float(np.max((contact - up) @ alpha_hat)) if up.size else -np.inf
        lever_plus = alpha_hat @ (contact - world_tip(beta, a, c, alpha + nu))
        lever_minus = alpha_hat @ (contact - world_tip(beta, a, c, alpha - nu))
        reg, lever, _ = gm.fence_slowest(beta, a, c, alpha, mu_c)
        assert gm.REGIMES[int(reg[0])] == "slipping_down"
        assert lever[0] == pytest.approx(lever_plus, rel=1e-12)
        assert lever_up < lever_plus < lever_minus


@pytest.mark.parametrize("alpha,mu_c", EXAMPLES)
def test_book_example_numbers(alpha, mu_c):
    """The composite bound for the example scenes, its pieces from (4.8) and (4.6), and
    what the printed (4.6) with the printed '-' sign would give instead."""
    a, c = 1.0, example_c(alpha, mu_c)
    bound = gm.fence_push_bound(a, c, alpha, D(45), D(80), mu_c)
    bt = D(69.4)
    stick = gm.fence_push_sticking_indefinite(bt, a, c) - gm.fence_push_sticking_indefinite(D(45), a, c)
    slip = (gm.fence_push_slipping_indefinite(D(80), a, c, alpha, mu_c, +1)
            - gm.fence_push_slipping_indefinite(bt, a, c, alpha, mu_c, +1))
    assert bound.pieces[0].push == pytest.approx(stick, rel=1e-10)
    assert bound.pieces[1].push == pytest.approx(slip, rel=1e-9)
    assert bound.total == pytest.approx(stick + slip, rel=1e-10)
    book = (gm.fence_push_slipping_indefinite_book_printed(D(80), a, c, alpha, mu_c, -1)
            - gm.fence_push_slipping_indefinite_book_printed(bt, a, c, alpha, mu_c, -1))
    assert book > slip  # the printed recipe is looser, not wrong-sided, here
    # Friction removes the frictionless worst case (the alpha tip is not in the sketch).
    assert bound.total < gm.fence_push_frictionless(a, c, alpha, D(45), D(80))
    if alpha == D(70):
        assert c == pytest.approx(0.5745897, abs=1e-7)
        assert stick == pytest.approx(1.1894959, abs=1e-6)
        assert slip == pytest.approx(0.4495524, abs=1e-6)
        assert book == pytest.approx(0.6022501, abs=1e-6)


# --- 4.3: the regimes' integrals --------------------------------------------------------


@pytest.mark.parametrize("sign", [1, -1])
@pytest.mark.parametrize("alpha,c,mu_c", [(D(70), 0.6, 0.25), (D(90), 0.9, 0.5), (D(60), 1.0, 0.1)])
def test_4_5_rate_is_the_lever_of_the_tilted_tip_and_4_6_integrates_it(sign, alpha, c, mu_c):
    a = 1.0
    nu = math.atan(mu_c)
    phi = alpha + sign * nu
    lo = max(0.05, math.pi / 2 - phi + 0.05, math.pi / 2 - alpha + 0.05)
    hi = math.pi - alpha - 0.05
    alpha_hat = np.array([math.cos(alpha), math.sin(alpha)])
    for beta in np.linspace(lo, hi, 4):
        tip = world_tip(beta, a, c, phi)
        lever = alpha_hat @ (gm.fence_contact(beta, c) - tip)
        assert gm.fence_rate_slipping(beta, a, c, alpha, mu_c, sign) == pytest.approx(lever / math.sin(alpha), rel=1e-11)
    q = gm.adaptive_quadrature(lambda b: gm.fence_rate_slipping(b, a, c, alpha, mu_c, sign), lo, hi, rtol=1e-12)
    f = gm.fence_push_slipping_indefinite
    assert f(hi, a, c, alpha, mu_c, sign) - f(lo, a, c, alpha, mu_c, sign) == pytest.approx(q.value, rel=1e-11)
    # The printed (4.6) is not an antiderivative of (4.5).
    g = gm.fence_push_slipping_indefinite_book_printed
    printed = g(hi, a, c, alpha, mu_c, sign) - g(lo, a, c, alpha, mu_c, sign)
    assert abs(printed - q.value) > 1e-3 * abs(q.value)


def test_4_6_reduces_to_3_41_at_mu_c_zero():
    a, c, alpha = 1.0, 0.7, D(75)
    b = np.linspace(D(30), D(95), 7)
    for sign in (1, -1):
        assert np.allclose(gm.fence_push_slipping_indefinite(b, a, c, alpha, 0.0, sign),
                           gm.fence_push_frictionless_indefinite(b, a, c, alpha), rtol=1e-14)
        assert np.allclose(gm.fence_push_slipping_indefinite_book_printed(b, a, c, alpha, 0.0, sign),
                           gm.fence_push_frictionless_indefinite(b, a, c, alpha), rtol=1e-14)


@pytest.mark.parametrize("alpha,c", [(D(70), 0.6), (D(90), 1.0), (D(110), 0.3)])
def test_4_7_point_b_and_4_8_against_quadrature(alpha, c):
    """B is the cor_disk tip line met by the sticking line; (4.7) is |c - B|, and the lever
    alpha . (c - B) = sin alpha |c - B|; (4.8) integrates (4.5) with it."""
    a = 1.0
    for beta in (D(30), D(60), D(85)):
        contact = gm.fence_contact(beta, c)
        scene = PushScene.create(a, contact, alpha, 0.0)
        line = disk_cor_locus(scene, outputs=("tip_line",)).tip_line
        b_pt = gm.fence_sticking_cor(beta, a, c)
        n_line = np.array([-line.direction[1], line.direction[0]])
        assert n_line @ (b_pt - line.point) == pytest.approx(0.0, abs=1e-12)  # on the tip line
        assert b_pt[0] == pytest.approx(contact[0], abs=1e-15)  # on the sticking line
        assert np.linalg.norm(contact - b_pt) == pytest.approx((c * c + a * a) / (c * math.sin(beta)), rel=1e-13)
        assert gm.fence_rate(beta, c, alpha, b_pt) == pytest.approx(gm.fence_rate_sticking(beta, a, c), rel=1e-12)
    q = gm.adaptive_quadrature(lambda b: gm.fence_rate_sticking(b, a, c), D(20), D(88), rtol=1e-12)
    f = gm.fence_push_sticking_indefinite
    assert f(D(88), a, c) - f(D(20), a, c) == pytest.approx(q.value, rel=1e-12)
    # (4.8) as printed, ((c^2 + a^2)/2c) log|(1 - cos)/(1 + cos)|.
    printed = (c * c + a * a) / (2 * c) * math.log((1 - math.cos(D(40))) / (1 + math.cos(D(40))))
    assert f(D(40), a, c) == pytest.approx(printed, rel=1e-13)


@pytest.mark.parametrize("alpha,c,mu_c", [(D(70), example_c(D(70), 0.25), 0.25), (D(90), 0.8, 0.3),
                                          (D(50), 0.9, 0.6), (D(120), 0.5, 0.2), (D(80), 1.0, 2.0)])
def test_composite_bound_equals_quadrature_of_the_pointwise_slowest_rate(alpha, c, mu_c):
    a = 1.0
    nu = math.atan(mu_c)
    bi = max(0.05, math.pi / 2 - alpha - nu + 0.05)
    bf = math.pi - alpha - 0.05
    bound = gm.fence_push_bound(a, c, alpha, bi, bf, mu_c)
    q = gm.adaptive_quadrature(lambda b: gm.fence_slowest(b, a, c, alpha, mu_c)[2], bi, bf, rtol=1e-12, max_intervals=20000)
    assert bound.total == pytest.approx(q.value, rel=1e-9)
    # The rate is continuous across every transition (a tip on the sticking line is B).
    for t in bound.transitions:
        r = gm.fence_slowest(np.array([t - 1e-9, t + 1e-9]), a, c, alpha, mu_c)[2]
        assert r[0] == pytest.approx(r[1], rel=1e-6)
    assert sum(p.push for p in bound.pieces) == pytest.approx(bound.total, rel=1e-14)


def test_composite_bound_tends_to_3_41_as_mu_c_vanishes():
    """mu_c -> 0: the sticking-slowest stretch (between the two tips' crossings) shrinks
    to nothing and both tilted tips become the tip of {COR}_alpha, so the bound tends to
    (3.41), as the book implies by writing (4.6) as (3.41) with alpha +- nu."""
    a, c, alpha = 1.0, example_c(D(70), 0.25), D(70)
    x0 = gm.fence_push_frictionless(a, c, alpha, D(45), D(80))
    errs = [abs(gm.fence_push_bound(a, c, alpha, D(45), D(80), mu).total - x0) for mu in (1e-2, 1e-4, 1e-6)]
    assert errs[1] < 0.02 * errs[0] and errs[2] < 1e-5
    assert gm.fence_push_bound(a, c, alpha, D(45), D(80), 0.0).total == x0


def test_fence_slowest_regimes_follow_the_sketches():
    """Sketch a-like (both tips right: the '-' tip), d/e-like (straddling: B), i-like (both
    left: the '+' tip); the chosen lever is never below any admissible candidate's."""
    a, c, alpha, mu_c = 1.0, 0.8, D(100), 0.1
    reg, lever, _ = gm.fence_slowest(D(30), a, c, alpha, mu_c)
    assert gm.REGIMES[int(reg[0])] == "slipping_up"  # phi > pi/2: tips on the CM's side
    a, c, alpha, mu_c = 1.0, example_c(D(70), 0.25), D(70), 0.25
    regs = gm.fence_slowest(np.radians([50, 75]), a, c, alpha, mu_c)[0]
    assert [gm.REGIMES[i] for i in regs] == ["sticking", "slipping_down"]


def test_integrate_fence_push_with_a_callback():
    a, c, alpha, mu_c = 1.0, 0.6, D(70), 0.25
    nu = math.atan(mu_c)
    q = gm.integrate_fence_push(lambda b: gm.fence_tip(b, a, c, alpha + nu), c, alpha, D(50), D(80))
    f = gm.fence_push_slipping_indefinite
    assert q.value == pytest.approx(f(D(80), a, c, alpha, mu_c, 1) - f(D(50), a, c, alpha, mu_c, 1), rel=1e-10)
    qv = gm.integrate_fence_push(lambda b: gm.fence_sticking_cor(b, a, c), c, alpha, D(50), D(80), vectorized=True)
    assert qv.value == pytest.approx(gm.fence_push_sticking_indefinite(D(80), a, c) - gm.fence_push_sticking_indefinite(D(50), a, c), rel=1e-10)


# --- 4.4: a disk pushed aside by a point -------------------------------------------------


def test_4_13_4_14_b_is_the_fence_b_with_c_equal_a():
    a = 1.3
    b = np.radians([10, 30, 60, 89])
    pts = gm.encounter_tip_line_cor(b, a)
    assert np.allclose(pts[:, 0], -a * np.cos(b))
    assert np.allclose(pts[:, 1], a * (np.sin(b) ** 2 - 2) / np.sin(b))
    assert np.allclose(pts[:, 0] / pts[:, 1], gm.encounter_tan_theta_min(b), rtol=1e-14)


def test_4_12_is_the_fence_rate_for_the_tangent_edge():
    """(4.2) with alpha = pi/2 - beta, c = a is dx/dxi (xi the disk's rotation; in 4.4 beta
    is not the rotation), so for any COR dx/dbeta (4.12) = dx/dxi (4.2) * dxi/dbeta (the
    re-derived rotation rate)."""
    a = 1.0
    rng = np.random.default_rng(4)
    for beta in (D(20), D(50), D(80)):
        alpha = math.pi / 2 - beta
        r = rng.normal(size=(20, 2)) * 2
        r[:, 0] = -np.abs(r[:, 0]) - 0.1
        lever_rate = gm.fence_rate(beta, a, alpha, r)  # = dx / dxi (rotation xi of the disk)
        assert np.allclose(gm.encounter_rate(beta, r[:, 0], r[:, 1], a),
                           lever_rate * gm.rotation_rate(beta, r[:, 0], r[:, 1], a), rtol=1e-12)


def test_4_15_re_derived_and_the_printed_form_differs():
    a = 2.0
    b = np.radians(np.linspace(5, 90, 18))
    t = gm.encounter_tan_theta_min(b)
    via_4_12 = a * (np.sin(b) + np.cos(b) / t)
    assert np.allclose(gm.encounter_rate_max(b, a), via_4_12, rtol=1e-13)
    assert np.allclose(gm.encounter_rate_max(b, a), 2 * a / np.sin(b), rtol=1e-15)
    assert not np.allclose(gm.encounter_rate_max_book_printed(b, a), via_4_12, rtol=1e-2)


@pytest.mark.parametrize("beta_i", [D(5), D(30), D(60), D(89)])
def test_4_16_against_integrating_4_12_with_4_14(beta_i):
    a = 1.7
    q = gm.integrate_encounter_length(lambda b: gm.encounter_tip_line_cor(b, a), a, beta_i, vectorized=True, rtol=1e-12)
    assert gm.encounter_length_max(beta_i, a) == pytest.approx(q.value, rel=1e-11)
    printed = -a * math.log((1 - math.cos(beta_i)) / (1 + math.cos(beta_i)))  # (4.16) at pi/2 minus at beta_i
    assert gm.encounter_length_max(beta_i, a) == pytest.approx(printed, rel=1e-12)
    assert gm.encounter_length_max_indefinite(math.pi / 2, a) == pytest.approx(0.0, abs=1e-15)


def test_4_16_near_pi_over_2_and_frictionless_length_is_half():
    a = 1.0
    for eps in (1e-2, 1e-4, 1e-6):
        x = gm.encounter_length_max(math.pi / 2 - eps, a)
        assert x == pytest.approx(2 * a * eps, rel=eps)  # rate -> 2a at beta = pi/2
        assert gm.encounter_length_frictionless(math.pi / 2 - eps, a) == pytest.approx(a * eps, rel=eps)
    for bi in (D(10), D(45)):
        assert gm.encounter_length_frictionless(bi, a) == pytest.approx(0.5 * gm.encounter_length_max(bi, a), rel=1e-13)
        # With mu_c = 0 the CM moves along the normal, theta = beta: a COR far along -n_perp.
        far = lambda b: 1e8 * np.array([-np.sin(b), -np.cos(b)]).T
        q = gm.integrate_encounter_length(far, a, bi, vectorized=True)
        assert q.value == pytest.approx(gm.encounter_length_frictionless(bi, a), rel=1e-7)


@pytest.mark.parametrize("mu_c", [0.05, 0.25, 0.5, 2.0])
def test_4_17_against_the_tip_side_and_cor_disk(mu_c):
    """Sketch i (the alpha + nu tip left of the sticking line) iff tan beta > 2 mu_c, from
    E with c = a, phi = pi/2 - beta + nu and from the cor_disk tip of a tangent edge."""
    a = 1.0
    nu = math.atan(mu_c)
    onset = gm.sketch_i_onset(mu_c)
    for beta in (onset - 0.05, onset + 0.05):
        if not 0 < beta < math.pi / 2:
            continue
        phi = math.pi / 2 - beta + nu
        left = gm.fence_tip_side(beta, a, a, phi) > 0
        assert bool(gm.sketch_i(beta, mu_c)) == bool(left) == (beta > onset)
        tip = world_tip(beta, a, a, phi)
        assert (tip[0] < -a * math.cos(beta)) == (beta > onset)
    assert gm.fence_tip_side(onset, a, a, math.pi / 2 - onset + nu) == pytest.approx(0.0, abs=1e-12)


def test_4_18_and_the_rotation_rate():
    """Sticking-line CORs roll the disk: dxi/dbeta = 1 and xi = pi/2 - beta_i; CORs left
    of the sticking line turn it less; the printed (4.22) agrees only on the line."""
    a = 1.0
    for bi in (D(10), D(45), D(80)):
        assert gm.rotation_max(bi) == pytest.approx(math.pi / 2 - bi)
        on_line = lambda b: np.array([-a * math.cos(b), -3.0])
        q = gm.integrate_rotation(on_line, a, bi)
        assert q.value == pytest.approx(math.pi / 2 - bi, rel=1e-12)
        qb = gm.integrate_rotation(on_line, a, bi, book_printed=True)
        assert qb.value == pytest.approx(math.pi / 2 - bi, rel=1e-12)
    b = D(45)
    x, y = -2.0, -1.0  # left of the sticking line: down-slipping
    assert 0 < gm.rotation_rate(b, x, y, a) < 1
    assert gm.rotation_rate(b, x, y, a) == pytest.approx(a * math.cos(b) / 2.0)
    assert gm.rotation_rate_book_printed(b, x, y, a) != pytest.approx(gm.rotation_rate(b, x, y, a), rel=1e-3)
    # Contours of constant rate are vertical lines (independent of y).
    assert gm.rotation_rate(b, x, -7.0, a) == gm.rotation_rate(b, x, 3.0, a)


def test_integrators_refuse_bad_input_and_report_non_finite_integrands():
    with pytest.raises(InvalidInput):
        gm.encounter_length_max(D(95), 1.0)
    with pytest.raises(InvalidInput):
        gm.integrate_encounter_length(lambda b: (0.0, -1.0), 1.0, D(30))  # x_COR = 0
    with pytest.raises(InvalidInput):
        gm.fence_push_bound(1.0, 0.5, D(70), D(45), D(80), -0.1)
