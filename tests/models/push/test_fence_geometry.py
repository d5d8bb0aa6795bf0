"""The fence-alignment geometry of book 3.4/4.3 from a world-frame scene
(models/push/fence_geometry.py): hand-computed cases, invariance under translation, rotation
and scale, mirror consistency, the chain of stages past an unstable flush edge, the
book's pictures (figures 3-1, 3-20, 3-21; the 4.3 example), and the offset of (4.24).
Book text references are line numbers of /work/shared/seed/000_11c73ac4ccaabe12.txt."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.push import gross_motion as gm
from models.push.fence_geometry import (
    convex_hull_indices,
    encounter_beta_from_offset,
    fence_alignment,
    fence_frame_alpha,
    frictionless_push_bounds,
    require_friction_frame,
)

D = math.radians
SQUARE = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
SQRT2 = math.sqrt(2.0)


def rot(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s], [s, c]])


def stage_summary(al):
    return [(s.contact_index, s.flush_index, s.contact_distance, s.beta_initial, s.beta_final,
             s.vertex_edge_angle, s.rotation) for s in al.stages]


def assert_alignment_close(a1, a2, length_scale: float = 1.0, tol: float = 1e-9):
    assert a1.disk_radius * length_scale == pytest.approx(a2.disk_radius, rel=tol)
    assert a1.alpha == pytest.approx(a2.alpha, abs=tol)
    assert len(a1.stages) == len(a2.stages)
    for s1, s2 in zip(a1.stages, a2.stages):
        assert (s1.contact_index, s1.flush_index) == (s2.contact_index, s2.flush_index)
        assert s1.contact_distance * length_scale == pytest.approx(s2.contact_distance, rel=tol)
        for name in ("beta_initial", "beta_final", "vertex_edge_angle", "rotation"):
            assert getattr(s1, name) == pytest.approx(getattr(s2, name), abs=tol), name
        assert s1.flush_edge_stable == s2.flush_edge_stable


# --- hand-computed cases ----------------------------------------------------------------


def test_square_at_30_degrees_against_a_fence_perpendicular_to_the_push():
    """Square of half-side 1 turned 30 deg CCW, a vertical fence (alpha = 90 deg) moving
    along +x. Its corners sit at 75, 165, 255, 345 deg on the circle of radius sqrt 2; the
    one at 165 deg (vertex 3, [-1, 1]) is farthest back: c = a = sqrt 2, beta = 180 - 165 =
    15 deg, above the CM, so the part turns clockwise. The edge to [-1, -1] (psi = 45 deg,
    the half right angle between the diagonal and the side) comes flush at
    beta_final = 180 - 90 - 45 = 45 deg: a 30 deg turn back to orientation 0."""
    al = fence_alignment(Footprint.create(SQUARE), D(30), D(90), 0.0)
    assert (al.sense, al.mirrored, al.initial_flush_edge, al.already_flush) == ("cw", False, None, False)
    assert al.alpha == pytest.approx(D(90), abs=1e-15)
    (st,) = al.stages
    assert (st.contact_index, st.flush_index, st.flush_is_polygon_edge, st.flush_edge_stable) == (3, 0, True, True)
    assert st.contact_distance == pytest.approx(SQRT2, rel=1e-15) and al.disk_radius == pytest.approx(SQRT2)
    assert st.beta_initial == pytest.approx(D(15), abs=1e-14)
    assert st.vertex_edge_angle == pytest.approx(D(45), abs=1e-14)
    assert st.beta_final == pytest.approx(D(45), abs=1e-14)
    assert st.rotation == pytest.approx(D(30), abs=1e-14) == al.total_rotation
    assert al.final_orientation == pytest.approx(0.0, abs=1e-14)
    assert al.first_contact_index == 3
    assert al.first_contact_point == pytest.approx(SQRT2 * np.array([math.cos(D(165)), math.sin(D(165))]), abs=1e-14)
    assert st.contact_fence_frame == pytest.approx(SQRT2 * np.array([-math.cos(D(15)), math.sin(D(15))]), abs=1e-14)
    assert al.fence_normal == pytest.approx([1.0, 0.0], abs=1e-15)
    assert al.final_edge == (3, 0)


def test_the_misoriented_rectangle_of_figure_3_1():
    """Line 1666: a misoriented rectangle pushed by a fence moving perpendicular to its
    face "will rotate CW as the fence advances and will cease to rotate when the edge of the
    rectangle comes into contact with the front edge of the fence". A 4 x 2 rectangle
    turned 20 deg CCW: the corner [-2, 1] leads (c = sqrt 5 = a), the short side comes
    flush: psi = atan 2, beta_final = 90 - psi = atan(1/2), beta_initial = beta_final - 20."""
    rect = [[-2.0, -1.0], [2.0, -1.0], [2.0, 1.0], [-2.0, 1.0]]
    al = fence_alignment(Footprint.create(rect), D(20), D(90), 0.0)
    (st,) = al.stages
    assert al.sense == "cw" and (st.contact_index, st.flush_index) == (3, 0)
    assert st.contact_distance == pytest.approx(math.sqrt(5.0)) == al.disk_radius
    assert st.vertex_edge_angle == pytest.approx(math.atan(2.0), abs=1e-14)
    assert st.beta_final == pytest.approx(math.atan(0.5), abs=1e-14)
    assert st.beta_initial == pytest.approx(math.atan(0.5) - D(20), abs=1e-14)
    assert al.final_orientation == pytest.approx(0.0, abs=1e-14)


def test_figure_3_20_the_contact_need_not_be_on_the_disk_and_beta_is_the_angle_of_the_cm():
    """Line 1682: "we circumscribe a disk of radius a about the workpiece ... centered at
    the CM ... the contact point need not be on the perimeter of the circumscribed disk";
    line 1686: beta is "the angle of the CM from the direction of motion of the pusher".
    A quadrilateral whose first vertex is inside its circumscribing disk; the fence moves
    horizontally (+x) with its face at 70 deg, and the workpiece turns clockwise (line
    1684) into the configuration of figure 3-21, its edge flush with the fence."""
    quad = [[-0.3, 0.5], [-0.1, -0.6], [1.2, -0.2], [0.6, 0.9]]
    fp = Footprint.create(quad, center_of_mass=[0.2, 0.1])
    al = fence_alignment(fp, 0.0, D(70), 0.0)
    (st,) = al.stages
    assert al.sense == "cw" and not al.mirrored and st.contact_index == 0
    assert st.contact_distance < al.disk_radius
    to_cm = fp.center_of_mass - np.array(quad[0])  # from the contact to the CM
    assert -math.atan2(to_cm[1], to_cm[0]) == pytest.approx(st.beta_initial, abs=1e-14)
    # The flush edge (contact -> vertex 1) points along -alpha_hat at the end (figure 3-21).
    edge = rot(st.orientation_final) @ (np.array(quad[1]) - np.array(quad[0]))
    assert edge / np.linalg.norm(edge) == pytest.approx(-np.array([math.cos(D(70)), math.sin(D(70))]), abs=1e-12)


def book_example_footprint():
    """A quadrilateral with the geometry of the 4.3 example (models/push/gross_motion.py,
    reconstructed; c = 0.5746 a as in tests/models/push/test_gross_bounds.py): CM at the origin,
    a = 1, the contact at c with beta = 45 deg, the edge leaving it clockwise at psi = 30
    deg, so that with alpha = 70 deg beta_final = 180 - 70 - 30 = 80 deg."""
    c = 0.5746
    v = c * np.array([-math.cos(D(45)), math.sin(D(45))])
    w = v + np.array([math.cos(D(-75)), math.sin(D(-75))])
    return Footprint.create([v, w, [1.0, 0.0], [0.3, 0.8]], center_of_mass=[0.0, 0.0]), c


def test_book_example_4_3_from_a_footprint():
    """Lines 1855-1923: alpha = 70 deg, beta from 45 to 80 deg, mu_c = 0.25, transition at
    69.4 deg; the composite closed form is 1.63903 a."""
    fp, c = book_example_footprint()
    al = fence_alignment(fp, 0.0, D(70), 0.0)
    (st,) = al.stages
    assert al.disk_radius == pytest.approx(1.0, rel=1e-15)
    assert st.contact_distance == pytest.approx(c, rel=1e-14)
    assert al.alpha == pytest.approx(D(70), abs=1e-14)
    assert st.beta_initial == pytest.approx(D(45), abs=1e-14)
    assert st.beta_final == pytest.approx(D(80), abs=1e-13)
    assert st.flush_edge_stable and al.sense == "cw"
    bound = gm.fence_push_bound(al.disk_radius, st.contact_distance, al.alpha, st.beta_initial, st.beta_final, 0.25)
    assert bound.total == pytest.approx(1.63903, abs=1e-5)
    assert math.degrees(bound.transitions[0]) == pytest.approx(69.4, abs=1e-2)


def test_oblique_fence_below_the_line_of_motion():
    """The square at 30 deg against a fence at 70 deg: the leading corner (165 deg) has
    alpha_hat . c = -sqrt2 cos 85 deg < 0, so the part turns counter-clockwise, to
    orientation 70 deg (a side along the fence). Reflected: alpha = 110 deg, beta_initial =
    -15 deg (the contact below the line of motion), psi = 45, beta_final = 25 deg. The
    frictionless bounds hold there; with friction the stage is refused."""
    al = fence_alignment(Footprint.create(SQUARE), D(30), D(70), 0.0)
    (st,) = al.stages
    assert (al.sense, al.mirrored) == ("ccw", True)
    assert al.alpha_unmirrored == pytest.approx(D(70), abs=1e-14) and al.alpha == pytest.approx(D(110), abs=1e-14)
    assert st.contact_index == 3 and st.flush_index == 2
    assert st.beta_initial == pytest.approx(D(-15), abs=1e-14)
    assert st.beta_final == pytest.approx(D(25), abs=1e-14)
    assert al.final_orientation == pytest.approx(D(70), abs=1e-14)
    longest, shortest = frictionless_push_bounds(al.disk_radius, st.contact_distance, al.alpha, st.beta_initial, st.beta_final)
    f, g = gm.fence_push_frictionless_indefinite, gm.fence_push_least_frictionless_indefinite
    args = (al.disk_radius, st.contact_distance, al.alpha)
    assert longest == float(f(st.beta_final, *args) - f(st.beta_initial, *args))
    assert shortest == float(g(st.beta_final, *args) - g(st.beta_initial, *args))
    assert 0.0 < shortest < longest
    with pytest.raises(InvalidInput):  # models.push.gross_motion's range check refuses beta <= 0
        gm.fence_push_frictionless(*args, st.beta_initial, st.beta_final)
    require_friction_frame(al, 0.0)
    with pytest.raises(InvalidInput) as err:
        require_friction_frame(al, 0.25)
    assert err.value.field == "orientation" and "(4.7)" in err.value.reason


def test_frictionless_bounds_are_the_book_forms_above_the_line_of_motion():
    fp, _ = book_example_footprint()
    al = fence_alignment(fp, 0.0, D(70), 0.0)
    (st,) = al.stages
    args = (al.disk_radius, st.contact_distance, al.alpha, st.beta_initial, st.beta_final)
    assert frictionless_push_bounds(*args) == (gm.fence_push_frictionless(*args), gm.fence_push_least_frictionless(*args))
    with pytest.raises(InvalidInput):
        frictionless_push_bounds(1.0, 0.5, D(70), D(50), D(40))
    with pytest.raises(InvalidInput):
        frictionless_push_bounds(1.0, 0.5, D(70), D(10), D(40))  # alpha + beta < pi/2
    with pytest.raises(InvalidInput):
        frictionless_push_bounds(1.0, 1.5, D(70), D(30), D(40))  # c > a


# --- flush edges and stages -------------------------------------------------------------


@pytest.mark.parametrize("orientation", [0.0, D(90), D(-180)])
def test_an_edge_already_flush_and_stable_needs_no_push(orientation):
    al = fence_alignment(Footprint.create(SQUARE), orientation, D(90), 0.0)
    assert al.already_flush and al.sense == "none" and al.stages == ()
    assert al.total_rotation == 0.0 and al.final_orientation == orientation
    assert al.initial_flush_edge == al.final_edge and al.first_contact_index in al.final_edge


def test_an_unstable_flush_edge_turns_about_its_end():
    """Triangle [0,0], [1,0], [5,1] (CM [2, 1/3]) resting on its short base against a fence
    pushing along +y: the CM's foot (x = 2) is off the base [0, 1], so a frictionless fence
    turns it clockwise about [1, 0] until the long side (slope 1/4) lies flush, where the
    foot (parameter 13/51) is inside: stable."""
    tri = Footprint.create([[0, 0], [1, 0], [5, 1]])
    al = fence_alignment(tri, 0.0, 0.0, D(90))
    assert al.initial_flush_edge == (1, 0) and not al.already_flush
    (st,) = al.stages
    assert (al.sense, st.contact_index, st.flush_index, st.flush_edge_stable) == ("cw", 1, 2, True)
    assert st.rotation == pytest.approx(math.atan(0.25), abs=1e-14)
    assert al.first_contact_index == 1 and al.first_contact_point == pytest.approx([1.0, 0.0], abs=1e-15)


def test_a_chain_of_two_stages():
    """The same triangle turned 5 deg counter-clockwise: the fence meets [0, 0] first,
    turns the part 5 deg until the short base is flush - unstable - and then atan(1/4)
    about [1, 0]."""
    tri = Footprint.create([[0, 0], [1, 0], [5, 1]])
    al = fence_alignment(tri, D(5), 0.0, D(90))
    s1, s2 = al.stages
    assert (s1.contact_index, s1.flush_index, s1.flush_edge_stable) == (0, 1, False)
    assert (s2.contact_index, s2.flush_index, s2.flush_edge_stable) == (1, 2, True)
    assert s1.rotation == pytest.approx(D(5), abs=1e-14)
    assert s2.rotation == pytest.approx(math.atan(0.25), abs=1e-14)
    assert s2.orientation_initial == s1.orientation_final
    assert al.total_rotation == pytest.approx(D(5) + math.atan(0.25), abs=1e-14)
    assert al.final_orientation == pytest.approx(-math.atan(0.25), abs=1e-14)
    assert al.final_edge == (1, 2)


def test_a_bridge_over_a_concavity_is_the_flush_edge():
    """A U open at the top, pushed down by a horizontal fence: the top of its hull spans
    the notch, a bridge, not an edge of the polygon."""
    u = [[0, 0], [4, 0], [4, 3], [3, 3], [3, 1], [1, 1], [1, 3], [0, 3]]
    fp = Footprint.create(u)
    al = fence_alignment(fp, D(10), 0.0, D(-90))
    assert al.stages and al.final_edge in ((2, 7), (7, 2))
    assert not al.stages[-1].flush_is_polygon_edge
    al2 = fence_alignment(fp, D(10), 0.0, D(90))  # from below: the base, a polygon edge
    assert al2.stages[-1].flush_is_polygon_edge


def _random_polygon(rng, n):
    ang = np.sort(rng.uniform(0, 2 * np.pi, n))
    r = rng.uniform(0.4, 1.0, n)
    return np.column_stack([r * np.cos(ang), r * np.sin(ang)]) + rng.uniform(-3, 3, 2)


def test_every_stage_ends_flush_on_the_support_line_and_the_last_is_stable():
    """Random star-shaped polygons, orientations, fences and pushes: at the start of each
    stage the contact vertex is the hull vertex farthest back along the fence normal; at
    its end the flush edge is parallel to the fence and on the support line; the last
    flush edge holds the CM's foot; the turns add up to the change of orientation."""
    rng = np.random.default_rng(7)
    checked = 0
    for _ in range(200):
        theta, fence, push = rng.uniform(-np.pi, np.pi, 3)
        try:
            fp = Footprint.create(_random_polygon(rng, int(rng.integers(3, 9))))
            al = fence_alignment(fp, theta, fence, push)
        except InvalidInput:
            continue
        n = al.fence_normal
        rel = fp.vertices - fp.center_of_mass
        for st in al.stages:
            depth0 = (rel @ rot(st.orientation_initial).T) @ n
            assert depth0[st.contact_index] == pytest.approx(depth0.min(), abs=1e-12)
            depth1 = (rel @ rot(st.orientation_final).T) @ n
            assert depth1[st.contact_index] == pytest.approx(depth1.min(), abs=1e-9)
            assert depth1[st.flush_index] == pytest.approx(depth1.min(), abs=1e-9)
            assert st.rotation >= 0.0
            assert st.beta_final == pytest.approx(gm.fence_final_beta(al.alpha, st.vertex_edge_angle), abs=0)
        if al.stages:
            last = al.stages[-1]
            end = rel @ rot(al.final_orientation).T
            p, q = end[last.contact_index], end[last.flush_index]
            t = float(-p @ (q - p)) / float((q - p) @ (q - p))
            assert -1e-9 <= t <= 1 + 1e-9  # the CM's foot lies on the flush edge
            sign = 1.0 if al.mirrored else -1.0
            assert al.final_orientation - theta == pytest.approx(sign * al.total_rotation, abs=1e-12)
            checked += 1
    assert checked > 150


