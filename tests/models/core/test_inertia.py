"""Radii of gyration and the impact-limit COR (book 7.4, (7.1)), each checked by an
independent computation: closed forms of regular polygons, seeded Monte Carlo integration,
rigid-body impulse mechanics, and the analytic quasi-static locus of models/locus/cor_disk.py."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core import inertia as mi
from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.core.scene import PushScene
from models.locus import cor_disk as cd
from tests.scenes import SEED, point_in_polygon, polygon_grid, scene_for_mu


def regular_polygon(n: int, circumradius: float, phase: float = 0.3, centre=(0.0, 0.0)) -> np.ndarray:
    th = phase + 2.0 * math.pi * np.arange(n) / n
    return np.asarray(centre) + circumradius * np.column_stack([np.cos(th), np.sin(th)])


def star_polygon(rng: np.random.Generator, n: int, centre=(0.0, 0.0)) -> np.ndarray:
    """A random simple, generally non-convex polygon: jittered angles keep every angular
    gap below pi, so it is star-shaped about ``centre`` and hence simple."""
    th = 2.0 * math.pi * (np.arange(n) + rng.uniform(0.0, 0.4, n)) / n
    r = rng.uniform(0.25, 1.0, n)
    return np.asarray(centre) + np.column_stack([r * np.cos(th), r * np.sin(th)])


L_SHAPE = np.array([[0, 0], [3, 0], [3, 1], [1, 1], [1, 2.5], [0, 2.5]], dtype=float)


def rotate(points: np.ndarray, angle: float, about=(0.0, 0.0)) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    rot = np.array([[c, -s], [s, c]])
    return (np.asarray(points) - about) @ rot.T + about


def monte_carlo_rho2(vertices: np.ndarray, about: np.ndarray, n: int, seed: int):
    """Mean of |x - about|^2 over uniform samples of the polygon (rejection from its
    bounding box) and the standard error of that mean."""
    rng = np.random.default_rng(seed)
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    pts = rng.uniform(lo, hi, size=(n, 2))
    pts = pts[point_in_polygon(pts, vertices)]
    d2 = np.sum((pts - about) ** 2, axis=1)
    return float(d2.mean()), float(d2.std(ddof=1) / math.sqrt(len(d2)))


# --- radii of gyration ---------------------------------------------------------------------


def test_disk_and_ring():
    assert mi.disk_radius_of_gyration(2.0) ** 2 == pytest.approx(2.0, rel=1e-15)  # a^2/2
    assert mi.ring_radius_of_gyration(2.0) == 2.0
    # the regular N-gon tends to the disk: rho^2 = R^2 (2 + cos x) / 6 = R^2/2 (1 - x^2/6 + ...),
    # x = 2 pi / N, so rho is below the disk's by about x^2 / 12
    n = 1000
    fp = Footprint.create(regular_polygon(n, 2.0))
    deficit = 1.0 - mi.polygon_radius_of_gyration(fp) / mi.disk_radius_of_gyration(2.0)
    assert deficit == pytest.approx((2.0 * math.pi / n) ** 2 / 12.0, rel=1e-3)
    # N equal point masses on the circle: a ring
    assert mi.support_radius_of_gyration(regular_polygon(7, 2.0), np.ones(7)) == pytest.approx(2.0, rel=1e-14)


@pytest.mark.parametrize("side", [1.0, 0.01, 250.0])
def test_square_closed_form(side):
    """Square of side s about its centre: rho^2 = s^2 / 6."""
    sq = side * np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float) + [10.0, -3.0]
    assert mi.polygon_radius_of_gyration(Footprint.create(sq)) ** 2 == pytest.approx(side * side / 6.0, rel=1e-12)


@pytest.mark.parametrize("n", [3, 5, 6, 11])
def test_regular_polygon_closed_form(n):
    """Regular n-gon of circumradius R: rho^2 = R^2 (2 + cos(2 pi / n)) / 6 (equilateral
    triangle of side s: s^2 / 12)."""
    fp = Footprint.create(regular_polygon(n, 1.7, centre=(-4.0, 9.0)))
    expected = 1.7**2 * (2.0 + math.cos(2.0 * math.pi / n)) / 6.0
    assert mi.polygon_radius_of_gyration(fp) ** 2 == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("vertices", [L_SHAPE, star_polygon(np.random.default_rng(SEED), 9)], ids=["L", "star"])
def test_polygon_against_monte_carlo(vertices):
    """Seeded Monte Carlo integration of |x - CM|^2 over the (non-convex) area: the exact
    formula lies within 5 standard errors (about 0.3 % here)."""
    fp = Footprint.create(vertices)
    mc, se = monte_carlo_rho2(fp.vertices, fp.center_of_mass, 400_000, SEED)
    exact = mi.polygon_radius_of_gyration(fp) ** 2
    assert abs(exact - mc) <= 5.0 * se
    assert se < 5e-3 * exact  # the check has teeth


def test_other_centre_of_mass_is_the_parallel_axis_shift():
    """About a CM off the area centroid c0: rho_c0^2 + |c0 - CM|^2 (and Monte Carlo)."""
    centroid = Footprint.create(L_SHAPE)
    cm = np.array([0.6, 0.7])
    shifted = Footprint.create(L_SHAPE, center_of_mass=cm)
    rho2 = mi.polygon_radius_of_gyration(shifted) ** 2
    expected = mi.polygon_radius_of_gyration(centroid) ** 2 + float(np.sum((centroid.center_of_mass - cm) ** 2))
    assert rho2 == pytest.approx(expected, rel=1e-13)
    mc, se = monte_carlo_rho2(L_SHAPE, cm, 400_000, SEED + 1)
    assert abs(rho2 - mc) <= 5.0 * se


def test_scale_rotation_translation_invariance():
    rng = np.random.default_rng(SEED + 2)
    for _ in range(10):
        v = star_polygon(rng, 8)
        rho = mi.polygon_radius_of_gyration(Footprint.create(v))
        lam = 10.0 ** rng.uniform(-3, 3)
        angle = rng.uniform(0, 2 * math.pi)
        shift = rng.uniform(-50, 50, 2)
        assert mi.polygon_radius_of_gyration(Footprint.create(lam * v)) == pytest.approx(lam * rho, rel=1e-12)
        moved = rotate(v, angle, about=rng.uniform(-5, 5, 2)) + shift
        assert mi.polygon_radius_of_gyration(Footprint.create(moved)) == pytest.approx(rho, rel=1e-12)
        assert mi.polygon_radius_of_gyration(Footprint.create(v[::-1])) == pytest.approx(rho, rel=1e-14)


def test_polygon_inscribed_in_its_disk_has_rho_below_a():
    rng = np.random.default_rng(SEED + 3)
    for _ in range(50):
        fp = Footprint.create(star_polygon(rng, int(rng.integers(3, 12))))
        rho = mi.polygon_radius_of_gyration(fp)
        assert 0.0 < rho < fp.circumradius
    # the bound is approached by thin shapes reaching the circle everywhere: a 200-gon
    # ring of width 1 % has rho within 1 % of a
    # a slit annulus: the outer circle CCW, then the inner one CW, cut along +x
    th = np.linspace(1e-4, 2.0 * math.pi - 1e-4, 200)
    circle = np.column_stack([np.cos(th), np.sin(th)])
    annulus = np.vstack([circle, 0.99 * circle[::-1]])
    fp = Footprint.create(annulus, center_of_mass=(0.0, 0.0))
    assert 0.99 < mi.polygon_radius_of_gyration(fp) < 1.0


def test_discrete_support():
    # dumbbell +-d: rho = d; weights 1:3 at distances 3 and 1: rho^2 = (9 + 3)/4 = 3
    assert mi.support_radius_of_gyration([[2.0, 0.0], [-2.0, 0.0]], [1, 1]) == pytest.approx(2.0, rel=1e-15)
    w = np.array([[3.0, 1.0], [-1.0, 1.0]])
    assert mi.support_radius_of_gyration(w, [1, 3], center_of_mass=(0.0, 1.0)) == pytest.approx(math.sqrt(3.0), rel=1e-15)
    with pytest.raises(InvalidInput) as err:
        mi.support_radius_of_gyration(w, [1, 3], center_of_mass=(0.0, 0.0))
    assert err.value.field == "center_of_mass"
    for bad in ([1, -1], [0, 0], [1]):
        with pytest.raises(InvalidInput) as err:
            mi.support_radius_of_gyration(w, bad)
        assert err.value.field == "weights"


# --- the impact COR (7.1) ------------------------------------------------------------------


def impulse_cor(scene: PushScene, rho: float, mass: float = 2.7) -> np.ndarray:
    """COR of the velocity change from a unit impulse along n at the contact (rigid body,
    no table friction): dv = n / M, domega = (c x n) / (M rho^2), r = CM + J dv / domega."""
    n = scene.normal
    c = scene.contact_rel
    dv = n / mass
    domega = (c[0] * n[1] - c[1] * n[0]) / (mass * rho * rho)
    return scene.center_of_mass + np.array([-dv[1], dv[0]]) / domega


def random_scene(rng: np.random.Generator) -> PushScene:
    a = 10.0 ** rng.uniform(-1, 1)
    cm = rng.uniform(-3, 3, 2)
    contact = cm + a * rng.uniform(-1.2, 1.2, 2)
    return PushScene.create(a, contact, rng.uniform(0, math.pi), rng.uniform(-math.pi, math.pi), cm)


def test_impact_cor_is_the_impulse_response():
    """(7.1) and its side of the CM from rigid-body impulse mechanics, both senses."""
    rng = np.random.default_rng(SEED + 4)
    senses = set()
    while len(senses) < 2 or rng.uniform() < 0.95:
        try:
            sc = random_scene(rng)
        except InvalidInput:
            continue
        rho = sc.disk_radius * rng.uniform(0.05, 1.0)
        expected = impulse_cor(sc, rho)
        got = mi.impact_cor(sc, rho)
        assert np.linalg.norm(got - expected) <= 1e-12 * (np.linalg.norm(expected) + np.linalg.norm(sc.center_of_mass))
        assert mi.impact_cor_distance(sc, rho) == pytest.approx(np.linalg.norm(expected - sc.center_of_mass), rel=1e-12)
        senses.add(sc.sense)


@pytest.mark.parametrize("mu", [0.05, 0.3, 0.6, 0.9, -0.4])
@pytest.mark.parametrize("placement", [dict(), dict(cm=(2.0, -1.0), edge_angle=0.7, push_direction=-0.4, a=3.0)])
def test_ring_impact_cor_is_the_locus_tip_3_37(mu, placement):
    """rho = a (circular rim): (7.1) coincides with the tip (3.37) of the analytic locus."""
    sc = scene_for_mu(mu, **placement)
    tip = cd.disk_cor_locus(sc, outputs=("tip",)).tip
    got = mi.impact_cor(sc, mi.ring_radius_of_gyration(sc.disk_radius))
    assert np.linalg.norm(got - tip.point) <= 1e-13 * (tip.distance + np.linalg.norm(sc.center_of_mass))


def test_ring_impact_cor_for_contact_beyond_the_disk():
    """|alpha . c| >= a: the locus's farthest point is on the disk (models/locus/cor_disk.py), but
    (7.1) with rho = a is the book's (3.37) a^2/|alpha . c|, on the same axis."""
    sc = scene_for_mu(1.5)
    loc = cd.disk_cor_locus(sc, outputs=("tip",))
    got = mi.impact_cor(sc, sc.disk_radius)
    assert np.linalg.norm(got - sc.center_of_mass) == pytest.approx(loc.tip.distance_book, rel=1e-14)
    assert np.allclose((got - sc.center_of_mass) / loc.tip.distance_book, loc.axis, atol=1e-14)


