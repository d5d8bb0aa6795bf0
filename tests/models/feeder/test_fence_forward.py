"""The slip rates of phase 5 (extreme B, book 5.1) and phase 6 (the reach, 1.8.6) of
models/feeder/fence.py against an independent computation: forward minimum-power solves of
random supports in the disk."""

import math

import numpy as np

from models.core.mpp import perp
from models.core.scene import PushScene
from models.feeder.fence import Fence, contact_interval, crossing, face_slip_rate, feeder_part, max_slip_rate, rotation
from solver import solve_forward_batch
from solver.spiral.simulate import random_supports


def sampled_motions(rng: np.random.Generator, scene: PushScene, radius: float,
                    mu: float) -> tuple[np.ndarray, np.ndarray]:
    """(slip, omega) per unit push of 400 random tripod, rim and dipod supports each in the
    disk, the converged turning ones (at least 95 % of each kind)."""
    slips, omegas = [], []
    for kind in ("tripod", "rim", "dipod"):
        pts, wts = random_supports(rng, 400, radius, kind=kind)
        res = solve_forward_batch(scene, pts, wts, mu_c=mu)
        ok = res.converged & (np.abs(res.omega) > 0)
        assert ok.mean() > 0.95
        slips.append(res.slip[ok])
        omegas.append(res.omega[ok])
    return np.concatenate(slips), np.concatenate(omegas)


def test_no_support_slips_faster_than_extreme_b_5_1():
    """dl/ddelta = -slip/omega of every forward solve stays below the disk bound's largest
    value (4.1: it lies on the locus of the cone edge n_e + mu_c e), and dipod supports,
    the extremes of the locus (3.3.8), come close to it."""
    part = feeder_part([[-1, -1], [1, -1], [1, 1], [-1, 1]])
    rng = np.random.default_rng(51)
    mu = 0.25
    for deg, delta_deg, frac in ((45, 10, 0.3), (60, 5, 0.6), (30, 20, 0.1)):
        g = math.radians(deg)
        fence = Fence.create(g, mu)
        j = 0
        u_c, h_c = part.cm_over_hull_edge(j)
        length = part.hull_edge(j)[1]
        ell = crossing(part, j, mu, fence.sign)
        ell += frac * (length - ell)
        delta = math.radians(delta_deg)
        t0 = np.array([math.cos(g), math.sin(g)])
        c = rotation(delta) @ ((ell - u_c) * t0 - h_c * perp(t0))
        bound, ccw = max_slip_rate(part.circumradius, c, g + delta, mu, 2048)
        assert ccw and bound > 0.0
        scene = PushScene.create(part.circumradius, c, g + delta, math.pi / 2)
        slip, omega = sampled_motions(rng, scene, part.circumradius, mu)
        rates = -slip / omega
        assert np.all(rates <= bound * (1 + 1e-6) + 1e-9)
        assert rates.max() >= 0.999 * bound  # measured: within 1e-5


def test_no_support_slips_toward_the_end_faster_than_the_reach_bound_1_8_6():
    """Phase 6 (book 1.8.6, ch. 4): while a vertex turns on the fence's face, the part's slip
    toward the fence's end per radian of turn, -sgn(gamma) slip / |omega| of every forward
    solve, stays below face_slip_rate, and dipods come close to it."""
    part = feeder_part([[0, 0], [3, 0], [3.5, 1.5], [1.5, 2.5], [-0.5, 1.2]], [1.4, 1.0])
    rng = np.random.default_rng(186)
    mu = 0.25
    checked = 0
    for deg, k, frac in ((40, 1, 0.6), (-52, 3, 0.3), (40, 0, 0.35), (-52, 4, 0.8)):
        fence = Fence.create(math.radians(deg), mu)
        start, width = contact_interval(part, k, fence.angle)
        theta = start + frac * width
        c = rotation(theta) @ part.hull[k]
        bound = face_slip_rate(part.circumradius, c, fence, mu, 2048)
        assert math.isfinite(bound)
        scene = PushScene.create(part.circumradius, c, fence.angle, math.pi / 2)
        slip, omega = sampled_motions(rng, scene, part.circumradius, mu)
        rates = -fence.sign * slip / np.abs(omega)
        assert np.all(rates <= bound * (1 + 1e-6) + 1e-9)
        if bound > 0.0:
            assert rates.max() >= 0.99 * bound
            checked += 1
    assert checked >= 2  # the bound is reached, not only respected
