"""Placing a feeder's fences on a belt (models/feeder/layout.py; book 1.8.6, figure 1-9):
lengths, positions and the reach beyond the part's first contact, by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.feeder.layout import lay_out


def test_alternating_fences_catch_the_part_near_their_root_and_same_side_ones_miss_it():
    a, w = 1.0, 10.0
    lay = lay_out([math.radians(45), math.radians(-30), math.radians(-30)], a, w, clearance=0.5, spacing=2.0)
    gap = 2.5
    assert lay.gap == gap
    f0, f1, f2 = lay.fences
    # the first hangs from the right, runs down to the left across w - gap = 7.5
    assert np.allclose(f0.root, [5.0, 0.0]) and np.allclose(f0.end, [-2.5, -7.5])
    assert f0.length == pytest.approx(7.5 * math.sqrt(2)) and f0.side == "right"
    # parts arrive beside its root (CM at x = 4): the least favourable contact at x = 3
    assert f0.reach == pytest.approx((3.0 + 2.5) * math.sqrt(2)) and lay.entry_x == 4.0
    # the second hangs from the left, 2 below the first end; the part leaves near x = -2.5
    assert np.allclose(f1.root, [-5.0, -9.5]) and f1.side == "left"
    assert np.allclose(f1.end, [2.5, -9.5 - 7.5 * math.tan(math.radians(30))])
    assert f1.reach == pytest.approx((2.5 - (-2.5 + 2.0)) / math.cos(math.radians(30)))
    # the third is on the same side: the part leaves the second near x = 2.5, beside the third's end
    assert f2.reach == 0.0
    assert lay.belt_length == pytest.approx(-f2.end[1])


def test_the_layout_scales_with_the_part_and_refuses_a_narrow_belt():
    ref = lay_out([0.7, -0.9], 1.0, 12.0, 0.1, 2.0)
    big = lay_out([0.7, -0.9], 1e3, 12e3, 100.0, 2e3)
    for f, g in zip(ref.fences, big.fences):
        assert np.allclose(g.root, 1e3 * f.root) and g.reach == pytest.approx(1e3 * f.reach)
    with pytest.raises(InvalidInput):
        lay_out([0.7], 1.0, 2.05, 0.1, 2.0)
    with pytest.raises(InvalidInput):
        lay_out([0.7], 1.0, 10.0, 0.1, 2.0, entry_x=6.0)
    with pytest.raises(InvalidInput):
        lay_out([0.7], 1.0, 10.0, 0.1, 2.0, entry_x=math.nan)
