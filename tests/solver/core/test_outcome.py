"""Every result of the solver layer's public entry points says how good it is
(solver/core/outcome.py): status, complete, solve_time_s and message, as dataclass fields or
properties, checked on the types the entry points of solver/__init__.py declare, on every
public result type exported there, and on real instances."""

from __future__ import annotations

import dataclasses
import typing

import numpy as np
import pytest

import solver
from models.core.scene import PushScene
from models.core.support import Support
from solver.core.outcome import OUTCOME_FIELDS, Outcome

RESULT_SUFFIXES = ("Result", "Solution", "Locus", "Boundary", "Sketch", "Table", "Schedule", "Plan", "Statistics", "Radii",
                   "Simulation", "Run", "Batch")


def _declares(cls: type, name: str) -> bool:
    fields = {f.name for f in dataclasses.fields(cls)} if dataclasses.is_dataclass(cls) else set()
    return name in fields or isinstance(getattr(cls, name, None), property)


def _result_types() -> list[type]:
    from_entry_points = [typing.get_type_hints(fn)["return"] for fn in solver.ENTRY_POINTS]
    exported = [getattr(solver, name) for name in solver.__all__ if name.endswith(RESULT_SUFFIXES)]
    return sorted({cls for cls in from_entry_points + exported if isinstance(cls, type)}, key=lambda c: c.__name__)


def test_every_entry_point_takes_a_problem_and_a_budget():
    for fn in solver.ENTRY_POINTS:
        hints = typing.get_type_hints(fn)
        params = [p for p in hints if p != "return"]
        assert len(params) == 2 and hints[params[1]] is solver.Budget, fn.__name__


@pytest.mark.parametrize("cls", _result_types(), ids=lambda c: c.__name__)
def test_every_public_result_type_is_an_outcome(cls):
    missing = [name for name in OUTCOME_FIELDS if not _declares(cls, name)]
    assert not missing, f"{cls.__name__} lacks {missing}"


def test_instances_are_outcomes_at_run_time():
    scene = PushScene.create(1.0, [-0.6, 0.4], np.pi / 2)
    fwd = solver.solve_forward(scene, Support.create([[0.5, 0.0], [-0.5, 0.0]], [1.0, 1.0], [0.0, 0.0]))
    mem = solver.membership(scene, [0.0, 0.0])
    for res in (fwd, mem):
        assert isinstance(res, Outcome)
        assert isinstance(res.status, str) and isinstance(res.complete, bool)
        assert res.solve_time_s >= 0.0 and isinstance(res.message, str)
