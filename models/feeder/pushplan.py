"""The baseline a user would otherwise pick: sensorless orienting by frictionless pushing with
a single straight pusher (Goldberg, "Orienting polygonal parts without sensors",
Algorithmica 10, 1993): the radius function, the push function and the shortest push plan.

Frames. The part's hull about its CM. A push comes from the direction omega (in the part's
frame: the unit vector u(omega) from the CM toward the pusher); the pusher's face is normal
to u and touches the hull at its support vertex. The radius function is the distance from
the CM to the face, r(omega) = max_k v_k . u(omega). A frictionless push turns the part so
that r decreases (the CM approaches the face: the contact force is along -u, its moment
about the CM turns the part toward the nearer minimum), until an edge lies on the face with
the CM's foot inside it: the minima of r are those edges' outward normals, its maxima the
directions of the vertices that are support vertices in their own direction. Between two
consecutive maxima lies one minimum; the push function p maps every omega of that interval
to it.

Plans. After a push the part's frame sees the pusher at a stable direction s. A next push
from the world direction turned by alpha sees it at s + alpha, and leaves it at p(s + alpha).
So the set S of possible stable directions becomes {p(s + alpha) : s in S}; a plan is a
sequence of alphas that leaves one direction (or, for a part with rotational symmetry of
order k, directions a turn of 2 pi / k apart). The image of S changes only where some
s + alpha crosses a maximum, so the alphas between consecutive crossings form classes; the
plan is found breadth first over the sets S, trying each class at its middle (the alpha
whose error tolerance, the half width of its class, is largest). Goldberg's algorithm finds
plans of the same least length in O(n^2 log n); the search here is exact and small for the
parts of a feeder.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.feeder.arcs import TWO_PI, wrap
from models.feeder.design_graph import DESIGN_DEFAULT, DesignTolerances, rotational_symmetry


@dataclass(frozen=True)
class PushFunction:
    """The stable directions (minima of the radius function, the outward normals of the
    stable edges, sorted) and the maxima between them: stable[i] is reached from every
    omega in (maxima[i], maxima[i + 1]) (cyclically)."""

    stable: np.ndarray
    maxima: np.ndarray
    edges: tuple[int, ...]

    @classmethod
    def of(cls, part: Footprint) -> PushFunction:
        hull = part.hull
        m = part.hull_size
        normals, stable, edges = [], [], []
        for j in range(m):
            _, length, e = part.hull_edge(j)
            normals.append(math.atan2(-float(e[0]), float(e[1])))  # outward normal: e turned by -90 degrees
            u_c, _ = part.cm_over_hull_edge(j)
            if 0.0 < u_c < length:  # the CM's foot strictly inside the edge: a minimum
                stable.append(wrap(normals[j]))
                edges.append(j)
        maxima = []
        for k in range(m):
            v = hull[k]
            ang = math.atan2(float(v[1]), float(v[0]))
            lo, hi = normals[(k - 1) % m], normals[k]  # vertex k supports directions from n_{k-1} to n_k
            width = wrap(hi - lo)
            if 0.0 < wrap(ang - lo) < width:
                maxima.append(wrap(ang))
        if not stable or len(maxima) != len(stable):
            raise InvalidInput("vertices", "the part's radius function has no stable edge (degenerate outline)")
        order = np.argsort(stable)
        stable_sorted = np.array(stable)[order]
        edges_sorted = tuple(int(edges[i]) for i in order)
        # maxima[i] is the maximum just before stable[i] (counter-clockwise)
        maxima_arr = np.array(sorted(maxima))
        before = np.array([maxima_arr[np.argmax([-wrap(s - mx) for mx in maxima_arr])] for s in stable_sorted])
        return cls(stable_sorted, before, edges_sorted)

    def index_of(self, omega: float) -> int:
        """The stable direction a push from ``omega`` (part frame) ends in."""
        d = np.array([wrap(omega - mx) for mx in self.maxima])
        return int(np.argmin(d))


@dataclass(frozen=True)
class PushPlan:
    """``alphas``: the turns of the push direction between pushes (the first push from any
    direction); ``final``: the stable directions left; ``tolerance``: the smallest half
    width of an alpha's class (how far each turn may err); ``depth_proven``: no plan with
    fewer pushes; None alphas when no plan was found up to ``max_pushes``, or (``complete``
    False) when the search was stopped first."""

    alphas: tuple[float, ...] | None
    final: frozenset[int]
    tolerance: float
    depth_proven: int
    states: int
    solve_time_s: float
    complete: bool = True


def _classes(pf: PushFunction, state: frozenset[int]) -> list[tuple[float, float]]:
    """(alpha at the middle, half width) of every class of turns for the set ``state``."""
    cuts = sorted({wrap(float(mx) - float(pf.stable[s])) for s in state for mx in pf.maxima})
    out = []
    for a, b in zip(cuts, cuts[1:] + [cuts[0] + TWO_PI]):
        if b - a > 0.0:
            out.append((wrap(0.5 * (a + b)), 0.5 * (b - a)))
    return out


def plan_pushes(part: Footprint, max_pushes: int = 20, tol: DesignTolerances = DESIGN_DEFAULT,
                expired: Callable[[], bool] | None = None) -> PushPlan:
    """The shortest push plan (module docstring), breadth first; among the shortest the one
    whose least tolerance is largest. ``expired`` is asked before every class of turns of
    every state expanded: once it answers True the search stops with what it proved
    (``complete`` False)."""
    t0 = time.perf_counter()
    pf = PushFunction.of(part)
    k = rotational_symmetry(part, tol)

    def goal(state: frozenset[int]) -> bool:  # one class of edges under the hull's symmetry (as the design's orbits)
        return len({pf.edges[s] % (part.hull_size // k) for s in state}) == 1

    start = frozenset(range(len(pf.stable)))
    if goal(start):
        return PushPlan((), start, math.inf, 0, 1, time.perf_counter() - t0)
    frontier: dict[frozenset[int], tuple[tuple[float, ...], float]] = {start: ((), math.inf)}
    seen = {start}
    for depth in range(1, max_pushes):
        nxt: dict[frozenset[int], tuple[tuple[float, ...], float]] = {}
        for state, (alphas, tolerance) in frontier.items():
            for alpha, half in _classes(pf, state):
                if expired is not None and expired():  # a state of a many-sided part has thousands of classes
                    return PushPlan(None, frozenset(), 0.0, depth - 1, len(seen), time.perf_counter() - t0, False)
                image = frozenset(pf.index_of(float(pf.stable[s]) + alpha) for s in state)
                t = min(tolerance, half)
                if image in seen and image not in nxt:
                    continue
                if image not in nxt or nxt[image][1] < t:
                    nxt[image] = (alphas + (alpha,), t)
        seen |= set(nxt)
        goals = [(s, v) for s, v in nxt.items() if goal(s)]
        if goals:
            state, (alphas, tolerance) = max(goals, key=lambda sv: sv[1][1])
            return PushPlan(alphas, state, tolerance, depth, len(seen), time.perf_counter() - t0)
        if not nxt:
            break
        frontier = nxt
    return PushPlan(None, frozenset(), 0.0, max_pushes, len(seen), time.perf_counter() - t0)