@pytest.mark.parametrize("mu", [0.3, 0.6, 0.9, 1.5])
def test_impact_cor_of_inscribed_polygons_lies_inside_the_quasi_static_locus_7_4(mu):
    """7.4: rho < a for every other workpiece, so the impact COR is inside the locus."""
    rng = np.random.default_rng(SEED + int(100 * mu))
    for _ in range(6):
        fp = Footprint.create(star_polygon(rng, int(rng.integers(3, 10))))
        a = fp.circumradius
        sc = scene_for_mu(mu, a=a, cm=fp.center_of_mass, edge_angle=float(rng.uniform(0.2, 2.9)))
        loc = cd.disk_cor_locus(sc, outputs=("tip", "boundary"), n_points=512)
        rho = mi.polygon_radius_of_gyration(fp)
        cor = mi.impact_cor(sc, rho)
        assert point_in_polygon(cor[None], loc.boundary)[0]
        assert np.linalg.norm(cor - sc.center_of_mass) < loc.tip.distance
        # and the ring's impact COR is not strictly inside it (it is the tip, a vertex)
        if mu < 1.0:
            assert not point_in_polygon(mi.impact_cor(sc, a)[None] + 1e-9 * a * loc.axis, loc.boundary)[0]


def test_translation_has_no_impact_cor():
    sc = scene_for_mu(0.0)
    assert mi.impact_cor(sc, 0.5) is None
    assert mi.impact_cor_distance(sc, 0.5) is None


