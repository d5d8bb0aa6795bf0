"""The exact sticking locus along the sticking line (solver/sketch/sticking_locus.py; book
4.1.4, 3.3.11.1, 6.3) against independent checks: forward minimum-power solves with pusher
friction (4.1; their sticking CORs), a brute-force sweep of force angles over the analytic
frictionless disk loci (the book's own definition of the sticking locus, 4.1.4),
frictionless membership (mu_c -> 0, and far loci ~185 L away), polygons inside their disks
(7.5), symmetries, the search range, the time limit, and the geometry of the book's
sticking-locus experiment (6.3)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.mpp import perp
from models.core.scene import PushScene
from models.core.support import random_balanced_tripods
from models.locus import cor_disk as cd
from solver.core.budget import Budget
from solver.locus.membership import membership
from solver.motion.forward import solve_forward_batch
from solver.sketch import sticking_locus as stl
from solver.sketch.sticking import sticking_feasibility, sticking_point
from solver.sketch.sticking_locus import sticking_locus, sticking_search_range
from tests.budgets import checks_budget
from tests.scenes import SEED, point_in_polygon, scene_for_mu
from tests.solver.sketch.sticking_checks import (
    L_SHAPE,
    NEAR_SCENES,
    SQUARE,
    TOL,
    U_SHAPE,
    check_witness,
    grid_lp,
    inside_some_interval,
    near_scene,
    polygon_grid,
    positions,
    sweep_union,
    transformed,
    u_scene,
)

# --- the derivation (4.1.2, 4.1.4, ch. 2) --------------------------------------------------


@pytest.mark.slow
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


@pytest.mark.slow
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


@pytest.mark.slow
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


@pytest.mark.slow
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


@pytest.mark.slow
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


@pytest.mark.slow
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


@pytest.mark.slow
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


@pytest.mark.slow
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


@pytest.mark.slow
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


@pytest.mark.slow
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


@pytest.mark.slow
def test_a_translation_along_the_push_sticks_and_is_reported():
    """CM on the push line through c and p in the cone: a pure translation sticks (COR at
    infinity); the finite sticking locus is empty here (every {COR}_phi reaches the line
    x = c_x only at the contact point)."""
    sc = PushScene.create(1.0, [-1.0, 0.0], math.pi / 2 + 0.2, 0.0)
    loc = sticking_locus(sc, 0.5, scan_points=32, seed_tripods=64, seed=SEED)
    assert loc.translation_sticks and loc.search_bound.startswith("cap")
    assert loc.status == "empty" and "translation" in loc.message
    assert not sticking_locus(sc, 0.1, scan_points=16, seed_tripods=0).translation_sticks


@pytest.mark.slow
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


@pytest.mark.slow
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


def test_time_limit_stops_the_locus():
    sc, mu_c = near_scene("near_translation")
    budget = checks_budget(20)
    loc = sticking_locus(sc, mu_c, budget=budget, seed_tripods=0)
    assert loc.time_limited and not loc.complete and loc.status in ("incomplete", "found", "empty")
    assert loc.n_queries < 20  # one budget check (at least) per query
    res = sticking_feasibility(sc, sticking_point(sc, -3.0), mu_c, budget=Budget.of(0.0))
    assert res.status == "undecided"


@pytest.mark.slow
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


@pytest.mark.slow
def test_agrees_with_the_cor_sketch_force_angle_sweep():
    """models/sketch/disk_sketch.py computes the sticking locus of a disk by the book's construction
    (a sweep of force angles over the analytic loci, refined by golden section): the ends
    agree to its boundary resolution (1024-point polygons). Where the sweep reaches beyond a
    certified end (contact_inside: 3.8e-6 a, a chord across a concave stretch of the locus
    boundary), frictionless membership at the sweep's own force angle certifies the sweep's
    point outside, and a 65536-point boundary moves the crossing back inside the bracket."""
    from models.sketch.disk_sketch import force_scene, sticking_locus_sweep

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


@pytest.mark.slow
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


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(4))
def test_book_6_3_ends_are_certified_whatever_the_seed(seed):
    """Issue 26: whether the 6.3 lower end was certified hung on the seed of the feasible
    tripods (their witness points warm the columns): with seed 0 the master stalled at a
    residual of 1.16e-6 just inside the end. Both ends are certified for every seed."""
    a, al = 1.25, math.radians(70)
    sc = PushScene.create(a, [-a * math.sin(al), a * math.cos(al)], al, 0.0)
    loc = sticking_locus(sc, 0.5, seed=seed)
    for end in (loc.lower, loc.upper):
        assert end.status == "bracketed" and end.certified
        check_witness(sc, end.feasible, 0.5)
    assert -5.53 < loc.lower.point[1] / a < -5.52


# --- the lowest end alone (what r*(beta) of 4.5.3 needs) -----------------------------------


@pytest.mark.parametrize("name", ["6.3", "u_shape"])
def test_the_lowest_end_alone_is_the_whole_locus_lower_end(name):
    """ends="lowest" (4.5.3 uses only the lower end): the scan stops at the first feasible
    probe below the contact and only that run's lower end is bracketed, from the same pair
    of probes as the whole locus, so the certified end is the same to the last digit, in
    a fraction of the queries. The U shape has two intervals below the contact: the lowest
    one's end is found."""
    if name == "6.3":
        a, al = 1.25, math.radians(70)
        sc, mu_c, fp = PushScene.create(a, [-a * math.sin(al), a * math.cos(al)], al, 0.0), 0.5, None
    else:
        (sc, mu_c), fp = u_scene(), U_SHAPE
    whole = sticking_locus(sc, mu_c, footprint=fp, seed=SEED)
    low = sticking_locus(sc, mu_c, footprint=fp, seed=SEED, ends="lowest")
    assert whole.lower.position < 0.0
    assert low.status == "found" and low.complete and low.intervals == () and low.upper is None
    assert "lowest end only" in low.message
    end = low.lower
    assert end.status == "bracketed" and end.certified
    assert end.feasible_position == whole.lower.feasible_position
    assert end.infeasible_position == whole.lower.infeasible_position
    check_witness(sc, end.feasible, mu_c)
    assert low.n_queries < 0.5 * whole.n_queries


def test_the_lowest_end_above_the_contact_falls_back_to_the_whole_locus():
    """The book's 6.3 scene mirrored: the locus lies above the contact (s > 0), no probe
    below it is feasible, and ends="lowest" scans the rest of the line and returns the whole
    locus, as ends="all" does."""
    a, al = 1.25, math.radians(70)
    sc = PushScene.create(a, [-a * math.sin(al), -a * math.cos(al)], -al, 0.0)
    whole = sticking_locus(sc, 0.5, seed=SEED)
    low = sticking_locus(sc, 0.5, seed=SEED, ends="lowest")
    assert whole.lower.position > 0.0 and len(low.intervals) == len(whole.intervals) == 1
    assert low.lower.position == whole.lower.position and low.upper.position == whole.upper.position
    assert low.n_queries == whole.n_queries
    with pytest.raises(InvalidInput, match="ends"):
        sticking_locus(sc, 0.5, ends="upper")
