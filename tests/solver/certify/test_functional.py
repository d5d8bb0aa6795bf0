"""The ray functional phi(w) = a + b . w + (beta (w - c) - q) . (u - d0)
(solver/certify/functional.py): its near and far forms are one function, it is affine
along rays from r (the boundary reduction behind 3.8-3.10 and 4.1.4), its point-mass value
is its infimum at r, and its interval lower bounds are sound for random coefficients and
candidates near, on and far from a disk and a polygon."""

from __future__ import annotations

from decimal import Decimal, getcontext

import numpy as np
import pytest

from models.core.footprint import Footprint
from solver.certify.functional import RayFunctional, far_delta
from solver.certify.outline import Outline, outline_in_frame, pieces_seen_from
from solver.core.tolerances import SOLVER_DEFAULT
from tests.scenes import SEED

L_SHAPE = Footprint.create([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]])
POLYGON = outline_in_frame(L_SHAPE.center_of_mass, L_SHAPE.circumradius, L_SHAPE, np.eye(2), SOLVER_DEFAULT)
DISK = Outline(1.0, np.zeros(2), np.eye(2), None)
ANCHOR = np.array([0.4, -0.3])


def _functional(rng, r, far: bool) -> RayFunctional:
    """Random coefficients of O(1); with ``far`` the far form (d0 the direction r -> anchor)."""
    bc = r - ANCHOR
    d0 = -bc / np.hypot(*bc)
    return RayFunctional(r, float(rng.normal()), rng.normal(size=2), float(rng.normal()), rng.normal(size=2),
                         ANCHOR, d0, far=far)


def _delta_50_digits(w, r, anchor) -> np.ndarray:
    """u - d0 in 50-digit decimal arithmetic (the reference)."""
    getcontext().prec = 50
    out = []
    rx, ry = Decimal(float(r[0])), Decimal(float(r[1]))
    bx, by = Decimal(float(anchor[0])) - rx, Decimal(float(anchor[1])) - ry
    bn = (bx * bx + by * by).sqrt()
    for wx, wy in w:
        ex, ey = Decimal(float(wx)) - rx, Decimal(float(wy)) - ry
        en = (ex * ex + ey * ey).sqrt()
        out.append([float(ex / en - bx / bn), float(ey / en - by / bn)])
    return np.array(out)


def test_far_delta_is_u_minus_d0_without_cancellation():
    """Delta = u - d0 from the cancellation-free formula agrees with a 50-digit computation
    to ~1e-14 relative to |Delta|, even at |r| = 1e6 where the plain difference of the two
    unit vectors loses six digits."""
    rng = np.random.default_rng(SEED)
    for dist in (3.0, 185.0, 1e6):
        r = dist * np.array([0.8, 0.6])
        w = rng.uniform(-1, 1, size=(50, 2))
        e = w - r
        rho = np.hypot(e[:, 0], e[:, 1])
        got = far_delta(w, e / rho[:, None], rho, r, ANCHOR)
        ref = _delta_50_digits(w, r, ANCHOR)
        rel = np.hypot(*(got - ref).T) / np.hypot(*ref.T)
        assert rel.max() < 1e-13, (dist, rel.max())
        if dist == 1e6:
            plain = e / rho[:, None] - (ANCHOR - r) / np.hypot(*(ANCHOR - r))
            assert (np.hypot(*(plain - ref).T) / np.hypot(*ref.T)).max() > 1e-12


@pytest.mark.parametrize("dist", [0.5, 3.0, 40.0])
def test_near_and_far_forms_are_one_function(dist):
    """a_o + b_o . w + beta rho + q_o . u equals a + b . w + (beta (w - c) - q) . (u - d0)."""
    rng = np.random.default_rng(SEED + 1)
    r = dist * np.array([-0.6, 0.8])
    fn_far = _functional(rng, r, far=True)
    fn_near = RayFunctional(r, fn_far.a, fn_far.b, fn_far.beta, fn_far.q, ANCHOR, fn_far.d0, far=False)
    pieces = pieces_seen_from(DISK, r, False)
    t = np.linspace(0.0, 2 * np.pi, 333)
    piece = (t > np.pi).astype(int)
    f1, e1 = fn_far.evaluate(pieces, piece, t)
    f2, e2 = fn_near.evaluate(pieces, piece, t)
    scale = 1.0 + dist
    assert np.allclose(f1, f2, rtol=0, atol=1e-12 * scale)
    assert np.allclose(e1, e2, rtol=0, atol=1e-12 * scale)
    # values (pricing's golden section) are evaluate's first output, to the bit
    assert np.array_equal(fn_far.values(pieces, piece, t), f1)
    assert np.array_equal(fn_near.values(pieces, piece, t), f2)


