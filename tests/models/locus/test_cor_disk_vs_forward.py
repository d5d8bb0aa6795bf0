"""Independent checks of the chapter-3 locus: the COR of given supports found by minimising
the dissipated power (3.7) directly (SOCP, Clarabel), and membership of candidate CORs by a
brute-force linear programme over a fine discretisation of the disk (3.8)-(3.10)."""

from __future__ import annotations

import math

import cvxpy as cp
import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.support import Support
from models.locus import cor_disk as cd
from solver.motion.forward import solve_forward
from tests.scenes import (
    MU_OUTER_INNER,
    MU_WITH_ARC,
    SEED,
    distance_to_polyline,
    point_in_polygon,
    random_tripods,
    scene_for_mu,
)


def solve_cor(sc, points, weights):
    """The forward solve of a support by the conic back end (cvxpy + Clarabel, polished by
    exact KKT steps): independent of the closed forms under test."""
    return solve_forward(sc, Support.create(points, weights, sc.center_of_mass), method="cvxpy")


def outer_dipod(rho: float, eta: float, omega: float) -> np.ndarray:
    """The figure 3-12 dipod whose COR is the boundary point (rho, eta) in the locus frame
    (x along alpha', unit disk): points at +-(sin w x_hat + cos w y_hat), y_hat from the COR
    towards the CM, x_hat = y_hat turned clockwise (the frame of (3.21))."""
    y_hat = np.array([math.cos(eta), -math.sin(eta)])
    x_hat = np.array([y_hat[1], -y_hat[0]])
    u = math.sin(omega) * x_hat + math.cos(omega) * y_hat
    return np.vstack([u, -u])


def local_point(rho: float, eta: float) -> np.ndarray:
    return np.array([-rho * math.cos(eta), rho * math.sin(eta)])


def power_about(sc, cor, points, weights) -> float:
    """Dissipated power per unit push, / (mu_s M g), if the part turned about ``cor``:
    (3.3) for the rotation rate, (3.6) for the power."""
    p = np.asarray(weights, float) / np.sum(weights)
    rate = abs(sc.rotation_per_push(cor))
    return rate * float(p @ np.linalg.norm(np.asarray(points) - cor, axis=1))


@pytest.mark.parametrize("mu", MU_OUTER_INNER[1:] + MU_WITH_ARC)
def test_figure_3_12_dipods_land_on_the_outer_boundary(mu):
    """(3.21)/(3.35): the dipod that generates a boundary point has its minimum-power COR
    exactly there."""
    sc = scene_for_mu(mu)  # locus frame = world frame rotated: axis alpha' = alpha_hat
    omega = np.linspace(cd.outer_corner_omega(mu) + 0.05, math.pi / 2 - 0.05, 5)
    rho, eta, _ = cd.outer_boundary(omega, mu)
    for r, e, w in zip(rho, eta, omega):
        pts = sc.to_world(outer_dipod(r, e, w))
        sol = solve_cor(sc, pts, [0.5, 0.5])
        expected = sc.to_world(local_point(r, e))
        assert abs(sol.gap) < 1e-9 * sol.power and sol.kkt_residual <= 1e-10
        # The analytic point dissipates the minimum power: it is the COR.
        assert power_about(sc, expected, pts, [0.5, 0.5]) <= sol.power * (1 + 1e-10)
        assert np.linalg.norm(sol.cor - expected) < 1e-7 * r


