"""Closed arcs of orientations on the circle [0, 2 pi): the sets a configuration map is made
of (book 5.2.1: bands B_j of final orientations, kernels K_j of initial ones).

An arc is (start, width) with start in [0, 2 pi) and width in [0, 2 pi]; width 2 pi is the
whole circle. :class:`Arcs` is a finite union of closed arcs, kept merged and sorted.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

TWO_PI = 2.0 * math.pi


def wrap(angle: float) -> float:
    """``angle`` in [0, 2 pi)."""
    x = math.fmod(float(angle), TWO_PI)
    if x < 0.0:
        x += TWO_PI
    return 0.0 if x >= TWO_PI else x


def ccw_distance(start: float, angle: float) -> float:
    """How far ``angle`` lies counter-clockwise from ``start``, in [0, 2 pi)."""
    return wrap(angle - start)


@dataclass(frozen=True)
class Arcs:
    """A union of closed arcs ``(start, width)``, merged (no two overlap or touch) and sorted
    by start. Build with :meth:`of`; :meth:`empty` and :meth:`circle` are the extremes."""

    arcs: tuple[tuple[float, float], ...]

    @classmethod
    def empty(cls) -> Arcs:
        return cls(())

    @classmethod
    def circle(cls) -> Arcs:
        return cls(((0.0, TWO_PI),))

    @classmethod
    def of(cls, arcs: Iterable[tuple[float, float]]) -> Arcs:
        """The union of arcs given as (start, width), any start, width >= 0 (>= 2 pi: the
        circle)."""
        items = []
        for start, width in arcs:
            w = float(width)
            if not (math.isfinite(w) and w >= 0.0):
                raise ValueError(f"an arc's width must be finite and >= 0, got {width!r}")
            if w >= TWO_PI:
                return cls.circle()
            items.append((wrap(start), w))
        if not items:
            return cls.empty()
        items.sort()
        # Merge on the line, then join the last arc with the first across 2 pi.
        merged: list[list[float]] = []
        for s, w in items:
            if merged and s <= merged[-1][0] + merged[-1][1]:
                end = max(merged[-1][0] + merged[-1][1], s + w)
                merged[-1][1] = end - merged[-1][0]
            else:
                merged.append([s, w])
        # the last arc may run past 2 pi over the first ones: absorb them
        while len(merged) > 1 and merged[-1][0] + merged[-1][1] >= merged[0][0] + TWO_PI:
            first = merged.pop(0)
            end = max(merged[-1][0] + merged[-1][1], first[0] + TWO_PI + first[1])
            merged[-1][1] = end - merged[-1][0]
        if any(w >= TWO_PI for _, w in merged):
            return cls.circle()
        return cls(tuple(sorted((wrap(s), w) for s, w in merged)))

    @property
    def is_empty(self) -> bool:
        return not self.arcs

    @property
    def measure(self) -> float:
        """Total angle covered (radians)."""
        return float(sum(w for _, w in self.arcs))

    def union(self, other: Arcs) -> Arcs:
        return Arcs.of(self.arcs + other.arcs)

    @classmethod
    def union_of(cls, sets: Iterable[Arcs]) -> Arcs:
        """The union of any number of sets (empty for none)."""
        return cls.of([arc for s in sets for arc in s.arcs])

    def contains(self, angle: float, slack: float = 0.0) -> bool:
        """True when ``angle`` lies in an arc widened by ``slack`` at both ends."""
        return any(ccw_distance(s - slack, angle) <= w + 2.0 * slack for s, w in self.arcs)

    def intersects(self, other: Arcs) -> bool:
        """True when a closed arc of one meets a closed arc of the other."""
        return self.distance(other) == 0.0

    def issubset(self, other: Arcs, slack: float = 0.0) -> bool:
        """True when every arc lies within an arc of ``other`` widened by ``slack`` at both
        ends (``other`` is merged, so a contiguous arc lies within one of its arcs)."""
        return all(any(ccw_distance(s2 - slack, s) + w <= w2 + 2.0 * slack for s2, w2 in other.arcs)
                   for s, w in self.arcs)

    def distance(self, other: Arcs) -> float:
        """The smallest angle between a point of one and a point of the other (0 when they
        meet; inf when either is empty)."""
        best = math.inf
        for s1, w1 in self.arcs:
            for s2, w2 in other.arcs:
                if ccw_distance(s1, s2) <= w1 or ccw_distance(s2, s1) <= w2:
                    return 0.0
                best = min(best, ccw_distance(s1 + w1, s2), ccw_distance(s2 + w2, s1))
        return best

    def shifted(self, angle: float) -> Arcs:
        """Every arc turned by ``angle``."""
        return Arcs.of((s + angle, w) for s, w in self.arcs)

    def cells(self, n: int) -> np.ndarray:
        """Which of ``n`` equal cells [2 pi i/n, 2 pi (i+1)/n] of the circle meet the set
        (boolean (n,)): a cell that touches a closed arc counts (the grid never loses a
        possible orientation)."""
        out = np.zeros(n, dtype=bool)
        h = TWO_PI / n
        for s, w in self.arcs:
            if w >= TWO_PI:
                out[:] = True
                return out
            lo = math.floor(s / h)
            hi = math.floor((s + w) / h)
            # a cell whose upper edge is exactly the arc's start touches it too
            if lo * h == s:
                lo -= 1
            idx = np.arange(lo, hi + 1) % n
            out[idx] = True
        return out