def test_phi_is_affine_along_rays_and_its_infimum_at_r_is_the_point_mass_value():
    """On w = r + rho u the functional is affine in rho (module docstring); as rho -> 0
    it tends to a_o + b_o . r + q_o . u, whose minimum over unit u is the point-mass value."""
    rng = np.random.default_rng(SEED + 2)
    r = np.array([0.2, -0.1])
    fn = _functional(rng, r, far=False)
    a_o, b_o, q_o = fn.near_coefficients()

    def phi(w):
        e = w - r
        rho = np.hypot(*e.T)
        return a_o + w @ b_o + fn.beta * rho + (e / rho[:, None]) @ q_o

    for ang in np.linspace(0, 2 * np.pi, 7):
        u = np.array([np.cos(ang), np.sin(ang)])
        rho = np.array([0.1, 0.4, 0.9])
        vals = phi(r + rho[:, None] * u)
        assert vals[1] == pytest.approx(vals[0] + (vals[2] - vals[0]) * (0.3 / 0.8), abs=1e-13)
    zeta = np.column_stack([np.cos(np.linspace(0, 2 * np.pi, 100_001)), np.sin(np.linspace(0, 2 * np.pi, 100_001))])
    limits = a_o + b_o @ r + zeta @ q_o
    assert fn.point_mass_value() == pytest.approx(limits.min(), abs=1e-9)
    assert fn.point_mass_value() <= limits.min() + 1e-15


@pytest.mark.parametrize("outline_name", ["disk", "polygon"])
def test_interval_lower_bounds_are_sound(outline_name):
    """Every interval lower bound (near and far forms; Lipschitz, second-order, zeroth-
    order) lies below phi sampled densely on the interval, for random coefficients, random
    intervals and candidates inside, on and far from the outline."""
    outline = DISK if outline_name == "disk" else POLYGON
    rng = np.random.default_rng(SEED + 3)
    candidates = [np.array([0.1, 0.2]), np.array([-0.3, 0.5]), np.array([2.5, -1.0]), np.array([60.0, 35.0]),
                  np.array([-400.0, 90.0])]
    if outline_name == "disk":
        candidates.append(np.array([0.6, 0.8]))
    else:
        candidates.append(outline.vertices[2].copy())
    checked = 0
    for r0 in candidates:
        r, on = outline.snap(r0)
        pieces = pieces_seen_from(outline, r, on)
        far = float(np.hypot(*r)) > 10.0
        for _ in range(10):
            fn = _functional(rng, r, far)
            k = int(rng.integers(len(pieces.piece_lo)))
            lo, hi = pieces.piece_lo[k], pieces.piece_hi[k]
            for _ in range(4):
                t0, t1 = np.sort(rng.uniform(lo, hi, 2))
                if rng.uniform() < 0.3:
                    t1 = t0 + (t1 - t0) * 1e-3
                pc = np.array([k])
                f0, e0 = fn.evaluate(pieces, pc, np.array([t0]))
                f1, e1 = fn.evaluate(pieces, pc, np.array([t1]))
                lb = fn.lower_bounds(pieces, pc, np.array([t0]), np.array([t1]), f0, f1, e0, e1)[0]
                ts = np.linspace(t0, t1, 2001)
                vals = fn.evaluate(pieces, np.full(ts.size, k), ts)[0]
                assert vals.min() >= lb - 1e-12 * (1.0 + abs(vals.min())), (r, k, t0, t1, vals.min(), lb)
                checked += 1
    assert checked >= 200
