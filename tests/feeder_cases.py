"""Parts and seeded random encounters for the feeder tests and benchmarks (book ch. 5)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from models.core.footprint import Footprint
from models.core.support import random_balanced_tripods
from models.feeder.fence import Fence, feeder_part

# (vertices, centre of mass); the CM of a uniform plate unless said otherwise
PARTS = {
    "square": ([[0, 0], [1, 0], [1, 1], [0, 1]], [0.5, 0.5]),
    "rectangle": ([[0, 0], [4, 0], [4, 1], [0, 1]], [2, 0.5]),
    "right triangle": ([[0, 0], [2, 0], [0, 3]], [2 / 3, 1]),
    # the five-sided part of figure 1-9 cannot be read from the OCR text: an irregular
    # pentagon without symmetry stands in for it (CM inside, not the plate's)
    "pentagon": ([[0, 0], [3, 0], [3.5, 1.5], [1.5, 2.5], [-0.5, 1.2]], [1.4, 1.0]),
    # an L of a 3 x 1 bar and a 1 x 2 bar: the fence touches its hull only
    "L-shape": ([[0, 0], [3, 0], [3, 1], [1, 1], [1, 3], [0, 3]], [1.1, 1.1]),
    # a 2 x 1 rectangle with one corner moved by 1 % of its width
    "near-symmetric": ([[0, 0], [2, 0], [2, 1], [0.02, 1.0]], [1.0, 0.5]),
}


def part(name: str) -> Footprint:
    return feeder_part(*PARTS[name])


@dataclass(frozen=True)
class Encounter:
    """One part with one support, its body points relative to the CM."""

    name: str
    part: Footprint
    body: np.ndarray
    weights: np.ndarray
    theta: float


def random_support(rng: np.random.Generator, name: str) -> tuple[np.ndarray, np.ndarray]:
    """A balanced tripod inside the part's outline (body frame, relative to the CM)."""
    verts, cm = PARTS[name]
    footprint = Footprint.create(verts, cm)
    pts, wts = random_balanced_tripods(rng, 1, footprint.circumradius, footprint=footprint)
    return pts[0] - np.asarray(cm, dtype=float), wts[0]


def random_encounter(rng: np.random.Generator, name: str) -> Encounter:
    body, wts = random_support(rng, name)
    return Encounter(name, part(name), body, wts, float(rng.uniform(-math.pi, math.pi)))


def random_fence(rng: np.random.Generator, degrees=(20.0, 65.0), mu=(0.0, 0.6)) -> tuple[Fence, float]:
    """A fence on a random side at a random angle, with a point mu_c interval."""
    gamma = float(rng.choice([-1.0, 1.0]) * math.radians(rng.uniform(*degrees)))
    mu_c = float(rng.uniform(*mu))
    return Fence.create(gamma, (mu_c, mu_c)), mu_c


class Clock:
    """A budget's clock for tests independent of the machine's speed: time stands still
    until ``run_out`` is set; then it is far past any deadline."""

    def __init__(self) -> None:
        self.run_out = False

    def __call__(self) -> float:
        return 1e9 if self.run_out else 0.0


class CountingClock:
    """Time stands still for ``calls`` readings, then is far past any deadline."""

    def __init__(self, calls: int) -> None:
        self.calls = calls

    def __call__(self) -> float:
        self.calls -= 1
        return 0.0 if self.calls >= 0 else 1e9


def first_contact_reach(the_part, fence, run):
    """How far the fence reaches beyond the run's first contact toward its end (None when the
    first contact is not a vertex on the face)."""
    cm, theta = run.cms[1], run.thetas[1]
    hull = cm + the_part.hull @ np.array([[math.cos(theta), math.sin(theta)], [-math.sin(theta), math.cos(theta)]])
    z = hull @ fence.normal
    along = float(hull[int(np.argmin(z))] @ (fence.sign * np.array([math.cos(fence.angle), math.sin(fence.angle)])))
    return along if z.min() <= 1e-9 * the_part.circumradius and along > 0.0 else None