@pytest.mark.parametrize("mu", [0.05, 0.3, 0.72, 1.5])
def test_figure_3_11_dipods_land_on_the_inner_boundary(mu):
    """(3.30): the dipod with weight a/(r+a) at a boundary point r inside the disk and the
    rest on the disk opposite it (figure 3-11, (3.15)) has its COR at r. Moving the
    support point 3% further out along the same ray leaves the locus: the COR moves away."""
    sc = scene_for_mu(mu)
    rho_min = float(cd.r_min(mu))
    for rho in np.linspace(rho_min + 0.1 * (1 - rho_min), 0.9, 4):
        eta = math.acos(float(cd.inner_boundary_cos_eta(rho, mu)))
        for factor, inside in ((0.999, True), (1.03, False)):
            r_loc = local_point(rho * factor, eta)
            pts = sc.to_world(np.vstack([-r_loc / np.linalg.norm(r_loc), r_loc]))
            weights = [rho * factor / (1 + rho * factor), 1 / (1 + rho * factor)]
            sol = solve_cor(sc, pts, weights)
            excess = power_about(sc, sc.to_world(r_loc), pts, weights) / sol.power - 1
            if inside:
                assert excess <= 1e-9, (rho, excess)
            else:
                assert excess > 1e-5, (rho, excess)


@pytest.mark.parametrize("mu", [0.05, 0.3, 0.6, 0.9, 1.5])
def test_random_tripods_fall_inside_the_boundary(mu):
    """3.3.3 / figure 3-5: the COR of every random tripod lies inside the locus."""
    rng = np.random.default_rng(SEED + int(mu * 1000))
    sc = scene_for_mu(mu)
    loc = cd.disk_cor_locus(sc, n_points=2048)
    cors = []
    for w, p in random_tripods(rng, 60):
        sol = solve_cor(sc, sc.to_world(w), p)
        if sol.cor is not None:
            cors.append(sol.cor)
            assert abs(sol.gap) < 1e-9 * sol.power
    cors = np.array(cors)
    inside = point_in_polygon(cors, loc.boundary)
    # points outside the polygon may only be within discretisation/solver error of it
    slack = distance_to_polyline(cors[~inside], loc.boundary)
    assert np.all(slack < 2e-4 * loc.tip.distance), slack


@pytest.mark.parametrize("mu", [0.2, 0.8])
def test_random_dipods_and_tetrapods_fall_inside(mu):
    """Mason's theorem 5 says tripods suffice for the extremes; other supports must not
    escape either."""
    rng = np.random.default_rng(SEED + 7)
    sc = scene_for_mu(mu)
    loc = cd.disk_cor_locus(sc, n_points=2048)
    for _ in range(25):
        k = int(rng.integers(2, 5))
        th = rng.uniform(0, 2 * math.pi, k)
        rad = np.sqrt(rng.uniform(0, 1, k))
        w = np.column_stack([rad * np.cos(th), rad * np.sin(th)])
        if k == 2:
            w[1] = -w[0] * rng.uniform(0.2, 1.0)  # collinear with the CM
        # weights with centroid at the CM: least-norm non-negative solution via LP
        pvar = cp.Variable(k, nonneg=True)
        prob = cp.Problem(cp.Minimize(cp.sum_squares(pvar)), [cp.sum(pvar) == 1, w.T @ pvar == 0])
        prob.solve(solver=cp.CLARABEL)
        if prob.status != cp.OPTIMAL:
            continue
        p = np.clip(pvar.value, 0, None)
        if np.linalg.norm(p @ w) > 1e-9:
            continue
        sol = solve_cor(sc, sc.to_world(w), p)
        if sol.cor is None:
            continue
        if not point_in_polygon(sol.cor[None], loc.boundary)[0]:
            assert distance_to_polyline(sol.cor[None], loc.boundary)[0] < 2e-4 * loc.tip.distance


# --- brute-force membership on a discretised disk ----------------------------------------


def disk_samples(n_rim: int = 720, n_rings: int = 24) -> np.ndarray:
    pts = [np.zeros((1, 2))]
    for k, rad in enumerate(np.linspace(0, 1, n_rings + 1)[1:]):
        n = max(8, int(n_rim * rad))
        th = np.linspace(0, 2 * math.pi, n, endpoint=False) + 0.37 * k
        pts.append(rad * np.column_stack([np.cos(th), np.sin(th)]))
    return np.vstack(pts)


DISK = disk_samples()


