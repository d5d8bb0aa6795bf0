"""Numbers on their way out of the service.

Whether a number in an answer is finite is declared once, on the answers' base
(:class:`service.common.responses.Out`); converters only copy values. What is here turns a
value into what a response field holds: arrays as nested lists, values the solver left
undecided (NaN) as None. :func:`finite` checks a number that does not go into a response
model (an SVG coordinate): a NaN or an infinity raises
:class:`service.errors.NonFiniteResult` (HTTP 422 ``numeric_range``, naming ``what``).
"""

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


def listed(value) -> list:
    """An array (a point, a vector, a polyline) as nested lists of floats (pydantic validates
    a list several times faster than the numpy array's scalars)."""
    return np.asarray(value, dtype=float).tolist()


def known(value):
    """None or NaN (a value the solver left undecided) become None; anything else as it is."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return None
    return value


def point_or_none(value) -> list[float] | None:
    """A point as [x, y], or None when it is not finite (a point that was not found)."""
    arr = np.asarray(value, dtype=float)
    return arr.tolist() if np.all(np.isfinite(arr)) else None


def difference(exact: float | None, closed: float | None) -> float | None:
    """exact - closed, None when either is missing."""
    return None if exact is None or closed is None else exact - closed


def design_margin(margin: float) -> float:
    """A feeder design's margin (1.8.6) for an answer: a design of one fence has no later
    fence to miss, so its margin is infinite, answered as pi (no angular error matters)."""
    return margin if math.isfinite(margin) else math.pi
