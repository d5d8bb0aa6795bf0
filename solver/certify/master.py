"""The restricted master of column generation: one L1-residual LP/SOCP for every certified
COR problem, solved by Clarabel, in two formulations: handed over directly in its conic
form (:class:`DirectMaster`, what :func:`master_for` gives without inequality rows) or
through cvxpy, compiled once per shape and re-solved with Parameters
(:class:`RestrictedMaster`, the reference, and the masters with inequality rows).

    min  ||e||_1 + sum(t)
    s.t. G P + PG (P0, z) - e = b            (equality rows: weights, centroid, ...)
         H P + PH (P0, z) + t >= 0, t >= 0   (the optional inequality block, e.g. a
                                              friction cone)
         P >= 0,  |z| <= P0                  (a point mass at r with its subgradient z)

Its optimum is 0 iff b is a non-negative combination of the columns (with the point mass
and the inequalities), and its duals (y on the equalities, lambda >= 0 on the
inequalities) satisfy y . G_j - lambda . H_j >= 0 on every column and y . b = -optimum:
the separating functional that pricing minimises over the outline
(:mod:`solver.certify.functional`).

Compiled problems are kept per thread (:class:`solver.core.threads.PerThreadCache`): no
cvxpy problem is ever used by two threads at once, and threads never wait for each other's
solves. A direct master keeps nothing between solves.
"""

from __future__ import annotations

from typing import Protocol

import clarabel
import cvxpy as cp
import numpy as np
import scipy.sparse as sp

from solver.core.backends import in_backend
from solver.core.errors import NotConverged
from solver.core.threads import PerThreadCache, ignore_inaccurate_solution_warning
from solver.core.tolerances import SolverTolerances

BASE_CAPACITY = 320
CAPACITY_STEP = 64
"""Column capacities of the compiled masters: BASE_CAPACITY, then the next multiple of
CAPACITY_STEP (one compiled problem each per shape and thread, ~15 ms to compile); unused
columns are padded with copies of column 0. Clarabel's time grows with the padded size:
doubling (the earlier ladder) padded 74 % of the part-bound map's masters, 319-386 columns,
to 640, at 6.2 ms a solve against 3.5 ms at 400 (issue 26's profile). The masters with
inequality rows (the sticking locus's friction cone) keep doubling: at 384 columns a far
sticking end (65 L from the contact) moved in its last digits to a point whose membership
query stalls undecided (tests/solver/sketch/test_sticking_locus.py, the far locus), and
they gain little (a tenth of their solves exceed 320 columns)."""


class MasterSolver(Protocol):
    """What column generation asks of a restricted master (either formulation below)."""

    def solve(self, g: np.ndarray, h: np.ndarray, pg: np.ndarray | None, ph: np.ndarray | None, b: np.ndarray,
              tol: SolverTolerances) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]: ...


