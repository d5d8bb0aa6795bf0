"""From request fields to domain objects, with every error located at the request's field.

The models and solvers name a bad input by their own argument names
(``InvalidInput(field, reason)``; a field inside a part of a problem is a dotted path,
e.g. "simulate.kind" or "supports.3"); :func:`located` re-raises such an error at the
request's place for it (a :class:`service.errors.FieldError`, HTTP 422 with that ``loc``).
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from contextlib import contextmanager

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from service.errors import FieldError

Loc = tuple[str | int, ...]


def field_path(field: str) -> Loc:
    """A dotted field path as a ``loc``: "supports.3" -> ("supports", 3)."""
    return tuple(int(part) if part.isdigit() else part for part in field.split("."))


@contextmanager
def located(prefix: Loc = (), rename: Mapping[str, Loc] | None = None) -> Iterator[None]:
    """Re-raise a domain ``InvalidInput(field, reason)`` as a :class:`FieldError` at
    ``rename[field]`` or, by default, at ``prefix`` + the field's path."""
    try:
        yield
    except InvalidInput as exc:
        loc = (rename or {}).get(exc.field, (*prefix, *field_path(exc.field)))
        raise FieldError(loc, exc.reason) from exc


def exactly_one(req, names: tuple[str, ...]) -> str:
    """The one field of ``names`` that is given (not null); FieldError otherwise."""
    given = [name for name in names if getattr(req, name) is not None]
    listing = ", ".join(names[:-1]) + f" or {names[-1]}"
    if not given:
        raise FieldError((names[0],), f"give exactly one of {listing}")
    if len(given) > 1:
        raise FieldError((given[1],), f"give exactly one of {listing}, not both {given[0]} and {given[1]}")
    return given[0]


def footprint_of(vertices, center_of_mass, field: Loc) -> Footprint:
    """``Footprint.create`` with its errors located at ``field`` (it calls the polygon
    "workpiece")."""
    with located(rename={"workpiece": field}):
        return Footprint.create(vertices, center_of_mass)
