"""Whole pushes simulated with the forward solver (solver/push/simulate.py) against the
gross-motion closed forms of models/push/gross_motion.py (book 3.4, 4.3, 4.4).

Supports: seeded random tripods in the disk (book 3.3.3, models.core.support), tripods on its
rim, and a fan of 64 diametral dipods (two half weights at opposite ends of a diameter,
the supports of the outer boundary, figure 3-12): they reach the edges of the COR loci,
and as the part turns by exactly dbeta while it sticks, a dipod keeps its angle to the
contact over a whole sticking stretch. Findings pinned here:

* mu_c = 0: no simulation exceeds (3.41) nor falls below the r_min push (an exact
  locus extreme), and the disk only translates: x = a ln cot(beta_i/2), xi = 0.
* mu_c > 0: the book's bounds use the tip line for the lower end of the sticking locus
  (4.1.4, 4.3.2, 4.4.1.1) and call the dip below it negligible. Rim tripods do land below
  the tip line, by up to about 3 % in dx/dbeta: dipods exceed the book's composite fence
  bound (mu_c = 1) by 1 % and (4.16) (mu_c = 5) by 1.3 and 2.6 %. Every such motion stays
  inside the exact
  sketch computed here by brute force from models.locus.cor_disk boundaries (the union over
  the friction cone of {COR}_phi on the sticking line, plus the slipping loci).
* The rotation of the disk stays within 0 <= xi <= pi/2 - beta_i (4.18), and its rate is
  -a cos beta / x_COR, not the printed (4.22).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.scene import PushScene
from models.core.support import random_balanced_tripods
from models.locus.cor_disk import disk_cor_locus
from models.push import gross_motion as gm
from solver.push import simulate as ps
from tests.scenes import SEED

D = math.radians
A = 1.0
EX_ALPHA, EX_MU = D(70.0), 0.25
T_694 = math.tan(D(69.4))
# The 4.3 example's c (see tests/models/push/test_gross_motion.py): reproduces 69.4 degrees.
EX_C = A * math.sqrt((1.0 + T_694**2) / (T_694 * math.tan(EX_ALPHA + math.atan(EX_MU)) - 1.0))


def rim_tripods(rng: np.random.Generator, n: int, a: float = A):
    """Balanced tripods with all three points on the rim of the disk (weights >= 0)."""
    pts, wts = [], []
    while len(pts) < n:
        th = rng.uniform(0.0, 2.0 * math.pi, 3)
        w = a * np.column_stack([np.cos(th), np.sin(th)])
        try:
            p = np.linalg.solve(np.vstack([np.ones(3), w.T]), [1.0, 0.0, 0.0])
        except np.linalg.LinAlgError:
            continue
        if np.all(p >= 0.0):
            pts.append(w)
            wts.append(p)
    return np.array(pts), np.array(wts)


@pytest.fixture(scope="module")
def supports():
    rng = np.random.default_rng(SEED)
    p_in, w_in = random_balanced_tripods(rng, 100, A)
    p_rim, w_rim = rim_tripods(rng, 100)
    return np.concatenate([p_in, p_rim]), np.concatenate([w_in, w_rim])


@pytest.fixture(scope="module")
def dipods():
    om = np.linspace(0.0, math.pi, 64, endpoint=False)
    u = A * np.column_stack([np.cos(om), np.sin(om)])
    return np.stack([u, -u], axis=1), np.full((64, 2), 0.5)


@pytest.fixture(scope="module")
def small_supports(supports):
    pts, wts = supports
    return np.concatenate([pts[:50], pts[100:150]]), np.concatenate([wts[:50], wts[100:150]])


# --- brute-force exact COR sketch (independent of models/push/gross_motion.py) ----------------


def _crossings(ring: np.ndarray, x0: float) -> np.ndarray:
    p, q = ring, np.roll(ring, -1, axis=0)
    m = ((p[:, 0] - x0) * (q[:, 0] - x0) <= 0.0) & (p[:, 0] != q[:, 0])
    t = (x0 - p[m, 0]) / (q[m, 0] - p[m, 0])
    return p[m, 1] + t * (q[m, 1] - p[m, 1])


def sketch_extremes(beta, a, c, alpha, mu_c, n_phi=121, n_points=3000, r_max=30.0):
    """Points of the COR sketch (4.1) where linear or linear-fractional functions of the
    COR take their extremes, from cor_disk boundaries: the sticking locus's lowest and
    highest points (every {COR}_phi, phi in [alpha - nu, alpha + nu], met with the sticking
    line), the boundary of {COR}_(alpha+nu) left of the sticking line and of
    {COR}_(alpha-nu) right of it. For the lowest crossing, loci with tips beyond r_max a
    (next to wrapping) are skipped: their lower crossings lie near the tip line, where
    finer loci already are; they do give the highest crossings.

    The lowest crossing has a sharp minimum in phi (where the tip passes the sticking
    line), so the best sample is refined by golden-section search."""
    nu = math.atan(mu_c)
    cv = gm.fence_contact(beta, c)
    x0 = cv[0]
    lo_phi = max(alpha - nu, math.acos(-min(1.0, a / (r_max * c))) - beta)  # k > a / r_max

    def ring(phi):
        return disk_cor_locus(PushScene.create(a, cv, phi, 0.0), outputs=("boundary",), n_points=n_points).boundary

    def lowest(phi):
        y = _crossings(ring(phi), x0)
        return y.min() if y.size else np.inf

    phis = np.linspace(lo_phi, alpha + nu, n_phi)
    rings = [ring(phi) for phi in phis]
    ys = [_crossings(r, x0) for r in rings]
    lows = np.array([y.min() if y.size else np.inf for y in ys])
    j = int(np.argmin(lows))
    lo, hi = phis[max(j - 1, 0)], phis[min(j + 1, n_phi - 1)]
    g = 0.5 * (math.sqrt(5.0) - 1.0)
    p1, p2 = hi - g * (hi - lo), lo + g * (hi - lo)
    f1, f2 = lowest(p1), lowest(p2)
    for _ in range(40):
        if f1 < f2:
            hi, p2, f2 = p2, p1, f1
            p1 = hi - g * (hi - lo)
            f1 = lowest(p1)
        else:
            lo, p1, f1 = p1, p2, f2
            p2 = lo + g * (hi - lo)
            f2 = lowest(p2)
    y_low = min(lows.min(), f1, f2)
    # The highest crossing comes from loci next to wrapping (huge tips): sample them too,
    # geometrically in k = phi_hat . c down to a / 3000.
    near = [math.acos(-kk / c) - beta for kk in a * np.geomspace(1.0 / r_max, 1.0 / 3000.0, 16)]
    ys += [_crossings(ring(phi), x0) for phi in near if alpha - nu <= phi <= alpha + nu]
    y_high = max(y.max() for y in ys if y.size)
    pts = [rings[-1][rings[-1][:, 0] <= x0]]  # {COR}_(alpha+nu), down-slipping
    if phis[0] == alpha - nu:
        pts.append(rings[0][rings[0][:, 0] >= x0])  # {COR}_(alpha-nu), up-slipping
    pts.append(np.array([[x0, y_low], [x0, y_high]]))
    return np.vstack(pts)


# --- fence alignment (3.4, 4.3) ---------------------------------------------------------

FENCES = [  # alpha, c, beta_i, beta_f
    (EX_ALPHA, EX_C, D(45), D(80)),  # the 4.3 example
    (D(90), 1.0, D(10), D(45)),  # a square's corner on a perpendicular fence
    (D(60), 0.9, D(40), D(85)),
]


@pytest.mark.parametrize("alpha,c,bi,bf", FENCES)
def test_fence_frictionless_never_beats_3_41_nor_the_r_min_push(supports, alpha, c, bi, bf):
    pts, wts = supports
    sim = ps.simulate_fence_alignment_batch(pts, wts, A, c, alpha, bi, bf, 0.0, n_steps=48)
    assert sim.converged
    upper = gm.fence_push_frictionless(A, c, alpha, bi, bf)
    lower = gm.fence_push_least_frictionless(A, c, alpha, bi, bf)
    assert np.all(sim.push <= upper) and np.all(sim.push >= lower)
    # Pointwise too: every COR is between r_min and the tip of the locus.
    slow = gm.fence_rate_frictionless(sim.beta_nodes, A, c, alpha)[:, None]
    fast = gm.fence_rate_least_frictionless(sim.beta_nodes, A, c, alpha)[:, None]
    assert np.all(sim.rate <= slow * (1 + 1e-9)) and np.all(sim.rate >= fast * (1 - 1e-9))
    assert sim.push.max() > 0.9 * upper  # not vacuous: the rim tripods come close


def test_fence_rate_is_equation_4_2_of_the_forward_cor(small_supports):
    pts, wts = small_supports
    sim = ps.simulate_fence_alignment_batch(pts, wts, A, EX_C, EX_ALPHA, D(45), D(80), EX_MU, n_steps=8)
    for j, b in enumerate(sim.beta_nodes):
        assert np.allclose(sim.rate[j], gm.fence_rate(b, EX_C, EX_ALPHA, sim.cor[j]), rtol=1e-9)


@pytest.mark.slow
def test_fence_book_example_with_friction(supports):
    """The 4.3 example (alpha = 70 deg, mu_c = 0.25): every support within the composite
    bound (4.8) + corrected (4.6), which is below the frictionless (3.41)."""
    pts, wts = supports
    sim = ps.simulate_fence_alignment_batch(pts, wts, A, EX_C, EX_ALPHA, D(45), D(80), EX_MU, n_steps=48)
    bound = gm.fence_push_bound(A, EX_C, EX_ALPHA, D(45), D(80), EX_MU).total
    assert sim.converged and np.all(sim.push <= bound)
    assert sim.push.max() > 0.95 * bound
    assert bound < gm.fence_push_frictionless(A, EX_C, EX_ALPHA, D(45), D(80))


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["tripods", "dipods"])
def test_fence_with_large_friction_exceeds_the_book_bound_inside_the_exact_sketch(supports, dipods, kind):
    """alpha = 60 deg, c = 0.9 a, mu_c = 1: supports stick with CORs below B, the
    tip-line approximation of the sticking locus's lower end, and need more push than the
    book's bound (dipods 1.8766, tripods 1.8615, bound 1.8569); every rate stays below the
    brute-force slowest COR of the sketch."""
    pts, wts = supports if kind == "tripods" else dipods
    alpha, c, bi, bf, mu = D(60), 0.9, D(40), D(85), 1.0
    sim = ps.simulate_fence_alignment_batch(pts, wts, A, c, alpha, bi, bf, mu, n_steps=32)
    book = gm.fence_push_bound(A, c, alpha, bi, bf, mu).total
    assert sim.converged
    assert sim.push.max() > (1.01 if kind == "dipods" else 1.002) * book
    book_rate = gm.fence_slowest(sim.beta_nodes, A, c, alpha, mu)[2]
    over = sim.rate > book_rate[:, None]
    b_y = gm.fence_sticking_cor(sim.beta_nodes, A, c)[:, 1]
    # Every excess is a sticking COR below B (the dip the book neglects).
    assert np.all(sim.mode[over] == 1)
    assert np.all(sim.cor[over][:, 1] < np.broadcast_to(b_y[:, None], over.shape)[over])
    assert np.max(sim.rate / book_rate[:, None]) < 1.03
    alpha_hat = np.array([math.cos(alpha), math.sin(alpha)])
    for j in (0, 12, 24):
        b = sim.beta_nodes[j]
        ext = sketch_extremes(b, A, c, alpha, mu)
        exact = np.max((gm.fence_contact(b, c) - ext) @ alpha_hat) / math.sin(alpha)
        assert sim.rate[j].max() <= exact * (1 + 5e-4)  # 5e-4: the brute force's sampling
        assert exact > book_rate[j]


@pytest.mark.slow
def test_fence_batch_agrees_with_pose_stepping_which_converges(supports):
    """One support that changes mode on the way, pushed by the 4.3 example's fence:
    the pose-stepping simulation (x steps of 2e-3 a and 4e-3 a) against the beta-stepped
    batch (256 Simpson steps)."""
    pts, wts = supports
    ref = ps.simulate_fence_alignment_batch(pts[:16], wts[:16], A, EX_C, EX_ALPHA, D(45), D(80), EX_MU, n_steps=256)
    switching = [j for j in range(16) if np.unique(ref.mode[:, j]).size >= 2]
    i = max(switching, key=lambda j: ref.push[j])  # the longest push that changes mode
    ref = ps.simulate_fence_alignment_batch(pts[i:i + 1], wts[i:i + 1], A, EX_C, EX_ALPHA, D(45), D(80), EX_MU, n_steps=256)
    coarse = ps.simulate_fence_alignment(pts[i], wts[i], A, EX_C, EX_ALPHA, D(45), D(80), EX_MU, step=4e-3)
    fine = ps.simulate_fence_alignment(pts[i], wts[i], A, EX_C, EX_ALPHA, D(45), D(80), EX_MU, step=2e-3)
    assert len(fine.modes) >= 2 and fine.not_optimal == 0
    assert fine.steps >= 400  # steps of about 1e-3 of the push
    assert abs(fine.push - ref.push[0]) < 1e-6 * ref.push[0]
    assert abs(coarse.push - ref.push[0]) < 2e-6 * ref.push[0]
    assert fine.rotation == pytest.approx(D(35), rel=1e-14)


# --- a disk pushed aside by a point (4.4) -----------------------------------------------


@pytest.mark.parametrize("bi", [D(20), D(60)])
def test_disk_frictionless_translates_along_the_normal(small_supports, bi):
    pts, wts = small_supports
    sim = ps.simulate_disk_encounter_batch(pts, wts, A, bi, 0.0, n_steps=48)
    assert sim.converged
    assert np.allclose(sim.push, gm.encounter_length_frictionless(bi, A), rtol=1e-6)
    assert np.allclose(sim.rotation, 0.0, atol=1e-12)


@pytest.fixture(scope="module")
def disk_runs(small_supports):
    pts, wts = small_supports
    return {(bi, mu): ps.simulate_disk_encounter_batch(pts, wts, A, D(bi), mu, n_steps=24)
            for bi in (20, 60) for mu in (0.25, 1.0, 5.0)}


@pytest.mark.slow
@pytest.mark.parametrize("bi", [20, 60])
@pytest.mark.parametrize("mu", [0.25, 1.0, 5.0])
def test_disk_rotation_within_4_18_and_rates_match_4_12(disk_runs, bi, mu):
    sim = disk_runs[(bi, mu)]
    assert sim.converged
    assert np.all(sim.rotation >= 0.0)
    assert np.all(sim.rotation <= gm.rotation_max(D(bi)) + 1e-12)
    # The batch's rates come from the CM velocity and a sin beta = y_pusher - y_CM; (4.12)
    # and the re-derived rotation rate from the forward COR must agree with them.
    b = np.broadcast_to(sim.beta_nodes[:, None], sim.rate.shape)
    x, y = sim.cor[..., 0], sim.cor[..., 1]
    assert np.allclose(sim.rate, gm.encounter_rate(b, x, y, A), rtol=1e-8)
    assert np.allclose(sim.rotation_rate, gm.rotation_rate(b, x, y, A), rtol=1e-8, atol=1e-12)
    # The printed (4.22) holds on the sticking line only.
    printed = gm.rotation_rate_book_printed(b, x, y, A)
    stick = sim.mode == 1
    assert np.allclose(printed[stick], 1.0, rtol=1e-8)
    slip = (sim.mode == 3) & (np.abs(sim.rotation_rate - printed) > 1e-3)
    assert slip.sum() >= 0.5 * (sim.mode == 3).sum()
    # Pointwise: never faster than the sticking-line roll.
    assert np.all(sim.rotation_rate <= 1.0 + 1e-9)


@pytest.mark.parametrize("bi", [20, 60])
def test_disk_length_within_4_16_for_moderate_friction(disk_runs, bi):
    for mu in (0.25, 1.0):
        sim = disk_runs[(bi, mu)]
        assert np.all(sim.push <= gm.encounter_length_max(D(bi), A))


@pytest.mark.slow
@pytest.mark.parametrize("bi", [20, 60])
def test_disk_with_large_friction_exceeds_4_16_inside_the_exact_sketch(dipods, bi):
    """mu_c = 5: sticking CORs below the tip line make dx/dbeta exceed 2a/sin beta by up
    to ~3 % and the dipods' encounters exceed (4.16) by 1.3 % (20 deg) and 2.6 % (60 deg);
    the brute-force sketch's extremes (the lowest and highest points of the sticking locus,
    the down-slipping locus) bound every rate from both sides, and its leftmost point
    bounds the rotation rate from below."""
    sim = ps.simulate_disk_encounter_batch(*dipods, A, D(bi), 5.0, n_steps=24)
    bound = gm.encounter_length_max(D(bi), A)
    assert sim.converged
    assert sim.push.max() > 1.01 * bound
    assert np.all(sim.rotation <= gm.rotation_max(D(bi)) + 1e-12) and np.all(sim.rotation >= 0.0)
    ratio = sim.rate / gm.encounter_rate_max(sim.beta_nodes, A)[:, None]
    assert ratio.max() < 1.04
    for j in (0, 8, 16):
        b = sim.beta_nodes[j]
        ext = sketch_extremes(b, A, A, math.pi / 2 - b, 5.0)
        ext = ext[ext[:, 0] < 0]
        rates = gm.encounter_rate(b, ext[:, 0], ext[:, 1], A)
        assert sim.rate[j].max() <= rates.max() * (1 + 5e-4)
        assert sim.rate[j].min() >= rates.min() * (1 - 5e-4)
        assert sim.rotation_rate[j].min() >= gm.rotation_rate(b, ext[:, 0].min(), 0.0, A) * (1 - 5e-4)


@pytest.mark.slow
def test_disk_batch_agrees_with_pose_stepping_which_converges(supports):
    """One support (sticks, then slips down) pushed aside from beta_i = 30 deg with
    mu_c = 0.25: pose stepping with x steps of 4e-3 a and 2e-3 a against the
    beta-stepped RK4 batch (256 graded steps)."""
    pts, wts = supports
    i = 1
    ref = ps.simulate_disk_encounter_batch(pts[i:i + 1], wts[i:i + 1], A, D(30), 0.25, n_steps=256)
    runs = [ps.simulate_disk_encounter(pts[i], wts[i], A, D(30), 0.25, step=s) for s in (4e-3, 2e-3)]
    assert {"sticking", "slipping_down"} <= set(runs[1].modes) and runs[1].not_optimal == 0
    err_x = [abs(r.push - ref.push[0]) for r in runs]
    err_r = [abs(r.rotation - ref.rotation[0]) for r in runs]
    assert err_x[1] < 2e-5 and err_r[1] < 2e-5
    assert runs[1].push == pytest.approx(runs[0].push, abs=2e-5)
    assert runs[1].rotation == pytest.approx(runs[0].rotation, abs=2e-5)
