"""The COR sketch (book 4.1): the nine sketches of figure 4-6 reconstructed from 4.1.5-4.1.6,
each produced by a scene and confirmed by forward solves on random pressure
distributions (their modes must be ones the sketch allows, their CORs inside its loci);
the sticking locus against forward-solved sticking CORs; symmetries and limits."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.mpp import perp
from models.core.scene import PushScene
from models.core.support import random_balanced_tripods
from models.locus import cor_disk as cd
from models.sketch.disk_sketch import IMPLIED_MODES, clip_half_plane, disk_cor_sketch, force_scene, tip_line_estimate
from solver.motion.forward import BatchResult, solve_forward_batch
from tests.scenes import CONFIGS, SEED, SHORT, SKETCH_SCENES, distance_to_polyline, point_in_polygon


def scene_of(params) -> PushScene:
    x, y, edge, _ = params
    return PushScene.create(1.0, (x, y), math.radians(edge), 0.0)


def forward(scene, mu_c, n=1500, seed=SEED) -> BatchResult:
    pts, wts = random_balanced_tripods(np.random.default_rng(seed), n, 1.0)
    br = solve_forward_batch(scene, pts, wts, mu_c=mu_c)
    assert br.converged.all()
    return br


@pytest.mark.slow
@pytest.mark.parametrize("letter, mirrored, params", SKETCH_SCENES)
def test_each_of_the_nine_sketches_is_produced_and_confirmed(letter, mirrored, params):
    """4.1.6: the sketch's letter, its configurations, what it implies, and forward solves:
    every mode seen is allowed, and a mode the sketch forbids never occurs."""
    scene, mu_c = scene_of(params), params[3]
    sk = disk_cor_sketch(scene, mu_c)
    assert (sk.sketch, sk.mirrored) == (letter, mirrored)
    pair = (SHORT[sk.plus.configuration], SHORT[sk.minus.configuration])
    assert (pair[::-1] if mirrored else pair) == CONFIGS[letter]
    assert set(sk.allowed_modes) == set(IMPLIED_MODES[sk.implication])
    br = forward(scene, mu_c)
    seen = {BatchResult.MODES[m] for m in br.mode}
    assert seen <= set(sk.allowed_modes), (seen, sk.allowed_modes)


def _inside_any(points, polygons, slack):
    ok = np.zeros(len(points), dtype=bool)
    for poly in polygons:
        ok |= point_in_polygon(points, poly)
        ok |= distance_to_polyline(points, poly) <= slack
    return ok


@pytest.mark.parametrize("letter, mirrored, params", SKETCH_SCENES[::3])
def test_forward_cors_lie_in_their_loci(letter, mirrored, params):
    """4.1.3-4.1.4: a sticking COR lies on the sticking line within the sticking locus; a
    slipping COR inside the slipping locus of its direction (up to the boundary polygons'
    resolution)."""
    scene, mu_c = scene_of(params), params[3]
    sk = disk_cor_sketch(scene, mu_c, n_points=1024)
    br = forward(scene, mu_c, n=1000, seed=SEED + 1)
    c, jp = scene.contact_point, perp(scene.push_hat)
    finite = np.all(np.isfinite(br.cor), axis=1)
    stick = (br.mode == 1) & finite
    if stick.any():
        t = (br.cor[stick] - c) @ jp
        assert np.abs((br.cor[stick] - c) @ scene.push_hat).max() < 1e-8
        span = sk.sticking.t_high - sk.sticking.t_low
        slack = 1e-3 * max(1.0, span)
        assert t.min() >= sk.sticking.t_low - slack and t.max() <= sk.sticking.t_high + slack
    for code, polys in ((2, sk.up_slipping), (3, sk.down_slipping)):
        sel = (br.mode == code) & finite
        if sel.any():
            scale = max(1.0, float(np.max(np.abs(br.cor[sel]))))
            assert _inside_any(br.cor[sel], polys, 2e-3 * scale).all()


def test_sticking_locus_far_end_when_the_cone_holds_the_line_through_the_cm():
    """A contact almost in line with the CM along the push: the cone holds force lines
    through the CM, loci {COR}_phi near them are needles reaching ~100 a, and so does the
    sticking locus; forward-solved sticking CORs fall inside it."""
    scene = PushScene.create(1.0, (0.7732, -0.00773), 1.66288, 0.0)
    mu_c = 1.248
    sk = disk_cor_sketch(scene, mu_c)
    assert sk.sticking is not None and sk.sticking.t_low > 10.0
    br = forward(scene, mu_c, n=1000)
    st = br.mode == 1
    t = (br.cor[st] - scene.contact_point) @ perp(scene.push_hat)
    assert sk.sticking.t_low * (1 - 1e-3) <= t.min() and t.max() <= sk.sticking.t_high * (1 + 1e-3)


@pytest.mark.slow
def test_small_friction_collapses_onto_the_frictionless_locus():
    """mu_c -> 0: both elementary loci tend to {COR}_alpha and the sticking locus to the
    frictionless locus cut by the sticking line (4.1)."""
    scene = PushScene.create(1.0, (-0.3, -0.9), math.radians(120), 0.0)
    sk = disk_cor_sketch(scene, 1e-6)
    free = cd.disk_cor_locus(scene, n_points=1024).boundary
    for loc in (sk.plus, sk.minus):
        assert distance_to_polyline(loc.boundary, free).max() < 1e-4
    jp = perp(scene.push_hat)
    inside = point_in_polygon(scene.contact_point + np.linspace(-3, 3, 6001)[:, None] * jp, free)
    ts = np.linspace(-3, 3, 6001)[inside]
    if ts.size:
        assert sk.sticking is not None
        assert abs(sk.sticking.t_low - ts.min()) < 2e-3 and abs(sk.sticking.t_high - ts.max()) < 2e-3


def test_tip_line_approximates_the_far_end_from_inside():
    """4.1.4: each {COR}_phi dips slightly below the tip line, so the sticking locus reaches
    a little beyond the tip-line estimate; the error is reported and small."""
    scene = PushScene.create(1.0, (-0.3, -0.9), math.radians(120), 0.0)
    sk = disk_cor_sketch(scene, 0.5)
    t_tip = tip_line_estimate(scene)
    assert t_tip == sk.tip_line_t
    far = sk.sticking.t_high if abs(sk.sticking.t_high - t_tip) < abs(sk.sticking.t_low - t_tip) else sk.sticking.t_low
    assert abs(far) > abs(t_tip)
    assert 0.0 < sk.tip_line_error < 0.1 * abs(t_tip)


def test_mirror_image_swaps_up_and_down():
    """4.1.6: reflecting the scene across the line through the CM along the push mirrors
    the sketch: same letter, mirrored flag flipped, up and down exchanged, sticking
    positions negated."""
    base = PushScene.create(1.0, (-0.3, -0.9), math.radians(120), 0.0)
    mirror = PushScene.create(1.0, (-0.3, 0.9), math.radians(-120), 0.0)
    a, b = disk_cor_sketch(base, 0.5), disk_cor_sketch(mirror, 0.5)
    assert a.sketch == b.sketch and a.mirrored != b.mirrored
    swap = {"slipping_up": "slipping_down", "slipping_down": "slipping_up", "sticking": "sticking"}
    assert {swap[m] for m in a.allowed_modes} == set(b.allowed_modes)
    assert math.isclose(a.sticking.t_low, -b.sticking.t_high, rel_tol=1e-6)
    assert math.isclose(a.sticking.t_high, -b.sticking.t_low, rel_tol=1e-6)


@pytest.mark.parametrize("scale", [1e-6, 1e6])
def test_scale_invariance(scale):
    base = disk_cor_sketch(PushScene.create(1.0, (-0.3, -0.9), math.radians(120), 0.0), 0.5)
    big = disk_cor_sketch(PushScene.create(scale, (-0.3 * scale, -0.9 * scale), math.radians(120), 0.0), 0.5)
    assert (base.sketch, base.mirrored, base.allowed_modes) == (big.sketch, big.mirrored, big.allowed_modes)
    assert math.isclose(big.sticking.t_low, scale * base.sticking.t_low, rel_tol=1e-9)
    assert math.isclose(big.sticking.t_high, scale * base.sticking.t_high, rel_tol=1e-9)


def test_force_scene_turns_the_force_and_keeps_the_locus_independent_of_the_push():
    """{COR}_phi depends on the force line only (3.8): the turned scene's normal is n turned
    by phi, and its locus equals that of the same force line pushed along another direction."""
    scene = PushScene.create(1.0, (-0.3, -0.9), math.radians(120), 0.0)
    turned, sign = force_scene(scene, 0.3)
    expect = np.array([math.cos(0.3) * scene.normal[0] - math.sin(0.3) * scene.normal[1],
                       math.sin(0.3) * scene.normal[0] + math.cos(0.3) * scene.normal[1]])
    assert np.allclose(turned.normal, expect)
    other = PushScene.create(1.0, scene.contact_point, scene.edge_angle + 0.3,
                             math.atan2(expect[1], expect[0]) + 0.7)
    b1 = cd.disk_cor_locus(turned, n_points=256).boundary
    b2 = cd.disk_cor_locus(other, n_points=256).boundary
    assert np.allclose(b1, b2, atol=1e-12)


def test_invalid_friction_is_refused():
    scene = PushScene.create(1.0, (-0.3, -0.9), math.radians(120), 0.0)
    for bad in (0.0, -1.0, math.inf, math.nan):
        with pytest.raises(InvalidInput) as e:
            disk_cor_sketch(scene, bad)
        assert e.value.field == "mu_c"


@pytest.mark.slow
@pytest.mark.parametrize("letter, mirrored, params", SKETCH_SCENES[::2])
def test_extreme_cor_bounds_every_forward_solved_cor(letter, mirrored, params):
    """4.2: the slowest/fastest COR of a gross motion is the sketch's extreme in some
    direction; no forward-solved COR goes beyond it (up to the polygon resolution)."""
    from models.sketch.disk_sketch import extreme_cor

    scene, mu_c = scene_of(params), params[3]
    sk = disk_cor_sketch(scene, mu_c, n_points=1024)
    br = forward(scene, mu_c, n=600, seed=SEED + 2)
    cors = br.cor[np.all(np.isfinite(br.cor), axis=1)]
    for ang in np.linspace(0, 2 * math.pi, 8, endpoint=False):
        u = np.array([math.cos(ang), math.sin(ang)])
        ext = extreme_cor(sk, u)
        assert ext is not None
        scale = max(1.0, abs(ext.value))
        assert (cors @ u).max() <= ext.value + 2e-3 * scale


def test_extreme_cor_without_friction_is_the_tip():
    """mu_c -> 0: the COR farthest along -alpha' (the locus axis) is the tip (3.37)."""
    from models.sketch.disk_sketch import extreme_cor

    scene = PushScene.create(1.0, (-0.3, -0.9), math.radians(120), 0.0)
    sk = disk_cor_sketch(scene, 1e-9, n_points=2048)
    tip = cd.disk_cor_locus(scene, outputs=["tip"]).tip.point
    ext = extreme_cor(sk, tip - scene.center_of_mass)
    assert np.linalg.norm(ext.point - tip) < 1e-3