def lp_member(r: np.ndarray, mu: float) -> bool:
    """Is r (locus frame, alpha' = +x, unit disk) the COR of some P >= 0 on the sampled disk?
    Stationarity of (3.7): sum P (|w - r| alpha - s (w - r)/|w - r|) = 0, s = alpha . (c - r)
    (3.8)-(3.10), plus sum P = 1, sum P w = 0; a point mass at r (if r is in the disk)
    contributes -s z with |z| <= its weight (the subgradient of |w - r| at w = r)."""
    alpha = np.array([1.0, 0.0])
    s = mu - r[0]
    if s <= 0:
        return False
    diff = DISK - r
    dist = np.linalg.norm(diff, axis=1)
    keep = dist > 1e-12
    diff, dist, w = diff[keep], dist[keep], DISK[keep]
    cols = np.vstack([np.ones(len(w)), w.T, dist * alpha[0] - s * diff[:, 0] / dist, dist * alpha[1] - s * diff[:, 1] / dist])
    pv = cp.Variable(len(w), nonneg=True)
    lhs = cols @ pv
    cons = []
    if np.linalg.norm(r) < 1.0:
        p0 = cp.Variable(nonneg=True)
        z = cp.Variable(2)
        cons.append(cp.norm(z) <= p0)
        lhs = lhs + cp.hstack([p0, p0 * r[0], p0 * r[1], -s * z[0], -s * z[1]])
    cons.append(lhs == np.array([1.0, 0.0, 0.0, 0.0, 0.0]))
    prob = cp.Problem(cp.Minimize(0), cons)
    prob.solve(solver=cp.CLARABEL)
    return prob.status == cp.OPTIMAL


@pytest.mark.slow
@pytest.mark.parametrize("mu", [0.3, 0.72, 0.9, 1.5])
def test_brute_force_membership_agrees_with_the_boundary(mu):
    """Points 4% inside the analytic boundary are CORs of some sampled support; points 4%
    outside are not (the LP on a 7,000-point disk sample is a check, not a certificate)."""
    ring, _, _ = cd.boundary_local(mu, 24)
    for k in range(0, len(ring), 3):
        p = ring[k]
        prev, nxt = ring[k - 1], ring[(k + 1) % len(ring)]
        tangent = nxt - prev
        normal = np.array([tangent[1], -tangent[0]]) / np.linalg.norm(tangent)  # outward (CCW ring)
        step = 0.04 * max(0.05, min(1.0, np.linalg.norm(p)))
        assert lp_member(p - step * normal, mu), (k, p)
        assert not lp_member(p + step * normal, mu), (k, p)


def test_mason_rule_sense_agrees_with_the_forward_solution():
    """1.6.2 with mu_c = 0: the side of the CM the line of force passes decides the sense."""
    rng = np.random.default_rng(SEED)
    for _ in range(20):
        mu = float(rng.uniform(0.05, 1.5) * rng.choice([-1.0, 1.0]))  # both senses
        sc = scene_for_mu(mu, edge_angle=float(rng.uniform(0.2, 2.9)), push_direction=float(rng.uniform(-0.5, 0.5)))
        w, p = random_tripods(rng, 1)[0]
        sol = solve_cor(sc, sc.to_world(w), p)
        assert (sol.omega < 0) == (sc.sense == "cw")


def test_force_through_the_cm_translates():
    sc = scene_for_mu(0.0)
    sol = solve_cor(sc, sc.to_world(np.array([[1.0, 0.3], [-1.0, -0.3]])), [1, 1])
    assert sol.cor is None
    assert np.allclose(sol.velocity_cm / np.linalg.norm(sol.velocity_cm), sc.normal, atol=1e-7)


def test_support_with_wrong_centroid_is_refused():
    with pytest.raises(InvalidInput) as err:
        solve_cor(scene_for_mu(0.3), [[1.0, 0.0], [0.0, 1.0]], [1, 1])
    assert err.value.field == "weights"
