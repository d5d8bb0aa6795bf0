"""The extreme-B slip rate of phase 5 (models/feeder/fence.py, book 5.1) against an
independent computation: forward minimum-power solves of random supports in the disk."""

import math

import numpy as np

from models.feeder.fence import Fence, Part, crossing, max_slip_rate, rotation
from models.mpp import perp
from models.scene import PushScene
from solver import solve_forward_batch
from solver.sim.spiral import random_supports


def test_no_support_slips_faster_than_extreme_b_5_1():
    """dl/ddelta = -slip/omega of every forward solve stays below the disk bound's largest
    value (4.1: it lies on the locus of the cone edge n_e + mu_c e), and dipod supports,
    the extremes of the locus (3.3.8), come close to it."""
    part = Part.create([[-1, -1], [1, -1], [1, 1], [-1, 1]])
    rng = np.random.default_rng(51)
    mu = 0.25
    for deg, delta_deg, frac in ((45, 10, 0.3), (60, 5, 0.6), (30, 20, 0.1)):
        g = math.radians(deg)
        fence = Fence.create(g, mu)
        j = 0
        u_c, h_c = part.cm_in_edge_frame(j)
        length = part.edge(j)[1]
        ell = crossing(part, j, mu, fence.sign)
        ell += frac * (length - ell)
        delta = math.radians(delta_deg)
        t0 = np.array([math.cos(g), math.sin(g)])
        c = rotation(delta) @ ((ell - u_c) * t0 - h_c * perp(t0))
        bound, ccw = max_slip_rate(part.radius, c, g + delta, mu, 2048)
        assert ccw and bound > 0.0
        scene = PushScene.create(part.radius, c, g + delta, math.pi / 2)
        rates = []
        for kind in ("tripod", "rim", "dipod"):
            pts, wts = random_supports(rng, 400, part.radius, kind=kind)
            res = solve_forward_batch(scene, pts, wts, mu_c=mu)
            ok = res.converged & (np.abs(res.omega) > 0)
            assert ok.mean() > 0.95
            rates.append(-res.slip[ok] / res.omega[ok])
        rates = np.concatenate(rates)
        assert np.all(rates <= bound * (1 + 1e-6) + 1e-9)
        assert rates.max() >= 0.999 * bound  # measured: within 1e-5