# --- invariance and mirror consistency --------------------------------------------------


L_SHAPE = [[0, 0], [3, 0], [3, 1], [1, 1], [1, 2.5], [0, 2.5]]
CASES = [(L_SHAPE, D(25), D(80), D(5)), (SQUARE, D(30), D(90), 0.0), (L_SHAPE, D(-40), D(100), D(170))]


@pytest.mark.parametrize("poly, theta, fence, push", CASES)
def test_translation_rotation_and_scale_invariance(poly, theta, fence, push):
    base = fence_alignment(Footprint.create(poly), theta, fence, push)
    moved = fence_alignment(Footprint.create(np.array(poly) + [123.0, -45.6]), theta, fence, push)
    assert_alignment_close(base, moved)
    scaled = fence_alignment(Footprint.create(np.array(poly) * 7.5), theta, fence, push)
    assert_alignment_close(base, scaled, length_scale=7.5)
    tiny = fence_alignment(Footprint.create(np.array(poly) * 1e-80), theta, fence, push)
    assert_alignment_close(base, tiny, length_scale=1e-80)
    gamma = D(37)  # turn the whole scene
    turned = fence_alignment(Footprint.create(np.array(poly) @ rot(gamma).T), theta, fence + gamma, push + gamma)
    assert_alignment_close(base, turned)
    # The footprint given pre-turned, or turned by the orientation: the same problem.
    fp = Footprint.create(poly)
    pre = fp.center_of_mass + (np.array(poly) - fp.center_of_mass) @ rot(gamma).T
    assert_alignment_close(base, fence_alignment(Footprint.create(pre), theta - gamma, fence, push))
    # theta + pi for the fence is the same fence.
    assert_alignment_close(base, fence_alignment(Footprint.create(poly), theta, fence + math.pi, push))


