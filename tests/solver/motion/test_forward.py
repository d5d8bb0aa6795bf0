"""The forward minimum-power solver (book ch. 2, 3.2-3.3.3, 4.1): three back ends and the
batched path agree, the answers satisfy (3.8) and the KKT conditions, and are checked
against brute force, the analytic locus (3.3.13), Mason's rule (1.6.2) and the slipping
equivalence of 4.1.3."""

from __future__ import annotations

import math

import cvxpy as cp
import numpy as np
import pytest

from models.core import mpp
from models.core.errors import InvalidInput
from models.core.scene import PushScene
from models.core.support import Support, random_balanced_tripods, uniform_disk_support
from models.locus import cor_disk as cd
from solver.core.errors import BackendNotFound, NotConverged, SolverError
from solver.core.outcome import Outcome
from solver.core.tolerances import SolverTolerances
from solver.motion.forward import METHODS, solve_forward, solve_forward_batch, solve_forward_scenes
from tests.scenes import SEED, distance_to_polyline, point_in_polygon, scene_for_mu

MUS = (0.05, 0.3, 0.9, 1.5)


def twist(res):
    """Normalised twist (v, omega L) of a result, L = 1 here."""
    return np.r_[res.velocity_cm, res.omega]


def random_support(rng, k: int, a: float = 1.0) -> Support:
    """k random points in the disk with random positive weights, then the centroid moved to
    the CM by translating the points (keeps them random, not inside any special set)."""
    w = a * np.sqrt(rng.uniform(size=k))[:, None] * np.column_stack(
        [np.cos(t := rng.uniform(0, 2 * math.pi, k)), np.sin(t)]
    )
    p = rng.uniform(0.1, 1.0, k)
    p /= p.sum()
    w = w - p @ w
    return Support.create(w, p, (0.0, 0.0))


@pytest.mark.parametrize("mu", MUS)
@pytest.mark.parametrize("k", [2, 3, 4, 7, 20])
def test_three_back_ends_agree_to_1e8(mu, k):
    """Newton, cvxpy/Clarabel (polished) and CasADi/IPOPT on the dual give the same twist
    (3.7) to 1e-8 on random supports."""
    rng = np.random.default_rng(SEED + k)
    scene = scene_for_mu(mu)
    for _ in range(3):
        sup = random_support(rng, k)
        res = {m: solve_forward(scene, sup, method=m) for m in ("newton", "cvxpy", "casadi")}
        for m, r in res.items():
            assert r.status == "optimal", (m, r)
            assert r.kkt_residual <= 1e-9
        ref = twist(res["newton"])
        for m in ("cvxpy", "casadi"):
            assert np.linalg.norm(twist(res[m]) - ref) <= 1e-8, m


def test_unpolished_conic_answer_is_close_but_polish_matters():
    """Clarabel's own arg-min is only accurate to ~sqrt(gap); the polished answer is the
    exact KKT point. The raw distance is reported, not hidden."""
    rng = np.random.default_rng(SEED)
    scene = scene_for_mu(0.3)
    sup = random_support(rng, 5)
    pol = solve_forward(scene, sup, method="cvxpy")
    raw = solve_forward(scene, sup, method="cvxpy", polish=False)
    assert pol.raw_twist_error is not None and pol.raw_twist_error < 1e-4
    assert np.linalg.norm(twist(raw) - twist(pol)) < 1e-4
    assert pol.kkt_residual <= 1e-10


@pytest.mark.parametrize("mu_c", [0.0, 0.4, 5.0])
def test_batch_equals_single_solves(mu_c):
    rng = np.random.default_rng(SEED + 1)
    scene = scene_for_mu(0.3)
    pts, wts = random_balanced_tripods(rng, 40, 1.0)
    br = solve_forward_batch(scene, pts, wts, mu_c=mu_c)
    assert br.converged.all()
    for i in range(0, 40, 7):
        for method in ("newton", "cvxpy", "casadi"):
            r = solve_forward(scene, Support.create(pts[i], wts[i], (0, 0)), mu_c=mu_c, method=method)
            assert r.mode == br.MODES[br.mode[i]]
            assert np.linalg.norm(np.r_[r.velocity_cm - br.velocity_cm[i], r.omega - br.omega[i]]) <= 1e-8


