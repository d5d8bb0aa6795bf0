"""The push scene of a request (service/common/scene.py): exactly one shape, the
polygon bounded by its circumscribing disk (book 3.1.8), warnings about the contact."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from models.core.errors import InvalidInput
from service.common.scene import contact_warnings, disk_or_footprint, prepare_push
from service.errors import FieldError

PUSH = dict(contact_point=[-0.5, -0.3], edge_angle=math.pi / 2, push_direction=0.0)
SQUARE = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]


def request(**fields):
    base = dict(disk_radius=None, workpiece=None, footprint=None, center_of_mass=None, **PUSH)
    return SimpleNamespace(**{**base, **fields})


def test_disk_and_polygon_scenes():
    prep = prepare_push(request(disk_radius=2.0))
    assert prep.scene.disk_radius == 2.0 and prep.footprint is None and prep.shape_field == "disk_radius"
    assert prep.warnings == () and prep.contact_distance_to_outline is None
    prep = prepare_push(request(footprint=SQUARE, contact_point=[-1.0, -0.3]))
    assert prep.scene.disk_radius == pytest.approx(math.sqrt(2.0)) and prep.shape_field == "footprint"
    assert prep.contact_distance_to_outline == pytest.approx(0.0, abs=1e-15) and prep.warnings == ()


def test_exactly_one_shape_and_the_field_of_a_bad_polygon():
    with pytest.raises(InvalidInput) as info:
        prepare_push(request())
    assert info.value.field == "disk_radius"
    with pytest.raises(InvalidInput) as info:
        prepare_push(request(disk_radius=1.0, workpiece=SQUARE))
    assert info.value.field == "workpiece"
    with pytest.raises(FieldError) as info:
        prepare_push(request(workpiece=[[0, 0], [1, 0], [2, 0]]))
    assert info.value.loc == ("workpiece",)


def test_warnings_about_the_contact():
    prep = prepare_push(request(footprint=SQUARE, contact_point=[-3.0, 0.0]))
    assert len(prep.warnings) == 2  # off the outline, and outside the circumscribing disk
    assert "away from the workpiece outline" in prep.warnings[0] and "outside the disk" in prep.warnings[1]
    assert contact_warnings(prep.scene) == [prep.warnings[1]]


def test_disk_or_footprint():
    scene, fp = disk_or_footprint(SimpleNamespace(disk_radius=1.0, footprint=None, center_of_mass=None, **PUSH))
    assert fp is None and scene.disk_radius == 1.0
    scene, fp = disk_or_footprint(SimpleNamespace(disk_radius=None, footprint=SQUARE, center_of_mass=None, **PUSH))
    np.testing.assert_array_equal(scene.center_of_mass, fp.center_of_mass)
    with pytest.raises(FieldError) as info:
        disk_or_footprint(SimpleNamespace(disk_radius=1.0, footprint=SQUARE, center_of_mass=None, **PUSH))
    assert info.value.loc == ("footprint",)
