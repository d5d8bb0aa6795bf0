"""The multi-start tripod NLP (Mason's theorem 5, book 1.6.3, 3.3.3) as an independent
check of the analytic disk locus (3.3.4-3.3.12, models/locus/cor_disk.py), and on polygons
against the circumscribing disk and against brute-force sampling of tripods."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.footprint import Footprint, triangle_areas, triangulate
from models.core.support import Support
from models.locus import cor_disk as cd
from solver.core.errors import NotConverged, SolverError
from solver.core.outcome import Outcome
from solver.core.tolerances import SOLVER_DEFAULT, SolverTolerances
from solver.motion import tripod_search as ts
from solver.motion.forward import solve_forward
from tests.budgets import checks_budget
from tests.scenes import SEED, distance_to_polyline, point_in_polygon, scene_for_mu

SQUARE = [[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]]
L_SHAPE = [[0, 0], [3, 0], [3, 1], [1, 1], [1, 2.5], [0, 2.5]]


def support(boundary: np.ndarray, cm: np.ndarray, d: np.ndarray) -> float:
    """max d . (b - CM) over the vertices of the analytic boundary polygon."""
    return float(np.max((boundary - cm) @ d))


def inside_or_on(point: np.ndarray, boundary: np.ndarray, slack: float) -> bool:
    return bool(point_in_polygon(point[None], boundary)[0] or distance_to_polyline(point[None], boundary)[0] <= slack)


# --- the disk: the NLP against the analytic locus ------------------------------------------


@pytest.mark.parametrize("mu", [0.3, 0.6])
def test_disk_tip_is_reached_from_inside_3_37(mu):
    """Along the axis the extreme tripod COR is the tip a^2/|alpha . c| (3.37), reached by
    the diametral dipod perpendicular to the axis (figure 3-12 at omega = pi/2)."""
    sc = scene_for_mu(mu, a=1.7, cm=(0.4, -0.9), edge_angle=1.2, push_direction=0.3)
    a = sc.disk_radius
    tip = cd.disk_cor_locus(sc, outputs=("tip",)).tip
    res = ts.extreme_cor_search(sc, tip.point - sc.center_of_mass, n_starts=8, seed=SEED)
    assert res.objective <= tip.distance + 1e-9 * a  # never beyond the analytic tip
    assert tip.distance - res.objective <= 1e-8 * a  # and it gets there (brief: 1e-3 a)
    assert np.linalg.norm(res.cor - tip.point) <= 1e-6 * a
    assert res.n_verified >= 1 and res.verification in ("cor", "power")
    loaded = res.weights > 0.0
    assert loaded.sum() == 2
    rel = res.points[loaded] - sc.center_of_mass
    assert np.allclose(np.linalg.norm(rel, axis=1), a, rtol=1e-9)  # on the rim
    assert np.allclose(rel @ tip.point, rel @ sc.center_of_mass, atol=1e-6 * a * a)  # perpendicular to the axis
    assert np.allclose(res.weights[loaded], 0.5, atol=1e-9)


@pytest.mark.parametrize("mu", [0.3, 0.6])
@pytest.mark.parametrize("side", [1.0, -1.0])
def test_disk_perpendicular_extreme_stays_inside_and_converges(mu, side):
    """Across the axis the extreme is where the boundary meets the disk, (3.32): a COR on a
    support point, which the NLP approaches to within its support margin."""
    sc = scene_for_mu(mu)
    a = sc.disk_radius
    loc = cd.disk_cor_locus(sc, outputs=("boundary", "disk_crossings"), n_points=4096)
    d = side * np.array([-loc.axis[1], loc.axis[0]])
    h = support(loc.boundary, sc.center_of_mass, d)
    crossing = loc.disk_crossings.points[np.argmax(loc.disk_crossings.points @ d)]
    gaps = []
    for margin in (1e-3, 1e-5):
        res = ts.extreme_cor_search(sc, d, n_starts=8, seed=SEED, support_margin=margin)
        assert inside_or_on(res.cor, loc.boundary, 1e-9 * a)
        gap = h - res.objective
        assert 0.0 < gap <= margin * a
        assert np.linalg.norm(res.cor - crossing) <= 2.0 * margin * a
        gaps.append(gap)
    assert gaps[1] < 0.05 * gaps[0]  # linear convergence in the margin


def test_disk_oblique_directions_stay_inside():
    """Directions between axis and perpendicular land on the outer boundary (3.35)."""
    sc = scene_for_mu(0.45, edge_angle=2.0)
    a = sc.disk_radius
    loc = cd.disk_cor_locus(sc, outputs=("boundary",), n_points=8192)
    perp = np.array([-loc.axis[1], loc.axis[0]])
    for ang in (0.4, 0.9):
        d = math.cos(ang) * loc.axis + math.sin(ang) * perp
        res = ts.extreme_cor_search(sc, d, n_starts=8, seed=SEED)
        h = support(loc.boundary, sc.center_of_mass, d)
        # the chord polygon's support function is below the true one by < 1e-6 a here
        assert abs(res.objective - h) <= 1e-6 * a
        assert distance_to_polyline(res.cor[None], loc.boundary)[0] <= 1e-6 * a


# --- polygons --------------------------------------------------------------------------------


def polygon_scene(vertices, mu, edge_angle=1.3):
    fp = Footprint.create(vertices)
    sc = scene_for_mu(mu, a=fp.circumradius, cm=fp.center_of_mass, edge_angle=edge_angle)
    return fp, sc


@pytest.mark.slow
def test_square_stays_inside_the_circumscribing_disk_locus():
    """The square's supports are supports of its circumscribing disk, so its extremes lie in
    the disk's locus. Along the axis the best tripod is the diagonal dipod, whose COR lies
    on the disk boundary (a diametral dipod, figure 3-12): the search reaches it."""
    fp, sc = polygon_scene(SQUARE, 0.3)
    a = sc.disk_radius
    loc = cd.disk_cor_locus(sc, outputs=("boundary", "tip"), n_points=4096)
    perp = np.array([-loc.axis[1], loc.axis[0]])
    for d in (loc.axis, perp, -perp):
        res = ts.extreme_cor_search(sc, d, footprint=fp, n_starts=10, seed=SEED)
        assert inside_or_on(res.cor, loc.boundary, 1e-7 * a)
        assert res.objective <= support(loc.boundary, sc.center_of_mass, d) + 1e-7 * a
        assert np.all(fp.vertices.min(axis=0) - 1e-12 <= res.points) and np.all(res.points <= fp.vertices.max(axis=0) + 1e-12)
    res = ts.extreme_cor_search(sc, loc.axis, footprint=fp, n_starts=10, seed=SEED)
    diagonals = [np.array([fp.vertices[i], fp.vertices[i + 2]]) for i in (0, 1)]
    dipod = max(float(loc.axis @ (solve_forward(sc, Support.create(dg, [1, 1], sc.center_of_mass)).cor - sc.center_of_mass)) for dg in diagonals)
    assert res.objective >= dipod - 1e-9 * a
    assert res.objective < loc.tip.distance - 0.1 * a  # the square's locus is smaller


def test_non_convex_polygon_beats_brute_force_tripods():
    """L-shaped footprint: the NLP's extreme is at least as far as the best of 60 random
    tripods on the footprint (forward solves), stays in the circumscribing disk's locus,
    and its feet are on the footprint (not merely in its convex hull)."""
    fp, sc = polygon_scene(L_SHAPE, 0.4, edge_angle=0.8)
    a = sc.disk_radius
    loc = cd.disk_cor_locus(sc, outputs=("boundary",), n_points=4096)
    d = loc.axis
    res = ts.extreme_cor_search(sc, d, footprint=fp, n_starts=16, seed=SEED)
    # independent sampler: rejection from the bounding box, weights centring the CM (3.3.3)
    rng = np.random.default_rng(SEED + 1)
    lo, hi = fp.vertices.min(axis=0), fp.vertices.max(axis=0)
    best_random, count = -np.inf, 0
    while count < 60:
        feet = rng.uniform(lo, hi, size=(3, 2))
        if not np.all(point_in_polygon(feet, fp.vertices)):
            continue
        rel = feet - sc.center_of_mass
        p = np.linalg.solve(np.vstack([np.ones(3), rel.T]), [1.0, 0.0, 0.0])
        if np.any(p <= 1e-3):
            continue
        count += 1
        cor = solve_forward(sc, Support.create(feet, p, sc.center_of_mass)).cor
        best_random = max(best_random, float(d @ (cor - sc.center_of_mass)))
    assert res.objective >= best_random
    assert inside_or_on(res.cor, loc.boundary, 1e-7 * a)
    on_footprint = point_in_polygon(res.points, fp.vertices) | np.array([fp.distance_to_outline(p) <= 1e-9 * a for p in res.points])
    assert np.all(on_footprint)
    assert len(res.optima) >= 2  # a non-convex footprint has several local optima


# --- search behaviour ----------------------------------------------------------------------


def test_seeded_and_reproducible():
    sc = scene_for_mu(0.5)
    d = np.array([0.3, 1.0])
    r1 = ts.extreme_cor_search(sc, d, n_starts=5, seed=3)
    r2 = ts.extreme_cor_search(sc, d, n_starts=5, seed=3)
    assert r1.objective == r2.objective and np.array_equal(r1.cor, r2.cor)
    assert [s.status for s in r1.starts] == [s.status for s in r2.starts]
    assert np.allclose(r1.direction, d / np.linalg.norm(d))


def test_time_limit_stops_launching_starts():
    """A budget of 4 clock readings: one at the build, one before each start; the fourth
    start finds it expired, and so does every later one."""
    sc = scene_for_mu(0.5)
    res = ts.extreme_cor_search(sc, [1.0, 0.0], n_starts=1000, seed=1, budget=checks_budget(4))
    assert res.time_limit_reached and not res.complete
    assert [s.status == "skipped_time_limit" for s in res.starts] == [False] * 3 + [True] * 997
    assert [s.complete for s in res.starts] == [True] * 3 + [False] * 997
    assert res.message.endswith("; 997 not run (time limit)")


def test_every_start_is_reported():
    sc = scene_for_mu(0.3)
    res = ts.extreme_cor_search(sc, [0.0, 1.0], n_starts=6, seed=2)
    assert len(res.starts) == 6
    assert res.n_verified + res.n_power_verified == sum(s.verification in ("cor", "power") for s in res.starts)
    for s in res.starts:
        if s.verification in ("cor", "power"):
            assert s.feasible and s.stationarity <= 1e-8
            assert s.objective <= res.objective
        if s.verification == "cor":
            assert s.forward_distance <= SOLVER_DEFAULT.witness_cor_rel
        if s.verification == "power":
            assert s.power_excess <= SOLVER_DEFAULT.kkt


def test_results_are_outcomes():
    res = ts.extreme_cor_search(scene_for_mu(0.3), [0.0, 1.0], n_starts=4, seed=2)
    assert isinstance(res, Outcome) and res.status == "found" and res.complete
    assert res.message.startswith(f"extreme COR verified by {res.verification} check: {res.n_verified} of 4")
    for s in res.starts:
        assert isinstance(s, Outcome) and s.complete and s.message.startswith(f"start {s.index}: {s.status}")


@pytest.mark.slow
def test_unverifiable_search_raises():
    """With checks that nothing can pass, the search refuses to answer."""
    impossible = SolverTolerances(kkt=-1.0)
    with pytest.raises(NotConverged, match="verified"):
        ts.extreme_cor_search(scene_for_mu(0.5), [1.0, 0.0], n_starts=3, seed=0, verify_rel=0.0, tol=impossible)


def test_casadi_failure_becomes_solver_error(monkeypatch):
    def broken(*args, **kwargs):
        raise RuntimeError("plugin missing")

    monkeypatch.setattr(ts.ca, "nlpsol", broken)
    with pytest.raises(SolverError, match="plugin missing"):
        ts.extreme_cor_search(scene_for_mu(0.5), [1.0, 0.0], n_starts=1)


@pytest.mark.parametrize(
    "kwargs,field",
    [
        (dict(direction=[0.0, 0.0]), "direction"),
        (dict(direction=[float("nan"), 1.0]), "direction"),
        (dict(direction=[1.0, 0.0, 0.0]), "direction"),
        (dict(n_starts=0), "n_starts"),
        (dict(support_margin=0.0), "support_margin"),
    ],
)
def test_invalid_arguments(kwargs, field):
    args = dict(direction=[1.0, 0.0])
    args.update(kwargs)
    with pytest.raises(InvalidInput) as err:
        ts.extreme_cor_search(scene_for_mu(0.5), **args)
    assert err.value.field == field


def test_translation_and_foreign_footprint_are_refused():
    with pytest.raises(InvalidInput) as err:
        ts.extreme_cor_search(scene_for_mu(0.0), [1.0, 0.0])
    assert err.value.field == "contact_point"
    fp = Footprint.create(SQUARE)
    with pytest.raises(InvalidInput) as err:
        ts.extreme_cor_search(scene_for_mu(0.3, cm=(0.2, 0.0)), [1.0, 0.0], footprint=fp)
    assert err.value.field == "center_of_mass"


# --- triangulation -----------------------------------------------------------------------------




def test_random_start_tripods_are_centred_on_the_cm():
    """3.3.3: start tripods have weights >= MIN_START_WEIGHT putting the centroid on the CM."""
    rng = np.random.default_rng(SEED)
    fp = Footprint.create(L_SHAPE)
    tris = triangulate(fp.vertices - fp.center_of_mass)
    for _ in range(20):
        feet, q0, _, p0 = ts.draw_start(rng, None, None)
        assert np.all(np.linalg.norm(feet, axis=1) <= 1.0)
        assert np.allclose(p0 @ feet, 0.0, atol=1e-12) and np.all(p0 >= ts.MIN_START_WEIGHT)
        assert np.array_equal(q0, feet.reshape(-1))
        feet, q0, idx, p0 = ts.draw_start(rng, tris, triangle_areas(tris))
        assert np.all(point_in_polygon(feet + fp.center_of_mass, fp.vertices))
        assert np.allclose(p0 @ feet, 0.0, atol=1e-12) and np.all(p0 >= ts.MIN_START_WEIGHT)
        assert np.all(q0 >= 0.0) and np.all(q0.reshape(3, 2).sum(axis=1) <= 1.0)
