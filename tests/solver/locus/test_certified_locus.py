"""Certified loci (solver/locus/certified_locus.py): the analytic disk boundary of chapter 3
bracketed point by point, and exact polygon loci (7.5, figure 3-6) traced by certified
brackets, checked against nested disks, forward-solved tripods and a deliberately wrong
boundary."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.core.scene import PushScene
from models.core.support import random_balanced_tripods
from models.locus import cor_disk as cd
from solver.core.budget import Budget
from solver.core.tolerances import SOLVER_DEFAULT
from solver.locus.certified_locus import (
    STRICT_WITNESS_RESIDUAL,
    certified_disk_boundary,
    certified_polygon_boundary,
    certify_brackets,
    outward_normals,
    polygon_trace,
    ray_exit,
    trace_ray,
)
from solver.locus.membership import membership
from solver.motion.forward import solve_forward_batch
from tests.scenes import SEED, point_in_polygon, scene_for_mu
from tests.solver.locus.membership_checks import (
    FRAME,
    SQUARE,
    check_dual,
    disk_samples,
    equations_residual,
    polygon_samples,
)

TOL = SOLVER_DEFAULT


def recompute_error(sc, res, length) -> float:
    """Rounding error of the naive recomputation of (w - r)/|w - r| in equations_residual for
    support points close to r (the solver itself works in coordinates centred on r)."""
    w = res.witness_points - sc.center_of_mass
    r = res.cor - sc.center_of_mass
    s = abs(float(sc.alpha_hat @ (sc.contact_rel - r)))
    rho = np.linalg.norm(w - r, axis=1)
    scale = np.linalg.norm(w, axis=1) + np.linalg.norm(r)
    return float(res.witness_weights @ (8 * np.finfo(float).eps * (1 + s / length) * (1 + scale / rho))) + 1e-14


# --- the disk: chapter 3's analytic boundary ---------------------------------------------------


@pytest.mark.slow
@pytest.mark.parametrize("mu", [0.05, 0.5, 0.9, 1.5])
def test_certified_disk_boundary_matches_the_analytic_one(mu):
    """(3.30), (3.35) and the perimeter arcs (models/locus/cor_disk.py): at every boundary point
    the pair r -+ delta nu (delta = boundary_bracket a / 2) is certified inside / outside, so
    the true boundary passes within delta of the analytic one. 3.3.13 notes that the
    quotient-locus boundaries behind these formulas were only checked empirically; this is
    a certificate at each point."""
    sc = scene_for_mu(mu, **FRAME)
    a = sc.disk_radius
    res = certified_disk_boundary(sc, n_points=32)
    assert len(res.pairs) == len(res.boundary) >= 32
    assert res.delta == pytest.approx(0.5 * TOL.boundary_bracket * a)
    assert res.wrong == () and res.undecided == ()
    assert res.n_certified == len(res.pairs)
    assert res.max_error_bound == res.delta
    samples = disk_samples(sc, n_rings=80, n_rim=720)
    for k, pair in enumerate(res.pairs):
        assert np.linalg.norm(pair.inner.cor - (pair.point - res.delta * pair.normal)) <= 1e-12 * a
        assert np.linalg.norm(pair.outer.cor - (pair.point + res.delta * pair.normal)) <= 1e-12 * a
        assert pair.inner.witness_residual <= STRICT_WITNESS_RESIDUAL
        assert equations_residual(sc, pair.inner, a) <= STRICT_WITNESS_RESIDUAL + recompute_error(sc, pair.inner, a)
        if k % 8 == 0:  # the dual certificates, independently (dense 2-D sampling)
            check_dual(sc, pair.outer, samples, a)


@pytest.mark.parametrize("factor, verdict", [(0.99, "both_inside"), (1.01, "both_outside")])
def test_a_wrong_boundary_is_caught(factor, verdict):
    """Negative control: the analytic boundary shrunk or grown by 1% about the CM is not the
    boundary, and every bracket must say so."""
    sc = scene_for_mu(0.3, **FRAME)
    ring = cd.disk_cor_locus(sc, n_points=16).boundary
    moved = sc.center_of_mass + factor * (ring - sc.center_of_mass)
    pairs = certify_brackets(sc, moved, outward_normals(moved), 0.5 * TOL.boundary_bracket * sc.disk_radius)
    assert [p.verdict for p in pairs] == [verdict] * len(pairs)


def test_translation_scene_has_no_boundary_to_certify():
    sc = scene_for_mu(0.0)
    with pytest.raises(InvalidInput):
        certified_disk_boundary(sc, n_points=16)
    with pytest.raises(InvalidInput):
        certified_polygon_boundary(sc, SQUARE, n_rays=4)


# --- polygons (7.5, figure 3-6) -----------------------------------------------------------------


def assert_inside_own_rays(sc, footprint, cors, traced):
    """Each COR lies no farther from the centre than the certified crossing on its own ray
    (trace_ray), i.e. inside the locus as traced exactly along that ray."""
    trace = polygon_trace(sc, footprint)
    for cor in cors:
        ray = trace_ray(trace, cor - traced.centre)
        assert ray.verdict == "bracketed"
        assert np.linalg.norm(cor - traced.centre) <= ray.t_out * traced.length_scale


def _disk_scene(sc: PushScene, radius: float) -> PushScene:
    return PushScene.create(radius, sc.contact_point, sc.edge_angle, sc.push_direction, sc.center_of_mass)


def _ray_distances(traced, ring):
    return np.array([ray_exit(ring, traced.centre, ray.direction) for ray in traced.rays])


@pytest.fixture(scope="module")
def square_trace():
    sc = scene_for_mu(0.3, a=SQUARE.circumradius)
    return sc, certified_polygon_boundary(sc, SQUARE, n_rays=32)


@pytest.mark.slow
def test_square_trace_is_certified_and_star_shaped(square_trace):
    sc, tr = square_trace
    assert tr.centre_result.status == "inside"
    assert np.allclose(tr.centre, sc.center_of_mass)  # the CM is a COR (point mass there)
    assert tr.n_certified == len(tr.rays) == 32
    assert tr.uncertified_rays == () and tr.multi_crossing_rays == ()
    for ray in tr.rays:
        assert ray.inner.status == "inside" and ray.outer.status == "outside"
        assert ray.outer.lower_bound_method == "branch_and_bound"
        assert (ray.t_out - ray.t_in) * tr.length_scale <= tr.width * (1 + 1e-9)
        assert ray.inner.witness_residual <= STRICT_WITNESS_RESIDUAL


@pytest.mark.slow
def test_square_locus_lies_between_its_inscribed_and_circumscribed_disks(square_trace):
    """7.5: a footprint inside another with the same CM has a locus inside the other's. The
    square holds its inscribed disk (radius 1/2) and sits in its circumscribed one, so along
    every ray its crossing lies between theirs (analytic, 3.30/3.35); and it is strictly
    smaller than the circumscribed disk's somewhere (figure 3-6)."""
    sc, tr = square_trace
    outer = _ray_distances(tr, cd.disk_cor_locus(_disk_scene(sc, SQUARE.circumradius), n_points=4096).boundary)
    inner = _ray_distances(tr, cd.disk_cor_locus(_disk_scene(sc, 0.5), n_points=4096).boundary)
    t_in = np.array([r.t_in for r in tr.rays]) * tr.length_scale
    t_out = np.array([r.t_out for r in tr.rays]) * tr.length_scale
    chord = 1e-5 * outer  # the 4096-point reference polygons' own chord error
    assert np.all(t_in <= outer + chord)
    assert np.all(t_out >= inner - chord)
    assert np.min(t_out / outer) < 0.75


