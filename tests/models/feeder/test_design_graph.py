"""The design search of models/feeder/design_graph.py (book 5.3, 5.4): the breadth-first search
with its dominance pruning against exhaustive enumeration, the goal against the product of
the fences' maps (5.4, 5.5), and rotational symmetry."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.feeder.design_graph import DesignGraph, rotational_symmetry, search_design
from models.feeder.fence import Fence, feeder_part, fence_map
from models.feeder.maps import sequence
from tests.feeder_cases import part

ANGLES = (15.0, 35.0, 55.0, 80.0)


def graph_of(name: str, mu_c: float = 0.25, angles=ANGLES) -> DesignGraph:
    p = part(name)
    maps = [fence_map(p, Fence.create(s * math.radians(d), mu_c)) for s in (1.0, -1.0) for d in angles]
    return DesignGraph.build(p, maps)


def brute_force(graph: DesignGraph, max_depth: int, alternate: bool):
    """(least depth, largest margin among the designs of that depth) by enumerating every
    sequence, or None."""
    n = len(graph.maps)
    for depth in range(1, max_depth + 1):
        best = None
        for seq in itertools.product(range(n), repeat=depth):
            if alternate and any(graph.side(a) == graph.side(b) for a, b in zip(seq, seq[1:])):
                continue
            if not graph.first_ok[seq[0]]:
                continue
            occ, margin = graph.start[seq[0]], math.inf
            for g, f in zip(seq, seq[1:]):
                got = graph.step(g, occ, f)
                if got is None:
                    break
                occ, m = got
                margin = min(margin, m)
            else:
                if graph.is_goal(seq[-1], occ):
                    best = margin if best is None else max(best, margin)
        if best is not None:
            return depth, best
    return None


def test_rotational_symmetry_of_the_hull():
    assert rotational_symmetry(part("square")) == 4
    assert rotational_symmetry(part("rectangle")) == 2
    assert rotational_symmetry(part("pentagon")) == 1
    assert rotational_symmetry(part("near-symmetric")) == 1
    tri = [[math.cos(a), math.sin(a)] for a in (0.3, 0.3 + 2 * math.pi / 3, 0.3 + 4 * math.pi / 3)]
    assert rotational_symmetry(feeder_part(tri)) == 3
    assert rotational_symmetry(feeder_part(tri, [0.01, 0.0])) == 1  # the CM off the centre


@pytest.mark.parametrize("name", ["rectangle", "right triangle", "pentagon", "L-shape", "near-symmetric"])
@pytest.mark.parametrize("alternate", [True, False])
def test_the_pruned_search_finds_the_least_depth_and_the_best_margin_5_3_2(name, alternate):
    """Dominance pruning (a set containing one already searched, at no smaller margin) is
    exact: the breadth-first search finds the depth and the margin that enumerating every
    sequence of up to five fences finds, or proves, as enumeration does, that none exists."""
    graph = graph_of(name)
    depth = 5 if alternate else 4
    got = search_design(graph, depth, alternate=alternate)
    ref = brute_force(graph, depth, alternate)
    if ref is None:
        assert got.design is None and got.depth_proven >= depth or got.exhausted
    else:
        assert got.design is not None and len(got.design.fences) == ref[0]
        assert got.design.margin == pytest.approx(ref[1], abs=1e-12)
        assert got.depth_proven == ref[0] - 1


@pytest.mark.parametrize("name", ["rectangle", "right triangle", "pentagon", "L-shape"])
def test_a_design_leaves_the_bands_of_the_product_of_its_maps_5_4(name):
    """The bands a design leaves the part in are the bands of the product of its fences'
    maps (5.4, 5.5) that some initial orientation reaches, and they form one band up to
    the part's symmetry."""
    graph = graph_of(name, angles=(15.0, 30.0, 45.0, 60.0, 75.0))
    res = search_design(graph, 8, alternate=False)
    assert res.design is not None
    product = sequence([graph.maps[f].map for f in res.design.fences])
    reached = {j for j, k in enumerate(product.kernels) if not k.is_empty}
    assert reached == set(res.design.final_bands)
    assert graph.is_goal(res.design.fences[-1], res.design.final_bands)
    assert product.jam.is_empty and product.unaligned.is_empty