def test_the_sweep_solved_together_is_the_sweep_one_locus_at_a_time_4_1_4():
    """Issue 26: the sticking sweep (4.1.4) solves the loci of its coarse angles at once and
    runs its two golden searches in lockstep; each span is the span of that locus alone."""
    from models.sketch.disk_sketch import sticking_spans

    sc = PushScene.create(1.25, [-1.25 * math.sin(1.2217), 1.25 * math.cos(1.2217)], 1.2217, 0.0)
    phis = [float(p) for p in np.linspace(-0.46, 0.46, 37)]
    together = sticking_spans(sc, phis, 256)
    alone = [sticking_spans(sc, [p], 256)[0] for p in phis]
    assert together == alone and sum(s is not None for s in alone) > 5


def _clip_loop(poly, normal, offset):
    """Sutherland-Hodgman written as the loop the vectorised clip replaced (one edge at a time)."""
    out = []
    s = poly @ normal - offset
    for i in range(len(poly)):
        j = (i + 1) % len(poly)
        if s[i] > 0.0:
            out.append(poly[i])
        if (s[i] > 0.0) != (s[j] > 0.0):
            out.append(poly[i] + s[i] / (s[i] - s[j]) * (poly[j] - poly[i]))
    return np.array(out) if out else np.empty((0, 2))


def test_the_slipping_pieces_clip_is_the_edge_by_edge_loop():
    """The half-plane clip that cuts the slipping loci out of {COR}_{alpha +- nu} (4.1.3,
    figure 4-2): the same points in the same order as the edge-by-edge loop, bitwise, on
    seeded polygons and with vertices exactly on the line."""
    rng = np.random.default_rng(20261204)
    for _ in range(500):
        poly = rng.normal(size=(int(rng.integers(3, 40)), 2))
        normal, offset = rng.normal(size=2), float(rng.normal())
        assert np.array_equal(clip_half_plane(poly, normal, offset), _clip_loop(poly, normal, offset))
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    for offset in (0.0, 0.5, 1.0, 2.0):
        got = clip_half_plane(square, np.array([1.0, 0.0]), offset)
        assert np.array_equal(got, _clip_loop(square, np.array([1.0, 0.0]), offset))
    assert clip_half_plane(square, np.array([1.0, 0.0]), 2.0).shape == (0, 2)
