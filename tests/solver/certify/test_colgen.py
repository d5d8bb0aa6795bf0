"""Column generation (solver/certify/colgen.py) on a certified problem's rows: an inside
candidate ends with a witness satisfying the rows to rounding, an outside one with a dual
whose certified bound over the whole outline has the margin (checked by dense sampling of
the functional), grid-only pricing is labelled as no certificate, an expired budget leaves
the candidate undecided, and warm columns are used. The rows are membership's (3.8)-(3.10)
for the disk, in the locus frame."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from models.locus.cor_disk import disk_cor_locus
from solver.certify.colgen import MAX_WARM_POINTS, Messages, decide, pricing_threshold
from solver.certify.outline import grid
from solver.certify.witness import residual
from solver.core.budget import UNLIMITED, Budget
from solver.core.tolerances import SOLVER_DEFAULT
from solver.locus.membership import PlainRows, outline_of
from tests.budgets import checks_budget
from tests.scenes import scene_for_mu

TOL = SOLVER_DEFAULT
MESSAGES = Messages(inside="in", outside="out")
SCENE = scene_for_mu(0.3)


def _rows(point_world) -> PlainRows:
    outline = outline_of(SCENE, None)
    r, on = outline.snap(outline.to_local(point_world))
    alpha = outline.vector_to_local(SCENE.alpha_hat)
    c = outline.vector_to_local(SCENE.contact_rel) / outline.length
    return PlainRows(outline, r, on, outline.contains(r, on), alpha, float(alpha @ (c - r)))


def _boundary_pair(k=5, offset=1e-3):
    ring = disk_cor_locus(SCENE, n_points=32).boundary
    tangent = ring[(k + 1) % 32] - ring[k - 1]
    nu = np.array([tangent[1], -tangent[0]]) / np.hypot(*tangent)
    return ring[k] - offset * nu, ring[k] + offset * nu


def test_inside_ends_with_a_witness_on_the_rows():
    rows = _rows(_boundary_pair()[0])
    dec = decide(rows, TOL, UNLIMITED, MESSAGES)
    assert dec.status == "inside" and dec.certificate_kind == "witness" and dec.message == "in"
    assert dec.y is None and dec.lower_bound is None
    g, h = rows.columns(dec.points, *_directions(rows, dec.points))
    pg, ph = rows.point_mass_columns() if rows.in_footprint else (None, None)
    assert residual(rows.b, g, h, dec.weights, pg, ph, dec.point_mass) <= TOL.membership_residual
    assert np.all(dec.weights > 0.0)


def _directions(rows, pts):
    e = pts - rows.pieces.r
    rho = np.hypot(e[:, 0], e[:, 1])
    return e / rho[:, None], rho


def test_outside_ends_with_a_certified_dual_checked_by_dense_sampling():
    rows = _rows(_boundary_pair()[1])
    dec = decide(rows, TOL, UNLIMITED, MESSAGES)
    assert dec.status == "outside" and dec.certificate_kind == "dual" and dec.message == "out"
    assert dec.lower_bound_method == "branch_and_bound"
    assert dec.margin == pytest.approx(dec.lower_bound - float(dec.y @ rows.b), abs=1e-15)
    assert dec.margin > TOL.certificate_margin
    fn = rows.functional(dec.y, dec.lam)
    t = np.linspace(0.0, 2.0 * np.pi, 400_001)
    vals = fn.evaluate(rows.pieces, (t > np.pi).astype(int), t)[0]
    assert vals.min() >= dec.lower_bound - 1e-15
    # the dual separates every column the master had: y . G_j >= 0 (to the conic tolerance)
    g, _ = rows.columns(dec.points, *_directions(rows, dec.points))
    assert np.all(dec.y @ g >= -1e-8)


def test_grid_pricing_is_no_certificate():
    dec = decide(_rows(_boundary_pair()[1]), TOL, UNLIMITED, MESSAGES, certify=False)
    assert dec.status == "outside" and dec.certificate_kind == "none" and dec.lower_bound_method == "grid"
    assert "not a certificate" in dec.message


def test_an_expired_budget_leaves_the_candidate_undecided():
    dec = decide(_rows(_boundary_pair()[1]), TOL, Budget.of(0.0), MESSAGES)
    assert dec.status == "undecided" and dec.iterations == 0 and "time limit" in dec.message
    dec = decide(_rows(_boundary_pair(offset=5e-7)[1]), TOL, checks_budget(2), MESSAGES)
    assert dec.status in ("undecided", "outside") and dec.iterations <= 2


def test_warm_columns_are_taken_and_capped():
    """A previous witness given as warm columns lets the next query end in one round; at
    most MAX_WARM_POINTS warm points join the grid's columns."""
    inner = _rows(_boundary_pair()[0])
    first = decide(inner, TOL, UNLIMITED, MESSAGES)
    again = decide(inner, TOL, UNLIMITED, MESSAGES, warm_local=first.points)
    assert again.status == "inside" and again.iterations == 1
    gp, gt = grid(inner.pieces)
    n_grid = len(np.unique(np.round(inner.pieces.geom(gp, gt)[0], 14), axis=0))
    many = decide(inner, TOL, UNLIMITED, MESSAGES, warm_local=inner.pieces.geom(np.zeros(200, int),
                                                                                np.linspace(0.01, 3.0, 200))[0])
    assert many.n_columns - 4 * (many.iterations - 1) <= n_grid + MAX_WARM_POINTS
    assert many.n_columns >= n_grid + MAX_WARM_POINTS