@pytest.mark.parametrize("poly, theta, fence, push", CASES)
def test_mirror_image_turns_the_other_way_with_the_same_numbers(poly, theta, fence, push):
    """Reflect the whole scene across the x axis: y -> -y for the vertices, angles negated.
    The problem is the same up to the sense; the reflection inside fence_alignment undoes
    it."""
    base = fence_alignment(Footprint.create(poly), theta, fence, push)
    mirror_poly = np.array(poly) * [1.0, -1.0]
    mirrored = fence_alignment(Footprint.create(mirror_poly), -theta, -fence, -push)
    assert mirrored.mirrored != base.mirrored
    assert {base.sense, mirrored.sense} == {"cw", "ccw"}
    assert base.alpha == pytest.approx(mirrored.alpha, abs=1e-12)
    assert base.alpha_unmirrored == pytest.approx(math.pi - mirrored.alpha_unmirrored, abs=1e-12)
    # Footprint.create reverses the reflected (clockwise) outline: index i <-> n-1-i.
    n = len(poly)
    assert len(base.stages) == len(mirrored.stages)
    for s1, s2 in zip(base.stages, mirrored.stages):
        assert s2.contact_index == n - 1 - s1.contact_index and s2.flush_index == n - 1 - s1.flush_index
        for name in ("contact_distance", "beta_initial", "beta_final", "vertex_edge_angle", "rotation"):
            assert getattr(s1, name) == pytest.approx(getattr(s2, name), abs=1e-12)
    assert base.final_orientation == pytest.approx(-mirrored.final_orientation, abs=1e-12)


