"""Arcs of orientations (book 5.2.1: the bands and kernels of a configuration map)."""

import math

import numpy as np
import pytest

from models.feeder.arcs import TWO_PI, Arcs, wrap


def test_merge_overlapping_touching_and_across_zero():
    a = Arcs.of([(0.5, 0.5), (0.9, 0.3), (1.2, 0.1), (TWO_PI - 0.2, 0.3), (3.0, 0.0)])
    np.testing.assert_allclose(np.array(a.arcs), [(0.5, 0.8), (3.0, 0.0), (TWO_PI - 0.2, 0.3)])
    assert a.measure == pytest.approx(1.1)
    assert a.contains(0.05) and a.contains(3.0) and not a.contains(2.0)
    assert a.contains(3.0 + 1e-3, slack=1e-3) and not a.contains(3.0 + 2e-3, slack=1e-3)
    assert a.contains(0.5 - 1e-3, slack=1e-3) and a.contains(TWO_PI - 0.2 - 1e-3, slack=1e-3)


def test_wide_arcs_are_the_circle():
    assert Arcs.of([(1.0, 7.0)]) == Arcs.circle()
    assert Arcs.of([(0.0, 4.0), (3.5, 3.0)]) == Arcs.circle()


def test_intersection_is_of_closed_arcs():
    a = Arcs.of([(1.0, 0.5)])
    assert a.intersects(Arcs.of([(1.5, 0.2)]))  # touching ends meet
    assert not a.intersects(Arcs.of([(1.5 + 1e-9, 0.2)]))
    assert Arcs.of([(TWO_PI - 0.1, 0.2)]).intersects(Arcs.of([(0.05, 0.01)]))
    assert not Arcs.empty().intersects(Arcs.circle())


def test_cells_never_lose_an_orientation():
    rng = np.random.default_rng(5)
    n = 360
    for _ in range(200):
        s, w = rng.uniform(0, TWO_PI), rng.uniform(0, 1.0)
        cells = Arcs.of([(s, w)]).cells(n)
        for x in np.linspace(s, s + w, 50):
            i = int(math.floor(wrap(x) / (TWO_PI / n))) % n
            assert cells[i]
        # and marks no cell farther than one cell from the arc
        assert cells.sum() <= math.ceil(w / (TWO_PI / n)) + 2
