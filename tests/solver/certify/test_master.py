"""The restricted master (solver/certify/master.py): its optimum is 0 exactly when b is a
non-negative combination of the columns, its duals separate otherwise (y . G_j -
lambda . H_j >= 0 on the columns, y . b = -optimum: the Farkas functional that pricing
minimises), compiled problems are per thread, and answers do not depend on what the thread
solved before."""

from __future__ import annotations

import threading

import cvxpy as cp
import numpy as np
import pytest

from solver.certify.master import BASE_CAPACITY, CAPACITY_STEP, compiled_master_for, master_for
from solver.core.errors import NotConverged, SolverError
from solver.core.tolerances import SOLVER_DEFAULT
from tests.scenes import SEED

TOL = SOLVER_DEFAULT


def _instance(rng, feasible: bool, n_ineq: int = 0):
    g = np.vstack([np.ones(40), rng.normal(size=(3, 40))])
    h = rng.normal(size=(n_ineq, 40))
    p = np.zeros(40)
    p[:4] = rng.uniform(0.1, 1.0, 4)
    p /= p.sum()
    b = g @ p if feasible else np.array([1.0, 5.0, 5.0, 5.0]) + np.abs(g[1:].max())
    if feasible and n_ineq:
        h[:, :4] = np.abs(h[:, :4])  # the chosen columns satisfy the inequalities
    return g, h, b


@pytest.mark.parametrize("n_ineq", [0, 2])
def test_a_feasible_right_hand_side_has_optimum_zero(n_ineq):
    g, h, b = _instance(np.random.default_rng(SEED), True, n_ineq)
    weights, pm, y, lam = master_for(4, n_ineq, 40).solve(g, h, None, None, b, TOL)
    assert np.all(weights >= 0.0) and np.all(pm == 0.0)
    assert np.abs(g @ weights - b).sum() < 1e-8
    assert lam.shape == (n_ineq,) and np.all(lam >= 0.0)
    if n_ineq:
        assert np.all(h @ weights >= -1e-8)


def test_an_infeasible_right_hand_side_is_separated_by_the_dual():
    """Farkas: y . G_j >= 0 for every column and y . b = -(L1 optimum) < 0."""
    g, h, b = _instance(np.random.default_rng(SEED + 1), False)
    weights, _, y, _ = master_for(4, 0, 40).solve(g, h, None, None, b, TOL)
    optimum = np.abs(g @ weights - b).sum()
    assert optimum > 1.0
    assert y @ b == pytest.approx(-optimum, rel=1e-6)
    assert np.all(y @ g >= -1e-7) and np.max(np.abs(y)) <= 1.0 + 1e-7


def test_capacities_grow_in_steps_and_pad_with_column_zero():
    """Issue 26: past BASE_CAPACITY the compiled master's capacity is the next multiple of
    CAPACITY_STEP (the doubling ladder padded most of the part-bound map's masters from
    ~330 to 640 columns, nearly doubling Clarabel's time); masters with inequality rows
    keep doubling."""
    m = compiled_master_for(4, 0, BASE_CAPACITY + 1)
    assert m.capacity == BASE_CAPACITY + CAPACITY_STEP
    assert compiled_master_for(4, 0, 700).capacity == 704 and compiled_master_for(4, 0, 10).capacity == BASE_CAPACITY
    assert compiled_master_for(4, 2, BASE_CAPACITY + 1).capacity == 2 * BASE_CAPACITY
    g, h, b = _instance(np.random.default_rng(SEED + 2), True)
    weights, *_ = m.solve(g, h, None, None, b, TOL)  # 40 columns in a 384-column problem
    assert weights.shape == (40,) and np.abs(g @ weights - b).sum() < 1e-8


def test_compiled_masters_are_per_thread():
    mine = compiled_master_for(5, 0, 10)
    assert compiled_master_for(5, 0, 200) is mine
    other = []
    t = threading.Thread(target=lambda: other.append(compiled_master_for(5, 0, 10)))
    t.start()
    t.join()
    assert other[0] is not mine


