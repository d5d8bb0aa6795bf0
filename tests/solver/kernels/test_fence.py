"""The compiled fence simulator (solver/kernels/fence.py) against its reference, the stepped
generator of solver/feeder/simulate.py (book 5.1, 6.4-6.6), on seeded cases: every test part
through random fences, placed fences of a belt, and the hard cases (a vertex exactly at the
fence's end, a part that jams, mu_c -> 0 and large, a fence nearly along the belt, a fence
too short to finish the turn). The two take the same steps up to rounding: the same
outcome, the same events, the final orientation to 1e-9 rad, a step or two more or less
where a rounding-sized difference moves an event across a step's end."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.feeder.fence import Fence
from solver.feeder.simulate import FeederSimSettings, FenceSegment, simulate_belt_batch, simulate_fence_batch
from solver.sim.kinematics import body_to_world
from tests.feeder_cases import PARTS, part, random_fence, random_support

THETA_AGREE = 1e-9
"""Radians: the final orientations of most runs of the two paths (measured: 2e-11 at most
over 600 random runs)."""
THETA_CHATTER = 1e-3
"""Radians: the final orientations of any run. Where a part turns off the fence's end while
its contact switches between sticking and slipping every step, the first-order steps of
both paths amplify a rounding-sized difference about twofold every two steps (measured:
1e-11 grew to 1.5e-5 over 80 steps); the simulator's own error there is about 0.5 degrees
(docs/benchmarks.md)."""
STEPS_AGREE = 3
"""Steps: a rounding-sized difference can split a step in two or join two."""


def assert_same_runs(got, ref):
    close = 0
    for i, (x, y) in enumerate(zip(got, ref, strict=True)):
        assert x.status == y.status, (i, x.message, y.message)
        assert [e.kind for e in x.events] == [e.kind for e in y.events], i
        assert x.flushed == y.flushed, i
        assert abs(x.step_count - y.step_count) <= STEPS_AGREE, (i, x.step_count, y.step_count)
        if y.theta_final is not None:
            assert abs(x.theta_final - y.theta_final) <= THETA_CHATTER, (i, x.theta_final - y.theta_final)
            close += abs(x.theta_final - y.theta_final) <= THETA_AGREE
        else:
            close += 1
        assert x.counts.solves == pytest.approx(y.counts.solves, abs=2 * STEPS_AGREE)
    if len(ref) >= 6:
        assert close >= 0.75 * len(ref), f"{close} of {len(ref)} runs end within {THETA_AGREE} rad"


@pytest.mark.parametrize("name", list(PARTS))
def test_random_parts_through_random_fences_take_the_reference_steps(name):
    rng = np.random.default_rng([20261203, list(PARTS).index(name)])
    the_part = part(name)
    for _ in range(2):
        fence, mu_c = random_fence(rng)
        supports = [random_support(rng, name) for _ in range(12)]
        thetas = rng.uniform(-math.pi, math.pi, 12)
        got = simulate_fence_batch(the_part, fence, mu_c, supports, thetas)
        ref = simulate_fence_batch(the_part, fence, mu_c, supports, thetas, compiled=False)
        assert_same_runs(got, ref)
        for x, y in zip(got, ref):
            assert [e.detail for e in x.events[:-1]] == [e.detail for e in y.events[:-1]]


@pytest.mark.slow  # 9 s over its cases: the heaviest of the everyday tier
@pytest.mark.parametrize("gamma, mu_c, length", [
    (0.6, 0.7, None),  # |tan gamma| = 0.68 <= mu_c: a flush part jams (6.4)
    (0.6, 1e-9, None),  # mu_c -> 0
    (1.35, 3.0, None),  # mu_c large, the fence steep enough to slide (tan 1.35 = 4.5)
    (-1.55, 0.1, None),  # a fence nearly along the belt
    (0.7, 0.25, 1.0),  # a fence too short for the part to finish turning (in radii)
])
def test_the_hard_fences_take_the_reference_steps(gamma, mu_c, length):
    rng = np.random.default_rng(int(1000 * abs(gamma)))
    fence = Fence.create(gamma, mu_c)
    for name in ("square", "pentagon", "L-shape"):
        the_part = part(name)
        supports = [random_support(rng, name) for _ in range(6)]
        thetas = rng.uniform(-math.pi, math.pi, 6)
        fl = None if length is None else length * the_part.circumradius
        got = simulate_fence_batch(the_part, fence, mu_c, supports, thetas, fence_length=fl)
        ref = simulate_fence_batch(the_part, fence, mu_c, supports, thetas, fence_length=fl, compiled=False)
        assert_same_runs(got, ref)
        if gamma == 0.6 and mu_c == 0.7:
            assert any(r.status == "jammed" for r in got)


def test_a_vertex_next_to_the_fence_end_takes_the_reference_steps():
    """The first-contact vertex drifts onto E but for 1e-12 a either side: the corner
    contacts, the refused steps (tests/solver/feeder/test_simulate_belt.py). Exactly at E
    the contact is any of three, and which one a rounding-sized difference picks decides
    the run: there both paths are held to an honest outcome by that module's test, not to
    each other."""
    rng = np.random.default_rng(95)
    settings = FeederSimSettings(max_steps=3000)
    for name in ("square", "pentagon", "rectangle"):
        the_part = part(name)
        a = the_part.circumradius
        for gamma in (0.6, -0.9):
            seg = FenceSegment.create(Fence.create(gamma, 0.25), [0.0, 0.0], 30.0 * a)
            for _ in range(2):
                theta = float(rng.uniform(-math.pi, math.pi))
                hull = body_to_world(np.zeros(2), theta, the_part.hull)
                k = int(np.argmin(hull @ seg.fence.normal))
                for off in (1e-12, -1e-12):
                    cm = np.array([-hull[k, 0] + off * a, 5.0 * a - hull[k, 1]])
                    support = random_support(rng, name)
                    (got,) = simulate_belt_batch(the_part, [seg], 0.25, [support], [theta], [cm], settings=settings)
                    (ref,) = simulate_belt_batch(the_part, [seg], 0.25, [support], [theta], [cm], settings=settings,
                                                 compiled=False)
                    assert_same_runs(got.runs, ref.runs)


def test_a_belt_of_placed_fences_takes_the_reference_steps():
    """Two placed fences, the second picking each part up where the first left it (5.4)."""
    the_part = part("rectangle")
    a = the_part.circumradius
    segs = [FenceSegment.create(Fence.create(0.7, 0.25), [-3.0 * a, 0.0], 12.0 * a),
            FenceSegment.create(Fence.create(-0.8, 0.25), [3.0 * a, -12.0 * a], 12.0 * a)]
    rng = np.random.default_rng(7)
    n = 20
    supports = [random_support(rng, "rectangle") for _ in range(n)]
    thetas = rng.uniform(-math.pi, math.pi, n)
    starts = np.column_stack([rng.uniform(2.0, 6.0, n) * a, np.full(n, 10.0 * a)])
    got = simulate_belt_batch(the_part, segs, 0.25, supports, thetas, starts)
    ref = simulate_belt_batch(the_part, segs, 0.25, supports, thetas, starts, compiled=False)
    for x, y in zip(got, ref, strict=True):
        assert len(x.runs) == len(y.runs) and x.status == y.status
        assert_same_runs(x.runs, y.runs)
    assert sum(len(b.runs) == 2 for b in got) >= n // 2


def test_a_run_kept_without_its_path_keeps_its_outcome_and_reach():
    """record=0: the same outcomes, steps and solves; the largest |x| of the hull over the
    run's poses equals the one over the recorded path."""
    the_part = part("pentagon")
    rng = np.random.default_rng(11)
    fence, mu_c = random_fence(rng)
    supports = [random_support(rng, "pentagon") for _ in range(10)]
    thetas = rng.uniform(-math.pi, math.pi, 10)
    full = simulate_fence_batch(the_part, fence, mu_c, supports, thetas)
    bare = simulate_fence_batch(the_part, fence, mu_c, supports, thetas, record=0)
    for x, y in zip(bare, full):
        assert not x.recorded and not x.events and len(x.pushes) == 2
        assert (x.status, x.theta_final, x.step_count, x.flushed) == (y.status, y.theta_final, y.step_count, y.flushed)
        reach = max(float(np.abs(body_to_world(c, t, the_part.hull)[:, 0]).max()) for c, t in zip(y.cms, y.thetas))
        assert x.outline_reach == pytest.approx(reach, rel=1e-12)


def test_a_part_the_compiled_solve_cannot_carry_runs_on_the_reference(monkeypatch):
    """A run whose forward solve the compiled Newton could not finish (status REFERENCE) is
    run again, whole, on the reference path."""
    from solver.kernels import codes
    from solver.kernels import fence as kernel

    real = kernel.run_belt

    def first_needs_reference(*args):
        summaries, path, events = real(*args)
        if args[-2] == 0:
            summaries[0, 0, codes.S_STATUS] = codes.REFERENCE
        return summaries, path, events

    monkeypatch.setattr(kernel, "run_belt", first_needs_reference)
    the_part = part("square")
    rng = np.random.default_rng(3)
    fence, mu_c = random_fence(rng)
    supports = [random_support(rng, "square") for _ in range(3)]
    thetas = rng.uniform(-math.pi, math.pi, 3)
    got = simulate_fence_batch(the_part, fence, mu_c, supports, thetas)
    ref = simulate_fence_batch(the_part, fence, mu_c, supports, thetas, compiled=False)
    assert got[0].outline_reach is None  # the reference's run
    np.testing.assert_array_equal(got[0].thetas, ref[0].thetas)
    assert_same_runs(got, ref)