@pytest.mark.slow
def test_random_tripod_cors_fall_inside_the_traced_square_locus(square_trace):
    """3.3.3 / figure 3-6: CORs of random tripods on the square (forward Newton solves) lie
    inside the traced boundary; one that falls outside the traced polygon (a chord cutting
    the boundary) must lie inside the certified crossing of its own ray."""
    sc, tr = square_trace
    rng = np.random.default_rng(SEED)
    pts, wts = random_balanced_tripods(rng, 5000, SQUARE.circumradius, footprint=SQUARE)
    out = solve_forward_batch(sc, pts, wts)
    cors = out.cor[out.converged & ~np.isnan(out.cor[:, 0])]
    assert len(cors) > 4000
    outside_polygon = cors[~point_in_polygon(cors, tr.boundary)]
    assert len(outside_polygon) < 0.01 * len(cors)
    assert_inside_own_rays(sc, SQUARE, outside_polygon, tr)


@pytest.mark.slow
def test_regular_polygon_locus_is_squeezed_between_two_disks():
    """7.5 on a 24-gon: it contains the disk of radius cos(pi/24) and lies in the unit disk
    (same CM), so its traced locus lies between those two disks' analytic loci along every
    ray; both are within 1% of each other here, so this pins the trace down."""
    n = 24
    th = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False) + 0.1
    poly = Footprint.create(np.column_stack([np.cos(th), np.sin(th)]), center_of_mass=(0.0, 0.0))
    sc = scene_for_mu(0.9, a=1.0)
    tr = certified_polygon_boundary(sc, poly, n_rays=8)
    assert tr.n_certified == 8
    outer = _ray_distances(tr, cd.disk_cor_locus(sc, n_points=4096).boundary)
    inner = _ray_distances(tr, cd.disk_cor_locus(_disk_scene(sc, math.cos(math.pi / n)), n_points=4096).boundary)
    t_in = np.array([r.t_in for r in tr.rays]) * tr.length_scale
    t_out = np.array([r.t_out for r in tr.rays]) * tr.length_scale
    assert np.all(t_in <= outer * (1 + 1e-5))
    assert np.all(t_out >= inner * (1 - 1e-5))


