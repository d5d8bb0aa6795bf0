"""Certified COR sketches (book 4.1 on the exact loci, 3.3.13, 7.5): solver/sketch/certified_sketch.py.

Checks: every piece lies inside the circumscribing disk's sketch (7.5: the disk's loci
contain the polygon's); forward solves of random supports on the polygon only take modes
the polygon's sketch allows and stick inside its exact sticking segment; the polygon's own
sketch can be sharper than the disk's (a scene where the disk allows slipping and the
rectangle must stick, confirmed by forward solves); a many-sided polygon approaches the
disk; the time limit reports where it got to."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.footprint import Footprint
from models.core.scene import PushScene
from models.core.support import random_balanced_tripods
from models.sketch.disk_sketch import disk_cor_sketch
from solver.core.budget import Budget
from solver.motion.forward import BatchResult, solve_forward_batch
from solver.sketch.certified_sketch import certified_sketch
from tests.scenes import SEED, distance_to_polyline, point_in_polygon

RECT = Footprint.create([[-1.5, -0.4], [1.5, -0.4], [1.5, 0.4], [-1.5, 0.4]])
N_RAYS = 16

# The rectangle pushed on its short left side, below the CM's line, the push turned 26.6
# deg down: its circumscribing disk (a = 1.55) allows sticking or slipping up (a
# mirrored sketch i), the rectangle itself must stick (sketch g).
MUST_STICK = dict(contact=np.array([-1.5, 0.18766172]), edge=0.5 * math.pi, push=-0.4635935760943159, mu_c=0.3)
# A push on the long lower side: sketch b for the disk and the rectangle alike.
ON_LONG_SIDE = dict(contact=np.array([-0.6, -0.4]), edge=0.3, push=0.5 * math.pi, mu_c=0.5)


def _scene(case) -> PushScene:
    return PushScene.create(RECT.circumradius, case["contact"], case["edge"], case["push"], RECT.center_of_mass)


@pytest.fixture(scope="module", params=["must_stick", "long_side"])
def sketched(request):
    case = MUST_STICK if request.param == "must_stick" else ON_LONG_SIDE
    sc = _scene(case)
    return case, sc, certified_sketch(sc, case["mu_c"], RECT, n_rays=N_RAYS), disk_cor_sketch(sc, case["mu_c"], n_points=1024)


@pytest.mark.slow
def test_every_piece_is_certified_and_inside_the_circumscribing_disks_sketch(sketched):
    """7.5: every pressure distribution on the rectangle is one on its circumscribing disk,
    so the rectangle's sticking segment lies within the disk's and each traced locus
    boundary point lies inside (or on, to the bracket) the disk's locus for that force."""
    case, sc, ps, disk = sketched
    assert ps.complete and not ps.time_limited and ps.message == "every piece certified"
    st, ds = ps.sketch.sticking, disk.sticking
    width = ps.sticking.lower.width + ps.sticking.upper.width
    assert ds.t_low - width <= st.t_low < st.t_high <= ds.t_high + width
    assert ps.sticking.lower.certified and ps.sticking.upper.certified
    for loc, dloc, trace in ((ps.sketch.plus, disk.plus, ps.plus_trace), (ps.sketch.minus, disk.minus, ps.minus_trace)):
        if trace is None:
            assert loc.configuration == "wrapped" and loc.boundary is None
            continue
        assert trace.n_certified == N_RAYS
        pts = loc.boundary
        inside = point_in_polygon(pts, dloc.boundary) | (distance_to_polyline(pts, dloc.boundary) <= 2e-3 * RECT.circumradius)
        assert inside.all()
        assert loc.configuration != "wrapped"
        assert np.linalg.norm(loc.tip - sc.center_of_mass) == pytest.approx(
            np.max(np.linalg.norm(pts - sc.center_of_mass, axis=1)))


@pytest.mark.slow
def test_forward_solves_on_the_rectangle_obey_its_sketch(sketched):
    """Random tripods on the rectangle (3.3.3, seeded): the mode each forward solve reports
    is one the polygon's sketch allows, and a sticking COR lies on the sticking line inside
    the exact segment (to its bracket)."""
    case, sc, ps, _ = sketched
    rng = np.random.default_rng(SEED + 41)
    pts, wts = random_balanced_tripods(rng, 400, RECT.circumradius, footprint=RECT)
    res = solve_forward_batch(sc, pts, wts, mu_c=case["mu_c"])
    assert res.converged.all()
    modes = {BatchResult.MODES[m] for m in res.mode}
    assert modes <= set(ps.sketch.allowed_modes)
    stick = res.mode == BatchResult.MODES.index("sticking")
    if not stick.any():  # the long-side push: these tripods all slip up (sketch d allows both)
        assert modes == {"slipping_up"}
        return
    jp = np.array([-math.sin(case["push"]), math.cos(case["push"])])
    t = (res.cor[stick] - case["contact"]) @ jp
    st = ps.sketch.sticking
    tol = ps.sticking.lower.width + ps.sticking.upper.width + 1e-9
    assert t.min() >= st.t_low - tol and t.max() <= st.t_high + tol


