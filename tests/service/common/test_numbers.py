"""Numbers leave the service finite (service/common/numbers.py): NaN and infinity raise
NonFiniteResult naming the quantity (HTTP 422 numeric_range), never reach the client."""

from __future__ import annotations

import math

import numpy as np
import pytest

from service.common.numbers import (
    difference,
    finite,
    finite_if_known,
    finite_list,
    finite_or_none,
    point_or_none,
)
from service.errors import NonFiniteResult


def test_finite_passes_floats_and_names_what_is_not():
    assert finite(np.float64(1.5), "x") == 1.5 and type(finite(np.float64(1.5), "x")) is float
    for bad in (math.nan, math.inf, -math.inf):
        with pytest.raises(NonFiniteResult) as info:
            finite(bad, "tip.distance")
        assert info.value.what == "tip.distance"


def test_finite_list_is_nested_floats():
    assert finite_list(np.array([[1.0, 2.0], [3.0, 4.0]]), "boundary") == [[1.0, 2.0], [3.0, 4.0]]
    with pytest.raises(NonFiniteResult):
        finite_list([1.0, math.nan], "cor")


def test_missing_and_undecided_values():
    assert finite_or_none(None, "x") is None and finite_or_none(2, "x") == 2.0
    with pytest.raises(NonFiniteResult):
        finite_or_none(math.nan, "x")  # NaN is not "not computed" here
    assert finite_if_known(None, "x") is None and finite_if_known(math.nan, "x") is None
    with pytest.raises(NonFiniteResult):
        finite_if_known(math.inf, "x")
    assert point_or_none([1.0, 2.0]) == [1.0, 2.0] and point_or_none([math.nan, 0.0]) is None
    assert difference(3.0, 1.0) == 2.0 and difference(None, 1.0) is None and difference(1.0, None) is None
