"""The mechanics layer's errors (models/core/errors.py): an InvalidInput names the API field and
the reason (the service turns it into a 422 at that field), and is a ValueError and a
ModelError."""

from __future__ import annotations

from models.core.errors import InvalidInput, ModelError


def test_invalid_input_names_its_field_and_reason():
    exc = InvalidInput("disk_radius", "must be positive")
    assert exc.field == "disk_radius" and exc.reason == "must be positive"
    assert str(exc) == "disk_radius: must be positive"
    assert isinstance(exc, ValueError) and isinstance(exc, ModelError)
