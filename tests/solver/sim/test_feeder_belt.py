"""Parts through the placed fences of a belt (solver/sim/feeder.py, simulate_belt_batch;
book 1.8.6, 5.4, figure 1-9), seeded:

* a fence placed anywhere in the world frame gives the run of the same fence in its own
  frame moved with it (translation invariance: every contact, the face's level included,
  is taken relative to the fence's end E), to rounding;
* on a belt laid out for a rectangle's two-fence design, every part arriving in the lane
  comes flush on both fences and ends in the product's band (5.4, 5.5), the second fence
  picking the part up where the first left it;
* a fence on the same side as the one before is passed untouched ("missed": the layout's
  reach 0), and the part keeps the orientation it had;
* a start with the fence through the part stops at once as "overlap"; bad segments and
  per-part mu_c of the wrong shape are refused.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.errors import InvalidInput
from models.feeder.fence import Fence, fence_map
from models.feeder.layout import lay_out
from models.feeder.maps import sequence
from solver.sim.feeder import FenceSegment, simulate_belt_batch, simulate_fence_batch
from tests.feeder_cases import part, random_support

SLACK = 1e-6  # radians: a final orientation against a band's edge


def test_a_placed_fence_gives_its_own_frame_run_moved_with_it():
    the_part = part("pentagon")
    a = the_part.radius
    rng = np.random.default_rng(91)
    fence = Fence.create(-0.75, 0.3)
    supports = [random_support(rng, "pentagon") for _ in range(4)]
    thetas = rng.uniform(-math.pi, math.pi, 4)
    alone = simulate_fence_batch(the_part, fence, 0.3, supports, thetas, fence_length=40.0 * a)
    shift = np.array([123.4, -56.7]) * a
    placed = simulate_belt_batch(the_part, [FenceSegment.create(fence, shift, 40.0 * a)], 0.3, supports, thetas,
                                 starts=[r.cms[0] + shift for r in alone])
    for ref, got in zip(alone, placed):
        run = got.runs[0]
        assert [(e.kind, e.detail[:20]) for e in run.events] == [(e.kind, e.detail[:20]) for e in ref.events]
        assert run.status == ref.status == "left" and got.status == "left"
        # rounding at the shifted coordinates may split one step in two near an event
        assert abs(len(run.pushes) - len(ref.pushes)) <= 2
        assert abs(run.theta_final - ref.theta_final) <= 1e-8
        assert np.allclose(run.cms[-1] - shift, ref.cms[-1], atol=1e-8 * a)


@pytest.mark.slow
def test_a_two_fence_rectangle_belt_brings_every_part_into_the_product_band_5_4():
    the_part = part("rectangle")
    a = the_part.radius
    mu = 0.25
    angles = [math.radians(-70.0), math.radians(65.0)]  # the shortest alternating design (docs/benchmarks.md)
    lay = lay_out(angles, a, 12.0 * a, 0.1 * a, 2.0 * a)
    segs = [FenceSegment.create(Fence.create(g, mu), p.end, p.length) for g, p in zip(angles, lay.fences)]
    product = sequence([fence_map(the_part, Fence.create(g, mu)).map for g in angles])
    rng = np.random.default_rng(92)
    n = 12
    supports = [random_support(rng, "rectangle") for _ in range(n)]
    thetas = rng.uniform(-math.pi, math.pi, n)
    start = [lay.entry_x, 1.1 * a]
    runs = simulate_belt_batch(the_part, segs, mu, supports, thetas, np.tile(start, (n, 1)))
    for theta, run in zip(thetas, runs):
        assert run.status == "left" and not run.missed and run.flushed
        assert [r.status for r in run.runs] == ["left", "left"]
        # the second run starts where the first ended
        assert np.array_equal(run.runs[1].cms[0], run.runs[0].cms[-1])
        assert product.allows(float(theta), run.theta_final, SLACK)
        # each fence's own run is inside that fence's map
        for g, r in zip(angles, run.runs):
            assert fence_map(the_part, Fence.create(g, mu)).map.allows(r.theta_initial, r.theta_final, SLACK)


def test_a_fence_on_the_same_side_as_the_one_before_is_missed():
    the_part = part("square")
    a = the_part.radius
    angles = [0.6, 0.6]
    lay = lay_out(angles, a, 12.0 * a, 0.1 * a, 2.0 * a)
    assert lay.fences[1].reach == 0.0
    segs = [FenceSegment.create(Fence.create(g, 0.2), p.end, p.length) for g, p in zip(angles, lay.fences)]
    rng = np.random.default_rng(93)
    supports = [random_support(rng, "square") for _ in range(3)]
    thetas = rng.uniform(-math.pi, math.pi, 3)
    runs = simulate_belt_batch(the_part, segs, 0.2, supports, thetas, np.tile([lay.entry_x, 1.1 * a], (3, 1)))
    for run in runs:
        assert [r.status for r in run.runs] == ["left", "missed"] and run.missed and run.status == "left"
        assert run.theta_final == run.runs[0].theta_final


def test_a_start_through_a_fence_is_an_overlap_and_bad_input_is_refused():
    the_part = part("square")
    fence = Fence.create(0.5, 0.2)
    seg = FenceSegment.create(fence, [0.0, 0.0], 10.0)
    body, wts = random_support(np.random.default_rng(94), "square")
    mid = 5.0 * seg.direction  # the CM on the fence's face: the fence passes through the part
    (run,) = simulate_belt_batch(the_part, [seg], 0.2, [(body, wts)], [0.3], [mid])
    assert run.status == "overlap" and run.theta_final is None and run.runs[0].counts.solves == 0
    with pytest.raises(InvalidInput, match="end"):
        FenceSegment.create(fence, [0.0, math.nan], 10.0)
    with pytest.raises(InvalidInput, match="length"):
        FenceSegment.create(fence, [0.0, 0.0], 0.0)
    with pytest.raises(InvalidInput, match="mu_c"):
        simulate_belt_batch(the_part, [seg], [0.2, 0.9], [(body, wts)] * 2, [0.3, 0.4])
    with pytest.raises(InvalidInput, match="fences"):
        simulate_belt_batch(the_part, [], 0.2, [(body, wts)], [0.3])