def test_square_at_minus_30_degrees_is_the_mirror_case():
    al = fence_alignment(Footprint.create(SQUARE), D(-30), D(90), 0.0)
    (st,) = al.stages
    assert (al.sense, al.mirrored, st.contact_index, st.flush_index) == ("ccw", True, 0, 3)
    assert (st.beta_initial, st.beta_final) == pytest.approx((D(15), D(45)), abs=1e-14)
    assert al.final_orientation == pytest.approx(0.0, abs=1e-14)


# --- refusals and helpers ---------------------------------------------------------------


def test_refusals_name_the_field():
    sq = Footprint.create(SQUARE)
    with pytest.raises(InvalidInput) as err:
        fence_alignment(sq, D(30), D(10), D(10))  # fence along the push
    assert err.value.field == "fence_angle"
    with pytest.raises(InvalidInput) as err:
        fence_alignment(sq, D(45), D(90), 0.0)  # a diagonal on the line of motion: translation
    assert err.value.field == "orientation" and "3.3.11.1" in err.value.reason
    with pytest.raises(InvalidInput) as err:
        fence_alignment(sq, math.nan, D(90), 0.0)
    assert err.value.field == "orientation"


def test_fence_frame_alpha_is_that_of_push_scene():
    from models.core.scene import PushScene

    for fence, push in ((0.3, 1.2), (2.0, -0.5), (-1.0, 3.0)):
        alpha, n = fence_frame_alpha(fence, push)
        scene = PushScene.create(1.0, [0.1, 0.2], fence, push)
        assert alpha == pytest.approx(scene.book_alpha, abs=1e-15)
        assert n == pytest.approx(scene.normal, abs=1e-15)


