"""The compiled dominance scan of the feeder design search (solver/kernels/search.py) against
its reference, models.feeder.design_graph.scan_reached (book 5.3.2: a node is pruned when a
node already reached has its set within the new one at no smaller margin): the same answer
on seeded sets of arcs, with arcs across 2 pi, the whole circle, touching ends within the
slack and a cell mask that rules a node out; and the same designs from the search."""

from __future__ import annotations

import math

import numpy as np

from models.feeder.arcs import TWO_PI, Arcs
from models.feeder.design_graph import ReachedSets, cell_mask, cell_words, scan_reached, search_design
from solver.kernels.search import scan_reached as compiled_scan
from tests.models.feeder.test_design_graph import graph_of

CELLS = 1440


def _random_arcs(rng):
    if rng.random() < 0.03:
        return Arcs.circle()
    return Arcs.of([(float(rng.uniform(0, TWO_PI)), float(rng.uniform(0.0, 1.5)))
                    for _ in range(int(rng.integers(1, 6)))])


def test_the_compiled_scan_answers_as_the_reference_5_3_2():
    rng = np.random.default_rng(20261204)
    both = [ReachedSets(CELLS), ReachedSets(CELLS, compiled_scan)]
    answers = []
    for i in range(300):  # past the arrays' first capacity (64) and their first width (4 arcs)
        arcs = _random_arcs(rng)
        margin = float(rng.choice([0.1, 0.2, math.inf]))
        for seen in both:
            seen.add(i % 5, frozenset({i % 3}), arcs, cell_mask(arcs, CELLS), margin)
    for _ in range(600):
        arcs = _random_arcs(rng)
        if rng.random() < 0.3:  # a node's own set, a hair wider: inside only within the slack
            own = both[0].arcs[int(rng.integers(len(both[0].arcs)))]
            arcs = Arcs.of([(s + 1e-13, w - 2e-13) for s, w in own.arcs]) if own.arcs[0][1] < TWO_PI else own
        mask, margin = cell_mask(arcs, CELLS), float(rng.choice([0.05, 0.15, 0.3]))
        query = np.array(arcs.arcs, dtype=float).reshape(-1, 2)
        args = (both[0].starts, both[0].widths, both[0].counts, both[0].margins, both[0].words, len(both[0].arcs),
                query)
        inverse = ~cell_words(mask, CELLS)
        for slack in (0.0, 1e-12):
            want = scan_reached(*args, inverse, margin, slack)
            assert compiled_scan(*args, inverse, margin, slack) == want
            answers.append(want)
        assert both[1].dominated(arcs, mask, margin, 1e-12, 0, frozenset({0, 1})) == \
            both[0].dominated(arcs, mask, margin, 1e-12, 0, frozenset({0, 1}))
    assert 0.05 < sum(answers) / len(answers) < 0.95  # both answers exercised


def test_the_search_finds_the_same_designs_on_the_compiled_scan_5_3():
    for name in ("pentagon", "right triangle"):
        graph = graph_of(name)
        for alternate in (False, True):
            ref = search_design(graph, 8, alternate=alternate)
            got = search_design(graph, 8, alternate=alternate, scan=compiled_scan)
            assert got.design == ref.design
            assert (got.nodes, got.pruned, got.depth_proven, got.per_depth_nodes) == \
                (ref.nodes, ref.pruned, ref.depth_proven, ref.per_depth_nodes)