@pytest.mark.slow
def test_the_rectangle_must_stick_where_its_disk_would_let_it_slip():
    """The polygon's own sketch is sharper than the circumscribing disk's: the disk's
    sketch (mirrored i) allows slipping up, the rectangle's (g) only sticking, and 400
    random tripods on the rectangle all stick."""
    sc = _scene(MUST_STICK)
    disk = disk_cor_sketch(sc, MUST_STICK["mu_c"], n_points=1024)
    ps = certified_sketch(sc, MUST_STICK["mu_c"], RECT, n_rays=N_RAYS)
    assert disk.sketch == "i" and "slipping_up" in disk.allowed_modes
    assert ps.sketch.sketch == "g" and ps.sketch.allowed_modes == ("sticking",)
    assert ps.sketch.implication == "must_stick"
    rng = np.random.default_rng(SEED + 42)
    pts, wts = random_balanced_tripods(rng, 400, RECT.circumradius, footprint=RECT)
    res = solve_forward_batch(sc, pts, wts, mu_c=MUST_STICK["mu_c"])
    assert (res.mode == BatchResult.MODES.index("sticking")).all()


@pytest.mark.slow
def test_a_many_sided_polygon_approaches_the_disk():
    """A regular 48-gon inscribed in the unit circle, pushed as the disk scene of figure
    4-12 (4.4): the same letter as the disk, and sticking ends within a few chord heights
    (1 - cos(pi/48) = 2.1e-3) of the disk's."""
    n = 48
    ang = 2.0 * math.pi * np.arange(n) / n
    poly = Footprint.create(np.stack([np.cos(ang), np.sin(ang)], axis=1))
    beta = 0.9
    c = np.array([-math.cos(beta), math.sin(beta)]) * math.cos(math.pi / n)
    sc = PushScene.create(poly.circumradius, c, 0.5 * math.pi - beta, 0.0, poly.center_of_mass)
    ps = certified_sketch(sc, 0.5, poly, n_rays=12)
    disk = disk_cor_sketch(sc, 0.5, n_points=1024)
    assert ps.complete
    assert ps.sketch.sketch == disk.sketch
    assert ps.sketch.sticking.t_low == pytest.approx(disk.sticking.t_low, abs=0.05)
    assert ps.sketch.sticking.t_high == pytest.approx(disk.sticking.t_high, abs=0.05)
    assert disk.sticking.t_low <= ps.sketch.sticking.t_low + 1e-6


def test_a_time_limit_says_where_it_stopped():
    sc = _scene(ON_LONG_SIDE)
    ps = certified_sketch(sc, ON_LONG_SIDE["mu_c"], RECT, n_rays=N_RAYS, budget=Budget.of(1e-6))
    assert ps.time_limited and not ps.complete
    assert "sticking locus" in ps.message or "rays traced in time" in ps.message


def test_a_push_through_the_cm_inside_the_cone_has_no_loci():
    """Mason's rule with the cone gives no sense (1.6.2): the part translates; nothing is
    traced."""
    sc = PushScene.create(RECT.circumradius, np.array([-1.5, 0.0]), 0.5 * math.pi, 0.0, RECT.center_of_mass)
    ps = certified_sketch(sc, 0.3, RECT, n_rays=N_RAYS)
    assert ps.sketch.sense == "none" and ps.plus_trace is None and ps.minus_trace is None
    assert ps.sketch.sticking is None and ps.sticking is None


@pytest.mark.slow
def test_a_disk_sketch_with_exact_sticking_ends_agrees_with_the_sweep():
    """No footprint: the analytic disk loci and the exact sticking ends; the loci, letter
    and modes are those of models.sketch.disk_sketch, and the ends agree with the book's sweep
    (4.1.4) to 1e-4 a."""
    sc = PushScene.create(1.0, np.array([-math.cos(0.6), math.sin(0.6)]), 0.5 * math.pi - 0.6, 0.0)
    cs = certified_sketch(sc, 0.25)
    sweep = disk_cor_sketch(sc, 0.25)
    assert cs.complete and cs.footprint is None and cs.plus_trace is None
    assert cs.sketch.sketch == sweep.sketch and cs.sketch.allowed_modes == sweep.allowed_modes
    assert np.array_equal(cs.sketch.plus.boundary, sweep.plus.boundary)
    assert cs.sketch.sticking.t_low == pytest.approx(sweep.sticking.t_low, abs=1e-4)
    assert cs.sketch.sticking.t_high == pytest.approx(sweep.sticking.t_high, abs=1e-4)
    assert cs.sketch.sticking.phi_low is None and sweep.sticking.phi_low is not None


@pytest.mark.slow
def test_the_letter_does_not_depend_on_the_number_of_rays():
    """Whether a traced locus crosses the sticking line decides its configuration (4.1.5):
    with only 8 uniform rays the chord polygon of {COR}_(alpha-nu) misses the line, and
    the rays added next to the point nearest to it find the crossing: sketch b, as with 32."""
    sc = _scene(ON_LONG_SIDE)
    coarse = certified_sketch(sc, ON_LONG_SIDE["mu_c"], RECT, n_rays=8)
    assert coarse.complete
    assert coarse.sketch.sketch == "b"
    assert (coarse.sketch.plus.configuration, coarse.sketch.minus.configuration) == ("pure_slipping", "same_sided_split")
    assert len(coarse.sketch.minus.boundary) > 8  # refined
