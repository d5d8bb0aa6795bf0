"""Column generation: decide one candidate r of a certified COR problem, with a witness
or a certificate.

A problem (:mod:`solver.locus.membership`, :mod:`solver.sketch.sticking`) describes itself
at r by a :class:`Rows` object: its columns at outline points, the point-mass columns when
r lies in the footprint, the right-hand side b, the dual functional of a (y, lambda), and
the outline seen from r. :func:`decide` then runs the loop

1. the restricted master (:mod:`solver.certify.master`) on the columns so far;
2. a residual within ``POLISH_BELOW`` is polished (:mod:`solver.certify.witness`); at most
   ``tol.membership_residual`` after the polish: **inside**, with the witness support (a
   master that stalls below ``POLISH_LAST_TRY`` is polished once more before giving up);
3. otherwise the master's dual (scaled to max(|y|, |lambda|) <= 1) is priced over the
   outline (:mod:`solver.certify.pricing`): grid local minima refined by golden section
   (new columns where they price below -min(``tol.pricing_tol``, residual -
   ``tol.membership_residual``), :func:`pricing_threshold`);
   when none lies below y . b + ``tol.certificate_margin`` and the point-mass value does
   not either, the branch and bound bounds phi over the whole outline: a bound with
   margin over y . b is a Farkas certificate, **outside**; points below its target become
   new columns;
4. with ``certify=False`` the decision "outside" rests on the grid only and is no
   certificate.

Everything is dimensionless (the problem's local frame); the problem turns the
:class:`Decision` back into its world-frame result.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from solver.certify.functional import DualFunctional
from solver.certify.master import DirectMaster, MasterSolver, compiled_master_for, master_for
from solver.certify.outline import ON_BOUNDARY_REL, Pieces, grid
from solver.certify.pricing import COLUMNS_PER_ROUND, branch_and_bound, golden, local_minima
from solver.certify.witness import POLISH_BELOW, exact_witness, residual
from solver.core.budget import Budget
from solver.core.tolerances import SolverTolerances

POINT_MASS_RADIUS = 1e-7
"""With r in the footprint, outline points closer than this (/ L) to r are not used as
columns: their columns are within this distance of the point-mass set, which the master
has."""

POLISH_LAST_TRY = 1e-4
"""A query whose master stalls (no improving column, no certificate) with a residual at most
this is polished once more before it is called undecided: just inside a boundary the master
alone can stall a little above POLISH_BELOW (the book's 6.3 sticking end: residual 1.16e-6
at 2.7e-7 L inside, undecided until this last polish; its witness is then checked like any
other)."""

MAX_WARM_POINTS = 64
"""Most warm-start points taken from a caller (the first ones are kept)."""

REPORT_WEIGHT_REL = 1e-9
"""Support points of a non-inside decision with weights below this fraction of the largest
are left out of the reported (approximate) support."""


class Rows(Protocol):
    """A certified COR problem at one candidate r (local frame, lengths / L)."""

    @property
    def b(self) -> np.ndarray:
        """Right-hand side of the equality rows."""
        ...

    @property
    def in_footprint(self) -> bool:
        """r lies in the closed footprint: a point mass at r is allowed."""
        ...

    @property
    def pieces(self) -> Pieces:
        """The outline seen from r."""
        ...

    def columns(self, w: np.ndarray, u: np.ndarray, rho: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(G (n_eq, k), H (n_ineq, k)) of outline points w (unit directions u from r,
        distances rho > 0)."""
        ...

    def point_mass_columns(self) -> tuple[np.ndarray, np.ndarray]:
        """(PG (n_eq, 3), PH (n_ineq, 3)): the point mass at r on (P0, z0, z1)."""
        ...

    def functional(self, y: np.ndarray, lam: np.ndarray) -> DualFunctional:
        """phi = y . G - lambda . H as a function on the outline and the point-mass set."""
        ...


@dataclass(frozen=True)
class Messages:
    """What a problem calls its two decisions (for the result's message)."""

    inside: str
    outside: str


