"""The feeder design as a CP-SAT model over code sets (book 5.3, 5.4): the fewest fences, with
a proof that no shorter design exists, or that none exists up to a depth.

For a depth D the model chooses one candidate fence per position d (``sel[d][f]``),
alternating sides when asked, and tracks which bands of the chosen fence the part may be in
(``occ[d][f][j]``, models/feeder/design_graph.py's code sets):

* position 0: every band of f with a kernel, and only fences that can come first;
* position d > 0: band j of f is occupied when f is chosen and some occupied band i of the
  previous fence g meets its kernel, occ[d][f][j] >= occ[d-1][g][i] + sel[d][f] - 1 for
  every (g, i, j) with B^g_i meeting K^f_j (5.4); a band of g that meets f's jam or
  unaligned set forbids f after it;
* the goal at position D - 1: the occupied bands lie in one symmetry class.

Occupancies are only bounded below, which is exact for feasibility: the solver can always
set them to the code sets themselves. Depths are tried in order 1, 2, ...: the first
feasible one is the least (every smaller one was proven infeasible), as the breadth-first
search of models/feeder/design_graph.py finds; the two are independent and must agree.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

from models.feeder.design_graph import DesignGraph
from solver.core.backends import in_backend
from solver.core.budget import UNLIMITED, Budget

MIN_TIME_LIMIT_S = 1e-3
"""The least time limit handed to CP-SAT (it needs a positive one)."""
CP_SAT_WORKERS = 1
"""Search workers of CP-SAT: one, so that a solve is repeatable and leaves the other core
to the service."""


@dataclass(frozen=True)
class CpSatDesign:
    """``fences``: the least design found (None: none); ``depth_proven``: every depth up to
    it proven infeasible; ``statuses``: CP-SAT's status per depth tried; ``complete`` False
    when a depth's solve ran out of time (the depths after it were not tried)."""

    fences: tuple[int, ...] | None
    depth_proven: int
    statuses: tuple[str, ...]
    complete: bool
    solve_time_s: float
    variables: int


def _solve_depth(graph: DesignGraph, depth: int, alternate: bool, time_limit_s: float | None):
    from ortools.sat.python import cp_model

    n = len(graph.maps)
    bands = [len(m.map.bands) for m in graph.maps]
    model = cp_model.CpModel()
    sel = [[model.new_bool_var(f"s{d}_{f}") for f in range(n)] for d in range(depth)]
    occ = [[[model.new_bool_var(f"o{d}_{f}_{j}") for j in range(bands[f])] for f in range(n)] for d in range(depth)]
    for d in range(depth):
        model.add_exactly_one(sel[d])
        for f in range(n):
            for j in range(bands[f]):
                model.add_implication(occ[d][f][j], sel[d][f])
    if alternate:
        for d in range(depth - 1):
            for side in (1.0, -1.0):
                same = [sel[d][f] for f in range(n) if graph.side(f) == side]
                nxt = [sel[d + 1][f] for f in range(n) if graph.side(f) == side]
                model.add(sum(same) + sum(nxt) <= 1)
    for f in range(n):
        if not graph.first_ok[f]:
            model.add(sel[0][f] == 0)
        for j in graph.start[f]:
            model.add_implication(sel[0][f], occ[0][f][j])
    for d in range(1, depth):
        for g in range(n):
            for f in range(n):
                meets = graph.meets[g][f]
                for i in range(bands[g]):
                    if graph.bad[g][f][i]:
                        model.add_bool_or([occ[d - 1][g][i].Not(), sel[d][f].Not()])
                        continue
                    for j in range(bands[f]):
                        if meets[i, j]:
                            model.add_bool_or([occ[d - 1][g][i].Not(), sel[d][f].Not(), occ[d][f][j]])
    last = depth - 1
    for f in range(n):
        classes = sorted(set(graph.orbit[f]))
        use = {o: model.new_bool_var(f"u{f}_{o}") for o in classes}
        for j in range(bands[f]):
            model.add_implication(occ[last][f][j], use[graph.orbit[f][j]])
        model.add(sum(use.values()) <= 1)
    solver = cp_model.CpSolver()
    solver.parameters.num_workers = CP_SAT_WORKERS
    if time_limit_s is not None:
        solver.parameters.max_time_in_seconds = max(float(time_limit_s), MIN_TIME_LIMIT_S)
    with in_backend("ortools"):
        status = solver.solve(model)
    name = solver.status_name(status)
    fences = None
    if status in (cp_model.OPTIMAL, cp_model.FEASIBLE):
        fences = tuple(next(f for f in range(n) if solver.boolean_value(sel[d][f])) for d in range(depth))
    return name, fences, len(model.proto.variables)


def shortest_design_cpsat(graph: DesignGraph, max_depth: int, alternate: bool = True,
                          budget: Budget = UNLIMITED) -> CpSatDesign:
    """Depths 1..``max_depth`` in order (module docstring) within ``budget``."""
    t0 = time.perf_counter()
    statuses: list[str] = []
    proven = 0
    variables = 0
    for depth in range(1, max_depth + 1):
        if budget.expired():
            return CpSatDesign(None, proven, tuple(statuses), False, time.perf_counter() - t0, variables)
        name, fences, variables = _solve_depth(graph, depth, alternate, budget.remaining_or_none())
        statuses.append(name)
        if fences is not None:
            return CpSatDesign(fences, proven, tuple(statuses), True, time.perf_counter() - t0, variables)
        if name != "INFEASIBLE":
            return CpSatDesign(None, proven, tuple(statuses), False, time.perf_counter() - t0, variables)
        proven = depth
    return CpSatDesign(None, proven, tuple(statuses), True, time.perf_counter() - t0, variables)
