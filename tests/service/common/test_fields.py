"""Shared request fields (service/common/fields.py): strict finite numbers within the
limits of service/limits.py, points of two coordinates, unknown fields rejected."""

from __future__ import annotations

import math

import pytest
from pydantic import ValidationError

from service.common.fields import Angle, Point, PushIn, Strict, TimeLimit
from service.limits import MAX_ABS_ANGLE, MAX_ABS_COORDINATE, TIME_LIMIT_HARD_MAX_S


class Probe(Strict):
    p: Point
    angle: Angle
    limit: TimeLimit


def errors(**fields):
    with pytest.raises(ValidationError) as info:
        Probe(**{"p": [0.0, 0.0], "angle": 0.0, "limit": 1.0, **fields})
    return [(e["loc"], e["type"]) for e in info.value.errors()]


def test_strict_finite_numbers_within_the_limits():
    assert Probe(p=[1, 2], angle=1, limit=1).p == [1.0, 2.0]  # integers are accepted
    assert errors(angle=True) == [(("angle",), "float_type")]
    assert errors(angle="1") == [(("angle",), "float_type")]
    assert errors(angle=math.nan) == [(("angle",), "finite_number")]
    assert errors(angle=2 * MAX_ABS_ANGLE) == [(("angle",), "less_than_equal")]
    assert errors(p=[0.0, 2 * MAX_ABS_COORDINATE]) == [(("p", 1), "less_than_equal")]
    assert errors(p=[0.0]) == [(("p",), "too_short")]
    assert errors(limit=0.0) == [(("limit",), "greater_than")]
    assert errors(limit=TIME_LIMIT_HARD_MAX_S + 1) == [(("limit",), "less_than_equal")]
    assert errors(extra=1) == [(("extra",), "extra_forbidden")]


def test_the_push_defaults_to_pushing_along_x():
    push = PushIn(contact_point=[-0.5, -0.3], edge_angle=1.0)
    assert push.push_direction == 0.0
