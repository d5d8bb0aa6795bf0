"""CasADi/IPOPT minimisation of the particle power (2.30) against the closed forms of
models/particle/balance.py and Newton's law (2.29) (book 2.5)."""

from __future__ import annotations

import math

import pytest

from models.core.errors import InvalidInput
from models.particle import balance as mp
from solver.core.errors import NotConverged, SolverError
from solver.core.outcome import Outcome
from solver.particle import solve as sp


@pytest.mark.parametrize("v_x,mg,eta", [(1.0, 1.0, 2.0), (0.2, 3.0, 4.0), (5.0, 0.1, 0.11)])
def test_n0_numeric_mpp_equals_newton(v_x, mg, eta):
    sol = sp.solve_particle(v_x, mg, eta, 0.0)
    assert sol.status == "Solve_Succeeded"
    assert sol.mpp_v_y_numeric == pytest.approx(sol.newton_v_y, rel=1e-10)
    assert abs(sol.relative_disagreement) <= 1e-10
    # Newton independently: v_y/|v| = mg/eta
    assert sol.newton_v_y / math.hypot(v_x, sol.newton_v_y) == pytest.approx(mg / eta, rel=1e-12)


@pytest.mark.parametrize("v_x,mg,eta", [(1.0, 1.0, 2.0), (0.05, 2.0, 0.5), (30.0, 1.0, 1e-3)])
def test_n1_numeric_mpp_is_half_of_newton(v_x, mg, eta):
    sol = sp.solve_particle(v_x, mg, eta, 1.0)
    assert sol.newton_v_y == pytest.approx(mg / eta, rel=1e-14)
    assert sol.mpp_v_y_numeric == pytest.approx(0.5 * mg / eta, rel=1e-10)
    assert sol.relative_disagreement == pytest.approx(0.5, rel=1e-12)


@pytest.mark.parametrize("n", [0.5, 2.0, 3.0, 0.05])
@pytest.mark.parametrize("v_x,mg,eta", [(1.0, 1.0, 2.0), (0.3, 2.0, 1.0), (40.0, 1.0, 0.01)])
def test_numeric_minimiser_equals_the_closed_form(n, v_x, mg, eta):
    sol = sp.solve_particle(v_x, mg, eta, n)
    assert sol.numeric_error <= 1e-10
    assert sol.mpp_v_y_numeric == pytest.approx(mp.mpp_v_y(v_x, mg, eta, n), rel=1e-10)
    # the minimiser of the power is not Newton's answer, and it really has lower power
    assert sol.relative_disagreement > 1e-3
    assert sol.power_mpp < sol.power_newton
    # the disagreement is the one predicted by (2.29) vs (2.32): g_n(mpp) (n+1) = g_n(newton)
    g = lambda u: float(mp.balance_function(u, v_x, n))
    assert (n + 1.0) * g(sol.mpp_v_y_numeric) == pytest.approx(g(sol.newton_v_y), rel=1e-9)


def test_n2_disagreement_by_the_predicted_factor():
    """n = 2, v_x = 1, mg/eta = 1: u^2 (1 + u^2) = k^2 gives u^2 = (sqrt(1 + 4k^2) - 1)/2."""
    sol = sp.solve_particle(1.0, 1.0, 1.0, 2.0)
    newton = math.sqrt((math.sqrt(5.0) - 1.0) / 2.0)
    mpp = math.sqrt((math.sqrt(1.0 + 4.0 / 9.0) - 1.0) / 2.0)
    assert sol.newton_v_y == pytest.approx(newton, rel=1e-13)
    assert sol.mpp_v_y_numeric == pytest.approx(mpp, rel=1e-10)
    assert sol.relative_disagreement == pytest.approx(1.0 - mpp / newton, rel=1e-12)


def test_badly_scaled_inputs_still_converge():
    """K = mg / (eta v_x^n) from 1e-12 to 1e21: the scaled NLP copes."""
    for args in [(1e-3, 5.0, 1.0, 7.0), (1e3, 1.0, 1e-3, 3.0), (1.0, 1.0, 1.0001, 0.0), (1e4, 1e-6, 1.0, 1.5)]:
        sol = sp.solve_particle(*args)
        assert sol.numeric_error <= 1e-9, args


@pytest.mark.parametrize(
    "args,field",
    [((1.0, 1.0, 0.0, 1.0), "eta"), ((1.0, 1.0, 2.0, -1.0), "n"), ((0.0, 1.0, 2.0, 1.0), "v_x"),
     ((1.0, 2.0, 2.0, 0.0), "eta")],
)
def test_invalid_inputs_raise_before_casadi(args, field):
    with pytest.raises(InvalidInput) as err:
        sp.solve_particle(*args)
    assert err.value.field == field


def test_ipopt_failure_becomes_solver_error(monkeypatch):
    """An IPOPT run that stops early (iteration cap 0) is reported, not returned."""
    real = sp.ipopt_options
    monkeypatch.setattr(sp, "ipopt_options", lambda tol: {**real(tol), "ipopt.max_iter": 0})
    with pytest.raises(NotConverged, match="Maximum_Iterations_Exceeded") as err:
        sp.solve_particle(1.0, 1.0, 2.0, 2.0)
    assert isinstance(err.value, SolverError)


def test_casadi_exception_becomes_solver_error(monkeypatch):
    """A CasADi construction error (here an unknown IPOPT option) becomes SolverError."""
    real = sp.ipopt_options
    monkeypatch.setattr(sp, "ipopt_options", lambda tol: {**real(tol), "ipopt.no_such_option": 1})
    with pytest.raises(SolverError):
        sp.solve_particle(1.0, 1.0, 2.0, 2.0)


def test_solve_is_timed():
    """The solution carries its solve time and iterations (no wall-clock bound: the suite
    must pass on a busy machine)."""
    sol = sp.solve_particle(1.0, 1.0, 2.0, 0.5)
    assert sol.solve_time_s > 0.0
    assert sol.iterations >= 1


def test_solution_is_an_outcome():
    """2.5: a returned solution is complete (IPOPT succeeded) and says what it found."""
    sol = sp.solve_particle(1.0, 1.0, 2.0, 1.0)
    assert isinstance(sol, Outcome) and sol.complete and sol.status == "Solve_Succeeded"
    assert sol.message.startswith(f"IPOPT Solve_Succeeded in {sol.iterations} iterations: v_y = ")


def test_one_call_reports_the_residuals_2_27_and_2_31():
    """The stationarity (2.31) holds at IPOPT's minimiser and Newton's balance (2.27) at
    Newton's answer, both relative to mg."""
    sol = sp.mpp_particle(sp.ParticleProblem(1.0, 1.0, 2.0, 1.0))
    assert sol.kkt_residual == abs(float(mp.power_derivative(sol.mpp_v_y_numeric, sol.scene))) / sol.scene.mg
    assert sol.kkt_residual < 1e-8 and abs(sol.newton_residual) < 1e-12
    assert sol.complete and "Newton" in sol.message and sol.status == "Solve_Succeeded"
    with pytest.raises(InvalidInput):
        sp.mpp_particle(sp.ParticleProblem(1.0, 2.0, 2.0, 0.0))  # n = 0 needs eta > mg (2.5)
