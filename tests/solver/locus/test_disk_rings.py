"""The compiled boundaries of many disk loci (solver/locus/disk_rings.py on
solver/kernels/disk.py) against the reference, models.locus.cor_disk.disk_boundaries
(3.30, 3.35): the same world points to rounding on seeded scenes at every scale, the same
refusals, and the same fence maps (book 5.1, phase 5: the slip paths' thousands of small
loci) whichever solves them."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.scene import PushScene
from models.feeder.fence import Fence, fence_maps
from models.locus.cor_disk import disk_boundaries as reference
from solver.locus.disk_rings import disk_boundaries
from tests.feeder_cases import part
from tests.scenes import SEED

AGREE = 1e-12
"""Largest difference of a boundary point, relative to the locus's size (its tip distance)."""


@pytest.mark.parametrize("a", [1e-6, 1.0, 1e6])
@pytest.mark.parametrize("n_points", [8, 65, 256])
def test_the_compiled_boundaries_are_the_reference(a, n_points):
    rng = np.random.default_rng(SEED)
    scenes = []
    for _ in range(60):
        edge = rng.uniform(-math.pi, math.pi)
        scenes.append(PushScene.create(a, a * rng.uniform(-1.5, 1.5, 2), edge,
                                       edge + math.pi / 2 + rng.uniform(-1.2, 1.2), a * rng.uniform(-0.5, 0.5, 2)))
    # and the hard moment arms: alpha . c -> 0 (a locus a^2/|alpha . c| long), the outer
    # dipods reaching the disk (1/sqrt 2), no outer piece (>= 1)
    for mu in (1e-9, 1e-4, 1.0 / math.sqrt(2.0), 1.0, 3.0):
        scenes.append(PushScene.create(a, [-0.5 * a, mu * a], 0.5 * math.pi, 0.0))
    got, ref = disk_boundaries(scenes, n_points), reference(scenes, n_points)
    for g, r, s in zip(got, ref, scenes):
        size = a * (1.0 / min(s.relative_moment_arm, 1.0)) + float(np.max(np.abs(s.center_of_mass)))
        assert g.shape == r.shape and np.max(np.abs(g - r)) <= AGREE * size


def test_the_compiled_boundaries_refuse_what_the_reference_refuses():
    through_cm = PushScene.create(1.0, [0.0, -1.0], 0.0, 0.5 * math.pi)
    bounded = PushScene.create(1.0, [-0.5, -0.3], 0.5 * math.pi, 0.0)
    for bad, field in (([through_cm], "scenes"), ([bounded], "n_points")):
        n = 4 if field == "n_points" else 64
        with pytest.raises(InvalidInput) as ref:
            reference(bad, n)
        with pytest.raises(InvalidInput) as got:
            disk_boundaries(bad, n)
        assert got.value.field == ref.value.field == field
    assert disk_boundaries([], 64) == []


def test_the_fence_maps_are_the_same_on_the_compiled_boundaries_5_1():
    """Phase 5 (5.1): the pentagon's maps on both sides of the belt, one mu_c and an interval:
    the same final edges, kernels and turns (B to 1e-12 rad) with either boundaries."""
    p = part("pentagon")
    fences = [Fence.create(s * math.radians(d), mu) for s in (1.0, -1.0) for d in (22.0, 63.0)
              for mu in ((0.25, 0.25), (0.1, 0.4))]
    for got, ref in zip(fence_maps(p, fences, boundaries=disk_boundaries), fence_maps(p, fences)):
        assert got.final_edges == ref.final_edges and got.map.kernels == ref.map.kernels
        for t, u in zip(got.turns, ref.turns):
            assert abs(t.least - u.least) <= 1e-12 and t.most == u.most
            assert (t.contact_lost, t.locus_evaluations, t.sense_flags) == (u.contact_lost, u.locus_evaluations,
                                                                               u.sense_flags)
