"""The reject gate's silhouette features (models/feeder/gate.py; book 7.1): the extent
against an independent rotation of the outline, its exact range over arcs against dense
sampling, and the separations it proposes."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.feeder.arcs import Arcs
from models.feeder.gate import GateSpec, extent, extent_range, separations
from tests.feeder_cases import PARTS, part


def bounding_box(hull: np.ndarray, theta: float) -> tuple[float, float]:
    """Width and height of the outline turned by theta, by an explicit rotation matrix."""
    r = np.array([[math.cos(theta), -math.sin(theta)], [math.sin(theta), math.cos(theta)]])
    pts = hull @ r.T
    return float(np.ptp(pts[:, 0])), float(np.ptp(pts[:, 1]))


@pytest.mark.parametrize("name", sorted(PARTS))
def test_extent_is_the_turned_outlines_bounding_box_7_1(name):
    p = part(name)
    rng = np.random.default_rng(11)
    for theta in rng.uniform(-4.0, 4.0, 20):
        w, h = bounding_box(p.hull, float(theta))
        assert extent(p, theta, "across")[0] == pytest.approx(w, rel=1e-12, abs=1e-12)
        assert extent(p, theta, "along")[0] == pytest.approx(h, rel=1e-12, abs=1e-12)


@pytest.mark.parametrize("name", ["pentagon", "right triangle", "L-shape"])
@pytest.mark.parametrize("feature", ["across", "along"])
def test_extent_range_over_an_arc_is_exact_against_dense_sampling(name, feature):
    """Ends, pieces and stationary points: the range holds every sampled value and its ends
    are reached to within the sampling's resolution: the largest value is a smooth maximum
    (second order in the step), the least may sit at a kink where the extreme vertex changes
    (first order: the extent's slope is at most the diameter)."""
    p = part(name)
    rng = np.random.default_rng(5)
    for _ in range(6):
        start, width = float(rng.uniform(0, 2 * math.pi)), float(rng.uniform(0.05, 2.5))
        lo, hi = extent_range(p, Arcs.of([(start, width)]), feature)
        grid = start + np.linspace(0.0, width, 20001)
        vals = np.array([bounding_box(p.hull, t)[0 if feature == "across" else 1] for t in grid])
        assert lo <= vals.min() + 1e-12 and vals.max() <= hi + 1e-12
        step = width / 20000
        assert vals.min() - lo <= 2.0 * p.circumradius * step and hi - vals.max() <= step * step * p.circumradius


def test_separations_split_ranges_with_the_margin_and_find_each_valid_split():
    ranges = {0: (1.0, 1.2), 1: (1.5, 1.7), 2: (1.45, 1.9), 3: (2.2, 2.4)}
    gates = separations(ranges, "across", 0.1)
    for g in gates:
        acc = [ranges[j] for j in g.accepted]
        rej = [ranges[j] for j in ranges if j not in g.accepted]
        if g.rule == "at_most":
            assert max(r[1] for r in acc) <= g.threshold - 0.1 and min(r[0] for r in rej) >= g.threshold + 0.1
        else:
            assert min(r[0] for r in acc) >= g.threshold + 0.1 and max(r[1] for r in rej) <= g.threshold - 0.1
    splits = {(g.rule, g.accepted) for g in gates}
    # 0 alone below, {0, 1, 2} below 3, 3 alone above, {1, 2, 3} above 0; 1 and 2 overlap
    assert splits == {("at_most", frozenset({0})), ("at_most", frozenset({0, 1, 2})),
                      ("at_least", frozenset({3})), ("at_least", frozenset({1, 2, 3}))}
    assert separations(ranges, "across", 0.3) == [] or all(g.margin >= 0.3 for g in separations(ranges, "across", 0.3))


@pytest.mark.parametrize(("kw", "field"), [({"features": ()}, "gate.features"), ({"features": ("width",)}, "gate.features"),
                                           ({"margin": -1.0}, "gate.margin"), ({"min_yield": 0.0}, "gate.min_yield")])
def test_a_gate_spec_refuses_what_no_gate_realises(kw, field):
    with pytest.raises(InvalidInput) as err:
        GateSpec(**kw)
    assert str(err.value).startswith(field + ":")
