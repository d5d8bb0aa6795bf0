"""Pricing over the outline (solver/certify/pricing.py): the branch and bound is sound
(never above phi anywhere on the outline) and effective (certifies 1e-6 below the true
minimum), golden section finds the minimum of a unimodal piece, and local minima come back
lowest first. The functionals are membership's (3.8)-(3.10) on its plain rows and on the
far conditioned rows, and the sticking locus's (4.1.4)."""

from __future__ import annotations

import numpy as np
import pytest

from models.core.footprint import Footprint
from solver.certify.outline import Outline, grid
from solver.certify.pricing import branch_and_bound, golden, local_minima
from solver.core.budget import UNLIMITED, Budget
from solver.locus.membership import ConditionedRows, PlainRows
from tests.scenes import SEED

SQUARE = Footprint.create([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]])
SQUARE_LOCAL = (SQUARE.vertices - SQUARE.center_of_mass) / SQUARE.circumradius
DISK = Outline(1.0, np.zeros(2), np.eye(2), None)
POLYGON = Outline(1.0, np.zeros(2), np.eye(2), SQUARE_LOCAL)
ALPHA = np.array([0.6, 0.8])
NORMAL = np.array([0.8, -0.6])
CONTACT = np.array([0.3, -0.2])

BNB_CASES = ["disk_inside", "disk_outside_near", "disk_on_circle", "edge_on", "vertex_on", "edge_near", "polygon_far",
             "disk_far_conditioned", "polygon_far_conditioned"]


def _rows(case):
    """Rows of a membership candidate r (local frame, L = 1) for each case."""
    if case.startswith("disk"):
        outline = DISK
        r = {"disk_inside": np.array([0.3, -0.4]), "disk_outside_near": np.array([0.6, 0.8]) * (1 + 1e-7),
             "disk_on_circle": np.array([0.6, 0.8]), "disk_far_conditioned": -60.0 * ALPHA + 0.4 * NORMAL}[case]
        on = case == "disk_on_circle"
    else:
        outline = POLYGON
        sq = SQUARE_LOCAL
        r = {"edge_on": sq[0] + 0.3 * (sq[1] - sq[0]), "vertex_on": sq[2],
             "edge_near": sq[0] + 0.3 * (sq[1] - sq[0]) - [0.0, 1e-7],
             "polygon_far": np.array([2.0, 1.5]), "polygon_far_conditioned": -40.0 * ALPHA - 0.7 * NORMAL}[case]
        on = case in ("edge_on", "vertex_on")
    s = float(ALPHA @ (CONTACT - r))
    in_f = outline.contains(r, on)
    if case.endswith("conditioned"):
        return ConditionedRows(outline, r, on, in_f, ALPHA, NORMAL, CONTACT, s, outline.reach(CONTACT))
    return PlainRows(outline, r, on, in_f, ALPHA, s)


def _dense_minimum(fn, pieces):
    """phi's minimum over 100,000 points per piece plus points crowding the pieces' ends
    (where r projects)."""
    n = len(pieces.piece_lo)
    dense_p = np.concatenate([np.full(100_000, k) for k in range(n)])
    dense_t = np.concatenate([np.linspace(lo, hi, 100_000) for lo, hi in zip(pieces.piece_lo, pieces.piece_hi)])
    ends = np.concatenate([lo + np.geomspace(1e-12, 1e-2, 2000) for lo in pieces.piece_lo]
                          + [hi - np.geomspace(1e-12, 1e-2, 2000) for hi in pieces.piece_hi])
    endp = np.concatenate([np.full(2000, k) for k in range(n)] * 2)
    return float(fn.evaluate(pieces, np.concatenate([dense_p, endp]), np.concatenate([dense_t, ends]))[0].min())


@pytest.mark.slow
@pytest.mark.parametrize("case", BNB_CASES)
def test_branch_and_bound_is_sound_and_effective(case):
    """The 1-D pricing bound over the outline (Lipschitz and second-order bounds of
    solver/certify/functional.py, derivative bounds of solver/certify/outline.py): never
    above phi at any of the ~400,000 sampled outline points, and able to certify 1e-6 below
    their minimum."""
    rng = np.random.default_rng(SEED + BNB_CASES.index(case))
    rows = _rows(case)
    pieces = rows.pieces
    gp, gt = grid(pieces)
    for _ in range(4):
        fn = rows.functional(rng.uniform(-1, 1, 5), np.zeros(0))
        f_min = _dense_minimum(fn, pieces)
        for _ in range(5):
            out = branch_and_bound(fn, pieces, gp, gt, f_min - 1e-6, 2_000_000, UNLIMITED)
            if out.certified:
                break
            # the bound found points the dense sampling missed (sharp dips next to r):
            # they must be real, and the next round aims below them
            vp, vlo, vhi = out.violators
            vals = fn.evaluate(pieces, vp, 0.5 * (vlo + vhi))[0]
            assert len(vp) and np.all(vals < f_min - 1e-6)
            f_min = float(vals.min())
        assert out.certified, (case, out.lower_bound, f_min, out.intervals)
        assert out.lower_bound <= f_min + 1e-15
        assert out.lower_bound >= f_min - 1e-6


def test_branch_and_bound_stops_at_its_interval_cap_and_budget():
    """An impossible target (far above the minimum) is refused soundly: uncertified, with a
    lower bound below the minimum, at the interval cap or when the budget has expired."""
    rows = _rows("disk_inside")
    fn = rows.functional(np.array([0.2, -0.5, 0.3, 0.7, -0.1]), np.zeros(0))
    gp, gt = grid(rows.pieces)
    f_min = _dense_minimum(fn, rows.pieces)
    capped = branch_and_bound(fn, rows.pieces, gp, gt, f_min + 1.0, 1000, UNLIMITED)
    late = branch_and_bound(fn, rows.pieces, gp, gt, f_min + 1.0, 2_000_000, Budget.of(0.0))
    for out in (capped, late):
        assert not out.certified and out.lower_bound <= f_min


def test_golden_section_and_local_minima():
    """Golden section on a bracket of each grid minimum reaches the dense minimum; the local
    minima are returned lowest first."""
    rows = _rows("polygon_far")
    fn = rows.functional(np.array([0.1, 0.4, -0.3, 0.9, 0.2]), np.zeros(0))
    gp, gt = grid(rows.pieces)
    gf = fn.evaluate(rows.pieces, gp, gt)[0]
    lp, lt, lf = local_minima(fn, rows.pieces, gt, gf, 4)
    assert np.all(np.diff(lf) >= 0.0) and lf[0] <= gf.min()
    assert lf[0] == pytest.approx(_dense_minimum(fn, rows.pieces), abs=1e-9)
    t, f = golden(fn, rows.pieces, lp[:1], rows.pieces.piece_lo[lp[:1]], rows.pieces.piece_hi[lp[:1]])
    assert f[0] <= lf[0] + 1e-12
