"""The part's own bound on leaving a fence's end (solver/feeder/part_bound.py; book 5.1
phase 5 on the part's own loci, 3.3.5, 7.5): it holds every COR that sampled pressure
distributions give (an independent forward solve), it narrows the disk's bands and never
widens them, simulated parts end inside its maps, and it keeps the map's symmetries."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.footprint import Footprint
from models.core.mpp import perp
from models.core.scene import PushScene
from models.core.support import random_balanced_tripods
from models.feeder.fence import (
    PUSH_ANGLE,
    Fence,
    canonical_edge,
    canonical_outline,
    feeder_part,
    fence_map,
    max_slip_rate,
    rotation,
    slip_normal,
)
from models.sketch.disk_sketch import force_scene
from solver.feeder.part_bound import PartBoundSettings, PartLoci, outline_dipods
from solver.feeder.simulate import simulate_fence_batch
from solver.motion.forward import solve_forward_batch
from tests.feeder_cases import PARTS, part, random_encounter

SEED = 20261126
CHEAP = PartBoundSettings(contacts=5, turns=1, refine_levels=0, max_rays_per_aim=2)
DIPODS_ONLY = PartBoundSettings(contacts=9, max_rays_per_aim=0)


@pytest.mark.parametrize("name", ["pentagon", "L-shape", "right triangle"])
def test_dipods_on_the_outline_balance_on_the_cm_3_3_5(name):
    """Each dipod's feet lie on the outline, on a line through the CM, weighted so that
    their centroid is the CM (3.1.5); the L-shape's CM lies outside its outline."""
    p = part(name)
    pts, wts = outline_dipods(p.vertices, 180)
    assert 0 < len(pts) <= 180 and np.all(wts > 0.0)
    assert np.allclose(np.sum(pts * wts[:, :, None], axis=1), 0.0, atol=1e-12 * p.circumradius)
    assert np.allclose(wts.sum(axis=1), 1.0)
    assert np.allclose(pts[:, 0, 0] * pts[:, 1, 1] - pts[:, 0, 1] * pts[:, 1, 0], 0.0, atol=1e-12 * p.circumradius ** 2)
    a, b = p.vertices, np.roll(p.vertices, -1, axis=0)
    for foot in pts.reshape(-1, 2):  # distance to the nearest outline segment
        t = np.clip(np.einsum("ij,ij->i", foot - a, b - a) / np.einsum("ij,ij->i", b - a, b - a), 0.0, 1.0)
        assert np.min(np.hypot(*(a + t[:, None] * (b - a) - foot).T)) < 1e-12 * p.circumradius


def test_the_slip_bound_holds_every_sampled_cor_and_is_tighter_than_the_disk_5_1_7_5():
    """At contacts inside a cell and several turns, the part's slip bound is at least the
    largest slip of 3000 random balanced tripods on the part (their CORs by the forward
    minimum-power solve, an independent method), and well below the disk's bound (7.5)."""
    p, fence, mu = part("pentagon"), Fence.create(math.radians(40.0), 0.25), 0.25
    rng = np.random.default_rng(SEED)
    ratios = []
    for j in (0, 3):
        u_c, h_c, length, ell0 = canonical_edge(p, j, fence, mu)
        loci = PartLoci(p, fence, PartBoundSettings(contacts=3, turns=1))
        rate = loci.rate_for(j, mu)
        assert loci.cost.rays == loci.cost.rays_bracketed > 0
        outline = canonical_outline(p, j, fence)
        pts, wts = random_balanced_tripods(rng, 3000, p.circumradius, footprint=Footprint.create(outline, (0.0, 0.0)))
        g = abs(fence.angle)
        t0 = np.array([math.cos(g), math.sin(g)])
        for ell in ell0 + (length - ell0) * np.array([0.3, 0.6, 0.95]):
            contact = (ell - u_c) * t0 - h_c * perp(t0)
            turned, _ = force_scene(PushScene.create(p.circumradius, contact, g, PUSH_ANGLE), -math.atan(mu))
            cors = np.asarray(solve_forward_batch(turned, pts, wts).cor)
            cors = cors[np.all(np.isfinite(cors), axis=1)]
            assert len(cors) > 2900
            for delta in (0.0, 0.4, 0.8):
                w = rotation(-delta) @ slip_normal(np.array([math.cos(g + delta), math.sin(g + delta)]))
                sampled = float(np.max((cors - contact) @ w))
                disk, _ = max_slip_rate(p.circumradius, rotation(delta) @ contact, g + delta, mu, 400)
                assert sampled <= rate(ell, delta) and sampled <= disk
                ratios.append(rate(ell, delta) / disk)
    assert np.median(ratios) < 0.8


