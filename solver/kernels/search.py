"""The feeder design search's dominance scan (book 5.3.2), compiled (numba): the twin of
:func:`models.feeder.design_graph.scan_reached` (the reference its tests compare it with),
one node reached at a time with an early exit instead of chunks of arrays and a Python
object per candidate. The arc test is :meth:`models.feeder.arcs.Arcs.issubset`'s
arithmetic, operation for operation (C's fmod for the wrap, numpy's here as math's there), so the answer is the same."""

from __future__ import annotations

import math

import numpy as np
from numba import njit, types

from solver.kernels import ensure_cache

CACHE = True
"""Compiled code kept on disk (numba's cache; solver/kernels/__init__.py says where)."""
ensure_cache()  # before the first function is compiled or loaded

ENTRY_POINTS = ("scan_reached",)
"""Compiled with explicit signatures when the module is imported (the others are compiled
into them)."""

TWO_PI = 2.0 * math.pi


@njit(cache=CACHE)
def _wrap(angle):
    """models.feeder.arcs.wrap: ``angle`` in [0, 2 pi)."""
    x = np.fmod(angle, TWO_PI)
    if x < 0.0:
        x += TWO_PI
    return 0.0 if x >= TWO_PI else x


@njit(cache=CACHE)
def _within(starts, widths, count, arcs, slack):
    """Arcs.issubset: every arc of the node within an arc of ``arcs`` widened by ``slack``."""
    for a in range(count):
        s, w = starts[a], widths[a]
        inside = False
        for b in range(arcs.shape[0]):
            if _wrap(s - (arcs[b, 0] - slack)) + w <= arcs[b, 1] + 2.0 * slack:
                inside = True
                break
        if not inside:
            return False
    return True


_F1, _F2 = types.float64[:], types.float64[:, :]
SCAN_SIGNATURE = (_F2, _F2, types.int64[:], _F1, types.uint64[:, :], types.int64, _F2, types.uint64[:], types.float64,
                  types.float64)


@njit([SCAN_SIGNATURE], cache=CACHE)
def scan_reached(starts, widths, counts, margins, words, n, arcs, inverse, margin, slack):
    """models.feeder.design_graph.scan_reached: a node among the first ``n`` with a margin
    >= ``margin``, no cell outside the new mask and its arcs within ``arcs``."""
    for i in range(n):
        if not margins[i] >= margin:
            continue
        outside = False
        for k in range(inverse.shape[0]):
            if words[i, k] & inverse[k] != 0:
                outside = True
                break
        if outside:
            continue
        if _within(starts[i], widths[i], counts[i], arcs, slack):
            return True
    return False
