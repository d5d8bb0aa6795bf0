"""Numbers on their way out (service/common/numbers.py): arrays as nested lists, undecided
values (NaN) as None; a number that goes into no response model (an SVG coordinate) is
checked by ``finite``, which names the quantity (HTTP 422 numeric_range). Whether the
numbers of an answer are finite is declared once on its base: tests/service/test_responses.py."""

from __future__ import annotations

import math

import numpy as np
import pytest

from service.common.numbers import difference, finite, known, listed, point_or_none
from service.errors import NonFiniteResult


def test_finite_passes_floats_and_names_what_is_not():
    assert finite(np.float64(1.5), "x") == 1.5 and type(finite(np.float64(1.5), "x")) is float
    for bad in (math.nan, math.inf, -math.inf):
        with pytest.raises(NonFiniteResult) as info:
            finite(bad, "tip.distance")
        assert info.value.what == "tip.distance"


def test_listed_is_nested_plain_floats():
    got = listed(np.array([[1.0, 2.0], [3.0, 4.0]], dtype=np.float32))
    assert got == [[1.0, 2.0], [3.0, 4.0]] and type(got[0][0]) is float
    assert listed((1, 2)) == [1.0, 2.0]


def test_missing_and_undecided_values():
    assert known(None) is None and known(math.nan) is None and known(2.5) == 2.5
    assert known(math.inf) == math.inf  # refused where it lands: an answer's part (Out)
    assert point_or_none([1.0, 2.0]) == [1.0, 2.0] and point_or_none([math.nan, 0.0]) is None
    assert difference(3.0, 1.0) == 2.0 and difference(None, 1.0) is None and difference(1.0, None) is None
