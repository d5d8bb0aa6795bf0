"""The shared SVG helpers (service/common/svg.py): clipping keeps far-away coordinates out
of the pictures; the view frame draws in units of 10^k and refuses subnormal views."""

from __future__ import annotations

import numpy as np
import pytest

from service.common.svg import (
    axis_label,
    clip_line_to_box,
    clip_polygon_to_box,
    view_frame,
)
from service.errors import NonFiniteResult


def test_clip_polygon_to_box():
    square = np.array([[-2.0, -2.0], [2.0, -2.0], [2.0, 2.0], [-2.0, 2.0]])
    clipped = clip_polygon_to_box(square, np.array([-1.0, -1.0]), np.array([1.0, 1.0]))
    assert np.all(np.abs(clipped) <= 1.0)
    x, y = clipped[:, 0], clipped[:, 1]
    area = 0.5 * abs(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
    assert area == pytest.approx(4.0)
    far = np.array([[0.0, 0.0], [1e14, 1.0], [1e14, -1.0]])
    assert np.max(np.abs(clip_polygon_to_box(far, np.array([-3.0, -3.0]), np.array([3.0, 3.0])))) <= 3.0


def test_clip_line_to_box():
    seg = clip_line_to_box(np.array([0.0, 0.5]), np.array([1.0, 0.0]), np.array([-1.0, -1.0]), np.array([1.0, 1.0]))
    np.testing.assert_allclose(seg, [[-1.0, 0.5], [1.0, 0.5]])
    assert clip_line_to_box(np.array([0.0, 5.0]), np.array([1.0, 0.0]), np.array([-1.0, -1.0]), np.array([1.0, 1.0])) is None


def test_view_frame_units_and_origin():
    """A part of size 1e-9 at 1e9 is drawn relative to its centre in units of 1e-9."""
    half, unit_exp, scale, origin = view_frame([np.array([1e-9, 1e-9])], np.array([1e9, 0.0]))
    assert half == pytest.approx(1.15e-9) and unit_exp == -9 and scale == 1e-9
    np.testing.assert_array_equal(origin, [1e9, 0.0])
    half, unit_exp, scale, origin = view_frame([np.array([1.0, 0.5])], np.array([0.3, 0.0]))
    assert unit_exp == 0 and scale == 1.0 and not origin.any()
    assert axis_label("x", 0.0, 0) == "x" and axis_label("x", 1e9, -9) == "(x − (1e+09)) × 1e9"
    with pytest.raises(NonFiniteResult):
        view_frame([np.array([1e-320, 0.0])], np.zeros(2))