def test_convex_hull_drops_interior_and_collinear_points():
    pts = np.array([[0, 0], [1, 0], [2, 0], [2, 2], [1, 1], [0, 2]], dtype=float)
    hull = convex_hull_indices(pts)
    assert sorted(hull) == [0, 2, 3, 5]
    x, y = pts[hull].T
    assert np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) > 0  # counter-clockwise


# --- (4.24): the offset of the disk encounter --------------------------------------------


def test_offset_4_24():
    for a, d in ((1.0, 0.5), (3.0, 0.1), (2.0, 1.9)):
        beta = encounter_beta_from_offset(a, d)
        assert 0 < beta < math.pi / 2
        assert a * (1.0 - math.sin(beta)) == pytest.approx(d, rel=1e-13)
    assert encounter_beta_from_offset(1.0, 0.5) == pytest.approx(D(30), abs=1e-15)
    # A tiny offset keeps its digits: pi/2 - beta = sqrt(2 d / a) (1 + d/(12 a) + ...).
    assert math.pi / 2 - encounter_beta_from_offset(1.0, 1e-20) == pytest.approx(math.sqrt(2e-20), rel=1e-12)
    for d in (0.0, 1.0, -0.1, 2.0):
        with pytest.raises(InvalidInput) as err:
            encounter_beta_from_offset(1.0, d)
        assert err.value.field == "offset"


def test_a_nearly_collinear_contact_vertex_survives_the_mirror_image():
    """3.4: a counter-clockwise turn is reflected onto the book's clockwise case; the hull
    must be the mirror image of the same hull. Recomputed, a vertex nearly collinear at
    the 1e9 scale of its neighbours (the contact here) was dropped, and the alignment
    failed with a ValueError (found by the live contract test)."""
    fp = Footprint.create([[1000.0, -2.4e-107], [979553195.7, -1.2e-263], [1.02, 1.1], [9.9e-80, 1.5e-180],
                           [0.0, -121343364.5], [-5.1e-160, -705681225.4]])
    al = fence_alignment(fp, 0.0, 1e-5, 0.0)
    assert al.mirrored and al.sense == "ccw" and al.first_contact_index == 2
    assert al.stages and al.final_edge == (2, 1)