def test_power_is_minimal_against_random_feasible_twists():
    """Brute force: no twist satisfying the contact constraint (3.3) dissipates less (3.7)."""
    rng = np.random.default_rng(SEED + 2)
    scene = scene_for_mu(0.3)
    for _ in range(5):
        sup = random_support(rng, 4)
        r = solve_forward(scene, sup)
        a = mpp.contact_generalized_force(scene.normal, scene.contact_rel)
        x0 = twist(r)
        basis = np.linalg.svd(a[None])[2][1:]
        for scale in (1e-4, 1e-2, 1.0):
            trial = x0 + scale * rng.normal(size=(2000, 2)) @ basis
            powers = [mpp.power(t, sup.points, sup.weights) for t in trial]
            assert min(powers) >= r.power - 1e-12


@pytest.mark.parametrize("mu", MUS)
def test_cor_satisfies_book_stationarity(mu):
    """(3.8): d_r alpha - s v_r = 0 at the COR (when it is on no support point)."""
    rng = np.random.default_rng(SEED + 3)
    scene = scene_for_mu(mu)
    for _ in range(10):
        sup = random_support(rng, 3)
        r = solve_forward(scene, sup)
        if r.cor is None or r.cor_on_support is not None:
            continue
        res = mpp.stationarity_residual(r.cor, sup.points, sup.weights, scene.contact_rel, scene.alpha_hat)
        d_r, _ = mpp.weighted_distance_direction(r.cor, sup.points, sup.weights)
        assert np.linalg.norm(res) <= 1e-8 * max(1.0, d_r * np.linalg.norm(r.cor))


def test_cor_on_a_support_point_is_found_exactly():
    """A heavy support point near the contact pins the part: the COR sits on it (the
    non-smooth optimum the book's Newton iteration (3.11) could not reach)."""
    scene = scene_for_mu(0.5)
    w = np.array([[0.2, -0.1], [-0.5, 0.9], [-0.6, -0.8]])
    p = np.array([0.9, 0.05, 0.05])
    w = w - p @ w
    sup = Support.create(w, p, (0, 0))
    r = solve_forward(scene, sup)
    assert r.cor_on_support is not None
    assert np.allclose(r.cor, sup.points[r.cor_on_support], atol=1e-14)
    assert r.kkt_residual <= 1e-12
    ref = solve_forward(scene, sup, method="casadi")
    assert np.linalg.norm(ref.cor - r.cor) <= 1e-7


def test_translation_is_a_normal_answer():
    """Line of force through the CM and a symmetric support: pure translation (3.3.11.1)."""
    scene = PushScene.create(1.0, (-1.0, 0.0), math.pi / 2, 0.0)
    w = np.array([[0.0, 0.5], [0.0, -0.5], [0.5, 0.0], [-0.5, 0.0]])
    sup = Support.create(w, np.ones(4), (0, 0))
    for method in ("newton", "cvxpy", "casadi"):
        r = solve_forward(scene, sup, method=method)
        assert r.cor is None and r.sense == "none", method
        assert abs(r.omega) <= 1e-9
        assert np.allclose(r.velocity_cm, [1.0, 0.0], atol=1e-9)


@pytest.mark.slow
@pytest.mark.parametrize("mu", (0.05, 0.3, 0.72, 0.9, 1.5))
def test_random_tripod_cors_lie_in_the_analytic_locus(mu):
    """Figure 3-5 by the batched solver: every tripod COR is inside the analytic boundary
    (3.30)/(3.35) of 3.3.13, up to the boundary's chord error."""
    rng = np.random.default_rng(SEED + 4)
    scene = scene_for_mu(mu)
    pts, wts = random_balanced_tripods(rng, 20000, 1.0)
    br = solve_forward_batch(scene, pts, wts)
    assert br.converged.all() and br.kkt_residual.max() <= 1e-10
    loc = cd.disk_cor_locus(scene, n_points=4096)
    poly = loc.boundary
    cor = br.cor[np.all(np.isfinite(br.cor), axis=1)]
    out = ~point_in_polygon(cor, poly)
    if out.any():
        assert distance_to_polyline(cor[out], poly).max() <= 2e-3


