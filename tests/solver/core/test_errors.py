"""The optimisation layer's errors (solver/core/errors.py): one family under SolverError
(itself a ModelError, so the service maps every one of them), and BackendNotFound an input
error naming its field."""

from __future__ import annotations

import pytest

from models.core.errors import InvalidInput, ModelError
from solver.core.errors import BackendNotFound, Infeasible, NotConverged, SolverError, TimeLimitReached


@pytest.mark.parametrize("cls", [NotConverged, Infeasible])
def test_solver_failures_are_solver_errors(cls):
    exc = cls("IPOPT ended with Maximum_Iterations_Exceeded")
    assert isinstance(exc, SolverError) and isinstance(exc, ModelError)
    assert not isinstance(exc, InvalidInput)


def test_time_limit_reached_says_where_and_keeps_the_partial_result():
    exc = TimeLimitReached("the sketch at beta = 0.3", 2.0, 2.5, partial=[1, 2])
    assert isinstance(exc, SolverError)
    assert exc.partial == [1, 2] and exc.elapsed_s == 2.5
    assert str(exc) == "time limit 2 s reached after 2.5 s, before the sketch at beta = 0.3"
    assert "no limit" in str(TimeLimitReached("x", None, 1.0))


def test_backend_not_found_is_an_input_error_on_its_field():
    exc = BackendNotFound("method", "guess", ("newton", "cvxpy", "casadi"))
    assert isinstance(exc, InvalidInput) and isinstance(exc, SolverError)
    assert exc.field == "method" and exc.available == ("newton", "cvxpy", "casadi")
    assert "'guess'" in exc.reason and "'newton', 'cvxpy', 'casadi'" in exc.reason
