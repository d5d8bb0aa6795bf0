"""The batched exact minimum-power solver (solver/motion/newton.py, book 3.2-3.3.3): its
result says how good it is. (Its answers are checked against the other back ends, brute
force and the analytic locus in test_forward.py.)"""

from __future__ import annotations

import numpy as np
import pytest

from models.core.support import random_balanced_tripods
from solver.core.outcome import Outcome
from solver.motion.newton import solve_batch, sum_rows
from tests.scenes import SEED


def frictionless_rows(b: int):
    """(3.3) for a contact at c = (-1, 0.2) pushed along n = (1, 0): v_x - 0.2 omega = 1."""
    m = np.tile(np.array([[[1.0, 0.0, -0.2]]]), (b, 1, 1))
    return m, np.ones((b, 1))


def test_batch_solution_is_an_outcome():
    pts, wts = random_balanced_tripods(np.random.default_rng(SEED), 30, 1.0)
    m, q = frictionless_rows(30)
    sol = solve_batch(pts, wts, m, q, kkt_tol=1e-10, max_iter=80)
    assert isinstance(sol, Outcome) and sol.status == "optimal" and sol.complete
    assert sol.message == "30 of 30 problems met the KKT tolerance" and sol.solve_time_s > 0.0
    capped = solve_batch(pts, wts, m, q, kkt_tol=-1.0, max_iter=80)  # no residual is small enough
    assert capped.status == "not_converged" and not capped.complete
    assert capped.message == "0 of 30 problems met the KKT tolerance"


@pytest.mark.parametrize("k", [1, 2, 3, 5, 7, 8, 12])
def test_row_sums_are_numpys_bitwise(k):
    """Issue 26: the Newton's row sums add a few columns one by one (10x faster than
    ``.sum(1)`` on (B, 3) arrays); below SUM_COLUMNS_BELOW terms that is numpy's own order,
    so every answer stays bitwise the same (checked on 590,000 tripods when it landed)."""
    x = np.random.default_rng(SEED + k).normal(size=(1000, k)) * 10.0 ** np.arange(k)
    assert np.array_equal(sum_rows(x), x.sum(1))
    y = np.random.default_rng(SEED).normal(size=(50, k, 4))  # axis 1 of a 3-D array too
    assert np.array_equal(sum_rows(y), y.sum(1))
