"""A disk herded by a pusher on a spiral, simulated with the forward solver
(solver/spiral/simulate.py; book 4.4, 4.5).

Physical checks, all seeded:

* the paths: positions, tangents, revolutions, the mirror image of a clockwise spiral;
* the contact search finds a dip of the pusher into the disk just deeper than the graze
  depth even when sampling far more coarsely than the dip is wide, and ignores shallower
  touches;
* a straight path reproduces simulate_disk_encounter (4.4) for the same support and
  collision parameter (pose stepping in x against event-driven stepping along a path), and
  a huge circle approaches it;
* a circle far above b_inf = a (1 + mu_c) (4.25) and a gently shrinking spiral push the
  disk inward at every contact (|CM| falls, beta never falls);
* the step converges (halving it changes the final CM by less than STEP_TOL a);
* a spiral that shrinks by nearly a per revolution at small radius pushes disks out (the
  check can fail);
* mu_c = 0: the contact force lies along the normal and the disk only translates (4.4.2.1);
* symmetry: a clockwise path with mirrored support and start gives the mirrored
  trajectory; turning everything turns the trajectory;
* the worst case of 4.5.2-4.5.3: the witness support of the lower end of the exact
  sticking locus (solver/sketch/sticking.py) on a circle 1 % tighter than r*(beta) is pushed out
  (beta falls), 0.2 % looser it is not: the simulation and r*(beta) agree; on a spiral
  that keeps shrinking during the contact, 0.2 % above r*(beta) at the collision is not
  enough: the worst disk is lost (finding: "at worst chased", 4.5.5, holds for circles);
* a schedule planned by the book's recursion (4.26) (solver/spiral/critical_radius.py, models/spiral/path.py)
  herds random supports from random starts inside b_1 into the promised radius.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from solver.push.simulate import simulate_disk_encounter
from solver.spiral import simulate as ss
from tests.budgets import checks_budget

A = 1.0
MU = 0.25
SEED = 20261122
FAST = ss.SPIRAL_SIM_FAST
STEP_TOL = 5e-4  # final CM change / a when the step halves from 0.1 a to 0.05 a
ENCOUNTER_TOL = 5e-4  # push length and rotation vs simulate_disk_encounter at step 0.05 a


def mirror(p):
    q = np.array(p, dtype=float)
    q[..., 1] *= -1.0
    return q


# --- paths ------------------------------------------------------------------------------


def test_spiral_path_geometry():
    path = ss.spiral_path([5.0, 4.0, 3.5], centre=(1.0, -2.0), start_angle=0.3)
    assert path.u_end == pytest.approx(3 * 2 * math.pi)
    assert np.allclose(path.revolution_marks, 2 * math.pi * np.arange(1, 4))
    for u, b in [(0.0, 5.0), (2 * math.pi, 4.0), (3 * math.pi, 3.75), (4 * math.pi, 3.5), (5.5 * math.pi, 3.5)]:
        assert np.linalg.norm(path.position(u) - path.centre) == pytest.approx(b)
    # Tangents are derivatives (central differences inside a piece), one-sided at knots.
    for u in (0.7, 2 * math.pi + 1.0, 5 * math.pi):
        h = 1e-6
        num = (path.position(u + h) - path.position(u - h)) / (2 * h)
        assert np.allclose(path.tangent(u), num, atol=1e-8)
    k = 2 * math.pi
    assert np.allclose(path.tangent(k, left=True), (path.position(k) - path.position(k - 1e-7)) / 1e-7, atol=1e-6)
    assert np.allclose(path.tangent(k), (path.position(k + 1e-7) - path.position(k)) / 1e-7, atol=1e-6)
    # Counter-clockwise: the centre is on the left; clockwise is the mirror image.
    t = path.tangent(1.0)
    rel = path.position(1.0) - path.centre
    assert rel[0] * t[1] - rel[1] * t[0] > 0.0
    ccw = ss.spiral_path([5.0, 4.0])
    cw = ss.spiral_path([5.0, 4.0], clockwise=True)
    u = np.linspace(0.0, ccw.u_end, 17)
    assert np.allclose(cw.position(u), mirror(ccw.position(u)), atol=1e-12)
    with pytest.raises(InvalidInput):
        ss.spiral_path([3.0, -1.0])


def test_polyline_path_follows_its_points_and_counts_revolutions():
    ang = np.linspace(0.0, 4 * math.pi, 129)
    rad = np.linspace(5.0, 3.0, 129)
    pts = np.column_stack([rad * np.cos(ang), rad * np.sin(ang)])
    path = ss.polyline_path(pts)
    seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    assert path.u_end == pytest.approx(seg.sum())
    assert np.allclose(path.position(path.breakpoints), pts[1:-1], atol=1e-12)
    assert path.final_radius == pytest.approx(3.0)
    assert not path.clockwise and path.revolution_marks.size == 2
    assert np.allclose(path.position(path.revolution_marks), [[4.0, 0.0], [3.0, 0.0]], atol=1e-9)
    assert ss.polyline_path(mirror(pts)).clockwise


@pytest.mark.slow
def test_planner_polyline_converges_to_the_analytic_spiral(tripods):
    """The pusher polyline of models/spiral.spiral_polyline (same radii, clockwise from the
    top) pushes the disk as the analytic path does, to O(chord deviation)."""
    mspiral = pytest.importorskip("models.spiral.path")
    pts, wts = tripods
    radii = [4.0, 3.4, 2.9]
    start = np.array([-1.5, 2.0])
    ref = ss.simulate_spiral(ss.spiral_path(radii, clockwise=True, start_angle=math.pi / 2), pts[3], wts[3], A, MU,
                             start, 0.0, ss.SpiralSimSettings(step=0.02))
    poly = mspiral.spiral_polyline(radii, points_per_revolution=1024)
    run = ss.simulate_spiral(ss.polyline_path(poly.points), pts[3], wts[3], A, MU, start, 0.0, FAST)
    # The polyline also re-touches the disk just after a contact ends, where its next
    # corner turns in by 2 pi / 1024: contacts at beta ~ pi/2 - 0.006, of depth ~1e-5 a.
    deep = [c for c in run.contacts if c.depth_initial > 1e-3 * A]
    assert ref.n_contacts >= 2 and len(deep) == ref.n_contacts
    assert all(c.depth_initial < 1e-4 * A for c in run.contacts if c not in deep)
    assert np.linalg.norm(run.final_cm - ref.final_cm) < 2e-4 * A
    assert np.allclose(run.revolution_cm_radius, ref.revolution_cm_radius, atol=2e-4)


# --- contact search ---------------------------------------------------------------------




# --- a straight path is the encounter of 4.4 --------------------------------------------


@pytest.fixture(scope="module")
def tripods():
    rng = np.random.default_rng(SEED)
    return ss.random_supports(rng, 8, A, "tripod")


@pytest.mark.slow
def test_straight_path_reproduces_the_disk_encounter(tripods):
    pts, wts = tripods
    bi = math.radians(30.0)
    cm0 = A * np.array([math.cos(bi), -math.sin(bi)])
    line = ss.polyline_path([[-2.0, 0.0], [8.0, 0.0]], centre=(0.0, -1e6))
    big = 1e4
    circle = ss.spiral_path([big], centre=(0.0, -big), clockwise=True, start_angle=math.pi / 2 + 2.0 / big,
                            final_turns=8.0 / (2 * math.pi * big))
    for i in (0, 1):
        ref = simulate_disk_encounter(pts[i], wts[i], A, bi, MU, step=2e-3)
        run = ss.simulate_spiral(line, pts[i], wts[i], A, MU, cm0, settings=ss.SpiralSimSettings(step=0.05))
        (c,) = run.contacts
        assert run.status == "completed" and run.not_optimal == 0
        assert c.u_start == pytest.approx(2.0, abs=1e-9) and c.beta_initial == pytest.approx(bi, abs=1e-9)
        assert c.side == "inside" and c.beta_final == pytest.approx(math.pi / 2)
        assert abs((c.u_end - c.u_start) - ref.push) < ENCOUNTER_TOL
        assert abs(-run.final_theta - ref.rotation) < ENCOUNTER_TOL
        # A circle of radius 1e4 a through the same points: the same encounter to O(a/R).
        run_c = ss.simulate_spiral(circle, pts[i], wts[i], A, MU, cm0, settings=ss.SpiralSimSettings(step=0.05))
        (cc,) = run_c.contacts
        assert abs((cc.u_end - cc.u_start) * big - ref.push) < 2e-3
        assert abs(run_c.final_theta - run.final_theta) < 2e-3


# --- pushed in, pushed out --------------------------------------------------------------


def test_circle_far_above_b_inf_pushes_every_disk_in():
    """Circle of radius 3a (b_inf = 1.25 a): the disks stick out of it by at most 0.35 a, so
    beta >= 0.71 at first contact, where r*(beta) < 2.7 a: the disk is pushed in, left
    tangent inside at |CM| = 3a - a, and later turns only touch it."""
    rng = np.random.default_rng(SEED + 1)
    r_circle = 3.0
    n = 6
    pts, wts = ss.random_supports(rng, n, A, "dipod")
    depth = rng.uniform(0.05, 0.35, n)
    phi = rng.uniform(0.5, 2 * math.pi - 0.5, n)
    starts = (r_circle - A + depth)[:, None] * np.column_stack([np.cos(phi), np.sin(phi)])
    path = ss.spiral_path([r_circle], final_turns=2.0)
    batch = ss.simulate_spiral_batch(path, pts, wts, A, MU, starts, rng.uniform(0, 2 * math.pi, n), FAST)
    assert batch.all_inside and batch.escaped == 0 and batch.not_optimal == 0
    for run, d in zip(batch.runs, depth):
        (c,) = run.contacts
        # First contact where |P| = R meets |P - CM| = a: sin(beta) = (R^2 - rho^2 + a^2) / (2 a R).
        rho = r_circle - A + d
        assert math.sin(c.beta_initial) == pytest.approx((r_circle**2 - rho**2 + A * A) / (2 * A * r_circle), abs=1e-9)
        assert c.depth_initial < d  # the circle meets the disk nearer grazing than a straight line
        assert c.side == "inside" and c.beta_min >= c.beta_initial - 1e-12
        assert c.cm_radius_end < c.cm_radius_start
        assert run.final_radius == pytest.approx(r_circle - A, abs=1e-7)
        assert np.allclose(run.revolution_cm_radius, r_circle - A, atol=1e-7)


@pytest.mark.slow
def test_gentle_spiral_pushes_in_at_every_contact():
    path = ss.spiral_path(np.linspace(4.0, 3.0, 6))
    batch = ss.spiral_check(path, A, MU, 3, seed=SEED + 2, kind="rim", settings=FAST, start_inner_radius=2.5)
    assert batch.all_inside and batch.not_optimal == 0 and batch.solver_failures == 0
    assert batch.margin >= -FAST.promise_tol
    for run in batch.runs:
        assert run.n_contacts >= 2
        for c in run.contacts:
            assert c.side == "inside" and c.cm_radius_end < c.cm_radius_start
            assert c.beta_min >= c.beta_initial - 1e-12
        # Once reached, the disk's distance from the centre falls every revolution.
        rev = run.revolution_cm_radius
        first = int(np.argmax(rev < rev[0]))
        assert np.all(np.diff(rev[first:]) < 0.0)


@pytest.mark.slow
def test_too_fast_spiral_pushes_disks_out():
    """Delta b = 0.9 a at b = 1.6 a (mu_c = 0.25: b_inf = 1.25 a, and the critical d* there
    is a small fraction of a): some disks are left outside the path."""
    path = ss.spiral_path([2.5, 1.6])
    batch = ss.spiral_check(path, A, MU, 8, seed=SEED + 3, kind="dipod", settings=FAST)
    assert batch.escaped >= 2 and not batch.all_inside
    for i in batch.escaped_indices:
        run = batch.runs[i]
        assert run.status == "escaped" and run.contacts[-1].side == "outside"
        assert run.contacts[-1].beta_min < run.contacts[-1].beta_initial
        assert run.contacts[-1].beta_final == pytest.approx(-math.pi / 2)


# --- convergence, friction, symmetry ----------------------------------------------------


def test_step_converges():
    path = ss.spiral_path([4.0, 3.4, 2.9])
    rng = np.random.default_rng(SEED + 4)
    pts, wts = ss.random_supports(rng, 1, A, "rim")
    start = np.array([-1.5, 2.0])
    runs = [ss.simulate_spiral(path, pts[0], wts[0], A, MU, start, 0.4, ss.SpiralSimSettings(step=h))
            for h in (0.2, 0.1, 0.05)]
    assert all(r.status == "completed" and r.n_contacts >= 2 for r in runs)
    d1 = np.linalg.norm(runs[1].final_cm - runs[0].final_cm)
    d2 = np.linalg.norm(runs[2].final_cm - runs[1].final_cm)
    assert d2 < STEP_TOL * A
    assert d2 < 0.5 * d1  # second order: about a quarter
    assert abs(runs[2].final_theta - runs[1].final_theta) < 10 * STEP_TOL


def test_frictionless_pusher_pushes_along_the_normal():
    path = ss.spiral_path([3.5, 3.0, 2.6])
    batch = ss.spiral_check(path, A, 0.0, 3, seed=SEED + 5, kind="cloud", settings=FAST, start_inner_radius=2.0)
    assert batch.all_inside
    for run in batch.runs:
        assert run.n_contacts >= 1 and set(run.modes) == {"frictionless"}
        assert run.max_force_angle < 1e-9
        assert np.allclose(run.trajectory_theta, run.trajectory_theta[0], atol=1e-9)  # no rotation


def test_friction_cone_holds_with_friction():
    path = ss.spiral_path([3.5, 3.0])
    batch = ss.spiral_check(path, A, MU, 2, seed=SEED + 6, kind="tripod", settings=FAST, start_inner_radius=2.0)
    for run in batch.runs:
        assert run.n_contacts >= 1
        assert run.max_force_angle <= math.atan(MU) + 1e-9


def test_mirror_and_rotation_symmetry(tripods):
    pts, wts = tripods
    start = np.array([1.6, 1.4])
    radii = [3.5, 3.0, 2.7]
    base = ss.simulate_spiral(ss.spiral_path(radii), pts[2], wts[2], A, MU, start, 0.3, FAST)
    assert base.n_contacts >= 2
    mir = ss.simulate_spiral(ss.spiral_path(radii, clockwise=True), mirror(pts[2]), wts[2], A, MU, mirror(start),
                             -0.3, FAST)
    assert np.allclose(mir.trajectory_u, base.trajectory_u, atol=1e-9)
    assert np.allclose(mir.trajectory_cm, mirror(base.trajectory_cm), atol=1e-9)
    assert np.allclose(mir.trajectory_theta, -base.trajectory_theta, atol=1e-9)
    psi = 1.1
    rot = np.array([[math.cos(psi), -math.sin(psi)], [math.sin(psi), math.cos(psi)]])
    turned = ss.simulate_spiral(ss.spiral_path(radii, start_angle=psi), pts[2], wts[2], A, MU, rot @ start,
                                0.3 + psi, FAST)
    assert np.allclose(turned.trajectory_u, base.trajectory_u, atol=1e-9)
    assert np.allclose(turned.trajectory_cm, base.trajectory_cm @ rot.T, atol=1e-9)
    assert np.allclose(turned.trajectory_theta, base.trajectory_theta + psi, atol=1e-9)


def test_bad_inputs_are_refused(tripods):
    pts, wts = tripods
    path = ss.spiral_path([3.0, 2.5])
    with pytest.raises(InvalidInput):
        ss.simulate_spiral(path, 2.0 * pts[0], wts[0], A, MU, [0.0, 0.0])  # support outside the disk
    with pytest.raises(InvalidInput):
        ss.simulate_spiral(path, pts[0], wts[0], A, MU, [2.5, 0.5])  # the pusher starts in the disk
    with pytest.raises(InvalidInput):
        ss.simulate_spiral(path, pts[0], wts[0], A, -0.1, [0.0, 0.0])


def test_time_limit_reports_where_it_got():
    path = ss.spiral_path([4.0, 3.4, 2.9])
    batch = ss.spiral_check(path, A, MU, 3, seed=SEED + 7, settings=FAST, budget=checks_budget(30))
    assert sum(batch.statuses.values()) == 3 and not batch.all_inside
    assert set(batch.statuses) <= {"time_limit", "not_run", "completed"}
    for run in batch.runs:
        if run.status == "time_limit":
            assert run.u_reached < path.u_end and run.path_fraction < 1.0


# --- the worst case of 4.5.2-4.5.3 -------------------------------------------------------


@pytest.fixture(scope="module")
def witness():
    """At beta = 0.8 the lowest sticking COR (solver/sketch/sticking.py, certified bracket of
    1e-6 a) gives r*(beta) = 2.371 a (4.5.3); its witness support (nearly a rim dipod) is
    the support whose COR is that worst one. Points relative to the CM in the frame of
    encounter_scene: push along +x, the disk below the pusher's line."""
    beta = 0.8
    r_star, pts, wts = ss.worst_case_support(A, beta, MU)
    return beta, r_star, pts, wts