@pytest.mark.parametrize("mu_c", [0.0, 0.2, 1.0, 10.0])
def test_mason_rule_agrees_with_every_solve(mu_c):
    """1.6.2: the sense of rotation from the friction cone and the line of motion is the
    sense of every solved motion, whatever the pressure distribution."""
    rng = np.random.default_rng(SEED + 5)
    for trial in range(12):
        contact = rng.uniform(-1.2, 1.2, 2)
        edge = rng.uniform(0, math.pi)
        push = rng.uniform(0, 2 * math.pi)
        try:
            scene = PushScene.create(1.0, contact, edge, push)
        except InvalidInput:
            continue
        rule = mpp.mason_sense(scene.contact_rel, scene.normal, scene.push_hat, mu_c)
        pts, wts = random_balanced_tripods(rng, 300, 1.0)
        br = solve_forward_batch(scene, pts, wts, mu_c=mu_c)
        assert br.converged.all()
        senses = np.where(np.abs(br.omega) < 1e-12, 0, np.sign(br.omega))
        expect = {"ccw": 1, "cw": -1, "none": 0}[rule]
        assert np.all(senses == expect), (trial, rule, np.unique(senses))


def test_friction_modes_are_consistent():
    """4.1: sticking keeps the contact point with the pusher and its force inside the
    friction cone; slipping puts the force on a cone edge and the slip matches its side."""
    rng = np.random.default_rng(SEED + 6)
    scene = PushScene.create(1.0, (-0.9, -0.35), math.radians(70.0), 0.0)
    seen = set()
    for mu_c in (0.1, 0.5, 2.0):
        nu = math.atan(mu_c)
        for _ in range(40):
            pts, wts = random_balanced_tripods(rng, 1, 1.0)
            r = solve_forward(scene, Support.create(pts[0], wts[0], (0, 0)), mu_c=mu_c)
            assert r.status == "optimal"
            seen.add(r.mode)
            f = r.contact_force
            fn, ft = f @ scene.normal, f @ scene.alpha_hat
            assert fn > 0.0
            vc = r.velocity_cm + r.omega * mpp.perp(scene.contact_rel)
            if r.mode == "sticking":
                assert np.allclose(vc, scene.push_hat, atol=1e-10)
                assert abs(ft) <= mu_c * fn * (1 + 1e-9)
            else:
                assert math.isclose(abs(math.atan2(ft, fn)), nu, rel_tol=1e-9)
                rel = (scene.push_hat - vc) @ scene.alpha_hat
                assert np.sign(rel) == np.sign(ft)
                up = (vc - scene.push_hat) @ mpp.perp(scene.push_hat) > 0
                assert r.mode == ("slipping_up" if up else "slipping_down")
            assert abs(r.gap) <= 1e-9 * r.power
    assert "sticking" in seen and len(seen) >= 2


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_slipping_equals_frictionless_with_edge_turned_by_nu(sign):
    """4.1.3: slipping with the force on the cone edge alpha +- nu is the frictionless
    motion for an edge turned by that angle (the same COR), rescaled."""
    rng = np.random.default_rng(SEED + 7)
    base = PushScene.create(1.0, (-0.9, -0.35), math.radians(70.0), 0.0)
    mu_c = 0.3
    nu = math.atan(mu_c)
    count = 0
    for _ in range(60):
        pts, wts = random_balanced_tripods(rng, 1, 1.0)
        sup = Support.create(pts[0], wts[0], (0, 0))
        r = solve_forward(base, sup, mu_c=mu_c)
        if r.mode == "sticking":
            continue
        ft = r.contact_force @ base.alpha_hat
        # Force direction n + s mu t turns the normal by s*nu towards t: edge turned too.
        s = 1.0 if ft > 0 else -1.0
        turn = s * nu if (base.normal[0] * base.alpha_hat[1] - base.normal[1] * base.alpha_hat[0]) > 0 else -s * nu
        turned = PushScene.create(1.0, base.contact_point, base.edge_angle + turn, base.push_direction)
        f = solve_forward(turned, sup)
        assert np.linalg.norm(f.cor - r.cor) <= 1e-8 * max(1.0, np.linalg.norm(r.cor))
        count += 1
    assert count >= 5


