"""Parts through the placed fences of a belt (solver/feeder/simulate.py, simulate_belt_batch;
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
  per-part mu_c of the wrong shape are refused;
* a vertex meeting the fence exactly at its end (a hard case) ends with an honest outcome.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.feeder.fence import Fence, fence_map
from models.feeder.layout import lay_out
from models.feeder.maps import sequence
from solver.feeder.simulate import FeederSimSettings, FenceSegment, simulate_belt_batch, simulate_fence_batch
from solver.sim.kinematics import body_to_world
from tests.feeder_cases import part, random_support

SLACK = 1e-6  # radians: a final orientation against a band's edge


def test_a_placed_fence_gives_its_own_frame_run_moved_with_it():
    the_part = part("pentagon")
    a = the_part.circumradius
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
    a = the_part.circumradius
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
    a = the_part.circumradius
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
    with pytest.raises(InvalidInput, match="mu_c"):
        simulate_belt_batch(the_part, [seg], [[0.2, 0.2, 0.2]], [(body, wts)] * 2, [0.3, 0.4])
    with pytest.raises(InvalidInput, match="fences"):
        simulate_belt_batch(the_part, [], 0.2, [(body, wts)], [0.3])


def test_a_vertex_meeting_the_fence_exactly_at_its_end_gives_an_honest_outcome():
    """Hard case (issue 12): the part's first-contact vertex drifts exactly onto the fence's
    end E (and 1e-12 a either side). The contact's normal is then any between the face's
    and the two edges'; a part that hangs past the end has vertices below the face's line
    without the fence entering it (the step is checked by clipping the fence against the
    hull, not by those vertices). Every run ends with an outcome, never a silent wrong one:
    a run that left with an edge flush lies in its fence's map; one that left without is
    flagged ``flushed`` False (outside the map's assumption); a run the simulator cannot
    advance says so (stalled or step limit) and stops early, and these stay few (one of 54:
    a square's vertex exactly at E). E never pulls the part."""
    rng = np.random.default_rng(95)
    settings = FeederSimSettings(max_steps=3000)
    done = cut = corner = 0
    for name in ("square", "pentagon", "rectangle"):
        the_part = part(name)
        a = the_part.circumradius
        for gamma in (0.6, -0.9):
            fence = Fence.create(gamma, 0.25)
            seg = FenceSegment.create(fence, [0.0, 0.0], 30.0 * a)
            cmap = fence_map(the_part, fence).map
            for _ in range(3):
                theta = float(rng.uniform(-math.pi, math.pi))
                hull = body_to_world(np.zeros(2), theta, the_part.hull)
                k = int(np.argmin(hull @ fence.normal))
                for off in (0.0, 1e-12, -1e-12):
                    cm = np.array([-hull[k, 0] + off * a, 5.0 * a - hull[k, 1]])
                    (run,) = simulate_belt_batch(the_part, [seg], 0.25, [random_support(rng, name)], [theta], [cm],
                                                 settings=settings)
                    r = run.runs[0]
                    assert_never_pulled(the_part, r, 0.0, 1e-9 * a)
                    corner += any("a vertex at the fence's end" in e.detail for e in r.events)
                    if r.status in ("stalled", "step_limit"):
                        cut += 1
                        assert r.theta_final is None and not r.complete
                        # a stall stops after stall_steps refused steps, not at the step limit
                        assert r.status == "step_limit" or len(r.pushes) < 1000
                        continue
                    done += 1
                    assert r.status in ("left", "missed")
                    if r.status == "left" and r.flushed:
                        assert cmap.allows(theta, r.theta_final, SLACK)
    assert done + cut == 54 and cut <= 2  # 1: a square's vertex exactly at E stalls
    assert corner >= 1  # a run where no step advanced until another contact at E was taken



def assert_never_pulled(the_part, run, e_y, tol):
    """E only pushes: while the part lies wholly below E it drifts freely with the belt
    (a step's CM moves down by the whole push)."""
    for k in range(len(run.pushes) - 1):
        hull = body_to_world(run.cms[k], float(run.thetas[k]), the_part.hull)
        if hull[:, 1].max() < e_y - tol:
            dp = run.pushes[k + 1] - run.pushes[k]
            assert run.cms[k + 1][1] - run.cms[k][1] == pytest.approx(-dp, rel=1e-9, abs=tol)


def test_a_part_below_the_fence_end_is_never_pulled_by_it():
    """A square whose vertex met E exactly (seeded case) once turned about E onto the edge
    at that vertex that faces away from it, and E, treated as pushing that edge, dragged
    the part along below it for hundreds of steps. E pushes only the edges that face it
    (their inward normal along the belt's relative motion): the part now turns on the
    face and leaves."""
    the_part = part("square")
    a = the_part.circumradius
    theta = -0.16043389450841605
    body = np.array([[0.39358112325753225, -0.452484853808482], [0.053786277878386635, 0.39684822159856914],
                     [-0.37879954869662813, -0.22647738934019324]])
    wts = np.array([0.2385041826701444, 0.44981484798656823, 0.31168096934328743])
    fence = Fence.create(-0.9, 0.25)
    hull = body_to_world(np.zeros(2), theta, the_part.hull)
    k = int(np.argmin(hull @ fence.normal))
    start = np.array([-hull[k, 0], 2.0 * a - hull[k, 1] + 3.0 * a])
    (run,) = simulate_belt_batch(the_part, [FenceSegment.create(fence, [0.0, 0.0], 30.0 * a)], 0.25, [(body, wts)],
                                 [theta], [start], settings=FeederSimSettings(max_steps=400))
    r = run.runs[0]
    assert r.status == "left" and len(r.pushes) < 100
    assert_never_pulled(the_part, r, 0.0, 1e-9 * a)


def test_a_run_that_starts_in_contact_is_not_missed_and_the_callers_orientations_stay():
    """A run may start touching the fence (a pose taken from another run, or a belt's
    hand-over): it is the same run from there on, "left" with its edge flush, not
    "missed" for want of a drift onto the fence. The orientations passed in are the
    caller's and are not overwritten."""
    the_part = part("pentagon")
    rng = np.random.default_rng(96)
    fence = Fence.create(0.7, 0.25)
    support = random_support(rng, "pentagon")
    (ref,) = simulate_fence_batch(the_part, fence, 0.25, [support], [0.4])
    k = next(i for i, p in enumerate(ref.pushes) if p > ref.events[2].push)  # a step while flush
    seg = FenceSegment.create(fence, [0.0, 0.0], 40.0 * the_part.circumradius)
    thetas = np.array([float(ref.thetas[k])])
    (run,) = simulate_belt_batch(the_part, [seg], 0.25, [support], thetas, [ref.cms[k]])
    r = run.runs[0]
    assert ref.events[2].kind == "flush" and r.status == "left" and r.flushed
    assert "contact" not in [e.kind for e in r.events]
    assert r.theta_final == pytest.approx(ref.theta_final, abs=1e-9)
    assert thetas[0] == ref.thetas[k]


def test_a_batch_with_a_mu_c_per_part_runs_each_part_as_alone():
    """Parts with different mu_c share a fence's batch (solved per support size and mu_c):
    each run has the events and final orientation of the same part run alone."""
    the_part = part("rectangle")
    rng = np.random.default_rng(97)
    fence = Fence.create(-0.8, (0.1, 0.4))
    supports = [random_support(rng, "rectangle") for _ in range(4)]
    thetas = rng.uniform(-math.pi, math.pi, 4)
    mus = [0.1, 0.4, 0.1, 0.25]
    batch = simulate_fence_batch(the_part, fence, mus, supports, thetas)
    for (pts, w), theta, mu, got in zip(supports, thetas, mus, batch):
        (alone,) = simulate_fence_batch(the_part, fence, mu, [(pts, w)], [theta])
        assert [e.detail for e in got.events] == [e.detail for e in alone.events]
        assert got.theta_final == alone.theta_final
