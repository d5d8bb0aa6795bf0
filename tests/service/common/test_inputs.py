"""Domain errors located at the request's fields (service/common/inputs.py)."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from models.core.errors import InvalidInput
from service.common.inputs import exactly_one, field_path, footprint_of, located
from service.errors import FieldError


def test_located_renames_prefixes_and_follows_dotted_paths():
    with pytest.raises(FieldError) as info:
        with located(rename={"rings": ("pressure", "resolution")}):
            raise InvalidInput("rings", "too many")
    assert info.value.loc == ("pressure", "resolution") and info.value.reason == "too many"
    with pytest.raises(FieldError) as info:
        with located(("supports",)):
            raise InvalidInput("weights", "negative")
    assert info.value.loc == ("supports", "weights")
    with pytest.raises(FieldError) as info:
        with located():
            raise InvalidInput("supports.3", "its centre of mass differs from the scene's")
    assert info.value.loc == ("supports", 3)
    assert field_path("simulate.kind") == ("simulate", "kind")
    with located():  # nothing raised, nothing changed
        pass


def test_exactly_one_names_the_field():
    req = SimpleNamespace(g=None, length_unit=None)
    with pytest.raises(FieldError) as info:
        exactly_one(req, ("g", "length_unit"))
    assert info.value.loc == ("g",) and info.value.reason == "give exactly one of g or length_unit"
    req = SimpleNamespace(g=9.81, length_unit="m")
    with pytest.raises(FieldError) as info:
        exactly_one(req, ("g", "length_unit"))
    assert info.value.loc == ("length_unit",) and "not both g and length_unit" in info.value.reason
    assert exactly_one(SimpleNamespace(g=None, length_unit="cm"), ("g", "length_unit")) == "length_unit"


def test_footprint_errors_are_at_the_given_field():
    with pytest.raises(FieldError) as info:
        footprint_of([[0, 0], [1, 0], [2, 0]], None, ("pressure", "footprint"))
    assert info.value.loc == ("pressure", "footprint")
    fp = footprint_of([[0, 0], [2, 0], [2, 1], [0, 1]], None, ("footprint",))
    assert fp.center_of_mass.tolist() == [1.0, 0.5]
