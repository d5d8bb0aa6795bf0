"""Designs searched as placed (models/feeder/placed.py; book 5.3-5.4, 1.8.6, 7.1): the lane
against the fence's geometry, goals, and the search against a brute force over every fence
sequence whose yields come from the product of the maps (5.4), not from the search's own
bookkeeping, and whose placements are checked by the linear programme of
solver/feeder/placement.py."""

from __future__ import annotations

import itertools
import math
from functools import lru_cache

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.feeder.arcs import TWO_PI, Arcs
from models.feeder.design_graph import DesignGraph
from models.feeder.fence import Fence, fence_map, reach_profile
from models.feeder.gate import GateSpec
from models.feeder.maps import ConfigurationMap, sequence
from models.feeder.placed import FIRST_LOSSES, REACH_SLACK_RADII, Belt, Goal, PlacedGraph, search_placed
from solver.feeder.placement import place
from tests.feeder_cases import part

ANGLES = [math.radians(d) * s for s in (1.0, -1.0) for d in (30, 50, 70)]


@lru_cache(maxsize=None)
def setting(name: str):
    p = part(name)
    maps = [fence_map(p, Fence.create(g, (0.25, 0.25))) for g in ANGLES]
    profiles = [reach_profile(p, m.fence) for m in maps]
    return p, maps, profiles, DesignGraph.build(p, maps)


def test_the_lane_gives_the_reach_it_promises_from_the_least_favourable_contact_1_8_6():
    """A fence whose free end lies at the lane's edge has exactly the reach asked from the
    least favourable first contact: the point of the part's x span nearest the free end,
    measured along the fence (an independent intersection of the fence with that x)."""
    a = 1.0
    belt = Belt.create(20.0, a, entry_spread=0.5)
    for lane, gamma in [(None, 0.4), (None, 1.2), ((-3.0, 1.0), 0.4), ((-3.0, 1.0), -0.9), ((-3.0, 1.0), 1.2)]:
        sign = math.copysign(1.0, gamma)
        got = belt.lane_after(lane, sign, gamma, 2.5)
        assert got is not None
        x_end = got[1] if sign > 0 else got[0]  # the shortest fence
        root = np.array([sign * 10.0, 0.0])
        t = np.array([-sign * math.cos(abs(gamma)), -math.sin(abs(gamma))])  # down the fence from its root
        lo, hi, h = belt.arrival(lane)
        x_contact = (hi - h) if sign > 0 else (lo + h)  # the part's span edge nearest the end
        along = lambda x: (x - root[0]) / t[0]
        assert along(x_end) - along(x_contact) == pytest.approx(2.5, rel=1e-12)
    assert belt.lane_after(None, 1.0, 0.5, 100.0) is None  # wider than the belt
    assert belt.lane_after(None, -1.0, -0.5, 1.0) is None  # parts enter on the right: a left fence cannot come first


def test_a_goal_of_an_edge_against_a_guide_holds_its_orientations():
    """Edge j against the right guide: turned by an orientation of the goal, the edge's
    outward normal points along +x (within the tolerance); either side: +x or -x."""
    p = part("pentagon")
    for j in range(p.hull_size):
        right = Goal.edge_against_guide(p, j, "right", 0.05).accepted
        both = Goal.edge_against_guide(p, j, "either", 0.05).accepted
        assert right is not None and both is not None
        assert right.measure == pytest.approx(0.1) and both.measure == pytest.approx(0.2)
        start, width = right.arcs[0]
        theta = start + 0.5 * width
        e = p.hull[(j + 1) % p.hull_size] - p.hull[j]
        normal = np.array([e[1], -e[0]]) / np.hypot(*e)  # outward for a CCW hull
        turned = np.array([[math.cos(theta), -math.sin(theta)], [math.sin(theta), math.cos(theta)]]) @ normal
        assert turned == pytest.approx([1.0, 0.0], abs=1e-12)
        assert both.contains(theta) and both.contains(theta + math.pi)
    with pytest.raises(InvalidInput):
        Goal.edge_against_guide(p, 0, "top", 0.1)
    with pytest.raises(InvalidInput):
        Goal(Arcs.empty())


def brute_force(name: str, belt: Belt, depth: int, min_yield: float):
    """Every sequence of the candidates up to ``depth``: the occupied bands by the maps'
    code sets, the reach each fence needs, feasibility by forward lanes; the least depth
    with a goal and, at it, the largest yield from the product of the placed maps."""
    p, maps, profiles, g = setting(name)
    loss = (1.0 - min_yield) * TWO_PI
    slack = REACH_SLACK_RADII * p.circumradius
    best = {}
    for n in range(1, depth + 1):
        for seq in itertools.product(range(len(maps)), repeat=n):
            f0 = seq[0]
            reach, _ = profiles[f0].needed(Arcs.circle(), loss)
            if not math.isfinite(reach):
                continue
            lost = profiles[f0].unaligned(reach)
            reaches = [reach + slack]
            lane = belt.lane_after(None, maps[f0].fence.sign, maps[f0].fence.angle, reaches[0])
            occ = g.start[f0]
            ok = lane is not None
            for prev, f in zip(seq, seq[1:]):
                if not ok:
                    break
                step = g.step(prev, occ, f)
                if step is None:
                    ok = False
                    break
                need, sliver = profiles[f].needed(g.occupied_set(prev, occ), 1e-9)
                ok = math.isfinite(need) and sliver == 0.0
                reaches.append(need + slack)
                lane = belt.lane_after(lane, maps[f].fence.sign, maps[f].fence.angle, reaches[-1]) if ok else None
                ok = ok and lane is not None
                occ = step[0]
            if not ok or not g.is_goal(seq[-1], occ):
                continue
            first = maps[f0].map
            product = sequence([ConfigurationMap(first.bands, first.kernels, first.jam, lost)]
                               + [maps[f].map for f in seq[1:]])
            y = 1.0 - product.unaligned.union(product.jam).measure / TWO_PI
            if y >= min_yield:
                best.setdefault(n, []).append((y, seq, reaches))
        if n in best:
            return n, best[n]
    return None, []


