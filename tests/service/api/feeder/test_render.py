"""The feeder pictures' helpers (service/api/feeder/render.py)."""

import math

import numpy as np
import pytest

from models.feeder.arcs import Arcs
from service.api.feeder.render import degree_spans
from service.errors import NonFiniteResult


def test_arcs_become_degree_spans_split_at_zero():
    assert np.allclose(degree_spans(Arcs.of([(math.radians(10), math.radians(20))])), [(10.0, 20.0)])
    spans = degree_spans(Arcs.of([(math.radians(350), math.radians(30))]))
    assert np.allclose(sorted(spans), [(0.0, 20.0), (350.0, 10.0)])
    assert np.allclose(degree_spans(Arcs.circle()), [(0.0, 360.0)])
    assert degree_spans(Arcs.empty()) == []


def test_a_non_finite_arc_is_refused():
    with pytest.raises(NonFiniteResult):
        degree_spans(Arcs(arcs=((math.nan, 1.0),)))
