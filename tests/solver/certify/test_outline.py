"""The outline seen from a candidate r (solver/certify/outline.py): the frame, snapping and
containment, and the derivative bounds the branch and bound rests on, checked against
finite differences of w, rho = |w - r| and u = (w - r)/rho on random intervals, for r
inside, on, near and far from a disk and a polygon (3.1.8: the disk is the circumscribing
one of polygons)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from solver.certify.outline import (
    ON_BOUNDARY_REL,
    DiskPieces,
    Outline,
    grid,
    outline_in_frame,
    pieces_seen_from,
)
from solver.core.tolerances import SOLVER_DEFAULT
from tests.scenes import SEED

SQUARE = Footprint.create([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]])
L_SHAPE = Footprint.create([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]])


def _local(fp: Footprint) -> Outline:
    return outline_in_frame(fp.center_of_mass, fp.circumradius, fp, np.eye(2), SOLVER_DEFAULT)


DISK = Outline(1.0, np.zeros(2), np.eye(2), None)
CASES = {
    "disk_inside": (DISK, np.array([0.3, -0.4])),
    "disk_on": (DISK, np.array([0.6, 0.8]) * (1.0 + 0.5 * ON_BOUNDARY_REL)),
    "disk_near": (DISK, np.array([0.6, 0.8]) * (1.0 + 1e-3)),
    "disk_far": (DISK, np.array([50.0, 20.0])),
    "square_inside": (_local(SQUARE), np.array([0.1, -0.2])),
    "square_edge": (_local(SQUARE), None),
    "l_vertex": (_local(L_SHAPE), None),
    "l_far": (_local(L_SHAPE), np.array([-30.0, 12.0])),
}


def _case(name):
    outline, r = CASES[name]
    if r is None:
        v = outline.vertices
        r = v[0] + 0.3 * (v[1] - v[0]) if name == "square_edge" else v[3].copy()
    r, on = outline.snap(r)
    return outline, r, on


def test_frame_round_trip_and_reach():
    """to_local/to_world invert each other in a rotated, scaled frame; reach is the largest
    distance from a point over the footprint."""
    ang = 0.7
    frame = np.array([[math.cos(ang), -math.sin(ang)], [math.sin(ang), math.cos(ang)]])
    out = outline_in_frame(L_SHAPE.center_of_mass, L_SHAPE.circumradius, L_SHAPE, frame, SOLVER_DEFAULT)
    pts = np.array([[0.3, 2.0], [-5.0, 1.0]])
    assert np.allclose(out.to_world(out.to_local(pts)), pts, atol=1e-14)
    assert np.allclose(out.vector_to_world(out.vector_to_local([1.0, 2.0])), [1.0, 2.0], atol=1e-15)
    p = np.array([0.2, -0.1])
    d = np.hypot(*(out.vertices - p).T)
    assert out.reach(p) == pytest.approx(d.max(), rel=1e-15)
    assert DISK.reach(np.array([3.0, 4.0])) == pytest.approx(6.0)


def test_a_footprint_whose_centre_of_mass_is_not_the_scenes_is_refused():
    with pytest.raises(InvalidInput) as err:
        outline_in_frame(np.array([5.0, 0.0]), 1.0, SQUARE, np.eye(2), SOLVER_DEFAULT)
    assert err.value.field == "center_of_mass"


def test_snapping_and_containment():
    """Within ON_BOUNDARY_REL of the outline a candidate is moved onto it (vertex first);
    the closed footprint contains its outline."""
    sq = _local(SQUARE)
    v = sq.vertices
    r, on = sq.snap(v[2] + [0.3 * ON_BOUNDARY_REL, 0.0])
    assert on and np.array_equal(r, v[2])
    mid = 0.5 * (v[0] + v[1])
    r, on = sq.snap(mid + [0.0, -0.5 * ON_BOUNDARY_REL])
    assert on and abs(r[1] - mid[1]) < 1e-15 and sq.contains(r, on)
    r, on = sq.snap(mid + [0.0, -3.0 * ON_BOUNDARY_REL])
    assert not on and not sq.contains(r, on)
    assert sq.contains(np.zeros(2), False)
    r, on = DISK.snap(np.array([0.0, 1.0 + 0.5 * ON_BOUNDARY_REL]))
    assert on and r[1] == 1.0
    assert not DISK.contains(np.array([0.0, 1.0 + 2.0 * ON_BOUNDARY_REL]), False)


def test_grid_spans_every_piece_with_both_ends():
    outline, r, on = _case("square_edge")
    pieces = pieces_seen_from(outline, r, on)
    gp, gt = grid(pieces)
    for k, (lo, hi) in enumerate(zip(pieces.piece_lo, pieces.piece_hi)):
        ts = gt[gp == k]
        assert ts[0] == lo and ts[-1] == hi and np.all(np.diff(ts) > 0)


def _derivatives(pieces, piece, t, h):
    """Central differences of w, rho, u at parameters t (first and second)."""
    p = np.full(t.size, piece)
    out = []
    for dt in (-h, 0.0, h):
        out.append(pieces.geom(p, t + dt))
    (wm, rm, um), (w0, r0, u0), (wp, rp, up) = out
    d1 = [(wp - wm) / (2 * h), (rp - rm) / (2 * h), (up - um) / (2 * h)]
    d2 = [(wp - 2 * w0 + wm) / h**2, (rp - 2 * r0 + rm) / h**2, (up - 2 * u0 + um) / h**2]
    return d1, d2


@pytest.mark.parametrize("name", sorted(CASES))
def test_derivative_bounds_hold_on_random_intervals(name):
    """|w'| <= V, |w''| <= A, |rho'| <= R1, |rho''| <= R2, |u'| <= U1, |u''| <= U2 on every
    sampled interval (the derivations in DiskPieces and PolygonPieces)."""
    outline, r, on = _case(name)
    pieces = pieces_seen_from(outline, r, on)
    rng = np.random.default_rng(SEED + sorted(CASES).index(name))
    checked = 0
    for _ in range(60):
        k = int(rng.integers(len(pieces.piece_lo)))
        lo, hi = pieces.piece_lo[k], pieces.piece_hi[k]
        span = hi - lo
        t0, t1 = np.sort(rng.uniform(lo + 1e-3 * span, hi - 1e-3 * span, 2))
        h = 1e-4  # differences of w, rho, u carry rounding ~1e-16 / h^2 = 1e-8
        if t1 - t0 < 10 * h:
            continue
        ts = np.linspace(t0 + h, t1 - h, 201)
        _, rho0, _ = pieces.geom(np.array([k]), np.array([t0]))
        _, rho1, _ = pieces.geom(np.array([k]), np.array([t1]))
        bounds = pieces.derivative_bounds(np.array([k]), np.array([t0]), np.array([t1]), rho0, rho1)
        v, a, r1, r2, u1, u2 = (float(np.asarray(x).reshape(-1)[0]) for x in bounds)
        (dw, dr, du), (ddw, ddr, ddu) = _derivatives(pieces, k, ts, h)
        slack = 1e-4
        assert np.hypot(*dw.T).max() <= v * (1 + slack) + 1e-9
        assert np.abs(dr).max() <= r1 * (1 + slack) + 1e-9
        assert np.hypot(*du.T).max() <= u1 * (1 + slack) + 1e-6
        assert np.hypot(*ddw.T).max() <= a * (1 + slack) + 1e-4
        assert np.abs(ddr).max() <= r2 * (1 + slack) + 1e-4
        assert np.hypot(*ddu.T).max() <= u2 * (1 + slack) + 1e-4
        checked += 1
    assert checked >= 50


def test_the_far_field_disk_bound_is_of_order_one_over_the_distance():
    """For a far r (R = |r| >> 1) u turns at rate 1/2 + (1 - R^2)/(2 rho^2) = O(1/R): the
    bound max over the interval's ends is O(1/R), where the cruder
    1/2 + |1 - R^2|/(2 rho_min^2) is about 1 (what kept far candidates undecided)."""
    for big_r in (10.0, 185.0, 1e4):
        r = big_r * np.array([0.6, -0.8])
        pieces = DiskPieces(r, on_circle=False)
        for k in (0, 1):
            t0, t1 = np.array([pieces.piece_lo[k]]), np.array([pieces.piece_hi[k]])
            _, rho0, _ = pieces.geom(np.array([k]), t0)
            _, rho1, _ = pieces.geom(np.array([k]), t1)
            u1 = float(pieces.derivative_bounds(np.array([k]), t0, t1, rho0, rho1)[4][0])
            crude = 0.5 + abs(1 - big_r**2) / (2 * min(rho0[0], rho1[0]) ** 2)
            assert u1 <= 1.01 / (big_r - 1.0)
            assert crude > 0.99
