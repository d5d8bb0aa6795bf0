"""The restricted master of column generation: one L1-residual LP/SOCP for every certified
COR problem (cvxpy + Clarabel), compiled once per shape and re-solved with Parameters.

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
solves.
"""

from __future__ import annotations

import cvxpy as cp
import numpy as np

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


_MASTERS: PerThreadCache[tuple[int, int, int], RestrictedMaster] = PerThreadCache()
"""(n_eq, n_ineq, capacity) -> this thread's compiled master."""


def master_for(n_eq: int, n_ineq: int, n_columns: int) -> RestrictedMaster:
    """This thread's compiled master of the shape with room for ``n_columns`` columns."""
    if n_ineq:  # the sticking masters keep doubling (see CAPACITY_STEP)
        cap = BASE_CAPACITY
        while cap < n_columns:
            cap *= 2
    else:
        cap = max(BASE_CAPACITY, -(-n_columns // CAPACITY_STEP) * CAPACITY_STEP)
    return _MASTERS.get((n_eq, n_ineq, cap), lambda: RestrictedMaster(n_eq, n_ineq, cap))
