"""One fence across a belt: phases 1-6 of models/feeder/fence.py (book 5.1, 5.2, 6.4-6.6, 1.8.6)."""

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.feeder.arcs import TWO_PI, Arcs
from models.feeder.fence import (
    FINE,
    Fence,
    ReachProfile,
    SampledReach,
    canonical_edge,
    canonical_outline,
    contact_interval,
    endpoint_turn,
    feeder_part,
    fence_map,
    final_edges,
    reach_profile,
    rotation,
    sampled_reach,
)
from models.feeder.maps import matrix_product

SQUARE = [[-1, -1], [1, -1], [1, 1], [-1, 1]]
RECT = [[0, 0], [4, 0], [4, 1], [0, 1]]  # long edges 0 and 2
PENTAGON = ([[0, 0], [3, 0], [3.5, 1.5], [1.5, 2.5], [-0.5, 1.2]], [1.4, 1.0])
N = 360


def arcs_deg(arcs):
    return [(round(math.degrees(s), 6), round(math.degrees(w), 6)) for s, w in arcs.arcs]


def test_contact_intervals_partition_the_circle_phase_1():
    part = feeder_part(*PENTAGON)
    gamma = math.radians(-60)
    widths = [contact_interval(part, k, gamma)[1] for k in range(part.hull_size)]
    assert sum(widths) == pytest.approx(TWO_PI)
    for k in range(part.hull_size):  # vertex k is the lowest along n inside its interval
        s, w = contact_interval(part, k, gamma)
        for theta in s + w * np.array([0.1, 0.5, 0.9]):
            c, si = math.cos(theta), math.sin(theta)
            world = part.hull @ np.array([[c, si], [-si, c]])
            depth = world @ np.array([-math.sin(gamma), math.cos(gamma)])
            assert int(np.argmin(depth)) == k


def test_jam_at_the_friction_angle_6_4():
    """A flush part slides along the fence only if |tan gamma| > mu_c (6.4)."""
    part = feeder_part(SQUARE)
    gamma = math.atan(0.25)
    jammed = fence_map(part, Fence.create(gamma, 0.25))
    assert jammed.map.bands == () and jammed.map.jam.measure == pytest.approx(TWO_PI)
    assert jammed.notes
    sliding = fence_map(part, Fence.create(gamma * (1 + 1e-6), 0.25))
    assert len(sliding.map.bands) == 4 and sliding.map.jam.is_empty
    either = fence_map(part, Fence.create(gamma * 1.05, (0.2, 0.3)))
    assert len(either.map.bands) == 4 and not either.map.jam.is_empty


def test_flush_edge_stability_by_hand_phase_4():
    """A 4 x 1 rectangle on a +60 degree fence: its short edge (L = 1, CM at u_c = 0.5,
    h_c = 2) is stable while u_X = 0.5 - 2 mu_c >= 0, i.e. mu_c <= 0.25; its long edges
    (u_X = 2 - 0.5 mu_c) always are."""
    part = feeder_part(RECT, [2.0, 0.5])
    fence = Fence.create(math.radians(60), 0.2)
    long_edges = {j for j in range(4) if part.hull_edge(j)[1] == pytest.approx(4.0)}
    short = [j for j in range(4) if j not in long_edges]
    assert all(final_edges(part, j, fence) == {j} for j in range(4))
    steep = Fence.create(math.radians(60), 0.3)
    for j in short:
        assert final_edges(part, j, steep) <= long_edges and final_edges(part, j, steep)
    m = fence_map(part, steep)
    assert set(m.final_edges) == long_edges
    assert len(fence_map(part, fence).final_edges) == 4


def test_endpoint_extremes_5_1_6_5():
    """Leaving the end: the turn lies between B (> 0) and A = 90 deg - |gamma|, so the edge
    ends between somewhat more than the fence angle and along the belt (6.5, figure 6-9).
    The default tolerances agree with FINE to 0.3 degrees and lie on its safe side (B
    smaller: a wider band)."""
    part = feeder_part(SQUARE)
    last = 0.0
    for deg in (25, 35, 45, 55, 65):
        fence = Fence.create(math.radians(deg), 0.25)
        turn = endpoint_turn(part, 0, fence)
        fine = endpoint_turn(part, 0, fence, FINE)
        assert turn.most == pytest.approx(math.radians(90 - deg))
        assert 0.0 < turn.least < turn.most and turn.contact_lost
        assert fine.least - math.radians(0.3) < turn.least <= fine.least
        assert turn.sense_flags == 0
        # the final edge angle gamma + B rises with the fence angle
        assert deg + math.degrees(turn.least) > last
        last = deg + math.degrees(turn.least)