def test_a_query_the_direct_master_leaves_undecided_is_decided_again_on_the_compiled_one(monkeypatch):
    """Issue 26: decide solves its masters with Clarabel directly; only a query that ends
    undecided there, with time left, is decided again on the compiled (cvxpy) masters, and
    the second answer is taken only when it decides. Masters that are compiled anyway (with
    inequality rows) are not solved twice."""
    import solver.certify.colgen as colgen
    from solver.certify.master import compiled_master_for, master_for

    real = decide(_rows(_boundary_pair()[0]), TOL, UNLIMITED, MESSAGES)
    calls = []

    def fake(answers, direct=True):
        def run(rows, tol, budget, messages, warm_local, certify, master):
            calls.append(master)
            status = answers[len(calls) - 1]
            return dataclasses.replace(real, status=status, message=status), direct
        return run

    for answers, direct, budget, want, n_calls in (
        (["undecided", "outside"], True, UNLIMITED, "outside", 2),
        (["undecided", "undecided"], True, UNLIMITED, "undecided", 2),
        (["inside"], True, UNLIMITED, "inside", 1),
        (["undecided"], False, UNLIMITED, "undecided", 1),  # compiled already: the same answer again
        (["undecided"], True, checks_budget(0), "undecided", 1),  # no time left
    ):
        calls.clear()
        monkeypatch.setattr(colgen, "_decide", fake(answers, direct))
        got = decide(_rows(_boundary_pair()[0]), TOL, budget, MESSAGES)
        assert got.status == want and len(calls) == n_calls
        assert calls[0] is master_for and all(m is compiled_master_for for m in calls[1:])


def test_a_residual_below_the_pricing_tolerance_does_not_stop_improving_columns():
    """Weak duality: a column pricing at -d lowers the L1 residual by about d at most, so
    once the residual is below pricing_tol, columns pricing below -(residual -
    membership_residual) are still improving (the far sticking end of
    tests/solver/sketch/test_sticking_locus.py stalled at residual 1.1e-11 with columns at
    -9.4e-11, 'no improving column found'); with a larger residual pricing_tol rules."""
    assert pricing_threshold(1e-6, TOL) == TOL.pricing_tol
    assert pricing_threshold(TOL.pricing_tol + TOL.membership_residual, TOL) == pytest.approx(TOL.pricing_tol)
    assert pricing_threshold(1.1e-11, TOL) == pytest.approx(1.1e-11 - TOL.membership_residual)
    assert -9.4e-11 < -pricing_threshold(1.1e-11, TOL) and pricing_threshold(2e-12, TOL) > 0.0