def test_small_mu_c_tends_to_frictionless_and_large_mu_c_sticks():
    rng = np.random.default_rng(SEED + 8)
    scene = scene_for_mu(0.4)
    pts, wts = random_balanced_tripods(rng, 200, 1.0)
    free = solve_forward_batch(scene, pts, wts)
    tiny = solve_forward_batch(scene, pts, wts, mu_c=1e-10)
    assert np.allclose(tiny.omega, free.omega, rtol=1e-7, atol=1e-12)
    huge = solve_forward_batch(scene, pts, wts, mu_c=1e8)
    stick = huge.mode == 1
    assert stick.mean() > 0.9
    # Sticking CORs lie on the sticking line: through c, perpendicular to p (4.1.2).
    d = (huge.cor[stick] - scene.contact_point) @ scene.push_hat
    assert np.abs(d).max() <= 1e-9


@pytest.mark.parametrize("scale", [1e-6, 1.0, 1e6])
def test_scale_and_rotation_invariance(scale):
    rng = np.random.default_rng(SEED + 9)
    sup = random_support(rng, 4)
    base = solve_forward(scene_for_mu(0.3), sup)
    th = 0.7
    rot = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
    cm = np.array([3.0, -2.0]) * scale
    sc0 = scene_for_mu(0.3)
    scene = PushScene.create(
        scale, cm + scale * rot @ sc0.contact_point, sc0.edge_angle + th, sc0.push_direction + th, cm
    )
    moved = Support.create(cm + scale * sup.points @ rot.T, sup.weights, cm)
    r = solve_forward(scene, moved)
    assert np.allclose(r.cor, cm + scale * rot @ base.cor, rtol=0, atol=1e-9 * scale * np.linalg.norm(base.cor))
    assert math.isclose(r.omega * scale, base.omega, rel_tol=1e-9)
    assert math.isclose(r.power, base.power, rel_tol=1e-9)


def test_hard_cases_converge():
    """Nearly collinear tripods, a line of force almost through the CM (alpha.c -> 0), a
    contact far outside the disk, huge mu_c: every solve converges with KKT <= 1e-10."""
    rng = np.random.default_rng(SEED + 10)
    eps = 1e-7
    w = np.array([[-0.9, 0.0], [0.9, eps], [0.1, -eps]])
    a = np.vstack([np.ones(3), w.T])
    p = np.linalg.solve(a, [1.0, 0.0, 0.0])
    w = w - (p / p.sum()) @ w
    collinear = Support.create(w, np.abs(p), (0, 0), )
    for mu in (1e-9, 1e-4, 0.3, 50.0):
        scene = scene_for_mu(mu)
        for mu_c in (0.0, 0.5, 1e6):
            r = solve_forward(scene, collinear, mu_c=mu_c)
            assert r.status == "optimal" and r.kkt_residual <= 1e-10
            pts, wts = random_balanced_tripods(rng, 500, 1.0)
            br = solve_forward_batch(scene, pts, wts, mu_c=mu_c)
            assert br.converged.all()


def test_bad_supports_are_refused():
    with pytest.raises(InvalidInput) as e:
        Support.create([[1.0, 0.0], [0.5, 0.0]], [1.0, 1.0], (0, 0))
    assert e.value.field == "weights"
    with pytest.raises(InvalidInput):
        Support.create([[1.0, 0.0], [-1.0, 0.0]], [1.0, -1.0], (0, 0))
    with pytest.raises(InvalidInput):
        Support.balanced([[1.0, 0.0], [2.0, 0.0], [3.0, 1.0]], (0, 0))
    with pytest.raises(InvalidInput) as e:
        solve_forward(scene_for_mu(0.3), Support.create([[1, 0], [-1, 0]], [1, 1], (0, 0)), mu_c=-1.0)
    assert e.value.field == "mu_c"


