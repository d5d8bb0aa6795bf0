"""Named tolerances of the optimisation engine (solver/core/tolerances.py): frozen, with
presets ordered from fast to high accuracy."""

from __future__ import annotations

import dataclasses

import pytest

from solver.core.tolerances import SOLVER_DEFAULT, SOLVER_FAST, SOLVER_HIGH_ACCURACY


def test_presets_are_frozen_and_ordered():
    with pytest.raises(dataclasses.FrozenInstanceError):
        SOLVER_DEFAULT.kkt = 1.0  # type: ignore[misc]
    for name in ("kkt", "kkt_accept", "membership_residual", "boundary_bracket"):
        assert getattr(SOLVER_HIGH_ACCURACY, name) <= getattr(SOLVER_DEFAULT, name) <= getattr(SOLVER_FAST, name), name
    assert SOLVER_FAST.max_cg_iter <= SOLVER_DEFAULT.max_cg_iter
    assert SOLVER_DEFAULT.kkt <= SOLVER_DEFAULT.kkt_accept
