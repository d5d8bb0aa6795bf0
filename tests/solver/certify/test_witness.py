"""Witnesses (solver/certify/witness.py): the residual counts equality and inequality
violations, the exact polish turns an approximate non-negative support into a small one
that satisfies the rows to rounding (with the point mass in its cone), and warm points are
the heaviest first."""

from __future__ import annotations

import numpy as np

from solver.certify.witness import EXACT_RESIDUAL, exact_witness, heaviest_points, residual, violations
from tests.scenes import SEED


def _problem(rng, n_ineq=0):
    g = np.vstack([np.ones(60), rng.normal(size=(4, 60))])
    h = rng.normal(size=(n_ineq, 60))
    p = np.zeros(60)
    idx = rng.choice(60, 5, replace=False)
    p[idx] = rng.uniform(0.2, 1.0, 5)
    p /= p.sum()
    if n_ineq:
        h[:, idx] = np.abs(h[:, idx]) + 0.1
    return g, h, g @ p, p


def test_residual_counts_both_kinds_of_violation():
    g = np.eye(2)
    h = np.array([[1.0, -1.0]])
    eq, ineq, rows = violations(np.array([1.0, 1.0]), g, h, np.array([0.5, 2.0]), None, None, np.zeros(3))
    assert eq == 1.5 and ineq == 1.5 and np.allclose(rows, [-1.5])
    assert residual(np.array([1.0, 1.0]), g, h, np.array([0.5, 2.0]), None, None, np.zeros(3)) == 3.0


def test_polish_reaches_rounding_with_a_small_support():
    rng = np.random.default_rng(SEED)
    for n_ineq in (0, 2):
        g, h, b, p = _problem(rng, n_ineq)
        noisy = np.clip(p + 1e-7 * rng.uniform(0, 1, p.size), 0.0, None)  # a master-like answer
        w, pm, res = exact_witness(b, g, h, noisy, np.zeros(3), None, None, 1e-12)
        assert res <= 1e-13 and np.all(w >= 0.0) and np.all(pm == 0.0)
        assert np.count_nonzero(w) <= g.shape[0] + n_ineq
        assert residual(b, g, h, w, None, None, pm) == res


def test_polish_keeps_the_point_mass_in_its_cone():
    """A point mass (P0, z), |z| <= P0, with columns PG: the polished one stays in the cone."""
    rng = np.random.default_rng(SEED + 1)
    g, h, b, p = _problem(rng)
    pg = rng.normal(size=(5, 3))
    pg[0] = [1.0, 0.0, 0.0]
    pm_true = np.array([0.3, 0.1, -0.15])
    b = g @ (0.7 * p) + pg @ pm_true
    w, pm, res = exact_witness(b, g, h, 0.7 * p + 1e-8, pm_true + 1e-8, pg, np.zeros((0, 3)), 1e-12)
    assert res <= EXACT_RESIDUAL * 10 and pm[0] >= 0.0 and np.hypot(pm[1], pm[2]) <= pm[0] + 1e-15


def test_infeasible_rows_give_no_worse_than_the_given_support():
    """Rows no non-negative support satisfies: the polish returns a non-negative support
    whose residual is at most the given one (the master's), never a worse one."""
    g = np.vstack([np.ones(3), [0.0, 1.0, 2.0]])
    b = np.array([1.0, 5.0])
    w0 = np.array([0.0, 0.0, 1.0])
    given = residual(b, g, np.zeros((0, 3)), w0, None, None, np.zeros(3))
    w, pm, res = exact_witness(b, g, np.zeros((0, 3)), w0, np.zeros(3), None, None, 1e-12)
    assert np.all(w >= 0.0) and 0.0 < res <= given
    assert res == residual(b, g, np.zeros((0, 3)), w, None, None, pm)


def test_heaviest_points_first():
    pts = np.arange(10.0).reshape(5, 2)
    assert np.array_equal(heaviest_points(pts, np.array([0.1, 0.5, 0.2, 0.9, 0.0]), 2), pts[[3, 1]])
