"""Named tolerances of the mechanics layer (models/core/tolerances.py): frozen, with presets
ordered from fast to high accuracy, and the centroid tolerance shared structurally with
the optimisation engine's tolerances."""

from __future__ import annotations

import dataclasses

import pytest

from models.core.tolerances import (
    DEFAULT,
    FAST,
    HIGH_ACCURACY,
    SPIRAL_DEFAULT,
    SPIRAL_FAST,
    SPIRAL_HIGH_ACCURACY,
    SUPPORT_DEFAULT,
    CentroidTolerance,
    SpiralTolerances,
    Tolerances,
)
from solver.core.tolerances import SOLVER_DEFAULT


def test_presets_are_frozen_and_ordered():
    with pytest.raises(dataclasses.FrozenInstanceError):
        DEFAULT.root_rtol = 1.0  # type: ignore[misc]
    assert HIGH_ACCURACY.root_rtol <= DEFAULT.root_rtol <= FAST.root_rtol
    assert HIGH_ACCURACY.boundary_residual_rel <= DEFAULT.boundary_residual_rel <= FAST.boundary_residual_rel
    assert Tolerances.default() is DEFAULT and Tolerances.fast() is FAST and Tolerances.high_accuracy() is HIGH_ACCURACY
    assert SPIRAL_HIGH_ACCURACY.grazing_delta <= SPIRAL_DEFAULT.grazing_delta <= SPIRAL_FAST.grazing_delta
    assert SPIRAL_HIGH_ACCURACY.length_unit_rel <= SPIRAL_DEFAULT.length_unit_rel <= SPIRAL_FAST.length_unit_rel
    assert SpiralTolerances.default() is SPIRAL_DEFAULT


def test_the_centroid_tolerance_is_one_protocol_for_both_layers():
    """models.core.support.Support takes any CentroidTolerance: its own preset or the solver's."""
    tols: list[CentroidTolerance] = [SUPPORT_DEFAULT, SOLVER_DEFAULT]
    for tol in tols:
        assert tol.centroid_rel == 1e-9
