"""Spiral localization of a disk (book 4.5): schedules on a grid of radii, the graph that
solver/spiral/schedule.py hands to OR-Tools (shortest paths with a minimum step, where
greedy (4.26) is no longer optimal: :mod:`models.spiral.path`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from models.core.errors import InvalidInput
from models.core.tolerances import SPIRAL_DEFAULT
from models.spiral.critical import CriticalEnvelope, safe_reach
from models.spiral.path import revolution_length

# --------------------------------------------------------------------------------------
# Schedules on a grid of radii (the graph that solver/spiral/schedule.py hands to OR-Tools)


@dataclass(frozen=True)
class ScheduleGraph:
    """The DAG of safe revolutions between grid radii ``x`` (ascending, x[0] = target,
    x[-1] = b_1): an arc i -> j (i > j, from radius x_i to the next revolution's x_j) when
    x_i - x_j <= D(x_j) (the step is safe at the new radius, 4.26; D = d* capped by
    max_step) and x_i - x_j >= min_step, both in exact arithmetic (one ulp of slack towards
    safety). Incoming arcs of node j come from the contiguous range lo[j] <= i <= hi[j]
    (empty when lo > hi). ``tails``/``heads`` list every arc."""

    x: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    tails: np.ndarray
    heads: np.ndarray
    min_step: float | None
    max_step: float | None

    @property
    def n_arcs(self) -> int:
        return int(self.tails.size)


def schedule_grid(envelope: CriticalEnvelope, b_1: float, target: float, spacing: float | None = None,
                  resolution: int = 16, max_nodes: int = 200_000, max_step: float | None = None) -> np.ndarray:
    """Radii from ``target`` to ``b_1`` (both included). Uniform with ``spacing``, else
    adaptive: each next radius is x + D(x) / ``resolution`` (D = d* capped by max_step),
    i.e. about ``resolution`` grid points per safe step, so the grid is fine where the
    safe steps are short (near b_inf) and coarse where they are ~a. Every grid point is a
    real radius, so a schedule on it is exactly as safe as its arcs. More than
    ``max_nodes`` radii is refused (InvalidInput), as is an adaptive grid from a target
    below the envelope's floor (D = 0 there)."""
    b_1 = float(b_1)
    target = float(target)
    if not (math.isfinite(b_1) and math.isfinite(target) and 0.0 < target < b_1):
        raise InvalidInput("target", "need 0 < target < b_1")
    if spacing is not None:
        h = float(spacing)
        if not (math.isfinite(h) and h > 0.0):
            raise InvalidInput("spacing", "must be a positive length")
        n = int(math.ceil((b_1 - target) / h))
        if n + 1 > max_nodes:
            raise InvalidInput("spacing", f"gives {n + 1} grid radii, more than max_nodes = {max_nodes}")
        grid = target + h * np.arange(n + 1)
        grid[-1] = b_1
        return grid
    if resolution < 1:
        raise InvalidInput("resolution", "must be at least 1")
    out = [target]
    x = target
    while True:
        d = float(envelope.d_star(x, max_step))
        if d <= 0.0:
            raise InvalidInput("target", f"no safe step at radius {x:.9g}: below the table's floor {envelope.b_floor:.9g}")
        x = max(x + d / resolution, float(np.nextafter(x, np.inf)))
        if x >= b_1:
            break
        out.append(x)
        if len(out) + 1 > max_nodes:
            raise InvalidInput(
                "resolution",
                f"the adaptive grid needs more than max_nodes = {max_nodes} radii (the safe steps near the target "
                "are short): lower the resolution, raise the target or max_nodes",
            )
    out.append(b_1)
    return np.asarray(out)



def schedule_graph(envelope: CriticalEnvelope, x: ArrayLike, min_step: float | None = None,
                   max_step: float | None = None) -> ScheduleGraph:
    """The safe-revolution DAG on the radii ``x`` (see :class:`ScheduleGraph`)."""
    x = np.asarray(x, dtype=float)
    if x.ndim != 1 or x.size < 2 or np.any(np.diff(x) <= 0.0):
        raise InvalidInput("grid", "need at least two strictly increasing radii")
    D = np.asarray(envelope.d_star(x, max_step), dtype=float)
    upper = safe_reach(x, D)
    hi = np.searchsorted(x, upper, side="right") - 1
    idx = np.arange(x.size)
    lo = idx + 1
    if min_step is not None:
        m = float(min_step)
        if not (math.isfinite(m) and m >= 0.0):
            raise InvalidInput("min_step", "must be a finite length >= 0")
        # x_i - x_j >= m  <=  x_i >= fl(x_j + m) + 1 ulp
        lower = np.nextafter(x + m, np.inf)
        lo = np.maximum(lo, np.searchsorted(x, lower, side="left"))
    hi = np.where(D > 0.0, hi, -1)
    cnt = np.maximum(hi - lo + 1, 0)
    heads = np.repeat(idx, cnt)
    start = np.repeat(lo - np.cumsum(np.r_[0, cnt[:-1]]), cnt)
    tails = start + np.arange(int(cnt.sum()))
    return ScheduleGraph(x=x, lo=lo, hi=hi, tails=tails.astype(np.int64), heads=heads.astype(np.int64),
                         min_step=None if min_step is None else float(min_step),
                         max_step=None if max_step is None else float(max_step))


def greedy_on_graph(graph: ScheduleGraph) -> np.ndarray | None:
    """Greedy on the grid: from the current node take the smallest reachable radius. Node
    indices from b_1 (last) down to the target (0), or None when it gets stuck (possible
    only with a minimum step). Optimal without a minimum step (module docstring).
    hi[j] and lo[j] are nondecreasing in j (x_j + D(x_j) and x_j + m are), so the smallest
    j with hi[j] >= i is found by bisection, and if its lo[j] > i no larger j serves."""
    i = graph.x.size - 1
    path = [i]
    while i > 0:
        j = int(np.searchsorted(graph.hi, i, side="left"))
        if j >= i or graph.lo[j] > i:
            return None
        i = j
        path.append(i)
    return np.asarray(path)


def arc_costs(graph: ScheduleGraph, objective: str, unit: float, nodes: int = SPIRAL_DEFAULT.arc_nodes) -> np.ndarray:
    """Integer arc costs: 1 per revolution ("revolutions"), or the revolution's length
    (:func:`revolution_length` from x_tail to x_head) in units of ``unit``, rounded
    ("length")."""
    if objective == "revolutions":
        return np.ones(graph.n_arcs, dtype=np.int64)
    if objective == "length":
        out = np.empty(graph.n_arcs, dtype=np.int64)
        chunk = 200_000
        for s in range(0, graph.n_arcs, chunk):
            ls, _ = revolution_length(graph.x[graph.tails[s:s + chunk]], graph.x[graph.heads[s:s + chunk]], nodes)
            out[s:s + chunk] = np.rint(np.asarray(ls) / unit).astype(np.int64)
        return out
    raise InvalidInput("objective", "must be 'revolutions' or 'length'")


def shortest_path_potentials(graph: ScheduleGraph, costs: np.ndarray) -> np.ndarray:
    """Shortest-path distances from b_1 (the last node) to every node over the DAG, in the
    integer costs (exact; -1 = unreachable). Node j's incoming arcs come from a contiguous
    range of larger nodes, so one pass from the top down is exact. They are the dual
    potentials of the shortest-path LP: every arc's reduced cost c_ij + pi_i - pi_j >= 0,
    so pi_target is a lower bound on every schedule's cost (the certificate)."""
    n = graph.x.size
    INF = np.iinfo(np.int64).max // 4
    dist = np.full(n, INF, dtype=np.int64)
    dist[n - 1] = 0
    # arcs grouped by head j, tails ascending: costs for head j lie in one slice
    cnt = np.maximum(graph.hi - graph.lo + 1, 0)
    off = np.r_[0, np.cumsum(cnt)]
    for j in range(n - 2, -1, -1):
        if cnt[j] == 0:
            continue
        d = dist[graph.lo[j]:graph.hi[j] + 1] + costs[off[j]:off[j + 1]]
        dist[j] = min(int(d.min()), INF)
    dist[dist >= INF] = -1
    return dist
