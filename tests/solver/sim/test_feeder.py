"""A part meeting one fence on a belt, simulated quasi-statically (solver/sim/feeder.py;
book 5.1, 6.4, 6.5), against the configuration map of models/feeder/fence.py.

All seeded:

* every simulated outcome (random balanced tripods in the part, random initial
  orientation, fence angle on either side of the belt, mu_c) lies in the band of a kernel
  holding its initial orientation (5.2), or jams where the map says it may (6.4);
* the runs near the friction angle (|tan gamma| slightly above mu_c), where the map's
  extreme B once missed a stall of the slip (the slip per radian falls to 0 before it
  rises again), are inside too;
* jams: a flush part with |tan gamma| <= mu_c stops (6.4);
* symmetry: the mirror image of part, support, fence and start gives the mirrored final
  orientation; scaling the part by 1e-3 and 1e3 changes nothing;
* a run cut short by its step limit says so (no final orientation, not complete).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.errors import InvalidInput
from models.feeder.fence import Fence, Part, fence_map
from models.footprint import Footprint
from models.support import random_balanced_tripods
from solver.sim.feeder import FeederSimSettings, simulate_fence

PARTS = {
    "square": ([[0, 0], [1, 0], [1, 1], [0, 1]], [0.5, 0.5]),
    "rectangle": ([[0, 0], [4, 0], [4, 1], [0, 1]], [2, 0.5]),
    "right triangle": ([[0, 0], [2, 0], [0, 3]], [2 / 3, 1]),
    "pentagon": ([[0, 0], [3, 0], [3.5, 1.5], [1.5, 2.5], [-0.5, 1.2]], [1.4, 1.0]),
}
SLACK = 1e-6  # radians: the run's final orientation against a band's edge


def random_case(rng, name, gamma_deg=(20.0, 65.0), mu=(0.0, 0.6)):
    verts, cm = PARTS[name]
    part = Part.create(verts, cm)
    gamma = float(rng.choice([-1.0, 1.0]) * math.radians(rng.uniform(*gamma_deg)))
    mu_c = float(rng.uniform(*mu))
    pts, wts = random_balanced_tripods(rng, 1, part.radius, footprint=Footprint.create(verts, cm))
    return part, gamma, mu_c, pts[0] - np.asarray(cm, dtype=float), wts[0], float(rng.uniform(-math.pi, math.pi))


def assert_inside_map(part, gamma, mu_c, body, wts, theta):
    fence = Fence.create(gamma, (mu_c, mu_c))
    cmap = fence_map(part, fence).map
    run = simulate_fence(part, fence, mu_c, body, wts, theta)
    assert run.complete, run.message
    if run.status == "jammed":
        assert not cmap.jam.is_empty
        return run
    where = [run.theta_final + d for d in (-SLACK, 0.0, SLACK)]
    assert any(k.contains(theta) and any(b.contains(x) for x in where) for b, k in zip(cmap.bands, cmap.kernels)), \
        (gamma, mu_c, theta, run.theta_final, [e.detail for e in run.events])
    return run


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(PARTS))
def test_every_simulated_outcome_lies_in_its_band_5_2(name):
    rng = np.random.default_rng(52)
    statuses = set()
    for _ in range(6):
        run = assert_inside_map(*random_case(rng, name))
        statuses.add(run.status)
    assert "left" in statuses


@pytest.mark.slow
def test_near_the_friction_angle_the_slip_stalls_and_b_still_bounds_it_5_1():
    """|tan gamma| just above mu_c: the part slides off the end after a stall of its slip
    (the case that broke an integration of B in the contact's position)."""
    rng = np.random.default_rng(64)
    part = Part.create(*PARTS["square"])
    fp = Footprint.create(*PARTS["square"])
    for gamma_deg in (24.6, -28.3, 31.0):
        gamma = math.radians(gamma_deg)
        mu_c = 0.97 * math.tan(abs(gamma))
        pts, wts = random_balanced_tripods(rng, 1, part.radius, footprint=fp)
        body = pts[0] - 0.5
        for theta in rng.uniform(-math.pi, math.pi, 2):
            run = assert_inside_map(part, gamma, mu_c, body, wts[0], float(theta))
            assert run.status == "left"


def test_a_flush_part_jams_at_or_below_the_friction_angle_6_4():
    part = Part.create(*PARTS["square"])
    gamma = math.radians(30.0)
    mu_c = math.tan(gamma) + 0.01
    fence = Fence.create(gamma, mu_c)
    run = simulate_fence(part, fence, mu_c, [[0.2, 0.1], [-0.1, 0.15], [-0.1, -0.25]], [1, 1, 1], 0.3)
    assert run.status == "jammed" and run.theta_final is None
    assert run.events[-1].kind == "jam" and "6.4" in run.events[-1].detail
    assert not fence_map(part, fence).map.jam.is_empty


def test_mirror_image_gives_the_mirrored_outcome():
    rng = np.random.default_rng(7)
    part, gamma, mu_c, body, wts, theta = random_case(rng, "pentagon", mu=(0.1, 0.3))
    verts, cm = PARTS["pentagon"]
    fence = Fence.create(gamma, mu_c)
    run = simulate_fence(part, fence, mu_c, body, wts, theta)
    mverts = [[-x, y] for x, y in verts]
    mpart = Part.create(mverts, [-cm[0], cm[1]])
    mbody = body * np.array([-1.0, 1.0])
    mrun = simulate_fence(mpart, Fence.create(-gamma, mu_c), mu_c, mbody, wts, -theta)
    assert run.status == mrun.status == "left"
    assert math.remainder(run.theta_final + mrun.theta_final, 2 * math.pi) == pytest.approx(0.0, abs=1e-7)


@pytest.mark.parametrize("scale", [1e-3, 1e3])
def test_scaling_the_part_changes_no_orientation(scale):
    rng = np.random.default_rng(11)
    part, gamma, mu_c, body, wts, theta = random_case(rng, "right triangle", mu=(0.1, 0.3))
    verts, cm = PARTS["right triangle"]
    fence = Fence.create(gamma, mu_c)
    ref = simulate_fence(part, fence, mu_c, body, wts, theta)
    big = Part.create(np.array(verts, dtype=float) * scale, np.array(cm) * scale)
    got = simulate_fence(big, fence, mu_c, body * scale, wts, theta)
    assert ref.status == got.status == "left"
    assert got.theta_final == pytest.approx(ref.theta_final, abs=1e-7)
    assert [e.kind for e in got.events] == [e.kind for e in ref.events]


def test_a_run_cut_short_says_so():
    part = Part.create(*PARTS["square"])
    fence = Fence.create(math.radians(45.0), 0.2)
    run = simulate_fence(part, fence, 0.2, [[0.2, 0.1], [-0.1, 0.15], [-0.1, -0.25]], [1, 1, 1], 0.3,
                         settings=FeederSimSettings(max_steps=3))
    assert run.status == "step_limit" and not run.complete and run.theta_final is None
    assert len(run.pushes) <= 4


def test_bad_input_is_refused():
    part = Part.create(*PARTS["square"])
    fence = Fence.create(math.radians(45.0), 0.2)
    with pytest.raises(InvalidInput, match="mu_c"):
        simulate_fence(part, fence, 0.5, [[0.0, 0.0]], [1.0], 0.0)
    with pytest.raises(InvalidInput, match="support"):
        simulate_fence(part, fence, 0.2, [[0.1, 0.0], [-0.1, 0.0]], [1.0, -1.0], 0.0)
