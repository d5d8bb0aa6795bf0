"""The CP-SAT feeder design (solver/feeder/design_cpsat.py, book 5.3, 5.4) against the
breadth-first search of models/feeder/design_graph.py: the same least number of fences, the same
depths proven impossible, and a CP-SAT design that the code sets confirm."""

from __future__ import annotations

import math

import pytest

from models.feeder.design_graph import DesignGraph, search_design
from models.feeder.fence import Fence, fence_map
from solver import Budget
from solver.feeder.design_cpsat import shortest_design_cpsat
from tests.feeder_cases import Clock, part


def graph_of(name: str, angles) -> DesignGraph:
    p = part(name)
    return DesignGraph.build(p, [fence_map(p, Fence.create(s * math.radians(d), 0.25))
                                 for s in (1.0, -1.0) for d in angles])


def confirm(graph: DesignGraph, fences: tuple[int, ...], alternate: bool) -> bool:
    """Whether the sequence is a design by the code sets (5.4)."""
    if not graph.first_ok[fences[0]]:
        return False
    occ = graph.start[fences[0]]
    for g, f in zip(fences, fences[1:]):
        if alternate and graph.side(g) == graph.side(f):
            return False
        got = graph.step(g, occ, f)
        if got is None:
            return False
        occ = got[0]
    return graph.is_goal(fences[-1], occ)


@pytest.mark.parametrize(("name", "angles", "alternate"), [
    ("square", (15.0, 35.0, 55.0, 80.0), True),
    ("rectangle", (15.0, 35.0, 55.0, 80.0), True),
    ("right triangle", (15.0, 35.0, 55.0, 80.0), False),
    ("right triangle", (15.0, 35.0, 55.0, 80.0), True),
    ("pentagon", tuple(range(15, 81, 5)), False),
    ("L-shape", (15.0, 30.0, 45.0, 60.0, 75.0), False),
])
def test_cp_sat_and_the_search_agree_5_3(name, angles, alternate):
    graph = graph_of(name, angles)
    bfs = search_design(graph, 8, alternate=alternate)
    depth = 8 if bfs.design is None else len(bfs.design.fences)
    cp = shortest_design_cpsat(graph, depth, alternate=alternate)
    assert cp.complete
    if bfs.design is None:
        assert cp.fences is None and cp.depth_proven == depth
    else:
        assert cp.fences is not None and len(cp.fences) == depth
        assert cp.depth_proven == bfs.depth_proven == depth - 1
        assert confirm(graph, cp.fences, alternate)
        assert all(s == "INFEASIBLE" for s in cp.statuses[:-1]) and cp.statuses[-1] in ("OPTIMAL", "FEASIBLE")


def test_an_expired_budget_tries_no_depth():
    clock = Clock()
    budget = Budget.of(5.0, clock=clock)
    clock.run_out = True
    cp = shortest_design_cpsat(graph_of("rectangle", (35.0, 55.0)), 4, budget=budget)
    assert cp.fences is None and not cp.complete and cp.statuses == () and cp.depth_proven == 0
