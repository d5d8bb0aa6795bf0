"""Polygon footprints and their circumscribing disk (book 3.1.8)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.footprint import Footprint, inside_polygon, triangle_areas, triangulate
from tests.scenes import SEED, distance_to_polyline, point_in_polygon

SQUARE = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
L_SHAPE = [[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]]


def test_square_disk_is_the_circumscribed_circle():
    f = Footprint.create(SQUARE)
    assert np.allclose(f.center_of_mass, 0.0)
    assert f.circumradius == pytest.approx(math.sqrt(2))
    assert f.area == pytest.approx(4.0)


def test_l_shape_centroid_and_radius():
    f = Footprint.create(L_SHAPE)
    # two unit-area squares' centroids (1, 0.5)+(0.5, 0.5) and (0.5, 1.5): mean of 3 unit squares
    assert np.allclose(f.center_of_mass, [(1.5 + 0.5 + 0.5) / 3, (0.5 + 0.5 + 1.5) / 3])
    assert f.circumradius == pytest.approx(np.max(np.linalg.norm(np.array(L_SHAPE) - f.center_of_mass, axis=1)))


def test_clockwise_input_is_reoriented_and_far_offsets_keep_digits():
    off = np.array([1e6, -3e6])
    f = Footprint.create((np.array(SQUARE) + off)[::-1])
    assert np.allclose(f.center_of_mass, off, rtol=0, atol=1e-9)
    x, y = f.vertices.T
    assert 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) > 0


def test_given_centre_of_mass_sets_the_radius():
    f = Footprint.create(SQUARE, center_of_mass=[0.5, 0.0])
    assert f.circumradius == pytest.approx(math.hypot(1.5, 1.0))


@pytest.mark.parametrize(
    "vertices, field",
    [
        ([[0, 0], [1, 1]], "workpiece"),
        ([[0, 0], [1, 0], [2, 0]], "workpiece"),  # collinear
        ([[0, 0], [2, 2], [2, 0], [0, 2]], "workpiece"),  # bow-tie
        ([[0, 0], [2, 0], [1, 1], [2, 2], [0, 2], [1, 1]], "workpiece"),  # touches itself
        ([[0, 0], [1, 0], [1, 0], [0, 1]], "workpiece"),  # repeated vertex
        ([[0, 0], [1, float("inf")], [0, 1]], "workpiece"),
    ],
)
def test_bad_polygons_are_refused(vertices, field):
    with pytest.raises(InvalidInput) as err:
        Footprint.create(vertices)
    assert err.value.field == field


def test_centre_of_mass_outside_the_hull_is_refused():
    with pytest.raises(InvalidInput) as err:
        Footprint.create(SQUARE, center_of_mass=[3.0, 0.0])
    assert err.value.field == "center_of_mass"


def test_distance_to_outline():
    f = Footprint.create(SQUARE)
    assert f.distance_to_outline([1.0, 0.3]) == pytest.approx(0.0)
    assert f.distance_to_outline([0.0, 0.0]) == pytest.approx(1.0)


def test_small_polygon_far_from_the_origin_keeps_its_area():
    tri = np.array([[0.0, 0.0], [1e-3, 0.0], [0.0, 1e-3]]) + 1e6
    assert Footprint.create(tri).area == pytest.approx(0.5e-6, rel=1e-6)


@pytest.mark.parametrize("scale", [1e-110, 1e-6, 1.0, 1e6, 1e120])
def test_area_and_centroid_at_extreme_scales(scale):
    """The L shape's centroid (3/4, 5/4) and area 4 at every scale (no underflow of the
    shoelace products for tiny parts, no overflow for huge ones)."""
    v = np.array([[0, 0], [2, 0], [2, 1], [1, 1], [1, 3], [0, 3]], dtype=float) * scale
    f = Footprint.create(v)
    assert np.allclose(f.center_of_mass / scale, [0.75, 1.25], rtol=1e-12)
    assert math.isclose(f.area / scale / scale, 4.0, rel_tol=1e-12)


def test_triangulation_covers_the_polygon_exactly():
    rng = np.random.default_rng(SEED)
    polygons = [L_SHAPE, SQUARE, [[0, 0], [1, 0], [2, 0], [2, 1], [0, 1]]]  # one flat corner
    for _ in range(20):
        n = int(rng.integers(3, 14))
        th = 2 * math.pi * (np.arange(n) + rng.uniform(0, 0.4, n)) / n
        r = rng.uniform(0.2, 1.0, n)
        polygons.append(np.column_stack([r * np.cos(th), r * np.sin(th)]))
    for v in polygons:
        fp = Footprint.create(v)
        tris = triangulate(fp.vertices)
        assert len(tris) == len(fp.vertices) - 2
        areas = triangle_areas(tris)
        assert np.all(areas > 0.0)
        assert areas.sum() == pytest.approx(fp.area, rel=1e-12)
        assert np.all(point_in_polygon(tris.mean(axis=1), fp.vertices))


def test_inside_polygon_agrees_with_the_triangulation():
    """The even-odd test against an independent one: inside some triangle of the ear-clipped
    triangulation (barycentric signs); points within 1e-9 of the outline are left out."""
    rng = np.random.default_rng(SEED)
    for _ in range(15):
        n = int(rng.integers(3, 12))
        th = 2 * math.pi * (np.arange(n) + rng.uniform(0, 0.4, n)) / n
        r = rng.uniform(0.2, 1.0, n)
        fp = Footprint.create(np.column_stack([r * np.cos(th), r * np.sin(th)]))
        pts = rng.uniform(-1.1, 1.1, size=(400, 2))
        pts = pts[distance_to_polyline(pts, fp.vertices) > 1e-9]
        tris = triangulate(fp.vertices)
        a, b, c = (tris[:, k][None] for k in range(3))
        p = pts[:, None, :]

        def side(u, v, w):
            return (v[..., 0] - u[..., 0]) * (w[..., 1] - u[..., 1]) - (v[..., 1] - u[..., 1]) * (w[..., 0] - u[..., 0])

        in_tri = (side(a, b, p) >= 0) & (side(b, c, p) >= 0) & (side(c, a, p) >= 0)
        expected = in_tri.any(axis=1)
        assert 0 < expected.sum() < len(pts)
        assert np.array_equal(inside_polygon(fp.vertices, pts), expected)


# --- the one polygon type: hull, orientation, body frame, projection ----------------------


def star(rng: np.random.Generator, n: int) -> np.ndarray:
    """A random simple polygon, star-shaped about the origin (angular gaps below pi)."""
    th = 2.0 * math.pi * (np.arange(n) + rng.uniform(0.0, 0.4, n)) / n
    r = rng.uniform(0.3, 1.0, n)
    return np.column_stack([r * np.cos(th), r * np.sin(th)])


def test_the_hull_is_convex_counter_clockwise_holds_every_vertex_and_starts_at_the_least_x():
    rng = np.random.default_rng(SEED)
    for _ in range(50):
        f = Footprint.create(star(rng, int(rng.integers(4, 12))))
        h = f.hull
        e = np.roll(h, -1, axis=0) - h
        turns = e[:, 0] * np.roll(e[:, 1], -1) - e[:, 1] * np.roll(e[:, 0], -1)
        assert np.all(turns > 0.0)  # strictly convex: collinear points dropped
        for j in range(f.hull_size):  # every vertex on the inner side of every hull edge
            assert np.all(e[j, 0] * (f.vertices[:, 1] - h[j, 1]) - e[j, 1] * (f.vertices[:, 0] - h[j, 0]) >= -1e-12)
        rel = f.vertices - f.center_of_mass
        assert f.hull_indices[0] == min(range(len(rel)), key=lambda i: (rel[i, 0], rel[i, 1]))
        assert f.circumradius == pytest.approx(np.max(np.hypot(*(h - f.center_of_mass).T)), rel=1e-15)


def test_a_collinear_vertex_is_in_the_outline_but_not_in_the_hull():
    f = Footprint.create([[0, 0], [1, 0], [2, 0], [2, 1], [0, 1]])
    assert 1 not in f.hull_indices and f.hull_size == 4


def test_a_clockwise_outline_maps_its_vertices_back_to_the_order_given():
    given = np.array(L_SHAPE, dtype=float)[::-1]  # clockwise
    f = Footprint.create(given)
    assert f.input_reversed and not Footprint.create(L_SHAPE).input_reversed
    for i in range(len(given)):
        assert np.array_equal(f.vertices[i], given[f.input_index(i)])
    ccw = Footprint.create(L_SHAPE)
    assert [ccw.input_index(i) for i in range(len(L_SHAPE))] == list(range(len(L_SHAPE)))


def test_the_body_frame_moves_the_centre_of_mass_to_the_origin_and_keeps_the_rest():
    f = Footprint.create(L_SHAPE, center_of_mass=[0.7, 0.9])
    b = f.centred()
    assert np.array_equal(b.center_of_mass, [0.0, 0.0])
    assert np.array_equal(b.vertices, f.vertices - f.center_of_mass)
    assert (b.hull_indices, b.circumradius, b.area, b.input_reversed) == (
        f.hull_indices, f.circumradius, f.area, f.input_reversed)


def test_hull_edges_and_the_centre_of_mass_over_them():
    f = Footprint.create(SQUARE, center_of_mass=[0.5, -0.25])
    for j in range(f.hull_size):
        start, length, e = f.hull_edge(j)
        assert np.allclose(start + length * e, f.hull[(j + 1) % f.hull_size])
        assert f.hull_edge_angle(j) == pytest.approx(math.atan2(e[1], e[0]))
        u, h = f.cm_over_hull_edge(j)
        assert np.allclose(start + u * e + h * np.array([-e[1], e[0]]), f.center_of_mass)
        assert h > 0.0  # inside
    # the square's bottom edge: CM 0.75 above it, 1.5 along it from (-1, -1)
    j = next(j for j in range(4) if np.allclose(f.hull_edge(j)[0], [-1.0, -1.0]))
    assert f.cm_over_hull_edge(j) == pytest.approx((1.5, 0.75))


def test_the_projection_onto_the_outline_is_the_nearest_of_a_dense_sample():
    rng = np.random.default_rng(SEED)
    f = Footprint.create(L_SHAPE)
    a, b = f.vertices, np.roll(f.vertices, -1, axis=0)
    s = np.linspace(0.0, 1.0, 2001)[:, None, None]
    dense = (a + s * (b - a)).reshape(-1, 2)
    for p in rng.uniform(-1.0, 3.0, size=(40, 2)):
        foot = f.nearest_on_outline(p)
        best = float(np.min(np.hypot(*(dense - p).T)))
        assert float(np.hypot(*(foot - p))) == pytest.approx(f.distance_to_outline(p), abs=1e-15)
        assert best - 1e-3 <= f.distance_to_outline(p) <= best + 1e-12
        assert float(np.min(np.hypot(*(dense - foot).T))) <= 1e-3  # on the outline


@pytest.mark.parametrize("scale", [1e-6, 1e6])
def test_the_hull_does_not_depend_on_the_scale(scale):
    rng = np.random.default_rng(SEED + 1)
    v = star(rng, 9)
    assert Footprint.create(v * scale).hull_indices == Footprint.create(v).hull_indices


def test_a_symmetric_bow_tie_is_called_self_crossing_not_collinear():
    with pytest.raises(InvalidInput, match="not a simple polygon"):
        Footprint.create([[0, 0], [2, 2], [2, 0], [0, 2]])


def test_an_outline_edge_maps_to_the_hull_edge_it_lies_on():
    """Edges of the outline as given (either orientation) map to hull edges; a notch's
    edges map to none; edges split by a collinear vertex map to the one hull edge."""
    ell = [[0, 0], [3, 0], [3, 1], [1, 1], [1, 3], [0, 3]]
    f = Footprint.create(ell)
    assert [f.hull_edge_of_input(i) for i in range(6)] == [0, 1, None, None, 3, 4]
    g = Footprint.create(ell[::-1])
    assert [g.hull_edge_of_input(i) for i in range(6)] == [3, None, None, 1, 0, 4]
    split = [[0, 0], [1, 0], [2, 0], [2, 1], [0, 1]]
    assert [Footprint.create(split).hull_edge_of_input(i) for i in range(5)] == [0, 0, 1, 2, 3]
    assert [Footprint.create(split[::-1]).hull_edge_of_input(i) for i in range(5)] == [2, 1, 0, 0, 3]
