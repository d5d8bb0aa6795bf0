"""A reject gate after the fences (issue 24; book 7.1: "a sensor with a simple yes/no output
might detect a feature of the workpieces ... the presence of the sensor effectively removes
some possible initial orientations"): it measures one feature of the part's silhouette and
returns the parts it rejects to the start of the belt.

Features. The extent of the silhouette across the belt (world x) or along it (world y) at
orientation theta: with the hull's body points h_i and the world axis at angle alpha,

    extent(theta) = max_i h_i . u - min_i h_i . u,   u = (cos(alpha - theta), sin(alpha - theta)),

the width of the hull in the body direction psi = alpha - theta (R(theta)^T turns the world
axis into the body frame). Between the directions where u is normal to a hull edge the
extremes are two fixed vertices, so the width is one positive sinusoid |d| cos(psi - angle(d))
of the difference d of those vertices: on such a piece its least value is at an end of the
piece, its largest at an end or where u is along d. :func:`extent_range` evaluates the width
at the arc's ends and at every such direction inside it, so the range over an arc of
orientations is exact up to rounding.

A gate (:func:`separate`) accepts the parts whose feature is at most (or at least) a
threshold. It is valid for a set of final bands when the ranges of the accepted bands and of
the rejected ones lie on either side of the threshold, each at least ``margin`` from it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.feeder.arcs import TWO_PI, Arcs, ccw_distance

FEATURES = {"across": 0.0, "along": 0.5 * math.pi}
"""The world axis each feature measures along: across the belt (x), along it (y)."""
RULES = ("at_most", "at_least")
"""A gate accepts a feature at most, or at least, its threshold."""


def extent(part: Footprint, theta: float | np.ndarray, feature: str) -> np.ndarray:
    """The silhouette's extent along the feature's world axis at orientation(s) theta."""
    psi = FEATURES[feature] - np.atleast_1d(np.asarray(theta, dtype=float))
    proj = np.cos(psi)[:, None] * part.hull[None, :, 0] + np.sin(psi)[:, None] * part.hull[None, :, 1]
    return proj.max(axis=1) - proj.min(axis=1)


def critical_orientations(part: Footprint, feature: str) -> np.ndarray:
    """Orientations in [0, 2 pi) where the extent changes its pair of extreme vertices or is
    stationary on a pair (module docstring): u normal to an edge, or along the difference of
    two vertices."""
    h = part.hull
    d = h[:, None, :] - h[None, :, :]
    i, j = np.triu_indices(len(h), 1)
    along = np.arctan2(d[i, j, 1], d[i, j, 0])
    psi = np.concatenate([along, along + 0.5 * math.pi])
    psi = np.concatenate([psi, psi + math.pi])
    return np.mod(FEATURES[feature] - psi, TWO_PI)


def extent_range(part: Footprint, arcs: Arcs, feature: str, critical: np.ndarray | None = None) -> tuple[float, float]:
    """The least and largest extent over the orientations of ``arcs`` (exact: module
    docstring); ``critical`` caches :func:`critical_orientations`."""
    if arcs.is_empty:
        raise ValueError("the range of an empty set of orientations")
    crit = critical_orientations(part, feature) if critical is None else critical
    thetas = []
    for s, w in arcs.arcs:
        thetas.extend([s, s + w])
        thetas.extend(float(c) for c in crit if ccw_distance(s, float(c)) <= w)
    values = extent(part, np.array(thetas), feature)
    return float(values.min()), float(values.max())


MIN_YIELD = 0.25
"""The default least guaranteed yield per pass of a gate design (at most four passes a part
on average)."""
MARGIN_RADII = 0.005
"""The default margin of a gate's threshold, in part radii."""
MAX_DEPTH = 4
"""The default most fences before a gate: the gate search cannot prune as much as the
fences-only one (models/feeder/placed.py) and grows about twofold per fence."""


@dataclass(frozen=True)
class GateSpec:
    """What a design may use as a gate: the features allowed, the least margin (part units)
    between the threshold and any band's range (None: MARGIN_RADII of the part's radius), the
    least guaranteed yield per pass a gate design must reach to count, and the most fences
    before the gate."""

    features: tuple[str, ...] = tuple(FEATURES)
    margin: float | None = None
    min_yield: float = MIN_YIELD
    max_depth: int = MAX_DEPTH

    def __post_init__(self) -> None:
        if not self.features or any(f not in FEATURES for f in self.features):
            raise InvalidInput("gate.features", f"must be a non-empty list of {list(FEATURES)}")
        if self.margin is not None and not (math.isfinite(self.margin) and self.margin >= 0.0):
            raise InvalidInput("gate.margin", "must be a finite length >= 0")
        if not (0.0 < self.min_yield <= 1.0):
            raise InvalidInput("gate.min_yield", "must be in (0, 1]")
        if self.max_depth < 1:
            raise InvalidInput("gate.max_depth", "must be at least 1")


@dataclass(frozen=True)
class Gate:
    """A gate: the feature it measures, its rule, its threshold (part units), the margin from
    the threshold to the nearest band range, and the accepted bands (indices)."""

    feature: str
    rule: str
    threshold: float
    margin: float
    accepted: frozenset[int]

    def accepts(self, value: float | np.ndarray) -> np.ndarray:
        v = np.asarray(value, dtype=float)
        return v <= self.threshold if self.rule == "at_most" else v >= self.threshold


def separations(ranges: dict[int, tuple[float, float]], feature: str, margin: float) -> list[Gate]:
    """Every gate on one feature that splits the bands ``ranges`` (index -> least, largest
    extent) into a non-empty accepted set and the rest with at least ``margin`` on each side
    of the threshold (halfway between): for the rule at_most, the bands whose largest extent
    is below a gap in the sorted ranges; for at_least, those above it."""
    items = sorted(ranges.items(), key=lambda kv: kv[1][0])
    out = []
    for rule in RULES:
        seq = items if rule == "at_most" else sorted(ranges.items(), key=lambda kv: -kv[1][1])
        for cut in range(1, len(seq)):
            head, tail = seq[:cut], seq[cut:]
            if rule == "at_most":
                lo, hi = max(r[1] for _, r in head), min(r[0] for _, r in tail)
            else:
                lo, hi = max(r[1] for _, r in tail), min(r[0] for _, r in head)
            if hi - lo >= 2.0 * margin and hi > lo:
                out.append(Gate(feature, rule, 0.5 * (lo + hi), 0.5 * (hi - lo), frozenset(j for j, _ in head)))
    return out
