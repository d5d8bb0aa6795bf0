"""The shortest belt for a placed design (issue 24; book 1.8.6, figure 1-9): where each
fence's free end goes, given the reach each fence needs (models/feeder/placed.py).

Fence i (side s_i, angle gamma_i, reach R_i) hangs from x = s_i W/2 to its free end x_i and
drops (W/2 - s_i x_i) tan|gamma_i| along the belt; the next root is ``spacing`` below. The
belt's length from the first root to the last free end (and on to the gate, ``spacing``
further, when there is one) is

    sum_i (W/2 - s_i x_i) tan|gamma_i| + spacing (n - 1 [+ 1]),

a linear function of the x_i, minimised by one linear programme under the constraints of
placed.py: the gap at each free end, s_i x_i >= -W/2 + g ("width"), and each fence's reach
from where the part comes from, s_i x_i <= s_i x_(i-1) - h_i - R_i cos gamma_i ("reach";
x_0 the entry lane). The constraints whose duals are positive are the ones that rule out a
shorter belt; a fence at the shallowest candidate angle a flush part slides on is held steep
by jams (6.4).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cvxpy as cp
import numpy as np

from models.feeder.layout import PlacedFence, reach_from
from models.feeder.placed import Belt
from solver.core.backends import in_backend
from solver.core.errors import NotConverged

DUAL_ACTIVE = 1e-7
"""A constraint whose dual (per unit of objective) exceeds this is binding."""


@dataclass(frozen=True)
class Placement:
    """The fences placed, the gate's position (None: no gate), the belt's length, and what
    rules out a shorter belt: per fence the binding constraints ("reach", "width", "jam")."""

    belt: Belt
    fences: tuple[PlacedFence, ...]
    gate_y: float | None
    length: float
    binding: tuple[tuple[str, ...], ...]


def place(belt: Belt, angles: list[float], reaches: list[float], gate: bool = False,
          jam_held: list[bool] | None = None) -> Placement:
    """The shortest placement (module docstring) of fences at ``angles`` needing ``reaches``;
    ``jam_held[i]``: a shallower candidate for fence i would jam."""
    n = len(angles)
    sides = np.array([1.0 if g > 0.0 else -1.0 for g in angles])
    tans = np.array([math.tan(abs(g)) for g in angles])
    half, edge = 0.5 * belt.width, 0.5 * belt.width - belt.gap
    x = cp.Variable(n)
    width = [cp.multiply(sides, x) >= -edge]
    reach = []
    for i in range(n):
        h = belt.arrival(None)[2] if i == 0 else 2.0 * belt.part_radius
        prev = belt.entry_x if i == 0 else x[i - 1]
        need = h + reaches[i] * math.cos(angles[i])
        reach.append(sides[i] * x[i] <= sides[i] * prev - need)
    prob = cp.Problem(cp.Minimize(tans @ (half - cp.multiply(sides, x))), width + reach)
    try:
        with in_backend("clarabel"):
            prob.solve(solver=cp.CLARABEL)
    except cp.error.SolverError as exc:
        raise NotConverged(f"Clarabel failed on the belt's placement: {exc}") from exc
    if prob.status not in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE) or x.value is None:
        raise NotConverged(f"the belt's placement ended with status {prob.status}")
    xs = np.asarray(x.value, dtype=float)
    # the solver's answer may sit a rounding outside a bound: clip to the gap, keep the reach
    xs = np.where(sides > 0, np.maximum(xs, -edge), np.minimum(xs, edge))
    width_dual = np.asarray(width[0].dual_value, dtype=float).reshape(n)
    fences = []
    binding = []
    y = 0.0
    for i in range(n):
        root = np.array([sides[i] * half, y])
        span = half - sides[i] * xs[i]
        end = np.array([xs[i], y - span * tans[i]])
        lo, hi, h = belt.arrival(None if i == 0 else (xs[i - 1], xs[i - 1]))
        has = reach_from(float(angles[i]), float(xs[i]), lo - h, hi + h)
        fences.append(PlacedFence(float(angles[i]), "right" if sides[i] > 0 else "left", root, end,
                                  span / math.cos(angles[i]), has, float(reaches[i])))
        tight = []
        if float(np.asarray(reach[i].dual_value)) > DUAL_ACTIVE:
            tight.append("reach")
        if width_dual[i] > DUAL_ACTIVE:
            tight.append("width")
        if jam_held is not None and jam_held[i]:
            tight.append("jam")
        binding.append(tuple(tight))
        y = float(end[1]) - belt.spacing
    last = float(fences[-1].end[1]) if fences else 0.0
    gate_y = last - belt.spacing if gate else None
    length = -(gate_y if gate_y is not None else last)
    return Placement(belt, tuple(fences), gate_y, length, tuple(binding))
