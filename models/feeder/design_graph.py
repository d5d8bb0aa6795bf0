"""Designing a parts feeder: the shortest sequence of fences that leaves a part in one final
orientation band (book 5.3, 5.4), searched breadth first over the maps of candidate fences.

The design graph (:class:`DesignGraph`). Candidate fence f has bands B^f_j over kernels
K^f_j (5.2). After fences ..., g the part is in one of the bands S of g (its code set,
5.2.1); through fence f it reaches

    S' = { j : B^g_i meets K^f_j for some i in S }                                  (5.4)

and the step is refused when a band of S meets f's jam set (6.4) or the orientations f's
reach may not align (1.8.6): the part could stay on the fence or leave it unbounded. The
first fence sees every orientation: S' = every band with a non-empty kernel, refused when f
may jam or leaves orientations unaligned anywhere.

The goal (5.3.1): S is one band, or, for a part with rotational symmetry of order k (its
hull unchanged by a turn of 2 pi / k about the CM), bands of edges that are images of one
another under that turn (5.4: "a rectangle has two").

Search (5.3.2). Breadth first, so the first depth with a goal is the least. A node is the
set of orientations X = U_{i in S} B^g_i the part may have, with the last fence's side when
sides must alternate. The book prunes (1) among fences with equal code sets all but the
steepest, whose bands lie inside the others' (a fact of the physics), and (2) a node whose
set is a superset of a set reached at smaller depth by the same fence angle. Both follow
from one exact rule used here: if X is within Y, every sequence that works from Y works
from X through at least one more fence (maps are monotone; the goal is then judged on the
same last fence), so a node whose set contains one already reached at no greater depth, with
no smaller margin, is dropped unless it is a goal itself (a set within it may hold two bands
of its own fence inside one band of another); it needs no assumption on the physics.

Robustness (1.8.6). The margin of a step is how far the occupied set X stays from every
kernel it does not meet and from the fence's jam and unaligned sets: band edges may move
by less than that (a change of mu_c, an uneven surface, 6.6) without changing the code
sets. A design's margin is its smallest step margin; among the shortest designs the search
keeps, it returns the one with the largest margin. That is not always the largest of all
shortest designs: the margin is not monotone under inclusion (a set X within Y may pass
closer than Y to a kernel that Y meets), so a pruned Y can have had a continuation of larger
margin. Such a near miss is harmless in fact (X meeting that kernel still occupies no more
than Y does), so the measure is conservative there.
"""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.feeder.arcs import TWO_PI, Arcs
from models.feeder.fence import FenceMap, rotation


@dataclass(frozen=True)
class DesignTolerances:
    """Named tolerances of the design search.

    Attributes:
        symmetry_rel: a turn of the hull is a symmetry when every vertex lands this close
            (times the part's radius) to a vertex.
        subset_slack: radians by which a set may stick out of another and still count as
            within it (dominance).
        mask_cells: cells of the circle in each node's bit mask, a quick necessary test of
            dominance (a set within another touches only cells the other touches).
        sliver: radians of the orientations arriving at a placed fence that it may leave
            unaligned (models/feeder/placed.py): the cells around a balance that need more
            reach than any other, whose width falls like e^(-reach / M) (fence.py phase 6).
    """

    symmetry_rel: float = 1e-9
    subset_slack: float = 1e-12
    mask_cells: int = 1440
    sliver: float = 1e-9


DESIGN_DEFAULT = DesignTolerances()


def rotational_symmetry(part: Footprint, tol: DesignTolerances = DESIGN_DEFAULT) -> int:
    """The largest k such that turning the hull by 2 pi / k about the CM gives the hull."""
    hull = part.hull
    for k in range(part.hull_size, 1, -1):
        if part.hull_size % k:
            continue
        turned = (rotation(TWO_PI / k) @ hull.T).T
        d = np.hypot(turned[:, None, 0] - hull[None, :, 0], turned[:, None, 1] - hull[None, :, 1])
        if np.all(d.min(axis=1) <= tol.symmetry_rel * part.circumradius):
            return k
    return 1


