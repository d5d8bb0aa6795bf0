"""Designs searched as placed on a belt (issue 24; book 5.3-5.4, 1.8.6, figure 1-9, 7.1):
the fences are physical, each must catch the part where it arrives with reach enough to
align it, the goal is what the next station accepts, and a reject gate may take the parts
the fences cannot orient.

World frame as in models/feeder/layout.py: a belt of width W carries the part in -y between
x = -W/2 and x = +W/2; a fence of side s = sgn(gamma) hangs from x = s W/2 and runs toward
-s down to its free end at x = x_e, where a gap g = 2a + clearance to the other side lets
the part pass (s x_e >= -W/2 + g).

Catching and reach (1.8.6). A part leaves a fence at its free end: its CM is then within a
(its radius about the CM) of x_e, and it rides the belt straight on, so its hull lies within
x_e +- 2a. Parts enter in a lane: CM within entry_x +- spread, the hull within a more. A
fence of side s meets such a part first somewhere in that x span; from the least favourable
first contact, x_p - s h (x_p where the part comes from, h its half span), its reach along
the fence to the free end is (s (x_p - x_e) - h) / cos gamma. It must be at least the reach
the arriving orientations need (models/feeder/fence.py phase 6, :class:`ReachProfile`):

    s x_e <= s x_p - h - R cos|gamma|.                                              (lane)

The chain of these difference constraints between consecutive free ends is feasible exactly
when the forward pass keeps a non-empty interval of free-end positions: after a fence of side
+1 the free end may lie anywhere in [-W/2 + g, max x_p - h - R cos gamma], of side -1 in
[min x_p + h + R cos gamma, W/2 - g] (a wider interval leaves every later fence at least the
room of a narrower one). The search carries that interval (the lane); a placement within it
is chosen afterwards (solver/feeder/placement.py: the shortest belt).

The first fence sees every orientation, and near each balance where the part can slide
without turning no reach aligns it (phase 6): the first fence takes the least reach whose
unaligned set has measure at most the loss allowed, (1 - min_yield) 2 pi (for a gate design
also each share of FIRST_LOSSES below 1 - the gate's min_yield: a shorter fence that loses
more), and those initial orientations are lost (any outcome; they count against the
guaranteed yield). A later fence must align every orientation that may arrive at it but a
sliver of at most DesignTolerances.sliver radians (counted against the yield), or the step
is refused.

Goals (5.3.1 and the user's). By default one band per symmetry class (models/feeder/design_graph.py);
or a set G of accepted final orientations: a band is accepted when it lies within G.

Yield. Each node keeps, per band, the initial orientations that may end in it (the kernels
of the product of the maps, 5.4). The guaranteed yield per pass is the share of initial
orientations every outcome of which is accepted: 1 - |lost ∪ U_{j rejected} origin_j| / 2 pi.

A gate (models/feeder/gate.py) after the last fence may reject some bands: a node whose bands
split by one feature into accepted (within the goal) and rejected ones is a gate design.
Among designs, fewer fences first, then a fences-only design (every band accepted, yield at
least min_yield), then a gate design of the largest guaranteed yield (at least the gate's
min_yield), then the largest margin.

Dominance, fences only (design_graph.py's rule with the lane): a node is dropped when a
node already reached holds a set of orientations within its set, a lane containing its lane,
no more lost and no smaller margin; every continuation of the dropped node is then matched,
fence for fence, by one of the kept node (with alternating sides, only among nodes whose
last fence is on the same side). With a gate that is not enough: a smaller set of bands may
miss the accepted bands a gate needs, or carry more origins into a rejected band; so the
gate search drops only a node whose state (fence, bands, origins per band, lost set) is
matched by one reached before, and its depth proven and exhaustion are proofs as well.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.feeder.arcs import TWO_PI, Arcs
from models.feeder.design_graph import DESIGN_DEFAULT, DesignGraph, DesignTolerances, Progress, cell_mask
from models.feeder.fence import ReachBound
from models.feeder.gate import MARGIN_RADII, Gate, GateSpec, critical_orientations, extent_range, separations
from models.feeder.layout import CLEARANCE_RADII, SPACING_RADII

FIRST_LOSSES = (0.01, 0.02, 0.05, 0.1, 0.2, 0.4)
"""Shares of the initial orientations a gate design's first fence may leave unaligned, each
tried (a longer reach loses less but takes more of the belt's width)."""
REACH_SLACK_RADII = 0.25
"""Reach added to what the arriving orientations need, in part radii (the simulator's contact
tolerance and the first contact's exact point are not in the bound)."""


@dataclass(frozen=True)
class Belt:
    """The belt: its width, the part's radius about its CM, the clearance at each free end,
    the spacing from a free end to the next fence's root, the entry lane (x of the CM) and
    its half width ``entry_spread``."""

    width: float
    part_radius: float
    clearance: float
    spacing: float
    entry_x: float
    entry_spread: float = 0.0

    def __post_init__(self) -> None:
        a = self.part_radius
        if not (math.isfinite(self.width) and self.width > self.gap):
            raise InvalidInput("belt.width", f"must exceed the part's diameter plus the clearance ({self.gap:.6g})")
        if not (math.isfinite(self.spacing) and self.spacing >= 0.0):
            raise InvalidInput("belt.spacing", "must be finite and >= 0")
        if not (math.isfinite(self.clearance) and self.clearance >= 0.0):
            raise InvalidInput("belt.clearance", "must be finite and >= 0")
        if not (math.isfinite(self.entry_spread) and self.entry_spread >= 0.0):
            raise InvalidInput("belt.entry_spread", "must be finite and >= 0")
        if not (math.isfinite(self.entry_x) and abs(self.entry_x) + self.entry_spread + a <= 0.5 * self.width):
            raise InvalidInput("belt.entry_x", "the entry lane (plus the part's radius) must lie on the belt")

    @classmethod
    def create(cls, width: float, part_radius: float, clearance: float | None = None, spacing: float | None = None,
               entry_x: float | None = None, entry_spread: float = 0.0, first_side: float = 1.0) -> Belt:
        """Defaults: a tenth of a radius of clearance, a diameter of spacing, the lane beside
        the side ``first_side`` (the part's hull the clearance from it)."""
        a = float(part_radius)
        gap = CLEARANCE_RADII * a if clearance is None else float(clearance)
        if not (math.isfinite(width) and width > 2.0 * a + gap):  # before the lane, which it bounds
            raise InvalidInput("belt.width", f"must exceed the part's diameter plus the clearance ({2.0 * a + gap:.6g})")
        if entry_x is None and not 2.0 * (a + entry_spread + gap) <= float(width):
            raise InvalidInput("belt.entry_spread", "the entry lane (plus the part's radius and the clearance) must "
                                                    "fit on the belt")
        lane = (first_side * (0.5 * float(width) - a - entry_spread - gap)) if entry_x is None else float(entry_x)
        return cls(float(width), a, gap, SPACING_RADII * a if spacing is None else float(spacing), lane,
                   float(entry_spread))

    @property
    def gap(self) -> float:
        return 2.0 * self.part_radius + self.clearance

    def arrival(self, lane: tuple[float, float] | None) -> tuple[float, float, float]:
        """(least x, largest x, half span h) of where a part may come from: the entry lane
        (None) or the free ends of a lane."""
        if lane is None:
            return self.entry_x, self.entry_x, self.entry_spread + self.part_radius
        return lane[0], lane[1], 2.0 * self.part_radius

    def lane_after(self, lane: tuple[float, float] | None, sign: float, angle: float,
                   reach: float) -> tuple[float, float] | None:
        """The free-end positions of a fence (side ``sign``, ``angle``) with at least
        ``reach`` beyond the first contact of a part coming from ``lane`` (module docstring,
        (lane)); None when the belt is too narrow for it."""
        lo, hi, h = self.arrival(lane)
        need = h + reach * math.cos(angle)
        edge = 0.5 * self.width - self.gap
        out = (-edge, hi - need) if sign > 0.0 else (lo + need, edge)
        return out if out[0] <= out[1] else None


GUIDE_SIDES = ("right", "left", "either")
"""The guide an edge may lie against: the belt's right side (its outward normal +x), the
left (-x), or either (the part half a turn round)."""


@dataclass(frozen=True)
class Goal:
    """The final orientations the next station accepts (None: one band per symmetry class)."""

    accepted: Arcs | None = None

    def __post_init__(self) -> None:
        if self.accepted is not None and self.accepted.is_empty:
            raise InvalidInput("goal", "accepts no orientation")

    @classmethod
    def edge_against_guide(cls, part: Footprint, j: int, side: str, tolerance: float) -> Goal:
        """Hull edge j along the belt's motion against a guide on ``side`` (GUIDE_SIDES),
        within ``tolerance`` radians: the edge's outward normal phi_j - pi/2 (a CCW hull)
        turned by theta points along +x when theta = pi/2 - phi_j, along -x half a turn on."""
        if side not in GUIDE_SIDES:
            raise InvalidInput("goal.side", f"must be one of {list(GUIDE_SIDES)}")
        if not (math.isfinite(tolerance) and 0.0 < tolerance < 0.5 * math.pi):
            raise InvalidInput("goal.tolerance", "must be in (0, pi/2) radians")
        right = 0.5 * math.pi - part.hull_edge_angle(j)
        centres = {"right": [right], "left": [right + math.pi], "either": [right, right + math.pi]}[side]
        return cls(Arcs.of((c - tolerance, 2.0 * tolerance) for c in centres))


@dataclass(frozen=True)
class PlacedDesign:
    """A design: candidate fences in order with the reach each needs (part units), the bands
    of the last fence the part may end in and those accepted, the gate (None: fences only),
    the lost initial orientations (the first fence's unaligned ones), the guaranteed yield
    per pass, the margin (radians, design_graph.py), the lane of the last free end."""

    fences: tuple[int, ...]
    reaches: tuple[float, ...]
    final_bands: frozenset[int]
    accepted_bands: frozenset[int]
    gate: Gate | None
    lost: Arcs
    slivers: float
    guaranteed_yield: float
    margin: float
    lane: tuple[float, float]


@dataclass(frozen=True)
class PlacedSearchResult:
    """The design (None: none found), the depth proven (no design with fewer fences than
    this + 1), whether the search was exhausted, node counts, and how many steps each
    constraint refused (``refused``: jam, reach, width)."""

    design: PlacedDesign | None
    depth_proven: int
    exhausted: bool
    nodes: int
    pruned: int
    solve_time_s: float
    per_depth_nodes: tuple[int, ...]
    refused: dict[str, int] = field(default_factory=dict)


@dataclass
class _Node:
    fence: int
    occupied: frozenset[int]
    arcs: Arcs
    margin: float
    path: tuple[int, ...]
    reaches: tuple[float, ...]
    lane: tuple[float, float]
    origins: dict[int, Arcs]
    mask: int
    lost: Arcs  # initial orientations the first fence leaves unaligned
    slivers: float  # arriving orientations later fences leave unaligned (radians, summed)
    lost_measure: float = 0.0

    def __post_init__(self) -> None:
        self.lost_measure = self.lost.measure + self.slivers


class PlacedGraph:
    """The design graph with what placing needs: each candidate's reach profile, the goal's
    accepted bands, and each band's range of every gate feature."""

    def __init__(self, graph: DesignGraph, profiles: Sequence[ReachBound], goal: Goal,
                 gate: GateSpec | None) -> None:
        if len(profiles) != len(graph.maps):
            raise ValueError("one reach profile per candidate fence")
        self.graph = graph
        self.profiles = tuple(profiles)
        self.goal = goal
        if gate is not None and gate.margin is None:
            gate = replace(gate, margin=MARGIN_RADII * graph.maps[0].part.circumradius)
        self.gate = gate
        if goal.accepted is None:
            self.accepted = None
        else:
            acc = goal.accepted
            self.accepted = tuple(frozenset(j for j, b in enumerate(m.map.bands) if b.issubset(acc)) for m in graph.maps)
        self.ranges: tuple[dict[str, list[tuple[float, float]]], ...] = ()
        if gate is not None:
            part = graph.maps[0].part
            crit = {f: critical_orientations(part, f) for f in gate.features}
            self.ranges = tuple({f: [extent_range(part, b, f, crit[f]) for b in m.map.bands] for f in gate.features}
                                for m in graph.maps)

    def accepted_classes(self, f: int, occupied: frozenset[int]) -> list[frozenset[int]]:
        """The sets of bands a design may accept: those within the goal, or per symmetry
        class the bands of that class."""
        if self.accepted is not None:
            got = occupied & self.accepted[f]
            return [got] if got else []
        classes: dict[int, set[int]] = {}
        for j in occupied:
            classes.setdefault(self.graph.orbit[f][j], set()).add(j)
        return [frozenset(c) for c in classes.values()]

    def gates(self, f: int, occupied: frozenset[int]) -> list[Gate]:
        """Every gate after fence f that accepts only bands a design may accept."""
        if self.gate is None or len(occupied) < 2:
            return []
        allowed = self.accepted_classes(f, occupied)
        out: list[Gate] = []
        for feature in self.gate.features:
            ranges = {j: self.ranges[f][feature][j] for j in occupied}
            out.extend(g for g in separations(ranges, feature, self.gate.margin or 0.0)
                       if any(g.accepted <= c for c in allowed))
        return out


def _yield(lost: Arcs, slivers: float, origins: dict[int, Arcs], accepted: frozenset[int]) -> float:
    gone = Arcs.union_of([lost] + [origins[j] for j in origins if j not in accepted])
    return max(1.0 - (gone.measure + slivers) / TWO_PI, 0.0)


def _contains(outer: tuple[float, float], inner: tuple[float, float]) -> bool:
    return outer[0] <= inner[0] and inner[1] <= outer[1]


def _dominated(seen: list[_Node], node: _Node, slack: float) -> bool:
    """Fences only (module docstring): a node reached before with a set within this one's,
    a lane containing its lane, no more lost and no smaller margin."""
    for old in seen:
        if (old.margin >= node.margin and old.lost_measure <= node.lost_measure and old.mask & ~node.mask == 0
                and _contains(old.lane, node.lane) and old.arcs.issubset(node.arcs, slack)):
            return True
    return False


def _same_state(seen: list[_Node], node: _Node, slack: float) -> bool:
    """With a gate: a node reached before at the same fence with the same bands, a lane
    containing this one's, no more lost, no smaller margin and, band by band, origins within
    this one's. Only then is every continuation (the bands it reaches, a gate's split, its
    yield) matched; a smaller set of bands may lose the accepted ones a gate needs."""
    for old in seen:
        if (old.fence == node.fence and old.occupied == node.occupied and old.margin >= node.margin
                and _contains(old.lane, node.lane) and old.lost.issubset(node.lost, slack)
                and old.slivers <= node.slivers
                and all(old.origins[j].issubset(node.origins[j], slack) for j in node.occupied)):
            return True
    return False


@dataclass
class _Search:
    """One placed search's state (module docstring)."""

    pg: PlacedGraph
    belt: Belt
    min_yield: float
    tol: DesignTolerances
    refused: dict[str, int] = field(default_factory=lambda: {"jam": 0, "reach": 0, "width": 0})

    def firsts(self, losses: Sequence[float]) -> list[_Node]:
        """The first fences, one node per loss allowed (radians of initial orientations the
        first fence may leave unaligned: a fences-only design's, a gate design's)."""
        g = self.pg.graph
        out: list[_Node] = []
        for f, fm in enumerate(g.maps):
            if not fm.map.jam.is_empty or not g.start[f]:
                self.refused["jam"] += 1
                continue
            for loss in sorted(set(losses)):
                reach, _ = self.pg.profiles[f].needed(Arcs.circle(), loss)
                if not math.isfinite(reach):
                    self.refused["reach"] += 1
                    continue
                lost = self.pg.profiles[f].unaligned(reach)
                reach += REACH_SLACK_RADII * self.belt.part_radius
                lane = self.belt.lane_after(None, fm.fence.sign, fm.fence.angle, reach)
                if lane is None:
                    self.refused["width"] += 1
                    continue
                occ = g.start[f]
                arcs = g.occupied_set(f, occ)
                origins = {j: fm.map.kernels[j] for j in occ}
                out.append(_Node(f, occ, arcs, math.inf, (f,), (reach,), lane, origins,
                                 cell_mask(arcs, self.tol.mask_cells), lost, 0.0))
        return out

    def child(self, node: _Node, f: int) -> _Node | None:
        g = self.pg.graph
        fm = g.maps[f]
        got = g.step(node.fence, node.occupied, f)
        if got is None:
            self.refused["jam"] += 1
            return None
        occ, m = got
        need, sliver = self.pg.profiles[f].needed(node.arcs, self.tol.sliver)
        if not math.isfinite(need):
            self.refused["reach"] += 1
            return None
        reach = need + REACH_SLACK_RADII * self.belt.part_radius
        lane = self.belt.lane_after(node.lane, fm.fence.sign, fm.fence.angle, reach)
        if lane is None:
            self.refused["width"] += 1
            return None
        rows = sorted(node.occupied)
        origins = {}
        for j in occ:
            origins[j] = Arcs.union_of(node.origins[i] for i in rows if g.meets[node.fence][f][i, j])
        arcs = g.occupied_set(f, occ)
        return _Node(f, occ, arcs, min(node.margin, m), node.path + (f,), node.reaches + (reach,), lane, origins,
                     cell_mask(arcs, self.tol.mask_cells), node.lost, node.slivers + sliver)

    def designs(self, nd: _Node) -> list[tuple[float, float, _Node, Gate | None]]:
        """The designs the node makes, as (guaranteed yield, margin, node, gate): fences only
        when every band is accepted and the yield reaches min_yield, else every gate whose
        yield reaches the gate's min_yield."""
        if any(c == nd.occupied for c in self.pg.accepted_classes(nd.fence, nd.occupied)):
            y = _yield(nd.lost, nd.slivers, nd.origins, nd.occupied)
            return [(y, nd.margin, nd, None)] if y >= self.min_yield else []
        out: list[tuple[float, float, _Node, Gate | None]] = []
        for gate in self.pg.gates(nd.fence, nd.occupied):
            y = _yield(nd.lost, nd.slivers, nd.origins, gate.accepted)
            assert self.pg.gate is not None
            if y >= self.pg.gate.min_yield:
                out.append((y, nd.margin, nd, gate))
        return out

    def best(self, nodes: list[_Node]) -> PlacedDesign | None:
        """The best design among the nodes of one depth (module docstring), or None."""
        found = [d for nd in nodes for d in self.designs(nd)]
        pool = [d for d in found if d[3] is None] or found
        if not pool:
            return None
        y, margin, nd, gate = max(pool, key=lambda t: (t[0], t[1], t[2].lane[1] - t[2].lane[0]))
        accepted = nd.occupied if gate is None else gate.accepted
        return PlacedDesign(nd.path, nd.reaches, nd.occupied, accepted, gate, nd.lost, nd.slivers, y, margin, nd.lane)


def search_placed(pg: PlacedGraph, belt: Belt, max_depth: int, min_yield: float = 0.995, alternate: bool = False,
                  tol: DesignTolerances = DESIGN_DEFAULT, checkpoint: Callable[[str], None] | None = None,
                  progress: Progress | None = None) -> PlacedSearchResult:
    """Breadth-first search for the best placed design (module docstring) up to
    ``max_depth`` fences; ``checkpoint`` (a deadline) is called before each node's children
    and each candidate child, and ``progress`` then holds what was established."""
    if max_depth < 1:
        raise InvalidInput("max_depth", "must be at least 1")
    if not (0.0 < min_yield <= 1.0):
        raise InvalidInput("min_yield", "must be in (0, 1]")
    t0 = time.perf_counter()
    progress = Progress() if progress is None else progress
    s = _Search(pg, belt, min_yield, tol)
    g = pg.graph
    losses = [(1.0 - min_yield) * TWO_PI]
    if pg.gate is not None:
        most = 1.0 - pg.gate.min_yield
        losses += [share * TWO_PI for share in FIRST_LOSSES if share < most] + [most * TWO_PI]
    frontier = s.firsts(losses)
    prune = _dominated if pg.gate is None else _same_state

    def key_of(nd: _Node) -> tuple[object, ...]:
        """Nodes compared for pruning: by the last side when sides alternate; with a gate
        only nodes of the same fence and bands can match."""
        side = g.side(nd.fence) if alternate else 0.0
        return (side,) if pg.gate is None else (side, nd.fence, nd.occupied)

    seen: dict[tuple[object, ...], list[_Node]] = {}
    for node in frontier:
        seen.setdefault(key_of(node), []).append(node)
    nodes, pruned, per_depth = len(frontier), 0, [len(frontier)]
    depth = 1
    while True:
        progress.nodes, progress.pruned, progress.per_depth = nodes, pruned, list(per_depth)
        design = s.best(frontier)
        if design is not None:
            return PlacedSearchResult(design, depth - 1, False, nodes, pruned, time.perf_counter() - t0,
                                      tuple(per_depth), dict(s.refused))
        progress.depth_proven = depth
        if depth >= max_depth or not frontier:
            return PlacedSearchResult(None, depth, not frontier, nodes, pruned, time.perf_counter() - t0,
                                      tuple(per_depth), dict(s.refused))
        nxt: list[_Node] = []
        for node in frontier:
            if checkpoint is not None:
                progress.nodes, progress.pruned = nodes, pruned
                checkpoint(f"depth {depth + 1} of the placed design search ({nodes} nodes so far)")
            for f in range(len(g.maps)):
                if checkpoint is not None and f:
                    checkpoint(f"depth {depth + 1} of the placed design search ({nodes} nodes so far)")
                if alternate and g.side(f) == g.side(node.fence):
                    continue
                child = s.child(node, f)
                if child is None:
                    continue
                # a design is never pruned: a set within it need not be one by its own bands
                key = key_of(child)
                if not s.designs(child) and prune(seen.setdefault(key, []), child, tol.subset_slack):
                    pruned += 1
                    continue
                seen.setdefault(key, []).append(child)
                nxt.append(child)
                nodes += 1
        frontier = nxt
        per_depth.append(len(frontier))
        depth += 1