@dataclass(frozen=True)
class Decision:
    """The answer of :func:`decide` in the problem's local frame.

    ``status`` "inside" | "outside" | "undecided"; ``certificate_kind`` "witness", "dual"
    (outside with a sound branch-and-bound bound) or "none". ``points`` (k, 2) and
    ``weights`` (k,): the witness (inside) or the last master's support (others, small
    weights left out); ``point_mass`` (P0, z0, z1). ``residual``: the support's residual
    (for outside: the master's optimum). ``y``, ``lam``: the scaled dual (None for
    inside); ``lower_bound`` of phi over the footprint and point-mass set, ``margin`` =
    lower_bound - y . b, ``lower_bound_method`` "branch_and_bound" or "grid".
    """

    status: str
    certificate_kind: str
    points: np.ndarray
    weights: np.ndarray
    point_mass: np.ndarray
    residual: float
    y: np.ndarray | None
    lam: np.ndarray | None
    lower_bound: float | None
    margin: float | None
    lower_bound_method: str | None
    iterations: int
    n_columns: int
    bnb_intervals: int
    message: str


def _initial_columns(
    rows: Rows, gp: np.ndarray, gt: np.ndarray, warm_local: np.ndarray | None, min_rho: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Columns at the pricing grid's distinct points farther than ``min_rho`` from r and
    at up to MAX_WARM_POINTS warm points (local frame, on the outline)."""
    r = rows.pieces.r
    w_all, rho_all, u_all = rows.pieces.geom(gp, gt)
    usable = rho_all > min_rho
    pts, u, rho = w_all[usable], u_all[usable], rho_all[usable]
    _, uniq = np.unique(np.round(pts, 14), axis=0, return_index=True)
    uniq = np.sort(uniq)
    pts, u, rho = pts[uniq], u[uniq], rho[uniq]
    if warm_local is not None and len(warm_local):
        warm = np.asarray(warm_local, dtype=float).reshape(-1, 2)[:MAX_WARM_POINTS]
        e = warm - r
        wr = np.hypot(e[:, 0], e[:, 1])
        ok = wr > max(min_rho, ON_BOUNDARY_REL)
        if np.any(ok):
            pts = np.vstack([pts, warm[ok]])
            u = np.vstack([u, e[ok] / wr[ok][:, None]])
            rho = np.concatenate([rho, wr[ok]])
    g, h = rows.columns(pts, u, rho)
    return pts, g, h


def _clip_point_mass(pm: np.ndarray) -> np.ndarray:
    """(P0, z) moved into the cone |z| <= P0, P0 >= 0 (the master meets it to its
    tolerance only)."""
    p0 = max(float(pm[0]), 0.0)
    z = pm[1:].copy()
    zn = math.hypot(z[0], z[1])
    if zn > p0:
        z = z * (p0 / zn) if zn > 0.0 else z
    return np.array([p0, z[0], z[1]])


@dataclass
class _Pricing:
    """What one round's pricing found: the new columns (outline piece, parameter), or why
    column generation stops (``stop``, with the verdict), and the lower bound of the dual
    functional over the outline when it was computed (by ``method``)."""

    new_p: np.ndarray | None = None
    new_t: np.ndarray | None = None
    stop: str | None = None
    status: str = "undecided"
    kind: str = "none"
    lower: float | None = None
    method: str | None = None
    bnb_intervals: int = 0


def pricing_threshold(res: float, tol: SolverTolerances) -> float:
    """How far below zero a column must price to be added: ``tol.pricing_tol``, or
    res - ``tol.membership_residual`` once the residual res is that small. The L1 master's
    dual has |y|_inf <= 1 and the weights sum to about 1, so (weak duality) the columns
    pricing at -d or above can lower the residual by about d at most: only d <
    res - membership_residual shows that no column brings it to the acceptance threshold.
    The absolute tolerance alone stopped queries whose residual was already below it (a
    candidate 1.3e-7 L inside its locus, |s| = 66 L: residual 1.1e-11 after the polish,
    columns pricing at -9.4e-11; tests/solver/sketch/test_sticking_locus.py, the far
    locus). Pricing sees res > membership_residual (else the query was decided inside)."""
    return min(tol.pricing_tol, res - tol.membership_residual)


def _grid_pricing(gf: np.ndarray, minima: tuple[np.ndarray, np.ndarray, np.ndarray], yb: float, pm_val: float,
                  res: float, tol: SolverTolerances) -> _Pricing:
    """Uncertified pricing on the grid: outside as far as the grid sees, or its improving
    local minima as new columns."""
    lp, lt, lf = minima
    lower = float(min(np.min(gf), np.min(lf, initial=math.inf), pm_val))
    if lower - yb > tol.certificate_margin:
        # y separates b from every grid column: outside as far as the grid sees
        # (the certified pricing stops on the same margin, bounded soundly).
        return _Pricing(stop="grid pricing separates the candidate (not a certificate)", status="outside",
                        lower=lower, method="grid")
    improving = lf < -pricing_threshold(res, tol)
    if not np.any(improving):
        return _Pricing(stop="restricted master optimal on the grid; residual too small to decide", lower=lower,
                        method="grid")
    return _Pricing(lp[improving], lt[improving], lower=lower, method="grid")


def _certified_pricing(fn: DualFunctional, pieces: Pieces, grid_points: tuple[np.ndarray, np.ndarray],
                       minima: tuple[np.ndarray, np.ndarray, np.ndarray], yb: float, pm_val: float, res: float,
                       tol: SolverTolerances, budget: Budget, messages: Messages) -> _Pricing:
    """Certified pricing: when no grid minimum prices below the certificate's threshold, a
    sound branch and bound over the outline either certifies the candidate outside (a dual
    certificate), or finds the columns that violate it (refined by golden section)."""
    lp, lt, lf = minima
    gp, gt = grid_points
    t_cert = yb + tol.certificate_margin
    improving = lf < -pricing_threshold(res, tol)
    if not (not np.any(lf < t_cert) and pm_val >= t_cert):  # some column prices below: no certificate yet
        new_p, new_t = lp[improving], lt[improving]
        if new_p.size == 0:
            return _Pricing(stop="no improving column found")
        return _Pricing(new_p, new_t)
    target = t_cert if t_cert < -tol.pricing_tol else -tol.pricing_tol
    bnb = branch_and_bound(fn, pieces, gp, gt, target, tol.max_bnb_intervals, budget)
    found = _Pricing(lower=min(bnb.lower_bound, pm_val), method="branch_and_bound", bnb_intervals=bnb.intervals)
    if bnb.certified and found.lower - yb > tol.certificate_margin:
        return dataclasses.replace(found, stop=messages.outside, status="outside", kind="dual")
    if bnb.certified:
        return dataclasses.replace(found, stop=(
            f"column generation converged (pricing >= -{tol.pricing_tol:g}) with residual "
            f"{res:.3g} between the inside and outside thresholds"))
    if len(bnb.violators) == 0:
        return dataclasses.replace(found, stop="branch and bound hit its interval or time limit")
    vp, vlo, vhi = bnb.violators
    half = vhi - vlo
    lo = np.maximum(vlo - half, pieces.piece_lo[vp])
    hi = np.minimum(vhi + half, pieces.piece_hi[vp])
    vt, _ = golden(fn, pieces, vp, lo, hi)
    return dataclasses.replace(found, new_p=np.concatenate([lp[improving], vp]),
                               new_t=np.concatenate([lt[improving], vt]))


def decide(
    rows: Rows,
    tol: SolverTolerances,
    budget: Budget,
    messages: Messages,
    warm_local: np.ndarray | None = None,
    certify: bool = True,
) -> Decision:
    """Decide the candidate of ``rows`` (module docstring). ``warm_local``: extra initial
    support points on the outline (local frame). Stops undecided when the budget expires
    (checked before every round and inside the branch and bound).

    The restricted masters are solved by Clarabel directly (master_for); a query that ends
    undecided with time left is decided again with the compiled cvxpy formulation
    (compiled_master_for), whose different last digits decide some borderline and far
    candidates the direct one leaves (a witness or a dual certificate is checked the same
    way whichever solved the master)."""
    first, direct = _decide(rows, tol, budget, messages, warm_local, certify, master_for)
    if first.status != "undecided" or not direct or budget.expired():
        return first
    again, _ = _decide(rows, tol, budget, messages, warm_local, certify, compiled_master_for)
    return again if again.status != "undecided" else first


def _decide(rows: Rows, tol: SolverTolerances, budget: Budget, messages: Messages, warm_local: np.ndarray | None,
            certify: bool, master: Callable[[int, int, int], MasterSolver]) -> tuple[Decision, bool]:
    """:func:`decide` with the masters of ``master``, and whether they were direct ones."""
    pieces = rows.pieces
    gp, gt = grid(pieces)
    in_f = rows.in_footprint
    min_rho = POINT_MASS_RADIUS if in_f else 0.0
    pts, g, h = _initial_columns(rows, gp, gt, warm_local, min_rho)
    pg, ph = rows.point_mass_columns() if in_f else (None, None)
    n_eq, n_ineq = g.shape[0], h.shape[0]
    direct = isinstance(master(n_eq, n_ineq, g.shape[1]), DirectMaster)

    status, kind, message = "undecided", "none", ""
    weights = np.zeros(g.shape[1])
    pm = np.zeros(3)
    res = math.inf
    y = lam = None
    lower = margin = None
    method = None
    bnb_total = 0
    iterations = 0
    for iterations in range(1, tol.max_cg_iter + 1):
        if budget.expired():
            limit = "" if budget.limit_s is None else f" {budget.limit_s:g} s"
            message = f"time limit{limit} reached"
            iterations -= 1
            break
        weights, pm_raw, y_raw, lam_raw = master(n_eq, n_ineq, g.shape[1]).solve(g, h, pg, ph, rows.b, tol)
        pm = _clip_point_mass(pm_raw) if in_f else np.zeros(3)
        res = residual(rows.b, g, h, weights, pg, ph, pm)
        if res <= max(POLISH_BELOW, tol.membership_residual):
            weights, pm, res = exact_witness(rows.b, g, h, weights, pm, pg, ph, tol.membership_residual)
            if res <= tol.membership_residual:
                status, kind, message = "inside", "witness", messages.inside
                break
        scale = max(1.0, float(np.max(np.abs(y_raw))), float(np.max(lam_raw, initial=0.0)))
        y, lam = y_raw / scale, lam_raw / scale
        yb = float(y @ rows.b)
        fn = rows.functional(y, lam)
        pm_val = fn.point_mass_value() if in_f else math.inf
        gf = fn.values(pieces, gp, gt)
        minima = local_minima(fn, pieces, gt, gf, COLUMNS_PER_ROUND)
        if certify:
            pr = _certified_pricing(fn, pieces, (gp, gt), minima, yb, pm_val, res, tol, budget, messages)
        else:
            pr = _grid_pricing(gf, minima, yb, pm_val, res, tol)
        bnb_total += pr.bnb_intervals
        if pr.lower is not None:
            lower, margin, method = pr.lower, pr.lower - yb, pr.method
        if pr.stop is not None:
            status, kind, message = pr.status, pr.kind, pr.stop
            if status == "undecided" and res <= POLISH_LAST_TRY:
                w2, pm2, res2 = exact_witness(rows.b, g, h, weights, pm, pg, ph, tol.membership_residual)
                if res2 <= tol.membership_residual:
                    weights, pm, res = w2, pm2, res2
                    status, kind, message = "inside", "witness", messages.inside
            break
        new_p, new_t = pr.new_p, pr.new_t
        nw, nrho, nu = pieces.geom(new_p, new_t)
        ok = nrho > min_rho
        if not np.any(ok):
            message = "pricing points coincide with the candidate"
            break
        g2, h2 = rows.columns(nw[ok], nu[ok], nrho[ok])
        g = np.hstack([g, g2])
        h = np.hstack([h, h2])
        pts = np.vstack([pts, nw[ok]])
        weights = np.concatenate([weights, np.zeros(int(np.sum(ok)))])
    else:
        message = message or f"no decision after {tol.max_cg_iter} column-generation rounds"

    if status == "inside":
        sel = weights > 0.0
        y = lam = lower = margin = method = None
    else:
        sel = weights > REPORT_WEIGHT_REL * float(np.max(weights, initial=0.0))
    return Decision(
        status=status,
        certificate_kind=kind,
        points=pts[sel],
        weights=weights[sel],
        point_mass=pm if in_f else np.zeros(3),
        residual=float(res),
        y=y,
        lam=lam,
        lower_bound=lower,
        margin=margin,
        lower_bound_method=method,
        iterations=iterations,
        n_columns=int(g.shape[1]),
        bnb_intervals=bnb_total,
        message=message,
    ), direct