@dataclass(frozen=True)
class _PackedRows:
    """Row g of the graph's relations with every candidate's bands side by side (candidate
    f's columns are ``offsets[f]:offsets[f + 1]``), so one node's steps to every candidate
    are a few array reductions (:meth:`DesignGraph.steps`)."""

    offsets: np.ndarray
    meets: tuple[np.ndarray, ...]
    gap: tuple[np.ndarray, ...]
    bad: tuple[np.ndarray, ...]
    bad_gap: tuple[np.ndarray, ...]

    @classmethod
    def of(cls, gap: list[tuple[np.ndarray, ...]], bad_gap: list[tuple[np.ndarray, ...]]) -> _PackedRows:
        widths = [m.shape[1] for m in gap[0]]
        offsets = np.concatenate([[0], np.cumsum(widths)]).astype(np.intp)
        packed_gap = tuple(np.concatenate(row, axis=1) for row in gap)
        packed_bad_gap = tuple(np.stack(row, axis=1) if row else np.zeros((0, 0)) for row in bad_gap)
        return cls(offsets, tuple(d == 0.0 for d in packed_gap), packed_gap,
                   tuple(d == 0.0 for d in packed_bad_gap), packed_bad_gap)


@dataclass(frozen=True)
class DesignGraph:
    """The maps of the candidate fences and every relation the searches need (module
    docstring), precomputed: ``meets[g][f]`` (bands of g x bands of f) whether B^g_i meets
    K^f_j, ``gap[g][f]`` their distance, ``bad[g][f]`` whether B^g_i meets f's jam or
    unaligned set and ``bad_gap[g][f]`` its distance to them; ``start[f]`` the bands of f
    with a kernel; ``first_ok[f]`` whether f may come first; ``orbit[f][j]`` the symmetry
    class of band j's edge."""

    maps: tuple[FenceMap, ...]
    symmetry: int
    meets: tuple[tuple[np.ndarray, ...], ...]
    gap: tuple[tuple[np.ndarray, ...], ...]
    bad: tuple[tuple[np.ndarray, ...], ...]
    bad_gap: tuple[tuple[np.ndarray, ...], ...]
    start: tuple[frozenset[int], ...]
    first_ok: tuple[bool, ...]
    orbit: tuple[tuple[int, ...], ...]
    packed: _PackedRows

    @classmethod
    def build(cls, part: Footprint, maps: Sequence[FenceMap], tol: DesignTolerances = DESIGN_DEFAULT,
              checkpoint: Callable[[str], None] | None = None) -> DesignGraph:
        """The relations of every pair of candidates; ``checkpoint`` (a deadline) is called
        before each candidate's row."""
        if not maps:
            raise InvalidInput("fences", "need at least one candidate fence")
        k = rotational_symmetry(part, tol)
        step = part.hull_size // k
        stops = [f.map.jam.union(f.map.unaligned) for f in maps]
        gap, bad_gap = [], []
        for row, g in enumerate(maps):
            if checkpoint is not None:
                checkpoint(f"the design graph's row {row} of {len(maps)}")
            gap.append(tuple(np.array([[b.distance(kf) for kf in f.map.kernels] for b in g.map.bands], dtype=float)
                             .reshape(len(g.map.bands), len(f.map.kernels)) for f in maps))
            bad_gap.append(tuple(np.array([b.distance(stop) for b in g.map.bands], dtype=float) for stop in stops))
        # two sets meet exactly where their distance is 0 (Arcs.distance)
        meets = [tuple(d == 0.0 for d in row) for row in gap]
        bad = [tuple(d == 0.0 for d in row) for row in bad_gap]
        start = tuple(frozenset(j for j, kern in enumerate(f.map.kernels) if not kern.is_empty) for f in maps)
        first_ok = tuple(f.map.jam.is_empty and f.map.unaligned.is_empty and bool(s) for f, s in zip(maps, start))
        orbit = tuple(tuple(e % step for e in f.final_edges) for f in maps)
        return cls(tuple(maps), k, tuple(meets), tuple(gap), tuple(bad), tuple(bad_gap), start, first_ok, orbit,
                   _PackedRows.of(gap, bad_gap))

    def side(self, f: int) -> float:
        return self.maps[f].fence.sign

    def step(self, g: int, occupied: frozenset[int], f: int) -> tuple[frozenset[int], float] | None:
        """Fence f after the bands ``occupied`` of fence g: the bands of f reached and the
        step's margin, or None when the step is refused (jam or unaligned met)."""
        rows = np.array(sorted(occupied), dtype=np.intp)
        if self.bad[g][f][rows].any():
            return None
        hit = self.meets[g][f][rows].any(axis=0)
        reached = frozenset(int(j) for j in np.nonzero(hit)[0])
        margin = float(self.bad_gap[g][f][rows].min()) if rows.size else math.inf
        missed = ~hit
        if missed.any():
            margin = min(margin, float(self.gap[g][f][np.ix_(rows, np.nonzero(missed)[0])].min()))
        return reached, margin

    def steps(self, g: int, occupied: frozenset[int]) -> list[tuple[frozenset[int], float] | None]:
        """:meth:`step` to every candidate f at once (the same sets and margins: the same
        minima of the same numbers), from row g's relations packed side by side."""
        pk = self.packed
        rows = np.array(sorted(occupied), dtype=np.intp)
        refused = np.asarray(pk.bad[g][rows].any(axis=0))
        hit = np.asarray(pk.meets[g][rows].any(axis=0))
        if rows.size:
            stop_margin = pk.bad_gap[g][rows].min(axis=0)
            missed_gap = np.where(hit, math.inf, pk.gap[g][rows].min(axis=0))
        else:
            stop_margin = np.full(len(self.maps), math.inf)
            missed_gap = np.full(hit.shape, math.inf)
        out: list[tuple[frozenset[int], float] | None] = []
        hits = np.flatnonzero(hit)
        cuts = np.searchsorted(hits, pk.offsets).tolist()  # candidate f's hits: hits[cuts[f]:cuts[f + 1]]
        offsets = pk.offsets.tolist()
        missed_min = np.minimum.reduceat(missed_gap, pk.offsets[:-1]).tolist()  # every candidate has a band
        stops = stop_margin.tolist()
        for f, no in enumerate(refused.tolist()):
            if no:
                out.append(None)
                continue
            lo = offsets[f]
            reached = frozenset((hits[cuts[f]:cuts[f + 1]] - lo).tolist())
            margin = stops[f]
            if len(reached) < offsets[f + 1] - lo:
                margin = min(margin, missed_min[f])
            out.append((reached, margin))
        return out

    def is_goal(self, f: int, occupied: frozenset[int]) -> bool:
        return len({self.orbit[f][j] for j in occupied}) == 1

    def occupied_set(self, f: int, occupied: frozenset[int]) -> Arcs:
        return Arcs.union_of(self.maps[f].map.bands[j] for j in occupied)