@pytest.mark.parametrize("deg", [40.0, -55.0])
def test_the_outline_in_the_frame_of_leaving_the_end_5_1(deg):
    """canonical_outline puts the part where endpoint_turn's contact formula does: the
    flush edge's ends at l = 0 and l = L on the line through the contact, the CM at the
    origin, the part above the edge; mirrored (clockwise) for a fence with gamma < 0, the
    same shape (each vertex's distance from the CM kept)."""
    verts, cm = PENTAGON
    part = feeder_part(verts, cm)
    fence = Fence.create(math.radians(deg), 0.25)
    g = abs(fence.angle)
    t0 = np.array([math.cos(g), math.sin(g)])
    n0 = np.array([-t0[1], t0[0]])
    for j in range(part.hull_size):
        u_c, h_c, length, _ = canonical_edge(part, j, fence, 0.25)
        out = canonical_outline(part, j, fence)
        assert np.allclose(np.hypot(out[:, 0], out[:, 1]), np.hypot(part.vertices[:, 0], part.vertices[:, 1]))
        for ell in (0.0, length):
            contact = (ell - u_c) * t0 - h_c * n0
            assert np.min(np.hypot(*(out - contact).T)) < 1e-12 * part.circumradius
        assert np.all((out - ((0.0 - u_c) * t0 - h_c * n0)) @ n0 >= -1e-12)
        area = 0.5 * float(np.sum(out[:, 0] * np.roll(out[:, 1], -1) - np.roll(out[:, 0], -1) * out[:, 1]))
        assert math.copysign(1.0, area) == fence.sign


def test_an_own_slip_bound_narrows_extreme_b_and_none_is_the_disk_5_1():
    """endpoint_turn with the part's own slip bound (OwnRate) takes the smaller of it and
    the disk's: an infinite own bound is the disk's B, a zero one (no slip) is A, and one
    between lies between."""
    verts, cm = PENTAGON
    part = feeder_part(verts, cm)
    fence = Fence.create(math.radians(40), 0.25)
    lost = []
    for j in fence_map(part, fence).final_edges:
        disk = endpoint_turn(part, j, fence)
        inf = endpoint_turn(part, j, fence, own_rate=lambda j, mu: lambda ell, delta: math.inf)
        zero = endpoint_turn(part, j, fence, own_rate=lambda j, mu: lambda ell, delta: 0.0)
        some = endpoint_turn(part, j, fence, own_rate=lambda j, mu: lambda ell, delta: 2.0 * part.circumradius)
        assert inf.least == disk.least
        assert zero.least == zero.most and not zero.contact_lost
        assert disk.least < some.least <= zero.least
        lost.append(some.contact_lost)
    assert any(lost)  # a bound between: E leaves an edge between B and A


def test_a_force_line_through_a_vertex_may_leave_the_part_on_either_edge_phase_4():
    """The 4 x 1 rectangle at mu_c = 0.25: on a short edge u_X = u_c - mu_c h_c = 0.5 - 0.25 * 2
    = 0, the force line passes through the edge's vertex, and rounding decides whether the
    part stays or pivots onto the long edge (the simulator did pivot, the map once said it
    stays). Within crossing_rel of an end both are final; well away from 0.25 only the
    short edge is."""
    part = feeder_part(RECT, [2, 0.5])
    fence = Fence.create(math.radians(40), 0.25)
    assert [sorted(final_edges(part, j, fence)) for j in range(4)] == [[0], [0, 1], [2], [2, 3]]
    assert [sorted(final_edges(part, j, Fence.create(math.radians(40), 0.2))) for j in range(4)] == [[0], [1], [2], [3]]
    assert [sorted(final_edges(part, j, Fence.create(math.radians(40), 0.3))) for j in range(4)] == [[0], [0], [2], [2]]


def mirrored(vertices):
    return [[-x, y] for x, y in vertices]


def test_mirror_symmetry():
    """The mirror image (x -> -x) of part and fence (gamma -> -gamma) mirrors the map:
    theta -> -theta on both axes."""
    verts, cm = PENTAGON
    for deg in (30, 60):
        a = fence_map(feeder_part(verts, cm), Fence.create(math.radians(deg), 0.3))
        b = fence_map(feeder_part(mirrored(verts), [-cm[0], cm[1]]), Fence.create(math.radians(-deg), 0.3))
        ma, mb = a.map.matrix(N), b.map.matrix(N)
        flip = (-np.arange(N) - 1) % N  # cell i covers [i, i+1]: its mirror is cell -i-1
        assert np.array_equal(ma, mb[np.ix_(flip, flip)])