def hit_witness(witness, r_contact, shrink):
    """The witness disk hit at collision parameter beta by a counter-clockwise pusher
    whose radius is r_contact at the contact and falls by ``shrink`` per revolution (0: a
    circle). The path runs counter-clockwise, the mirror image of the book's drawing, so
    the support is mirrored too (x along the push, the book's 'down' towards the centre)."""
    beta, _, pts, wts = witness
    u0 = 0.3
    b1 = r_contact + shrink * u0 / (2 * math.pi)
    path = ss.spiral_path([b1, b1 - shrink], final_turns=0.0) if shrink > 0 else ss.spiral_path([b1], final_turns=0.3)
    cm, frame = ss.collision_pose(path, u0, beta, A)
    assert np.linalg.det(frame) == pytest.approx(-1.0)  # counter-clockwise: the mirror image
    body = pts @ frame.T
    run = ss.simulate_spiral(path, body, wts, A, MU, cm, settings=ss.SpiralSimSettings(step=0.02))
    first = run.contacts[0]
    assert first.beta_initial == pytest.approx(beta, abs=1e-9) and run.not_optimal == 0
    return run, first


@pytest.mark.slow
def test_witness_of_the_critical_radius_agrees_with_r_star(witness):
    """On circles (4.5.2, figure 4-18): 1 % tighter than r*(beta) the worst COR lies right of
    the critical line and beta falls (pushed out); 0.2 % looser, beta never falls (at worst
    chased: in contact for the whole 0.3 turns or pushed in)."""
    _, r_star, _, _ = witness
    _, tight = hit_witness(witness, 0.99 * r_star, 0.0)
    assert tight.beta_min < tight.beta_initial - 1e-3
    _, loose = hit_witness(witness, 1.002 * r_star, 0.0)
    assert loose.beta_min == pytest.approx(loose.beta_initial, abs=1e-12)