def test_uniform_disk_cor_is_on_the_axis_and_converges():
    """Figure 7-1: the COR of uniform pressure lies on the locus axis through the CM (the
    symmetry of 3.3.12), inside the locus, and converges as the disk is discretised finer."""
    scene = scene_for_mu(0.5)
    cors = [solve_forward(scene, uniform_disk_support(1.0, rings=n)).cor for n in (8, 16, 32)]
    axis = scene.axis
    for c in cors:
        assert abs(c @ mpp.perp(axis)) <= 1e-9
    d = [c @ axis for c in cors]
    assert abs(d[2] - d[1]) < 0.5 * abs(d[1] - d[0])
    loc = cd.disk_cor_locus(scene, n_points=2048)
    assert point_in_polygon(cors[-1][None], loc.boundary)[0]
    # Uniform pressure turns the part about a point between the tip and the CM.
    assert 0.0 < -d[-1] < loc.tip.distance


def test_large_support_pinned_on_a_heavy_point():
    """More than 16 points: the Newton-first path finds a COR on a support point exactly,
    and agrees with the CasADi dual solve."""
    rng = np.random.default_rng(SEED + 11)
    scene = scene_for_mu(0.5)
    w = rng.uniform(-0.7, 0.7, (60, 2))
    w[0] = [0.25, -0.15]
    p = np.full(60, 0.1 / 59)
    p[0] = 0.9
    w = w - p @ w
    sup = Support.create(w, p, (0, 0))
    r = solve_forward(scene, sup)
    ref = solve_forward(scene, sup, method="casadi")
    assert r.status == "optimal" and r.cor_on_support is not None
    assert np.allclose(r.cor, sup.points[r.cor_on_support], atol=1e-14)
    assert np.linalg.norm(twist(r) - twist(ref)) <= 1e-8


def test_batch_reports_slip_gap_and_iterations_like_single_solves():
    rng = np.random.default_rng(SEED + 12)
    scene = scene_for_mu(0.4)
    pts, wts = random_balanced_tripods(rng, 30, 1.0)
    for mu_c in (0.0, 0.5):
        br = solve_forward_batch(scene, pts, wts, mu_c=mu_c)
        for i in range(0, 30, 6):
            r = solve_forward(scene, Support.create(pts[i], wts[i], (0, 0)), mu_c=mu_c)
            assert math.isclose(br.slip[i], r.slip, rel_tol=1e-9, abs_tol=1e-12)
            assert abs(br.gap[i]) <= 1e-9 * br.power[i] and abs(r.gap) <= 1e-9 * r.power
            assert br.iterations[i] == r.iterations


@pytest.mark.parametrize("mu_c", [0.0, 0.3, 2.0])
def test_a_scene_per_support_equals_one_solve_each(mu_c):
    """solve_forward_scenes (one scene per support: contact, edge, push and CM all differ,
    as when a simulator steps many parts) gives each support the motion its own single
    solve gives, in every mode (4.1), with the slip and the power."""
    rng = np.random.default_rng(SEED + 31)
    b = 36
    pts, wts = random_balanced_tripods(rng, b, 1.0)
    scenes, world = [], []
    for i in range(b):
        cm = rng.uniform(-5.0, 5.0, 2)
        ang = rng.uniform(0.0, 2.0 * math.pi)
        contact = cm + rng.uniform(0.4, 1.0) * np.array([math.cos(ang), math.sin(ang)])
        edge = ang + 0.5 * math.pi + rng.uniform(-0.4, 0.4)  # the part lies on the edge's inner side
        push = edge + 0.5 * math.pi + rng.uniform(-1.0, 1.0) + math.pi
        scenes.append(PushScene.create(1.0, contact, edge, push, cm))
        world.append(pts[i] + cm)
    br = solve_forward_scenes(scenes, np.array(world), wts, mu_c=mu_c)
    assert br.converged.all()
    modes = set()
    for i in range(b):
        r = solve_forward(scenes[i], Support.create(world[i], wts[i], scenes[i].center_of_mass), mu_c=mu_c)
        modes.add(r.mode)
        assert r.mode == br.MODES[br.mode[i]]
        assert np.linalg.norm(np.r_[r.velocity_cm - br.velocity_cm[i], r.omega - br.omega[i]]) <= 1e-9
        assert math.isclose(br.slip[i], r.slip, rel_tol=1e-9, abs_tol=1e-12)
        assert math.isclose(br.power[i], r.power, rel_tol=1e-12)
    assert len(modes) >= (2 if mu_c == 0.3 else 1)  # mu_c 0.3: sticking and slipping both seen