@pytest.mark.slow  # 9 s: the heaviest of the everyday tier
def test_the_part_bound_narrows_the_disk_map_and_holds_simulated_parts_6_5():
    """The map with the part's own bound has the disk map's kernels and extremes A, and
    each band inside the disk's (B later, 7.5); 60 seeded simulated parts (random tripods
    in the part, random initial orientations) end inside it (6.5)."""
    name, fence, mu = "pentagon", Fence.create(math.radians(40.0), 0.25), 0.25
    p = part(name)
    disk = fence_map(p, fence)
    loci = PartLoci(p, fence, CHEAP)
    own = fence_map(p, fence, own_rate=loci.rate_for)
    assert own.bound == "part" and disk.bound == "disk" and own.final_edges == disk.final_edges
    narrower = 0.0
    for a, b, ka, kb in zip(disk.turns, own.turns, disk.map.kernels, own.map.kernels):
        assert ka.arcs == kb.arcs and a.most == b.most
        assert a.least <= b.least <= b.most
        narrower = max(narrower, b.least - a.least)
    assert narrower > math.radians(2.0)
    for band_d, band_o in zip(disk.map.bands, own.map.bands):
        assert band_o.issubset(band_d, 1e-12) and band_o.measure < band_d.measure
    rng = np.random.default_rng(SEED)
    encounters = [random_encounter(rng, name) for _ in range(60)]
    runs = simulate_fence_batch(p, fence, mu, [(e.body, e.weights) for e in encounters], [e.theta for e in encounters])
    left = [(e, r) for e, r in zip(encounters, runs) if r.status == "left"]
    assert len(left) >= 55
    assert all(own.map.allows(e.theta, r.theta_final, 1e-6) for e, r in left)


def mirrored(name):
    verts, cm = PARTS[name]
    return feeder_part([[-x, y] for x, y in verts], [-cm[0], cm[1]])


@pytest.mark.parametrize("deg", [35.0, -50.0])
def test_the_part_bound_keeps_mirror_symmetry_and_scale(deg):
    """The mirror image (x -> -x) of part and fence (gamma -> -gamma) has the same turns
    off the end; so has the part a million times smaller or larger (dipods only: the
    symmetry is the bound's own, whatever is traced)."""
    fence, twin = Fence.create(math.radians(deg), 0.2), Fence.create(math.radians(-deg), 0.2)
    p = part("pentagon")
    ref = fence_map(p, fence, own_rate=PartLoci(p, fence, DIPODS_ONLY).rate_for)
    assert any(t.least > d.least + 1e-3 for t, d in zip(ref.turns, fence_map(p, fence).turns))
    m = mirrored("pentagon")
    got = fence_map(m, twin, own_rate=PartLoci(m, twin, DIPODS_ONLY).rate_for)
    # the mirror reverses the hull's order: compare the turns as sets
    assert sorted(t.least for t in got.turns) == pytest.approx(sorted(t.least for t in ref.turns), abs=1e-6)
    verts, cm = PARTS["pentagon"]
    for scale in (1e-6, 1e6):
        s = feeder_part(np.array(verts) * scale, np.array(cm) * scale)
        scaled = fence_map(s, fence, own_rate=PartLoci(s, fence, DIPODS_ONLY).rate_for)
        assert [t.least for t in scaled.turns] == pytest.approx([t.least for t in ref.turns], abs=1e-6)


def test_a_failed_conic_solve_hands_its_contact_to_the_disk(monkeypatch):
    """A trace whose conic solve fails (Clarabel once did, on a restricted master) certifies
    nothing: that contact is bounded by the disk, the failure is counted, and the map is
    still made (never wider than the disk's, never narrower than its dipods allow)."""
    import solver.feeder.part_bound as pb
    from solver.core.errors import NotConverged

    def failing(*args, **kwargs):
        raise NotConverged("Clarabel failed on the restricted master")

    monkeypatch.setattr(pb, "trace_ray", failing)
    p, fence = part("right triangle"), Fence.create(math.radians(40.0), 0.25)
    loci = PartLoci(p, fence, CHEAP)
    got = fence_map(p, fence, own_rate=loci.rate_for)
    disk = fence_map(p, fence)
    assert [t.least for t in got.turns] == [t.least for t in disk.turns]
    assert loci.cost.solver_failures == loci.cost.rays > 0 and loci.cost.rays_bracketed == 0
