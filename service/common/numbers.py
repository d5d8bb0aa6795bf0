"""Numbers leave the service as plain finite floats: a NaN or an infinity raises
:class:`service.errors.NonFiniteResult` (HTTP 422 ``numeric_range``, naming the quantity)
instead of reaching the client. ``what`` names the quantity in that message."""

from __future__ import annotations

import math

import numpy as np

from service.errors import NonFiniteResult


def finite(value, what: str) -> float:
    """``value`` as a float; NonFiniteResult when it is NaN or infinite."""
    x = float(value)
    if not math.isfinite(x):
        raise NonFiniteResult(what)
    return x


def finite_list(value, what: str) -> list:
    """An array (a point, a vector, a polyline) as nested lists of floats; NonFiniteResult
    when any entry is NaN or infinite."""
    arr = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(arr)):
        raise NonFiniteResult(what)
    return arr.tolist()


def finite_or_none(value, what: str) -> float | None:
    """None stays None (not computed); anything else as :func:`finite`."""
    return None if value is None else finite(value, what)


def finite_if_known(value, what: str) -> float | None:
    """None or NaN (a value the solver left undecided) become None; anything else as
    :func:`finite`."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return None
    return finite(value, what)


def point_or_none(value) -> list[float] | None:
    """A point as [x, y], or None when it is not finite (a point that was not found)."""
    arr = np.asarray(value, dtype=float)
    return arr.tolist() if np.all(np.isfinite(arr)) else None


def difference(exact: float | None, closed: float | None) -> float | None:
    """exact - closed, None when either is missing."""
    return None if exact is None or closed is None else exact - closed