@dataclass(frozen=True)
class Design:
    """A sequence of candidate fences (indices), the bands it leaves the part in, and its
    margin (radians, module docstring)."""

    fences: tuple[int, ...]
    final_bands: frozenset[int]
    margin: float


@dataclass(frozen=True)
class SearchResult:
    """``design``: the shortest design with the largest margin (None: none found);
    ``depth_proven``: no design has fewer fences than this + 1 (every depth up to it was
    searched completely; with no design, none exists up to that depth); ``exhausted``: no
    design exists at any depth (every node reached was pruned: its set contains one
    already searched); ``designs_at_depth`` how many shortest designs were kept and
    compared; node counts per depth."""

    design: Design | None
    depth_proven: int
    exhausted: bool
    designs_at_depth: int
    nodes: int
    pruned: int
    solve_time_s: float = 0.0
    per_depth_nodes: tuple[int, ...] = field(default=())


@dataclass
class Progress:
    """What a search has established so far, kept up to date while it runs, so that a
    caller whose ``checkpoint`` stopped it can still report it: every depth up to
    ``depth_proven`` searched without a design, the nodes made and pruned."""

    depth_proven: int = 0
    nodes: int = 0
    pruned: int = 0
    per_depth: list[int] = field(default_factory=list)


@dataclass
class _Node:
    fence: int
    occupied: frozenset[int]
    arcs: Arcs
    margin: float
    path: tuple[int, ...]
    mask: int
    goal: bool


def cell_mask(arcs: Arcs, cells: int) -> int:
    """The cells the set touches, as the bits of an integer."""
    bits = np.packbits(arcs.cells(cells).astype(np.uint8), bitorder="little")
    return int.from_bytes(bits.tobytes(), "little")