@pytest.mark.parametrize("name", ["right triangle", "square", "rectangle"])
def test_the_placed_search_agrees_with_a_brute_force_over_every_sequence_5_3(name):
    p, maps, profiles, g = setting(name)
    belt = Belt.create(20.0 * p.circumradius, p.circumradius)
    res = search_placed(PlacedGraph(g, profiles, Goal(), None), belt, 3, min_yield=0.99)
    n, found = brute_force(name, belt, 3, 0.99)
    if n is None:
        assert res.design is None and (res.exhausted or res.depth_proven == 3)
        return
    d = res.design
    assert d is not None and len(d.fences) == n and res.depth_proven == n - 1
    y_best = max(y for y, _, _ in found)
    assert d.guaranteed_yield == pytest.approx(y_best, abs=1e-12)
    assert d.fences in {seq for _, seq, _ in found}
    # the linear programme places it with every reach and gap kept
    pl = place(belt, [ANGLES[f] for f in d.fences], list(d.reaches))
    assert all(f.reach >= r - 1e-9 * p.circumradius for f, r in zip(pl.fences, d.reaches))
    assert all(abs(f.end[0]) <= 0.5 * belt.width - belt.gap + 1e-9 * p.circumradius for f in pl.fences)


def brute_force_gated(name: str, belt: Belt, depth: int, gate: GateSpec):
    """As :func:`brute_force`, with a gate: every first-fence loss the search tries, and at
    the end of each sequence every gate after its last fence, the yield from the product's
    kernels (5.4): 1 - |unaligned u jam u the kernels of the rejected bands| / 2 pi."""
    p, maps, profiles, g = setting(name)
    pg = PlacedGraph(g, profiles, Goal(), gate)
    slack = REACH_SLACK_RADII * p.circumradius
    most = 1.0 - gate.min_yield
    losses = sorted({0.01 * TWO_PI} | {s * TWO_PI for s in FIRST_LOSSES if s < most} | {most * TWO_PI})
    for n in range(1, depth + 1):
        found = []
        for seq in itertools.product(range(len(maps)), repeat=n):
            for loss in losses:
                f0 = seq[0]
                reach, _ = profiles[f0].needed(Arcs.circle(), loss)
                if not math.isfinite(reach):
                    continue
                lost = profiles[f0].unaligned(reach)
                lane = belt.lane_after(None, maps[f0].fence.sign, maps[f0].fence.angle, reach + slack)
                occ, ok = g.start[f0], lane is not None
                for prev, f in zip(seq, seq[1:]):
                    step = g.step(prev, occ, f) if ok else None
                    if step is None:
                        ok = False
                        break
                    need, sliver = profiles[f].needed(g.occupied_set(prev, occ), 1e-9)
                    lane = belt.lane_after(lane, maps[f].fence.sign, maps[f].fence.angle, need + slack) \
                        if math.isfinite(need) and sliver == 0.0 else None
                    ok, occ = lane is not None, step[0]
                if not ok:
                    continue
                first = maps[f0].map
                prod = sequence([ConfigurationMap(first.bands, first.kernels, first.jam, lost)]
                                + [maps[f].map for f in seq[1:]])
                if g.is_goal(seq[-1], occ):
                    y = 1.0 - prod.unaligned.union(prod.jam).measure / TWO_PI
                    if y >= 0.99:
                        found.append((0, y, seq))
                    continue
                for gt in pg.gates(seq[-1], occ):
                    gone = Arcs.union_of([prod.unaligned, prod.jam]
                                         + [prod.kernels[j] for j in occ if j not in gt.accepted])
                    y = 1.0 - gone.measure / TWO_PI
                    if y >= gate.min_yield:
                        found.append((1, y, seq))
        if found:
            kind = min(k for k, _, _ in found)
            return n, max(y for k, y, _ in found if k == kind), kind
    return None, None, None


def test_the_gate_search_agrees_with_a_brute_force_over_every_sequence_7_1():
    """With a gate allowed the search prunes only states seen exactly; on the pentagon it
    finds the least depth a design exists at, prefers fences alone there, and reaches the
    largest guaranteed yield of the brute force (two fences, six candidates)."""
    name = "pentagon"
    p, maps, profiles, g = setting(name)
    belt = Belt.create(20.0 * p.circumradius, p.circumradius)
    gate = GateSpec(margin=0.005 * p.circumradius, min_yield=0.2)
    res = search_placed(PlacedGraph(g, profiles, Goal(), gate), belt, 2, min_yield=0.99)
    n, y_best, kind = brute_force_gated(name, belt, 2, gate)
    if n is None:
        assert res.design is None
        return
    d = res.design
    assert d is not None and len(d.fences) == n and (d.gate is not None) == (kind == 1)
    assert d.guaranteed_yield == pytest.approx(y_best, abs=1e-9)