def test_rotational_symmetry_of_the_square():
    """A square's map is unchanged by turning the part a quarter turn before and after:
    four bands a quarter turn apart."""
    m = fence_map(feeder_part(SQUARE), Fence.create(math.radians(50), 0.25)).map.matrix(N)
    q = N // 4
    assert np.array_equal(m, np.roll(np.roll(m, q, axis=0), q, axis=1))
    starts = sorted(s for b in fence_map(feeder_part(SQUARE), Fence.create(math.radians(50), 0.25)).map.bands
                    for s, _ in b.arcs)
    assert np.allclose(np.diff(starts), math.pi / 2)


@pytest.mark.parametrize("scale", [1e-6, 1e6])
def test_scale_invariance(scale):
    verts, cm = PENTAGON
    fence = Fence.create(math.radians(-45), 0.25)
    ref = fence_map(feeder_part(verts, cm), fence)
    got = fence_map(feeder_part(np.array(verts) * scale, np.array(cm) * scale), fence)
    assert got.final_edges == ref.final_edges
    for a, b in zip(got.map.bands + got.map.kernels, ref.map.bands + ref.map.kernels):
        assert np.allclose(np.array(a.arcs), np.array(b.arcs), atol=1e-9)


def test_every_orientation_reaches_a_band_and_intervals_widen_the_map():
    """Without jams every initial orientation has an outcome; a mu_c interval's map holds
    the maps of its ends (both senses wherever Mason's rule changes within it)."""
    part = feeder_part(*PENTAGON)
    lo = fence_map(part, Fence.create(math.radians(-55), 0.2)).map
    hi = fence_map(part, Fence.create(math.radians(-55), 0.35)).map
    both = fence_map(part, Fence.create(math.radians(-55), (0.2, 0.35))).map
    for m in (lo, hi, both):
        assert np.all(np.any(m.matrix(N), axis=0))
    assert np.all(both.matrix(N) >= lo.matrix(N)) and np.all(both.matrix(N) >= hi.matrix(N))


def test_bad_parts_and_fences_are_refused():
    with pytest.raises(InvalidInput, match="center_of_mass"):
        feeder_part(SQUARE, center_of_mass=[5, 0])
    with pytest.raises(InvalidInput, match="vertices"):
        feeder_part([[0, 0], [1, 1], [2, 2]])
    with pytest.raises(InvalidInput, match="fence_angle"):
        Fence.create(0.0, 0.2)
    with pytest.raises(InvalidInput, match="fence_angle"):
        Fence.create(math.pi / 2, 0.2)
    with pytest.raises(InvalidInput, match="mu_c"):
        Fence.create(0.5, (0.3, 0.2))
    with pytest.raises(InvalidInput, match="reach"):
        Fence.create(0.5, 0.2, reach=-1e-9)


def test_extreme_b_rises_with_mu_c_so_an_interval_takes_its_low_end_5_1():
    """More friction, less slip: B grows with mu_c on every edge (measured, not proved),
    which is why an interval's B, the least over samples including both ends, is the low
    end's."""
    part = feeder_part(*PENTAGON)
    for deg in (30.0, -50.0):
        for j in range(part.hull_size):
            bs = [endpoint_turn(part, j, Fence.create(math.radians(deg), mu)).least for mu in np.linspace(0.0, 0.5, 6)]
            assert np.all(np.diff(bs) > 0.0), (deg, j, bs)
            interval = endpoint_turn(part, j, Fence.create(math.radians(deg), (0.0, 0.5)))
            assert interval.least == pytest.approx(bs[0], abs=1e-12)