def test_an_exhausted_search_means_no_design_at_any_depth():
    """When every node is pruned the search says no design exists at any depth; enumeration
    to a greater depth agrees."""
    graph = graph_of("right triangle", angles=(15.0, 35.0, 55.0))
    res = search_design(graph, 12, alternate=True)
    if res.design is None and res.exhausted:
        assert brute_force(graph, 7, True) is None
    else:  # the candidate set admits a design: then enumeration finds the same depth
        ref = brute_force(graph, 12 if res.design is None else len(res.design.fences), True)
        assert res.design is not None and ref is not None and ref[0] == len(res.design.fences)


def test_a_square_needs_one_fence_and_a_fence_that_jams_is_never_used_6_4():
    graph = graph_of("square")
    res = search_design(graph, 3)
    assert res.design is not None and len(res.design.fences) == 1 and res.depth_proven == 0
    sq = part("square")
    jams = fence_map(sq, Fence.create(math.radians(10.0), 0.25))  # tan 10 deg < 0.25: flush parts jam
    graph = DesignGraph.build(sq, [jams])
    assert not graph.first_ok[0]
    res = search_design(graph, 3)
    assert res.design is None and res.exhausted and res.nodes == 0
    with pytest.raises(InvalidInput):
        search_design(graph, 0)
    assert np.isinf(search_design(graph_of("square"), 2).design.margin)


@pytest.mark.parametrize("name", ["rectangle", "right triangle", "pentagon", "L-shape", "near-symmetric"])
def test_steps_to_every_candidate_are_each_step_5_4(name):
    """Issue 26: the search takes one node's steps to every candidate at once from packed
    rows (DesignGraph.steps); each is exactly DesignGraph.step's code set (5.4) and margin,
    from every band set reached by up to three fences."""
    graph = graph_of(name, angles=(12.0, 28.0, 44.0, 61.0, 77.0))
    n = len(graph.maps)
    states = {(f, graph.start[f]) for f in range(n) if graph.start[f]}
    checked = 0
    for _ in range(3):
        nxt = set()
        for g, occ in states:
            many = graph.steps(g, occ)
            assert len(many) == n
            for f in range(n):
                one = graph.step(g, occ, f)
                assert many[f] == one  # the same frozenset and the same float, not approximately
                checked += 1
                if one is not None and one[0]:
                    nxt.add((f, one[0]))
        states = nxt
    assert checked > 100


def test_the_dominance_test_on_arrays_is_the_list_test_5_3_2():
    """Issue 26: the pruning's dominance test on arrays of margins and cell masks (ReachedSets)
    answers as the plain scan of every node reached: a node whose set lies within the new
    set at no smaller margin."""
    from models.feeder.arcs import Arcs
    from models.feeder.design_graph import ReachedSets, cell_mask

    rng = np.random.default_rng(20261127)
    cells = 1440

    def random_arcs():
        return Arcs.of([(float(rng.uniform(0, 2 * math.pi)), float(rng.uniform(0.01, 1.5)))
                        for _ in range(int(rng.integers(1, 4)))])

    seen, plain = ReachedSets(cells), []
    for i in range(150):  # past the arrays' first capacity (64)
        arcs = random_arcs()
        margin, mask = float(rng.choice([0.1, 0.2, math.inf])), cell_mask(arcs, cells)
        seen.add(i % 7, frozenset({i % 3}), arcs, mask, margin)
        plain.append((margin, mask, arcs))
    answers = []
    for _ in range(400):
        arcs = random_arcs()
        mask, margin = cell_mask(arcs, cells), float(rng.choice([0.05, 0.15, 0.3]))
        want = any(m >= margin and k & ~mask == 0 and a.issubset(arcs, 1e-12) for m, k, a in plain)
        fence, occupied = int(rng.integers(7)), frozenset({0, 1, 2})  # its subsets are looked up first
        assert seen.dominated(arcs, mask, margin, 1e-12, fence, occupied) == want
        answers.append(want)
    assert 0 < sum(answers) < len(answers)  # both answers were exercised