class RestrictedMaster:
    """The master of the module docstring for ``n_eq`` equality rows, ``n_ineq`` (possibly
    0) inequality rows and ``capacity`` columns."""

    def __init__(self, n_eq: int, n_ineq: int, capacity: int):
        self.n_eq, self.n_ineq, self.capacity = n_eq, n_ineq, capacity
        self.g = cp.Parameter((n_eq, capacity))
        self.pg = cp.Parameter((n_eq, 3))
        self.b = cp.Parameter(n_eq)
        self.p = cp.Variable(capacity, nonneg=True)
        self.pm = cp.Variable(3)  # (P0, z0, z1)
        self.e = cp.Variable(n_eq)
        self.eq = self.g @ self.p + self.pg @ self.pm - self.e == self.b
        constraints = [self.eq, cp.SOC(self.pm[0], self.pm[1:])]
        objective = cp.norm1(self.e)
        if n_ineq:
            self.h = cp.Parameter((n_ineq, capacity))
            self.ph = cp.Parameter((n_ineq, 3))
            self.t = cp.Variable(n_ineq, nonneg=True)
            self.ineq = self.h @ self.p + self.ph @ self.pm + self.t >= 0
            constraints.append(self.ineq)
            objective = objective + cp.sum(self.t)
        self.problem = cp.Problem(cp.Minimize(objective), constraints)

    def solve(
        self, g: np.ndarray, h: np.ndarray, pg: np.ndarray | None, ph: np.ndarray | None, b: np.ndarray,
        tol: SolverTolerances,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(weights (n,), point mass (P0, z0, z1), y (n_eq,), lambda (n_ineq,)) for the
        columns ``g`` (n_eq, n) and ``h`` (n_ineq, n); ``pg``/``ph`` None: no point mass."""
        n = g.shape[1]
        a = np.empty((self.n_eq, self.capacity))
        a[:, :n] = g
        a[:, n:] = g[:, :1]  # padding: copies of column 0 (merged back below)
        self.g.value = a
        self.pg.value = np.zeros((self.n_eq, 3)) if pg is None else pg
        self.b.value = b
        if self.n_ineq:
            hm = np.empty((self.n_ineq, self.capacity))
            hm[:, :n] = h
            hm[:, n:] = h[:, :1]
            self.h.value = hm
            self.ph.value = np.zeros((self.n_ineq, 3)) if ph is None else ph
        try:
            ignore_inaccurate_solution_warning()
            # warm_start=False: a fresh Clarabel solver for every solve, so that an answer
            # does not depend on the queries this thread solved before (with warm_start,
            # cvxpy updates the previous solver's data in place and Clarabel keeps the
            # first data's equilibration, which changes the last digits of later answers and
            # can flip a borderline decision). It costs about 10 % per query; turning the
            # equilibration off instead is as fast and reproducible but leaves some far and
            # borderline candidates undecided.
            with in_backend("clarabel"):
                self.problem.solve(
                    solver=cp.CLARABEL, warm_start=False,
                    tol_gap_abs=tol.conic_gap, tol_gap_rel=tol.conic_gap, tol_feas=tol.conic_gap,
                )
        except cp.error.SolverError as exc:
            raise NotConverged(f"Clarabel failed on the restricted master: {exc}") from exc
        if self.problem.status not in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE) or self.p.value is None:
            raise NotConverged(f"the restricted master ended with status {self.problem.status}")
        p = np.clip(np.asarray(self.p.value, dtype=float), 0.0, None)
        y = np.asarray(self.eq.dual_value, dtype=float).reshape(self.n_eq)
        if self.n_ineq:
            lam = np.clip(np.asarray(self.ineq.dual_value, dtype=float).reshape(self.n_ineq), 0.0, None)
        else:
            lam = np.zeros(0)
        pm = np.zeros(3) if pg is None else np.asarray(self.pm.value, dtype=float)
        weights = p[:n].copy()
        weights[0] += float(np.sum(p[n:]))
        return weights, pm, y, lam


class DirectMaster:
    """The same master handed to Clarabel directly in its conic form, at the exact number of
    columns (no compiled problem, no padding): cvxpy's parameter stuffing and unpacking
    were about half of each solve (issue 26's profile). Variables x = (P, P0, z, e, u, t):

        min  sum(u) + sum(t)
        s.t. G P + PG (P0, z) - e = b                 zero cone (duals y)
             -P <= 0,  e - u <= 0,  -e - u <= 0,  -t <= 0,
             -H P - PH (P0, z) - t <= 0               non-negative cone (duals lambda last)
             (P0, z) in the second-order cone

    Clarabel's duals z of ``A x + s = b`` satisfy c + A' z = 0, so on column j
    y . G_j - lambda . H_j = z_(P_j) >= 0 and y . b = -optimum: the separating functional
    of :class:`RestrictedMaster` with the same signs (tests/solver/certify/test_master.py
    checks the two against each other). Every solve starts cold, as there."""

    def __init__(self, n_eq: int, n_ineq: int):
        self.n_eq, self.n_ineq = n_eq, n_ineq

    def solve(
        self, g: np.ndarray, h: np.ndarray, pg: np.ndarray | None, ph: np.ndarray | None, b: np.ndarray,
        tol: SolverTolerances,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """As :meth:`RestrictedMaster.solve`."""
        m, k = self.n_eq, self.n_ineq
        n = g.shape[1]
        has_point_mass = pg is not None
        pg = np.zeros((m, 3)) if pg is None else np.asarray(pg, dtype=float)
        h = np.asarray(h, dtype=float).reshape(k, n)
        ph = np.zeros((k, 3)) if ph is None or not k else np.asarray(ph, dtype=float)
        a = _conic_matrix(np.asarray(g, dtype=float), h, pg, ph)
        n_x = n + 3 + 2 * m + k
        rhs = np.concatenate([np.asarray(b, dtype=float), np.zeros(a.shape[0] - m)])
        q = np.concatenate([np.zeros(n + 3 + m), np.ones(m + k)])
        cones = [clarabel.ZeroConeT(m), clarabel.NonnegativeConeT(n + 2 * m + 2 * k), clarabel.SecondOrderConeT(3)]
        settings = clarabel.DefaultSettings()
        settings.verbose = False
        settings.tol_gap_abs = settings.tol_gap_rel = settings.tol_feas = tol.conic_gap
        try:
            with in_backend("clarabel"):
                solution = clarabel.DefaultSolver(sp.csc_matrix((n_x, n_x)), q, a, rhs, cones, settings).solve()
        except Exception as exc:  # Clarabel's own errors (bad data, a panic) have no common base
            raise NotConverged(f"Clarabel failed on the restricted master: {exc}") from exc
        status = str(solution.status)
        if status not in ("Solved", "AlmostSolved"):
            raise NotConverged(f"the restricted master ended with status {status}")
        x, z = np.asarray(solution.x), np.asarray(solution.z)
        weights = np.clip(x[:n], 0.0, None)
        pm = x[n:n + 3].copy() if has_point_mass else np.zeros(3)
        y = z[:m].copy()
        lam = np.clip(z[m + n + 2 * m + k:m + n + 2 * m + 2 * k], 0.0, None) if k else np.zeros(0)
        return weights, pm, y, lam


def _conic_matrix(g: np.ndarray, h: np.ndarray, pg: np.ndarray, ph: np.ndarray) -> sp.csc_matrix:
    """DirectMaster's A, column by column (P, (P0, z), e, u, t) in CSC arrays; rows: the m
    equalities, then -P, e - u, -e - u, -t, -H P - PH (P0, z) - t, then the cone's 3."""
    m, n = g.shape
    k = h.shape[0]
    r_p, r_eu, r_neu, r_t, r_h, r_soc = m, m + n, 2 * m + n, 3 * m + n, 3 * m + n + k, 3 * m + n + 2 * k
    # P_j: G[:, j], -1 at its own row, -H[:, j]
    p_rows = np.concatenate([np.broadcast_to(np.arange(m)[:, None], (m, n)), (r_p + np.arange(n))[None, :],
                             np.broadcast_to((r_h + np.arange(k))[:, None], (k, n))])
    p_data = np.concatenate([g, -np.ones((1, n)), -h])
    # (P0, z)_c: PG[:, c], -PH[:, c], -1 in the cone
    c_rows = np.concatenate([np.broadcast_to(np.arange(m)[:, None], (m, 3)),
                             np.broadcast_to((r_h + np.arange(k))[:, None], (k, 3)), (r_soc + np.arange(3))[None, :]])
    c_data = np.concatenate([pg, -ph, -np.ones((1, 3))])
    i_m, i_k = np.arange(m), np.arange(k)
    e_rows = np.stack([i_m, r_eu + i_m, r_neu + i_m])  # e_i: -1 (equality), +1 (e - u), -1 (-e - u)
    e_data = np.broadcast_to(np.array([[-1.0], [1.0], [-1.0]]), (3, m))
    u_rows = np.stack([r_eu + i_m, r_neu + i_m])
    t_rows = np.stack([r_t + i_k, r_h + i_k])
    rows = np.concatenate([p_rows.T.ravel(), c_rows.T.ravel(), e_rows.T.ravel(), u_rows.T.ravel(), t_rows.T.ravel()])
    data = np.concatenate([p_data.T.ravel(), c_data.T.ravel(), e_data.T.ravel(), -np.ones(2 * m), -np.ones(2 * k)])
    counts = np.concatenate([np.full(n, m + 1 + k), np.full(3, m + k + 1), np.full(m, 3), np.full(m, 2), np.full(k, 2)])
    indptr = np.concatenate([[0], np.cumsum(counts)])
    return sp.csc_matrix((data, rows, indptr), shape=(r_soc + 3, n + 3 + 2 * m + k))


_MASTERS: PerThreadCache[tuple[int, int, int], RestrictedMaster] = PerThreadCache()
"""(n_eq, n_ineq, capacity) -> this thread's compiled master."""


def compiled_master_for(n_eq: int, n_ineq: int, n_columns: int) -> RestrictedMaster:
    """This thread's compiled (cvxpy) master of the shape with room for ``n_columns``
    columns: the reference formulation the direct one is checked against."""
    if n_ineq:  # the sticking masters keep doubling (see CAPACITY_STEP)
        cap = BASE_CAPACITY
        while cap < n_columns:
            cap *= 2
    else:
        cap = max(BASE_CAPACITY, -(-n_columns // CAPACITY_STEP) * CAPACITY_STEP)
    return _MASTERS.get((n_eq, n_ineq, cap), lambda: RestrictedMaster(n_eq, n_ineq, cap))


def master_for(n_eq: int, n_ineq: int, n_columns: int) -> MasterSolver:
    """The master column generation solves: Clarabel called directly (:class:`DirectMaster`;
    it holds no solver state, so threads may share it), except with inequality rows (the
    sticking locus's friction cone), which keep the compiled formulation: with the direct
    one the far sticking end of tests/solver/sketch/test_sticking_locus.py moved in its last
    digits to a witness whose membership in its frictionless locus neither formulation
    decides."""
    if n_ineq:
        return compiled_master_for(n_eq, n_ineq, n_columns)
    return DirectMaster(n_eq, n_ineq)