@pytest.mark.slow  # 7 s: the heaviest of the everyday tier
def test_reach_phase_6_1_8_6():
    """The orientations a fence's reach may not align (phase 6): none without a reach; fewer
    as the reach grows, nearly all for a reach of a tenth of the part; never empty for a
    point mu_c (near each unstable balance the part can slide without turning); the same
    orientations when part and reach scale together; mirrored with the part and fence."""
    verts, cm = PENTAGON
    part = feeder_part(verts, cm)
    a = part.circumradius
    assert fence_map(part, Fence.create(0.7, 0.25)).map.unaligned.is_empty
    # a reach of 0 (a part that may meet the fence at its end, as on a belt after a fence on
    # the same side) aligns nothing
    assert fence_map(part, Fence.create(0.7, 0.25, reach=0.0)).map.unaligned.measure == pytest.approx(TWO_PI)
    previous = None
    for reach in (0.1, 1.0, 3.0, 10.0, 100.0):
        got = fence_map(part, Fence.create(0.7, 0.25, reach=reach * a)).map.unaligned
        assert not got.is_empty
        if previous is not None:
            assert got.measure <= previous.measure
            assert all(previous.contains(s) and previous.contains(s + w) for s, w in got.arcs)
        previous = got
        if reach == 0.1:
            assert got.measure > math.radians(350)
    assert previous.measure < math.radians(5)
    for scale in (1e-6, 1e6):
        ref = fence_map(part, Fence.create(-0.9, 0.15, reach=2.0 * a)).map.unaligned
        big = fence_map(feeder_part(np.array(verts) * scale, np.array(cm) * scale),
                        Fence.create(-0.9, 0.15, reach=2.0 * a * scale)).map.unaligned
        assert np.allclose(np.array(big.arcs), np.array(ref.arcs), atol=1e-9)
    m1 = fence_map(part, Fence.create(0.6, 0.2, reach=2.0 * a)).map
    m2 = fence_map(feeder_part(mirrored(verts), [-cm[0], cm[1]]), Fence.create(-0.6, 0.2, reach=2.0 * a)).map
    c1, c2 = m1.unaligned.cells(N), m2.unaligned.cells(N)
    flip = (-np.arange(N) - 1) % N
    assert np.array_equal(c1, c2[flip])


def test_unaligned_orientations_allow_everything_and_pass_through_products_5_4():
    """An orientation the map does not bound allows every outcome: its column of the matrix
    is full, and a product marks every initial orientation that may reach it."""
    part = feeder_part(*PENTAGON)
    short = fence_map(part, Fence.create(0.7, 0.25, reach=1.0 * part.circumradius)).map
    full = fence_map(part, Fence.create(-0.9, 0.15)).map
    assert not short.unaligned.is_empty and full.unaligned.is_empty
    cols = short.unaligned.cells(N)
    assert short.matrix(N)[:, cols].all()
    theta = short.unaligned.arcs[0][0] + 0.5 * short.unaligned.arcs[0][1]
    assert all(short.allows(theta, f) for f in np.linspace(0, TWO_PI, 13))
    first_short = short.then(full)
    assert first_short.unaligned.contains(theta)
    second_short = full.then(short)
    reach_short = [k for k, b in enumerate(full.bands) if b.intersects(short.unaligned)]
    assert reach_short  # some band of the first fence meets the unaligned set
    for k in reach_short:
        s, w = full.kernels[k].arcs[0]
        assert second_short.unaligned.contains(s + 0.5 * w)
    assert not (matrix_product(short.matrix(N), full.matrix(N)) & ~second_short.matrix(N)).any()


@pytest.mark.slow  # 7 s a case: the heaviest of the everyday tier
@pytest.mark.parametrize(("verts", "cm", "gamma"), [
    ([[-1.8102071949042897, 0.5394001344053014], [-0.3889941148658179, -1.5262429273478046],
      [0.36675892323651266, -0.49389035386958713]], [-0.6108141288445317, -0.49357771560403013], -1.1404376484705965),
    ([[-0.719604865678823, 0.8833014990673552], [-0.7487467203847412, 0.6487407554890562],
      [-1.37310622596694, 0.8958965128334628]], [-0.9471526040101681, 0.8093129224632915], -0.7291720724061699),
])
def test_the_unaligned_set_does_not_depend_on_the_body_frame_phase_6(verts, cm, gamma):
    """Phase 6 over a mu_c interval for two random triangles (found by a review's search):
    turning the outline's own frame by phi turns the map by -phi, so the measure of the
    orientations a reach may not align stays the same. Each piece's turn before it was
    once recomputed from its start and width, leaving a span of rounding size before the
    last piece of a contact interval; its upper sum was 0/0, and the whole piece was marked
    unaligned in some frames and not others (41.3 deg against 32.0)."""
    ref = None
    for phi in (0.0, 0.3, 1.1, -2.0):
        v = np.array(verts) @ rotation(phi).T
        c = rotation(phi) @ np.array(cm)
        got = fence_map(feeder_part(v, c), Fence.create(gamma, (0.2, 0.4), reach=1e9)).map.unaligned.measure
        ref = got if ref is None else ref
        assert got == pytest.approx(ref, abs=1e-6)


