"""The shortest belt for a placed design (solver/feeder/placement.py; book 1.8.6, figure 1-9):
the linear programme against a brute force over the free ends, and what it says binds."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.feeder.placed import Belt
from solver.feeder.placement import place


def length_of(belt: Belt, angles, xs) -> float:
    half = 0.5 * belt.width
    return sum((half - math.copysign(1.0, g) * x) * math.tan(abs(g)) for g, x in zip(angles, xs)) \
        + belt.spacing * (len(angles) - 1)


def feasible(belt: Belt, angles, reaches, xs) -> bool:
    edge = 0.5 * belt.width - belt.gap
    prev, h = belt.entry_x, belt.arrival(None)[2]
    for g, r, x in zip(angles, reaches, xs):
        s = math.copysign(1.0, g)
        if s * x < -edge - 1e-12 or s * x > s * prev - h - r * math.cos(g) + 1e-12:
            return False
        prev, h = x, 2.0 * belt.part_radius
    return True


@pytest.mark.parametrize("angles", [(0.6, 0.9), (0.6, -1.1), (1.2, -0.4)])
def test_the_belt_is_the_shortest_placement_of_its_fences(angles):
    """Two fences (a same-side run, two alternating pairs): no feasible pair of free ends on a
    fine grid gives a shorter belt than the programme's, and its placement keeps every
    reach and gap; the binding constraints are the ones it sits on."""
    belt = Belt.create(20.0, 1.0)
    reaches = [3.0, 2.0]
    pl = place(belt, list(angles), reaches)
    xs = [float(f.end[0]) for f in pl.fences]
    assert feasible(belt, angles, reaches, xs)
    assert pl.length == pytest.approx(length_of(belt, angles, xs), rel=1e-9)
    grid = np.linspace(-10.0, 10.0, 801)
    best = min((length_of(belt, angles, (x1, x2)) for x1 in grid for x2 in grid
                if feasible(belt, angles, reaches, (x1, x2))), default=math.inf)
    assert pl.length <= best + 1e-6
    for f, r, b in zip(pl.fences, reaches, pl.binding):
        assert f.reach >= r - 1e-9 and f.reach_needed == r
        s = 1.0 if f.side == "right" else -1.0
        on_gap = abs(s * f.end[0] + 0.5 * belt.width - belt.gap) < 1e-6
        assert ("width" in b) == on_gap or "reach" in b


def test_a_gate_stands_a_spacing_past_the_last_fence():
    belt = Belt.create(20.0, 1.0)
    pl = place(belt, [0.6, -0.9], [3.0, 2.0], gate=True)
    assert pl.gate_y == pytest.approx(pl.fences[-1].end[1] - belt.spacing) and pl.length == pytest.approx(-pl.gate_y)