@pytest.mark.slow
def test_a_shrinking_spiral_loses_the_worst_disk_at_the_critical_radius(witness):
    """The book's recursion (4.26) sets the pusher's radius to r*(beta) at the collision and
    says that at worst the disk is chased (4.5.5). On a spiral the pusher keeps moving in
    during the chase: hit at 1.002 r*(beta) by a spiral shrinking 0.2 a or 0.5 a per
    revolution, the worst disk is pushed OUT and lost (the book's 'slightly slower spiral',
    which it does not quantify, is needed); at 1.01 r*(beta) it is pushed in."""
    _, r_star, _, _ = witness
    for shrink in (0.2, 0.5):
        run, first = hit_witness(witness, 1.002 * r_star, shrink)
        assert run.status == "escaped" and first.side == "outside"
    run, first = hit_witness(witness, 1.01 * r_star, 0.5)
    assert run.status == "completed" and first.side == "inside"
    assert first.beta_min == pytest.approx(first.beta_initial, abs=1e-12)


# --- a planned schedule (4.26) ----------------------------------------------------------


@pytest.fixture(scope="module")
def planned():
    """mu_c = 0.25, b_1 = 6 a: the recursion (4.26) (models/spiral.fastest_spiral) on the
    exact critical radius (solver.spiral.critical_radius.critical_radius_table, certified brackets) at a
    coarse beta grid (the envelope rounds to the safe side between grid points), to 1.7 a."""
    spiral = pytest.importorskip("solver.spiral.critical_radius")
    mspiral = pytest.importorskip("models.spiral.path")
    betas = np.array([0.45, 0.6, 0.75, 0.9, 1.05, 1.2, 1.35, 1.5, 1.56])
    table = spiral.critical_radius_table(A, MU, "exact", betas=betas, find_kink=False)
    rec = mspiral.fastest_spiral(table.envelope, 6.0, target=1.7)
    assert rec.reached_target
    env = table.envelope

    def r_star_bound(beta):
        """An upper bound of r*(beta): the envelope value of beta's cell (inf below it)."""
        k = np.searchsorted(env.betas, beta, side="right") - 1
        return np.where(k >= 0, env.envelope[np.clip(k, 0, None)], np.inf)

    return rec, ss.spiral_path(rec.radii), r_star_bound


