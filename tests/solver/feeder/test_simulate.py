"""A part meeting one fence on a belt, simulated quasi-statically (solver/feeder/simulate.py;
book 5.1, 6.4, 6.5), against the configuration map of models/feeder/fence.py.

All seeded:

* every simulated outcome (random balanced tripods in the part, random initial
  orientation, fence angle on either side of the belt, mu_c) lies in the band of a kernel
  holding its initial orientation (5.2), or jams where the map says it may (6.4);
* the runs near the friction angle (|tan gamma| slightly above mu_c), where the map's
  extreme B once missed a stall of the slip (the slip per radian falls to 0 before it
  rises again), are inside too;
* a sequence of two to four fences on alternating sides: every chained simulation (the
  final orientation of one fence the initial of the next, one support throughout) lies in
  the product of the fences' maps (5.1, 5.4, 5.5);
* jams: a flush part with |tan gamma| <= mu_c stops (6.4);
* symmetry: the mirror image of part, support, fence and start gives the mirrored final
  orientation; scaling the part by 1e-3 and 1e3 changes nothing;
* a run cut short by its step limit says so (no final orientation, not complete);
* the reach (1.8.6): parts started near a short fence's end come flush and land in their
  bands unless the map flags their orientation as unaligned, and every part that leaves
  unflushed was flagged.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.feeder.fence import Fence, feeder_part, fence_map
from models.feeder.maps import sequence
from solver import Budget
from solver.feeder.simulate import COMPILED_CHUNK, FeederSimSettings, simulate_fence, simulate_fence_batch
from tests.feeder_cases import (
    PARTS,
    CountingClock,
    first_contact_reach,
    part,
    random_encounter,
    random_fence,
    random_support,
)

SLACK = 1e-6  # radians: the run's final orientation against a band's edge


def random_case(rng, name, mu=(0.0, 0.6)):
    fence, mu_c = random_fence(rng, mu=mu)
    enc = random_encounter(rng, name)
    return enc.part, fence.angle, mu_c, enc.body, enc.weights, enc.theta


def assert_inside_map(part, gamma, mu_c, body, wts, theta):
    fence = Fence.create(gamma, (mu_c, mu_c))
    cmap = fence_map(part, fence).map
    run = simulate_fence(part, fence, mu_c, body, wts, theta)
    assert run.complete, run.message
    if run.status == "jammed":
        assert cmap.jam.contains(theta)
        return run
    assert cmap.allows(theta, run.theta_final, SLACK), (gamma, mu_c, theta, run.theta_final,
                                                        [e.detail for e in run.events])
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
    square = part("square")
    for gamma_deg in (24.6, -28.3, 31.0):
        gamma = math.radians(gamma_deg)
        mu_c = 0.97 * math.tan(abs(gamma))
        body, wts = random_support(rng, "square")
        for theta in rng.uniform(-math.pi, math.pi, 2):
            run = assert_inside_map(square, gamma, mu_c, body, wts, float(theta))
            assert run.status == "left"


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(PARTS))
def test_chained_simulations_lie_in_the_product_of_the_maps_5_4_5_5(name):
    rng = np.random.default_rng(55)
    the_part = part(name)
    for n_fences in (2, 4):
        side = float(rng.choice([-1.0, 1.0]))
        fences = []
        for i in range(n_fences):
            deg = rng.uniform(25.0, 60.0)
            mu_c = float(rng.uniform(0.05, 0.3))
            fences.append((Fence.create(side * (-1) ** i * math.radians(deg), (mu_c, mu_c)), mu_c))
        product = sequence([fence_map(the_part, f).map for f, _ in fences])
        for _ in range(2):
            body, wts = random_support(rng, name)
            theta0 = theta = float(rng.uniform(-math.pi, math.pi))
            for fence, mu_c in fences:
                run = simulate_fence(the_part, fence, mu_c, body, wts, theta)
                assert run.status == "left", run.message
                theta = run.theta_final
            assert product.allows(theta0, theta, SLACK)


def test_a_flush_part_jams_at_or_below_the_friction_angle_6_4():
    square = part("square")
    gamma = math.radians(30.0)
    mu_c = math.tan(gamma) + 0.01
    fence = Fence.create(gamma, mu_c)
    run = simulate_fence(square, fence, mu_c, [[0.2, 0.1], [-0.1, 0.15], [-0.1, -0.25]], [1, 1, 1], 0.3)
    assert run.status == "jammed" and run.theta_final is None
    assert run.events[-1].kind == "jam" and "6.4" in run.events[-1].detail
    assert fence_map(square, fence).map.jam.contains(0.3)


def test_mirror_image_gives_the_mirrored_outcome():
    rng = np.random.default_rng(7)
    the_part, gamma, mu_c, body, wts, theta = random_case(rng, "pentagon", mu=(0.1, 0.3))
    verts, cm = PARTS["pentagon"]
    fence = Fence.create(gamma, mu_c)
    run = simulate_fence(the_part, fence, mu_c, body, wts, theta)
    mverts = [[-x, y] for x, y in verts]
    mpart = feeder_part(mverts, [-cm[0], cm[1]])
    mbody = body * np.array([-1.0, 1.0])
    mrun = simulate_fence(mpart, Fence.create(-gamma, mu_c), mu_c, mbody, wts, -theta)
    assert run.status == mrun.status == "left"
    assert math.remainder(run.theta_final + mrun.theta_final, 2 * math.pi) == pytest.approx(0.0, abs=1e-7)


@pytest.mark.parametrize("scale", [1e-3, 1e3])
def test_scaling_the_part_changes_no_orientation(scale):
    rng = np.random.default_rng(11)
    the_part, gamma, mu_c, body, wts, theta = random_case(rng, "right triangle", mu=(0.1, 0.3))
    verts, cm = PARTS["right triangle"]
    fence = Fence.create(gamma, mu_c)
    ref = simulate_fence(the_part, fence, mu_c, body, wts, theta)
    big = feeder_part(np.array(verts, dtype=float) * scale, np.array(cm) * scale)
    got = simulate_fence(big, fence, mu_c, body * scale, wts, theta)
    assert ref.status == got.status == "left"
    assert got.theta_final == pytest.approx(ref.theta_final, abs=1e-7)
    assert [e.kind for e in got.events] == [e.kind for e in ref.events]


def test_a_run_cut_short_says_so():
    fence = Fence.create(math.radians(45.0), 0.2)
    run = simulate_fence(part("square"), fence, 0.2, [[0.2, 0.1], [-0.1, 0.15], [-0.1, -0.25]], [1, 1, 1], 0.3,
                         settings=FeederSimSettings(max_steps=3))
    assert run.status == "step_limit" and not run.complete and run.theta_final is None
    assert len(run.pushes) <= 4


def test_bad_input_is_refused():
    square = part("square")
    fence = Fence.create(math.radians(45.0), 0.2)
    with pytest.raises(InvalidInput, match="mu_c"):
        simulate_fence(square, fence, 0.5, [[0.0, 0.0]], [1.0], 0.0)
    with pytest.raises(InvalidInput, match="support"):
        simulate_fence(square, fence, 0.2, [[0.1, 0.0], [-0.1, 0.0]], [1.0, -1.0], 0.0)


@pytest.mark.parametrize("scale", [1e-6, 1e6])
def test_tiny_and_huge_parts_end_alike(scale):
    rng = np.random.default_rng(5)
    body, wts = random_support(rng, "right triangle")
    verts, cm = PARTS["right triangle"]
    fence = Fence.create(0.6, 0.2)
    ref = simulate_fence(part("right triangle"), fence, 0.2, body, wts, 1.0)
    scaled = feeder_part(np.array(verts, dtype=float) * scale, np.array(cm) * scale)
    got = simulate_fence(scaled, fence, 0.2, body * scale, wts, 1.0)
    assert got.status == ref.status == "left"
    assert got.theta_final == pytest.approx(ref.theta_final, abs=1e-7)


def test_at_the_friction_angle_exactly_a_flush_part_jams_6_4():
    """|tan gamma| = mu_c: the part cannot slide (the boundary case belongs to jamming)."""
    square = part("square")
    fence = Fence.create(math.atan(0.3), 0.3)
    body, wts = random_support(np.random.default_rng(9), "square")
    assert simulate_fence(square, fence, 0.3, body, wts, 0.4).status == "jammed"
    assert fence_map(square, fence).map.jam == fence_map(square, fence).map.jam.circle()


def test_a_fence_nearly_along_the_belt_and_one_too_short_are_flagged():
    """At 88 degrees the part still comes flush and lands in its map; at 89.9 degrees it
    turns so slowly (cos gamma per unit of travel) that it leaves a 40-radius fence still
    turning on a vertex: the run says it never came flush (the map assumes it did)."""
    square = part("square")
    body, wts = random_support(np.random.default_rng(5), "square")
    steep = Fence.create(math.radians(88.0), 0.2)
    run = simulate_fence(square, steep, 0.2, body, wts, 0.4)
    assert run.status == "left" and run.flushed
    assert fence_map(square, steep).map.allows(0.4, run.theta_final, SLACK)
    along = Fence.create(math.radians(89.9), 0.2)
    run = simulate_fence(square, along, 0.2, body, wts, 0.4)
    assert run.status == "left" and not run.flushed
    assert not fence_map(square, along).map.allows(0.4, run.theta_final, SLACK)


def test_a_part_that_never_touches_the_fence_is_missed():
    square = part("square")
    body, wts = random_support(np.random.default_rng(5), "square")
    run = simulate_fence(square, Fence.create(0.7, 0.2), 0.2, body, wts, 0.4, start_along=-0.5)
    assert run.status == "missed" and run.complete and run.theta_final == 0.4 and not run.flushed


@pytest.mark.slow
@pytest.mark.parametrize("name, gamma, mu_c", [("pentagon", 0.7, 0.25), ("rectangle", -0.6, 0.2)])
def test_a_part_the_reach_is_sure_to_align_comes_flush_and_lands_in_its_band_1_8_6(name, gamma, mu_c):
    """Phase 6 against simulation: parts start near a short fence's end (random support,
    orientation, place). With the map made for a reach no longer than the run's (from its
    first contact to the end), every run whose initial orientation the map does not flag as
    unaligned comes flush and ends in its band, and every run that leaves without coming
    flush was flagged. Seen with seed 186: 11 of 34 runs (pentagon) and 7 of 32 (rectangle)
    leave unflushed; none stalls (flush slides keep the edge's lower end on the face)."""
    the_part = part(name)
    a = the_part.circumradius
    reaches = [x * a for x in (0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 2.5)]
    maps = {r: fence_map(the_part, Fence.create(gamma, mu_c, reach=r)).map for r in reaches}
    fence = Fence.create(gamma, mu_c)
    rng = np.random.default_rng(186)
    supports, thetas, along = [], [], []
    for _ in range(40):
        supports.append(random_support(rng, name))
        thetas.append(float(rng.uniform(-math.pi, math.pi)))
        along.append(float(rng.uniform(0.05, 0.6)))
    unflushed = checked = 0
    runs = simulate_fence_batch(the_part, fence, mu_c, supports, thetas, fence_length=3.0 * a, start_along=along)
    for theta, run in zip(thetas, runs):
        if run.status != "left":
            assert run.status == "missed", run.message
            continue
        reach = first_contact_reach(the_part, fence, run)
        if reach is None or reach < reaches[0]:
            continue
        cmap = maps[max(r for r in reaches if r <= reach)]
        checked += 1
        if run.flushed:
            assert cmap.allows(theta, run.theta_final, SLACK), (theta, reach, run.theta_final)
        else:
            unflushed += 1
            assert cmap.unaligned.contains(theta), (theta, reach, [e.detail for e in run.events])
    assert checked >= 25 and unflushed >= 3


def test_an_edge_along_the_face_with_one_end_past_the_end_turns_off_it():
    """A pentagon started near a short fence's end turns on a vertex until an edge lies along
    the face with its other end past E (seed 7, run 21 of the reach experiment; its far end
    dips below the face's line by more than the contact tolerance): that edge is recognised
    along the face with E on it, the force line misses the supported part, and the part
    turns off E and leaves (it once stalled there)."""
    the_part = part("pentagon")
    body = [[-0.8404173878438121, 0.109846635030036], [-0.5757222468072696, -0.6418082265097688],
            [1.6583100419768, -0.13988285789584798]]
    wts = [0.6317887112091901, 0.035649556108578326, 0.33256173268223155]
    theta = -0.5572214545379439
    fence = Fence.create(0.7, 0.25)
    run = simulate_fence(the_part, fence, 0.25, body, wts, theta,
                         fence_length=3.0 * the_part.circumradius, start_along=0.29751214884635924)
    assert run.status == "left" and [e.kind for e in run.events][-2:] == ["end", "left"]
    assert fence_map(the_part, fence).map.allows(theta, run.theta_final, SLACK)


def test_an_edge_flush_past_the_end_slides_on_from_its_lower_end_and_leaves_in_its_band():
    """An edge comes flush with its downstream end already past E (the first stalled run of
    seed 20261126 in the reach benchmark's pentagon case). The end past E stood a rounding-
    sized tilt (4e-9) above the face; the slide put that end on the face's line, which sank
    the end over the fence below it by more than the contact tolerance, so every later step
    was refused and the run stalled (called "two contacts at once" until then). The lower
    end over the fence now goes onto the line: the part slides, turns off E and leaves
    inside its map, as all 19 runs of the benchmark that stalled so."""
    the_part = part("pentagon")
    body = [[-0.12626105018592337, -0.4097681415689577], [-0.9201117231123987, 0.6575124391929066],
            [1.604756486308196, 0.00033015158083182783]]
    wts = [0.4857029776336326, 0.30258851200486553, 0.21170851036150187]
    fence, theta = Fence.create(0.7, 0.25), -0.2664426255082293
    run = simulate_fence(the_part, fence, 0.25, body, wts, theta,
                         fence_length=3.0 * the_part.circumradius, start_along=0.3555560591083008)
    assert run.status == "left" and run.flushed
    assert [e.kind for e in run.events][-3:] == ["flush", "end", "left"]
    assert fence_map(the_part, fence).map.allows(theta, run.theta_final, SLACK)


def test_a_rectangle_whose_force_line_passes_through_a_vertex_pivots_inside_its_map_phase_4():
    """Found by the part-bound benchmark (seed 20261126, rectangle at +40 deg, run 2): the
    short edge comes flush with u_X exactly at its vertex (mu_c = 0.25), the part pivots
    onto the long edge and leaves there, which the map once did not allow."""
    the_part = part("rectangle")
    body = [[1.6929772521993534, -0.3321003033615051], [-1.7906592485903805, 0.29556866008676375],
            [1.370169414558387, -0.06128308904738089]]
    wts = [0.39853822477614437, 0.47418599261326055, 0.1272757826105951]
    fence, theta = Fence.create(math.radians(40.0), 0.25), -1.0318023906939398
    run = simulate_fence(the_part, fence, 0.25, body, wts, theta)
    assert run.status == "left" and run.flush_edges == [0]
    assert fence_map(the_part, fence).map.allows(theta, run.theta_final, SLACK)


def test_a_batch_of_parts_takes_exactly_the_steps_of_one_by_one_runs():
    """simulate_fence_batch steps many parts together (their forward solves batched per
    support size): every run has the events, steps, final orientation and solve count of
    the same part run alone, over tripods and four-point supports mixed, a part that jams,
    a part that misses the fence and a part that leaves."""
    rng = np.random.default_rng(77)
    for name, gamma, mu_c in (("pentagon", 0.7, 0.25), ("L-shape", -0.8, 0.15), ("square", 0.4, 0.5)):
        the_part = part(name)
        fence = Fence.create(gamma, mu_c)
        supports = [random_support(rng, name) for _ in range(5)]
        body, wts = supports[0]
        four = np.vstack([body, [[0.0, 0.0]]])
        supports.append((four, np.append(wts, 0.5)))  # k = 4, centroid still at the CM
        thetas = rng.uniform(-math.pi, math.pi, len(supports))
        along = np.full(len(supports), 0.7)
        along[-1] = 1.2  # beyond the fence's fixed end: the part drifts past it
        batch = simulate_fence_batch(the_part, fence, mu_c, supports, thetas, start_along=along)
        for (pts, w), theta, start, got in zip(supports, thetas, along, batch):
            alone = simulate_fence(the_part, fence, mu_c, pts, w, float(theta), start_along=float(start))
            assert [(e.kind, e.detail) for e in got.events] == [(e.kind, e.detail) for e in alone.events]
            assert got.status == alone.status and len(got.pushes) == len(alone.pushes)
            assert got.counts.solves == alone.counts.solves
            if alone.theta_final is not None:
                assert abs(got.theta_final - alone.theta_final) <= 1e-12
        statuses = {r.status for r in batch}
        assert "missed" in statuses and ("jammed" in statuses or name != "square")


def test_a_batch_past_its_budget_ends_every_run_still_going():
    """On the reference path the budget is checked before each batched round of solves:
    when it runs out, every run still going ends with status time_limit and no final
    orientation, having counted only the solves that ran; runs already finished keep their
    outcome."""
    the_part = part("pentagon")
    fence = Fence.create(0.7, 0.25)
    rng = np.random.default_rng(78)
    supports = [random_support(rng, "pentagon") for _ in range(4)]
    thetas = rng.uniform(-math.pi, math.pi, 4)
    along = [0.7, 0.7, 0.7, 1.2]  # the last misses the fence and finishes at once
    runs = simulate_fence_batch(the_part, fence, 0.25, supports, thetas, start_along=along,
                                budget=Budget.of(5.0, clock=CountingClock(12)), compiled=False)
    assert [r.status for r in runs] == ["time_limit"] * 3 + ["missed"]
    assert all(r.theta_final is None and not r.complete for r in runs[:3])
    assert all(0 < r.counts.solves < 20 for r in runs[:3]) and runs[3].counts.solves == 0


def test_a_compiled_batch_past_its_budget_ends_the_parts_not_started():
    """On the compiled path the budget is checked before each chunk of COMPILED_CHUNK parts:
    the parts of the chunks run are whole, those not started end time_limit, no final
    orientation, no solve counted (a budget of two clock readings: its start and the first
    chunk's check)."""
    the_part = part("pentagon")
    fence = Fence.create(0.7, 0.25)
    rng = np.random.default_rng(79)
    n = 2 * COMPILED_CHUNK + 3
    supports = [random_support(rng, "pentagon") for _ in range(n)]
    thetas = rng.uniform(-math.pi, math.pi, n)
    runs = simulate_fence_batch(the_part, fence, 0.25, supports, thetas, budget=Budget.of(5.0, clock=CountingClock(2)))
    assert all(r.complete and r.counts.solves > 0 for r in runs[:COMPILED_CHUNK])
    assert all(r.status == "time_limit" and r.theta_final is None and r.counts.solves == 0
               for r in runs[COMPILED_CHUNK:])
    assert "simulated parts 9-16 of 19" in runs[-1].events[0].detail