def test_undetermined_motion_is_refused():
    """Every support point and the contact at the CM: the rotation is free."""
    scene = PushScene.create(1.0, (0.0, 0.0), 0.0, math.pi / 2)
    with pytest.raises(InvalidInput) as e:
        solve_forward(scene, Support.create([[0.0, 0.0]], [1.0], (0, 0)))
    assert e.value.field == "points"


def test_tripod_sampling_gives_up_on_a_hopeless_region():
    from models.core.footprint import Footprint

    sliver = Footprint.create([[0, 0], [1, 1], [1, 1.001], [0, 0.001]])  # fills 0.1 % of its box
    with pytest.raises(InvalidInput):
        random_balanced_tripods(np.random.default_rng(1), 1000, 1.0, footprint=sliver, max_draws=3)


@pytest.mark.parametrize("scale", [1e-200, 1.0, 1e200])
def test_mason_rule_is_scale_free(scale):
    """1.6.2 depends on directions only: no under- or overflow at extreme part sizes."""
    assert mpp.mason_sense(np.array([0.0, -0.5]) * scale, np.array([1.0, 0.0]), np.array([1.0, 0.0]), 0.0) == "ccw"
    assert mpp.mason_sense(np.array([0.2, 0.5]) * scale, np.array([1.0, 0.0]), np.array([1.0, 0.0]), 0.3) == "cw"


def test_sticking_with_the_cor_on_a_support_point_finds_a_force_in_the_cone():
    """4.1.2: when the sticking COR sits on a support point the contact force is a set (the
    subgradient of that point's term); sticking is consistent if any member lies in the
    friction cone. Supports with a heavy point on the sticking line and mu_c large must
    stick there, as a 1-D brute-force minimisation of the power along the line agrees."""
    scene = PushScene.create(1.0, (-0.9, 0.2), math.radians(80.0), 0.0)
    c, jp = scene.contact_point, mpp.perp(scene.push_hat)
    rng = np.random.default_rng(SEED + 13)
    checked = 0
    for _ in range(20):
        heavy = c + rng.uniform(0.3, 1.2) * jp * rng.choice([-1.0, 1.0])
        others = rng.uniform(-0.8, 0.8, (3, 2))
        w = np.vstack([heavy, others])
        p = np.r_[0.85, rng.uniform(0.02, 0.08, 3)]
        p /= p.sum()
        shift = p @ w
        sup = Support.create(w - shift, p, (0, 0))
        sc = PushScene.create(1.0, c - shift, scene.edge_angle, 0.0)
        r = solve_forward(sc, sup, mu_c=1e6)
        assert r.status == "optimal", r
        if r.mode != "sticking" or r.cor_on_support is None:
            continue
        # brute force: the power of sticking rotations about points of the sticking line
        ts = np.linspace(-3, 3, 60000)  # even count: t = 0 (r = c) is not a COR
        cs, jps = sc.contact_point, mpp.perp(sc.push_hat)
        best = ts[int(np.argmin(_sticking_power(sc, sup, cs + ts[:, None] * jps)))]
        assert abs(((r.cor - cs) @ jps) - best) <= 2e-4
        f = r.contact_force
        assert f @ sc.normal > 0.0
        checked += 1
    assert checked >= 5