@pytest.mark.parametrize("n_ineq", [0, 2])
@pytest.mark.parametrize("feasible", [True, False])
@pytest.mark.parametrize("point_mass", [False, True])
def test_the_direct_master_is_the_compiled_one(n_ineq, feasible, point_mass):
    """Issue 26: the master handed to Clarabel directly (DirectMaster, no cvxpy) and the
    cvxpy formulation give the same optimum and the same separating duals (y, lambda:
    the Farkas functional is unique here), with and without the point mass (P0, z) and the
    inequality rows; the primal weights may differ where the optimum is not unique."""
    rng = np.random.default_rng(SEED + 10 + 4 * n_ineq + 2 * feasible + point_mass)
    g, h, b = _instance(rng, feasible, n_ineq)
    pg = 0.1 * rng.normal(size=(4, 3)) if point_mass else None
    ph = 0.1 * rng.normal(size=(n_ineq, 3)) if point_mass else None
    direct = master_for(4, n_ineq, 40).solve(g, h, pg, ph, b, TOL)
    compiled = compiled_master_for(4, n_ineq, 40).solve(g, h, pg, ph, b, TOL)

    def optimum(weights, pm):
        e = g @ weights + (0.0 if pg is None else pg @ pm) - b
        t = -(h @ weights + (0.0 if ph is None else ph @ pm))
        return np.abs(e).sum() + np.clip(t, 0.0, None).sum()

    assert optimum(direct[0], direct[1]) == pytest.approx(optimum(compiled[0], compiled[1]), abs=1e-8)
    assert np.abs(direct[2] - compiled[2]).max() < 1e-8
    assert np.abs(direct[3] - compiled[3]).max(initial=0.0) < 1e-8
    assert direct[2] @ b == pytest.approx(-optimum(direct[0], direct[1]), abs=1e-8)
    if not point_mass:
        assert np.all(direct[1] == 0.0)


def test_answers_do_not_depend_on_what_was_solved_before():
    """No warm start: the same master solved after a different one gives bitwise the same
    answer."""
    rng = np.random.default_rng(SEED + 3)
    g1, h1, b1 = _instance(rng, False)
    g2, h2, b2 = _instance(rng, True)
    m = master_for(4, 0, 40)
    first = m.solve(g1, h1, None, None, b1, TOL)
    m.solve(g2, h2, None, None, b2, TOL)
    again = m.solve(g1, h1, None, None, b1, TOL)
    for x, z in zip(first, again):
        assert np.array_equal(x, z)


def test_a_failing_conic_solve_is_not_converged(monkeypatch):
    def boom(*args, **kwargs):
        raise cp.error.SolverError("boom")

    monkeypatch.setattr(cp.Problem, "solve", boom)
    g, h, b = _instance(np.random.default_rng(SEED), True)
    with pytest.raises(NotConverged) as err:
        compiled_master_for(4, 0, 40).solve(g, h, None, None, b, TOL)
    assert isinstance(err.value, SolverError)


def test_a_direct_master_that_does_not_solve_is_not_converged(monkeypatch):
    """Clarabel stopped short (here its answer replaced by one of status MaxIterations):
    NotConverged, never a wrong answer."""
    import clarabel

    real = clarabel.DefaultSolver

    class Stopped:
        def __init__(self, *args):
            self.inner = real(*args)

        def solve(self):
            out = self.inner.solve()
            return type("Solution", (), {"status": "MaxIterations", "x": out.x, "z": out.z})()

    monkeypatch.setattr(clarabel, "DefaultSolver", Stopped)
    g, h, b = _instance(np.random.default_rng(SEED), False)
    with pytest.raises(NotConverged) as err:
        master_for(4, 0, 40).solve(g, h, None, None, b, TOL)
    assert isinstance(err.value, SolverError) and "MaxIterations" in str(err.value)