@pytest.mark.slow
def test_u_shape_whose_centre_of_mass_is_not_a_cor():
    """A U whose CM lies in its notch, off the footprint: no point mass can sit at the CM,
    and the CM is certified not a COR (dual checked on a dense grid of the U, 3.8). The trace
    then starts from the certified COR of uniform pressure (3.7) and still certifies every
    ray; CORs of random tripods on the U fall inside the traced 12-gon or, where a chord cuts
    the boundary, inside the certified crossing of their own ray."""
    u_shape = Footprint.create([(0, 0), (3, 0), (3, 3), (2, 3), (2, 1), (1, 1), (1, 3), (0, 3)])
    ell = u_shape.circumradius
    sc = scene_for_mu(0.4, a=ell, cm=u_shape.center_of_mass)
    at_cm = membership(sc, sc.center_of_mass, u_shape)
    assert not at_cm.in_footprint
    check_dual(sc, at_cm, polygon_samples(u_shape), ell)
    tr = certified_polygon_boundary(sc, u_shape, n_rays=12)
    assert np.linalg.norm(tr.centre - sc.center_of_mass) > 0.1 * ell
    assert tr.centre_result.status == "inside"
    assert tr.n_certified == 12
    rng = np.random.default_rng(SEED + 5)
    pts, wts = random_balanced_tripods(rng, 1000, ell, footprint=u_shape)
    out = solve_forward_batch(sc, pts, wts)
    cors = out.cor[out.converged & ~np.isnan(out.cor[:, 0])]
    outside_polygon = cors[~point_in_polygon(cors, tr.boundary)]
    assert len(outside_polygon) < 0.05 * len(cors)
    assert_inside_own_rays(sc, u_shape, outside_polygon, tr)


def test_time_limits_stop_early_and_say_so():
    """A certified boundary under a zero time limit does one point (disk) or no ray
    (polygon) and reports itself incomplete; with no limit it is complete."""
    sc = scene_for_mu(0.3)
    disk = certified_disk_boundary(sc, n_points=16, budget=Budget.of(0.0))
    assert not disk.complete and len(disk.pairs) == 1 and len(disk.boundary) == 16
    square = Footprint.create([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]])
    sq_scene = scene_for_mu(0.3, a=square.circumradius, cm=square.center_of_mass)
    poly = certified_polygon_boundary(sq_scene, square, n_rays=8, budget=Budget.of(0.0))
    assert not poly.complete and len(poly.rays) == 0 and poly.n_requested == 8
    full = certified_disk_boundary(sc, n_points=8)
    assert full.complete and full.n_certified == 8