def cell_words(mask: int, cells: int) -> np.ndarray:
    """A cell mask (:func:`cell_mask`) as 64-bit words, least significant first."""
    n = -(-cells // 64)
    return np.frombuffer(mask.to_bytes(8 * n, "little"), dtype="<u8").astype(np.uint64)


Scan = Callable[[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, int, np.ndarray, np.ndarray, float,
                 float], bool]
"""The dominance scan over every node reached (:func:`scan_reached`'s signature): the solver
passes its compiled twin (solver/kernels/search.py, from solver/feeder/design.py), the same
answer."""


def scan_reached(starts: np.ndarray, widths: np.ndarray, counts: np.ndarray, margins: np.ndarray, words: np.ndarray,
                 n: int, arcs: np.ndarray, inverse: np.ndarray, margin: float, slack: float) -> bool:
    """Whether one of the first ``n`` nodes reached (node i: its arcs ``starts[i, :counts[i]]``,
    ``widths[i, :counts[i]]``, margin, cell-mask words) has a margin >= ``margin``, no cell
    outside the new set's mask (``inverse``: its complement's words) and its arcs within the
    new set's ``arcs`` ((k, 2): start, width) widened by ``slack`` (:meth:`Arcs.issubset`).
    The quick conditions are tested on chunks of nodes at once, in the order reached, the
    arc test only where they hold; an answer found early stops the scan."""
    other = Arcs(tuple((float(s), float(w)) for s, w in arcs))
    lo, size = 0, ReachedSets.CHUNK
    while lo < n:  # in growing chunks: most answers come early
        hi = min(lo + size, n)
        ok = margins[lo:hi] >= margin
        ok &= ~(words[lo:hi] & inverse).any(axis=1)
        for i in np.flatnonzero(ok):
            k = lo + int(i)
            mine = Arcs(tuple(zip(starts[k, :counts[k]].tolist(), widths[k, :counts[k]].tolist())))
            if mine.issubset(other, slack):
                return True
        lo, size = hi, 2 * size
    return False


class ReachedSets:
    """The nodes reached on one side, for the dominance test: their margins, cell masks and
    arcs as arrays, so that the whole scan is one call of ``scan`` (:data:`Scan`)."""

    CHUNK = 256  # nodes tested at once by scan_reached: an answer found early stops the test

    def __init__(self, cells: int, scan: Scan = scan_reached) -> None:
        self.cells = cells
        self.scan = scan
        self.lookup_first = scan is scan_reached
        self.arcs: list[Arcs] = []
        self.masks: list[int] = []
        self.by_state: dict[tuple[int, frozenset[int]], int] = {}  # the state's node of largest margin
        self.margins = np.empty(64)
        self.words = np.empty((64, -(-cells // 64)), dtype=np.uint64)
        self.starts = np.empty((64, 4))
        self.widths = np.empty((64, 4))
        self.counts = np.zeros(64, dtype=np.int64)

    def add(self, fence: int, occupied: frozenset[int], arcs: Arcs, mask: int, margin: float) -> None:
        """A node reached: its last fence, code set, set of orientations, cell mask, margin."""
        n = len(self.arcs)
        if n == self.margins.size:
            self.margins = np.concatenate([self.margins, np.empty(n)])
            self.words = np.concatenate([self.words, np.empty_like(self.words)])
            self.starts = np.concatenate([self.starts, np.empty_like(self.starts)])
            self.widths = np.concatenate([self.widths, np.empty_like(self.widths)])
            self.counts = np.concatenate([self.counts, np.zeros_like(self.counts)])
        k = len(arcs.arcs)
        if k > self.starts.shape[1]:
            grow = np.empty((self.starts.shape[0], max(k, 2 * self.starts.shape[1]) - self.starts.shape[1]))
            self.starts = np.hstack([self.starts, grow])
            self.widths = np.hstack([self.widths, grow])
        self.margins[n] = margin
        self.words[n] = cell_words(mask, self.cells)
        self.starts[n, :k] = [s for s, _ in arcs.arcs]
        self.widths[n, :k] = [w for _, w in arcs.arcs]
        self.counts[n] = k
        self.arcs.append(arcs)
        self.masks.append(mask)
        state = (fence, occupied)
        if state not in self.by_state or self.margins[self.by_state[state]] < margin:
            self.by_state[state] = n

    def dominated(self, arcs: Arcs, mask: int, margin: float, slack: float, fence: int = -1,
                  occupied: frozenset[int] = frozenset()) -> bool:
        """A node already reached whose set lies within ``arcs`` at no smaller margin.

        With the reference scan, the nodes of the same fence whose code set is within
        ``occupied`` are tried first (their sets are unions of fewer of the same bands: the
        usual answer, found by looking up each subset); every node is tried, by the same
        test, before False. A compiled scan tries every node sooner than those look-ups."""
        for size in range(1, len(occupied) + 1 if self.lookup_first else 1):
            for sub in itertools.combinations(sorted(occupied), size):
                i = self.by_state.get((fence, frozenset(sub)))
                if (i is not None and self.margins[i] >= margin and self.masks[i] & ~mask == 0
                        and self.arcs[i].issubset(arcs, slack)):
                    return True
        query = np.array(arcs.arcs, dtype=float).reshape(-1, 2)
        return bool(self.scan(self.starts, self.widths, self.counts, self.margins, self.words, len(self.arcs), query,
                              ~cell_words(mask, self.cells), margin, slack))


def search_design(graph: DesignGraph, max_depth: int, alternate: bool = True,
                  tol: DesignTolerances = DESIGN_DEFAULT, checkpoint: Callable[[str], None] | None = None,
                  progress: Progress | None = None, scan: Scan = scan_reached) -> SearchResult:
    """Breadth-first search for the shortest design (module docstring) up to ``max_depth``
    fences; consecutive fences on opposite sides of the belt when ``alternate``.
    ``checkpoint`` (a deadline: it raises to stop) is called before each depth and each
    node's children; ``progress`` then holds what was established. ``scan`` runs the
    pruning's dominance scan (:data:`Scan`)."""
    if max_depth < 1:
        raise InvalidInput("max_depth", "must be at least 1")
    t0 = time.perf_counter()
    progress = Progress() if progress is None else progress
    n = len(graph.maps)
    frontier: list[_Node] = []
    for f in range(n):
        if graph.first_ok[f]:
            occ = graph.start[f]
            arcs = graph.occupied_set(f, occ)
            frontier.append(_Node(f, occ, arcs, math.inf, (f,), cell_mask(arcs, tol.mask_cells), graph.is_goal(f, occ)))
    nodes = len(frontier)
    pruned = 0
    per_depth = [len(frontier)]
    seen: dict[float, ReachedSets] = {}
    sets: dict[tuple[int, frozenset[int]], tuple[Arcs, int]] = {}  # (fence, code set) -> its set and mask
    best_margin: dict[tuple[int, frozenset[int]], float] = {}  # the same state reached before
    for node in frontier:
        seen.setdefault(graph.side(node.fence) if alternate else 0.0, ReachedSets(tol.mask_cells, scan)).add(
            node.fence, node.occupied, node.arcs, node.mask, node.margin)
    depth = 1
    while True:
        progress.nodes, progress.pruned, progress.per_depth = nodes, pruned, list(per_depth)
        goals = [nd for nd in frontier if nd.goal]
        if goals:
            best = max(goals, key=lambda nd: nd.margin)
            return SearchResult(Design(best.path, best.occupied, best.margin), depth - 1, False,
                                len(goals), nodes, pruned, time.perf_counter() - t0, tuple(per_depth))
        progress.depth_proven = depth
        if depth >= max_depth or not frontier:
            return SearchResult(None, depth, not frontier, 0, nodes, pruned, time.perf_counter() - t0, tuple(per_depth))
        nxt: list[_Node] = []
        for node in frontier:
            if checkpoint is not None:
                progress.nodes, progress.pruned = nodes, pruned
                checkpoint(f"depth {depth + 1} of the design search ({nodes} nodes so far)")
            for f, got in enumerate(graph.steps(node.fence, node.occupied)):
                if alternate and graph.side(f) == graph.side(node.fence):
                    continue
                if got is None:
                    continue
                occ, m = got
                margin = min(node.margin, m)
                key = graph.side(f) if alternate else 0.0
                # a goal is never pruned: a set within it need not be a goal by its own
                # fence's bands (two bands of one fence inside one band of another)
                goal = graph.is_goal(f, occ)
                if not goal and best_margin.get((f, occ), -math.inf) >= margin:  # the very state, no worse
                    pruned += 1
                    continue
                if (f, occ) not in sets:
                    arcs = graph.occupied_set(f, occ)
                    sets[(f, occ)] = (arcs, cell_mask(arcs, tol.mask_cells))
                arcs, mask = sets[(f, occ)]
                side = seen.setdefault(key, ReachedSets(tol.mask_cells, scan))
                if not goal and side.dominated(arcs, mask, margin, tol.subset_slack, f, occ):
                    pruned += 1
                    continue
                best_margin[(f, occ)] = margin
                child = _Node(f, occ, arcs, margin, node.path + (f,), mask, goal)
                side.add(f, occ, arcs, mask, margin)
                nxt.append(child)
                nodes += 1
        frontier = nxt
        per_depth.append(len(frontier))
        depth += 1