def test_the_reach_profile_is_phase_6_for_every_reach_at_once_1_8_6():
    """One profile answers every reach: its unaligned set is the map's for that reach;
    needed(X, allowance) is the least reach leaving at most the allowance of X's cells
    unaligned (the next smaller need leaves more); near a balance the cells split toward it,
    so the unaligned set shrinks with the reach like e^(-reach / M) but never vanishes."""
    verts, cm = PENTAGON
    part = feeder_part(verts, cm)
    a = part.circumradius
    profile = reach_profile(part, Fence.create(0.7, 0.25))
    for reach in (0.5, 2.0, 5.0, 20.0):
        via_map = fence_map(part, Fence.create(0.7, 0.25, reach=reach * a)).map.unaligned
        assert profile.unaligned(reach * a) == via_map
    rng = np.random.default_rng(3)
    for _ in range(20):
        x = Arcs.of([(float(rng.uniform(0, TWO_PI)), float(rng.uniform(0.01, 1.0)))])
        allowance = float(rng.choice([0.0, 1e-9, 1e-3]))
        reach, dropped = profile.needed(x, allowance)
        hit = profile.meeting(x)
        over = hit & (profile.need > reach)
        assert profile.width[over].sum() <= dropped + 1e-15 <= allowance + 1e-15
        if math.isfinite(reach) and reach > 0.0:
            lower = profile.need[hit & (profile.need < reach)]
            below = lower.max() if lower.size else 0.0
            assert profile.width[hit & (profile.need > below)].sum() > allowance
    slivers = [profile.unaligned(r * a).measure for r in (5.0, 10.0, 20.0, 1e6)]
    assert all(s1 > s2 for s1, s2 in zip(slivers, slivers[1:])) and slivers[2] < 1e-6
    # the innermost cells (e^-40 of a last cell, below a double's resolution of the angle)
    # are points: the balances themselves, unaligned at any reach
    assert not profile.unaligned(1e6 * a).is_empty


@pytest.mark.slow  # 6 s: the heaviest of the everyday tier
def test_over_a_mu_c_interval_a_design_samples_the_reach_per_mu_c_1_8_6():
    """One profile over [0.1, 0.3] leaves unaligned every orientation whose balance some
    mu_c there puts there (tens of degrees at any reach); a part has one mu_c, so a design
    takes one profile per sample: each needs its own reach, the union of their slivers is
    tiny, and the allowance is shared so the union stays within it."""
    verts, cm = PENTAGON
    part = feeder_part(verts, cm)
    a = part.circumradius
    whole = reach_profile(part, Fence.create(0.7, (0.1, 0.3)))
    sampled = sampled_reach(part, Fence.create(0.7, (0.1, 0.3)))
    assert isinstance(sampled, SampledReach) and len(sampled.profiles) == 3
    assert whole.unaligned(20 * a).measure > math.radians(45)
    assert sampled.unaligned(20 * a).measure < 1e-6
    circle = Arcs.circle()
    allowance = math.radians(2.0)
    reach, dropped = sampled.needed(circle, allowance)
    assert reach == max(p.needed(circle, allowance / 3)[0] for p in sampled.profiles)
    assert sampled.unaligned(reach).measure <= dropped <= allowance
    one, ref = sampled_reach(part, Fence.create(0.7, 0.25)), reach_profile(part, Fence.create(0.7, 0.25))
    assert isinstance(one, ReachProfile) and np.array_equal(one.need, ref.need) and np.array_equal(one.lo, ref.lo)


def test_maps_in_lockstep_are_the_maps_one_at_a_time_5_1():
    """Issue 26: the maps of many fences integrated in lockstep (fence_maps: every edge's
    slip path (5.1, phase 5) steps together and their disk loci are solved at once) have
    the bands of each map alone, to rounding, on both sides of the belt and over a mu_c
    interval."""
    from models.feeder.fence import fence_maps
    from tests.feeder_cases import part

    p = part("pentagon")
    fences = [Fence.create(s * math.radians(d), mu) for s in (1.0, -1.0) for d in (22.0, 41.0, 63.0)
              for mu in ((0.25, 0.25), (0.1, 0.4))]
    together = fence_maps(p, fences)
    for fence, got in zip(fences, together):
        alone = fence_map(p, fence)
        assert got.final_edges == alone.final_edges
        for t, u in zip(got.turns, alone.turns):
            assert abs(t.least - u.least) <= 1e-12 and t.most == u.most
            assert (t.contact_lost, t.locus_evaluations, t.sense_flags) == (u.contact_lost, u.locus_evaluations,
                                                                               u.sense_flags)
        assert got.map.kernels == alone.map.kernels