def _sticking_power(sc, sup, r):
    """Power (3.6) of the rotations about points r (m, 2) of the sticking line that move c
    with p."""
    cr = sc.contact_point - r
    omega = (mpp.perp(cr) @ sc.push_hat) / np.einsum("ij,ij->i", cr, cr)
    dist = np.linalg.norm(sup.points[None, :, :] - r[:, None, :], axis=2)
    return np.abs(omega) * (dist @ sup.weights)


def test_an_unknown_method_is_backend_not_found_on_the_method_field():
    """BackendNotFound is an InvalidInput before it is a SolverError: a handler picked by the
    exception's MRO (the service's, Starlette's) answers it as the input error on "method"."""
    with pytest.raises(BackendNotFound) as e:
        solve_forward(scene_for_mu(0.3), Support.create([[1, 0], [-1, 0]], [1, 1], (0, 0)), method="simplex")
    assert e.value.field == "method" and e.value.available == METHODS and "'simplex'" in e.value.reason
    mro = type(e.value).__mro__
    assert mro.index(InvalidInput) < mro.index(SolverError)


@pytest.mark.parametrize("method", METHODS)
def test_results_say_how_good_they_are(method):
    """ForwardResult and BatchResult implement Outcome: complete exactly when optimal."""
    scene = scene_for_mu(0.3)
    sup = random_support(np.random.default_rng(SEED), 5)
    r = solve_forward(scene, sup, mu_c=0.4, method=method)
    assert isinstance(r, Outcome) and r.status == "optimal" and r.complete
    assert r.message.startswith(f"optimal {r.mode} motion by {method}: COR (")
    never = SolverTolerances(kkt_accept=-1.0)  # no residual is accepted
    r = solve_forward(scene, sup, mu_c=0.4, method=method, tol=never)
    assert r.status == "not_converged" and not r.complete
    pts, wts = random_balanced_tripods(np.random.default_rng(SEED), 20, 1.0)
    b = solve_forward_batch(scene, pts, wts, mu_c=0.4)
    assert isinstance(b, Outcome) and b.status == "optimal" and b.complete and b.solve_time_s > 0.0
    assert b.message == "20 of 20 supports converged"
    b = solve_forward_batch(scene, pts, wts, mu_c=0.4, tol=never)
    assert b.status == "not_converged" and not b.complete and b.message == "0 of 20 supports converged"


def test_a_failing_conic_solve_is_not_converged(monkeypatch):
    def boom(*args, **kwargs):
        raise cp.error.SolverError("numerical trouble")

    monkeypatch.setattr(cp.Problem, "solve", boom)
    sup = random_support(np.random.default_rng(SEED), 4)
    with pytest.raises(NotConverged, match="numerical trouble"):
        solve_forward(scene_for_mu(0.3), sup, method="cvxpy")


@pytest.mark.parametrize("scale", [1e-300, 1e-200, 1e-160, 1e150, 1e300])
def test_the_motion_scales_down_to_the_smallest_lengths(scale):
    """(3.3.12) Scaling the scene and the support scales the COR: below ~1e-154 the squares
    of lengths underflow, so the problem's length scale is taken with hypot, not a norm of
    squares (a disk of 1e-300 was refused as 'every point at the centre of mass')."""
    base = PushScene.create(1.0, [-0.5, -0.3], math.pi / 2)
    pts = np.array([[0.6, 0.0], [-0.3, 0.5], [-0.3, -0.5]])
    ref = solve_forward(base, Support.create(pts, [1, 1, 1], [0.0, 0.0]), method="newton")
    scene = PushScene.create(scale, [-0.5 * scale, -0.3 * scale], math.pi / 2)
    got = solve_forward(scene, Support.create(pts * scale, [1, 1, 1], [0.0, 0.0]), method="newton")
    assert np.allclose(got.cor / scale, ref.cor, rtol=1e-12, atol=1e-12)