@pytest.mark.slow
def test_planned_schedule_herds_random_supports_into_the_promise(planned):
    """16 random supports of four kinds, random orientations, CMs uniform inside b_1 - a:
    none is pushed out, all end inside b_N, beta never falls during a contact, and the
    book's own criterion (pusher radius >= r*(beta), 4.5.2-4.5.3) holds at every simulated
    instant of every contact (against the envelope's upper bound of r* on each beta cell),
    so it would for any support. The slack comes from the collision depth: on a circular
    pass it is Delta b (1 - a/b + Delta b / 2b), not the Delta b that 4.5.1 assumes."""
    rec, path, r_star_bound = planned
    for j, kind in enumerate(ss.SUPPORT_KINDS):
        seed = SEED + 10 + j
        batch = ss.spiral_check(path, A, MU, 4, seed=seed, kind=kind, settings=FAST)
        assert batch.not_optimal == 0 and batch.solver_failures == 0
        assert batch.escaped == 0, f"(4.26) failed: kind {kind}, seed {seed}, runs {batch.escaped_indices}"
        assert batch.all_inside, f"kind {kind}, seed {seed}: outside the promise {batch.outside_promise_indices}"
        assert batch.max_final_extent <= rec.radii[-1] + FAST.promise_tol * A
        assert batch.min_beta_change >= -1e-12
        for run in batch.runs:
            margins = ss.criterion_margins(run, path, r_star_bound)
            assert np.all(margins > 0.0), f"kind {kind}, seed {seed}: margin {margins.min()}"