@pytest.mark.parametrize("rho", [0.0, -1.0, float("nan"), float("inf"), 1.0 + 1e-9, "x"])
def test_invalid_radius_of_gyration(rho):
    with pytest.raises(InvalidInput) as err:
        mi.impact_cor(scene_for_mu(0.3), rho)
    assert err.value.field == "radius_of_gyration"


def test_invalid_disk_radius():
    for bad in (0.0, -2.0, float("nan")):
        with pytest.raises(InvalidInput):
            mi.disk_radius_of_gyration(bad)
        with pytest.raises(InvalidInput):
            mi.ring_radius_of_gyration(bad)


# --- mean distance (the quasi-static check's rbar, 6.8) by closed forms and quadrature ------

L_SHAPE_MD = np.array([[0, 0], [3, 0], [3, 1], [1, 1], [1, 2.5], [0, 2.5]], dtype=float)
"""An L whose reflex vertex and edges give the mean distance every case of its formula."""


def grid_mean_distance(vertices: np.ndarray, about, cells: int = 1500) -> float:
    pts = polygon_grid(vertices, cells)
    return float(np.mean(np.linalg.norm(pts - np.asarray(about), axis=1)))


def test_mean_distance_closed_forms():
    # From the centre of a square of side s: s (sqrt 2 + ln(1 + sqrt 2)) / 6. From a corner:
    # the square is a quadrant of the square of side 2s about that corner, so twice that.
    s = 2.0
    square = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=float)
    centre = s * (math.sqrt(2.0) + math.log1p(math.sqrt(2.0))) / 6.0
    assert mi.polygon_mean_distance(square, (0.0, 0.0)) == pytest.approx(centre, rel=1e-14)
    assert mi.polygon_mean_distance(square[::-1], (0.0, 0.0)) == pytest.approx(centre, rel=1e-14)
    assert mi.polygon_mean_distance(square, (1.0, 1.0)) == pytest.approx(2.0 * centre, rel=1e-14)
    # The regular N-gon tends to the disk's 2R/3.
    n = 4096
    th = 2.0 * math.pi * np.arange(n) / n
    ngon = np.column_stack([np.cos(th), np.sin(th)])
    assert mi.polygon_mean_distance(ngon, (0.0, 0.0)) == pytest.approx(2.0 / 3.0, rel=1e-6)


@pytest.mark.slow
@pytest.mark.parametrize("about", [(0.2, 0.3), (1.0, 1.0), (1.0, 0.5), (2.0, 2.0), (-1.0, 4.0), (3.0, 0.0)])
def test_mean_distance_against_a_grid(about):
    """Inside, on an edge, at a reflex vertex, outside (also beyond an edge's line)."""
    assert mi.polygon_mean_distance(L_SHAPE_MD, about) == pytest.approx(grid_mean_distance(L_SHAPE_MD, about), rel=1e-4)


def test_mean_distance_needs_vertices_away_from_the_point():
    with pytest.raises(InvalidInput) as exc:
        mi.polygon_mean_distance(np.zeros((3, 2)), (0.0, 0.0))
    assert exc.value.field == "footprint"
