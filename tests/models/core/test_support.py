"""Discrete pressure distributions (models/core/support.py; book 3.1.5, 3.3.3, 7.1, 7.5): a
support's centroid is its CM (else refused, naming the weights), balanced tripods put it
there, uniform pressure on a disk or a polygon has its exact area centroid and weights
proportional to area, and random balanced tripods (figure 3-5) are seeded and balanced."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.core.inertia import polygon_second_moments
from models.core.support import (
    Support,
    SupportBatch,
    balancing_weights,
    random_balanced_tripods,
    uniform_disk_support,
    uniform_polygon_support,
)
from models.core.tolerances import SupportTolerances
from tests.scenes import SEED

L_SHAPE = Footprint.create([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]])


def test_create_normalises_merges_and_checks_the_centroid_3_1_5():
    s = Support.create([[1.0, 0.0], [-1.0, 0.0], [1.0, 0.0], [0.0, 5.0]], [1.0, 2.0, 1.0, 0.0], [0.0, 0.0])
    assert s.weights.sum() == pytest.approx(1.0) and len(s.points) == 2  # merged, zero weight dropped
    assert np.allclose(s.weights @ s.points, 0.0)
    with pytest.raises(InvalidInput) as err:
        Support.create([[1.0, 0.0], [-1.0, 0.0]], [1.0, 2.0], [0.0, 0.0])
    assert err.value.field == "weights" and "3.1.5" in err.value.reason
    loose = Support.create([[1.0, 0.0], [-1.0, 0.0]], [1.0, 1.0 + 1e-8], [0.0, 0.0], SupportTolerances(centroid_rel=1e-6))
    assert len(loose.points) == 2


@pytest.mark.parametrize("points,weights,field", [
    ([[0.0, 0.0]], [1.0, 2.0], "weights"),
    ([[0.0, float("nan")]], [1.0], "points"),
    ([[0.0, 0.0]], [-1.0], "weights"),
    ([[0.0, 0.0]], [0.0], "weights"),
    ([], [], "points"),
])
def test_bad_supports_name_the_field(points, weights, field):
    with pytest.raises(InvalidInput) as err:
        Support.create(points, weights, [0.0, 0.0])
    assert err.value.field == field


def test_balanced_tripod_weights_3_3_3():
    s = Support.balanced([[1.0, 0.0], [-0.5, 0.8], [-0.4, -0.9]], [0.0, 0.0])
    assert np.all(s.weights > 0.0) and np.allclose(s.weights @ s.points, 0.0, atol=1e-15)
    with pytest.raises(InvalidInput):
        Support.balanced([[1.0, 0.0], [2.0, 0.0], [3.0, 0.1]], [0.0, 0.0])  # CM outside the triangle


def test_uniform_disk_support_has_the_exact_centroid_and_second_moment():
    """Annular-sector cells at their exact centroids: the centroid is the CM, and the
    second moment approaches a^2/2 (uniform disk, 7.1) as the rings refine."""
    a, cm = 2.0, np.array([0.3, -1.0])
    s = uniform_disk_support(a, cm, rings=40)
    assert np.allclose(s.weights @ s.points, cm, atol=1e-14)
    second = s.weights @ np.sum((s.points - cm) ** 2, axis=1)
    assert second == pytest.approx(a * a / 2.0, rel=2e-3)
    with pytest.raises(InvalidInput):
        uniform_disk_support(0.0)


def test_uniform_polygon_support_is_the_area_centroid_with_area_weights():
    s = uniform_polygon_support(L_SHAPE, subdivisions=24)
    assert np.allclose(s.weights @ s.points, L_SHAPE.center_of_mass, atol=1e-14)
    # the polar second moment about the CM approaches the exact one (models.core.inertia)
    area, polar = polygon_second_moments(L_SHAPE.vertices, L_SHAPE.center_of_mass)
    second = s.weights @ np.sum((s.points - L_SHAPE.center_of_mass) ** 2, axis=1)
    assert second == pytest.approx(polar / area, rel=2e-3)
    moved = Footprint.create(L_SHAPE.vertices, center_of_mass=[0.5, 0.5])
    with pytest.raises(InvalidInput) as err:
        uniform_polygon_support(moved)
    assert err.value.field == "center_of_mass"


def test_random_balanced_tripods_are_seeded_balanced_and_inside():
    """Figure 3-5's model: three points uniform in the disk (or footprint), weights >= 0
    with the centroid at the CM; equal seeds give equal draws."""
    for fp in (None, L_SHAPE):
        pts, wts = random_balanced_tripods(np.random.default_rng(SEED), 500, 1.5, (0.2, 0.1), footprint=fp)
        again, _ = random_balanced_tripods(np.random.default_rng(SEED), 500, 1.5, (0.2, 0.1), footprint=fp)
        cm = np.array([0.2, 0.1]) if fp is None else fp.center_of_mass
        assert pts.shape == (500, 3, 2) and np.array_equal(pts, again)
        assert np.all(wts >= 0.0) and np.allclose(wts.sum(axis=1), 1.0)
        assert np.allclose(np.einsum("nk,nkd->nd", wts, pts), cm, atol=1e-12)
        if fp is None:
            assert np.all(np.hypot(*(pts - cm).reshape(-1, 2).T) <= 1.5)
    thin = Footprint.create([[0, 0], [10, 0], [10, 0.01], [0, 0.01]], center_of_mass=[9.99, 0.005])
    with pytest.raises(InvalidInput):
        random_balanced_tripods(np.random.default_rng(SEED), 50, 1.0, footprint=thin, max_draws=3)
    assert math.isfinite(float(wts.sum()))


def test_a_support_batch_is_its_supports_one_by_one_3_1_5():
    """SupportBatch.create checks a batch at once as Support.create checks each support:
    the same normalised weights, and the first bad support is named by its index."""
    points, weights = random_balanced_tripods(np.random.default_rng(SEED), 200, 1.0, center_of_mass=(0.3, -0.2))
    weights = weights * np.random.default_rng(SEED).uniform(1.0, 5.0, (200, 1))  # unnormalised
    batch = SupportBatch.create(points, weights, (0.3, -0.2))
    for j in (0, 57, 199):
        one = Support.create(points[j], weights[j], (0.3, -0.2))
        np.testing.assert_allclose(batch.weights[j], one.weights, rtol=1e-15, atol=0)
    assert len(batch) == 200
    off = points.copy()
    off[123, 0] += (0.5, 0.0)  # moves support 123's centroid off the CM
    with pytest.raises(InvalidInput) as err:
        SupportBatch.create(off, weights, (0.3, -0.2))
    assert err.value.field == "weights" and "support 123" in err.value.reason and "3.1.5" in err.value.reason


@pytest.mark.parametrize("change,field,index", [
    (lambda p, w: w.__setitem__((7, 1), 0.0), "weights", 7),
    (lambda p, w: w.__setitem__((9, 2), -1.0), "weights", 9),
    (lambda p, w: (p.__setitem__(4, [[1.0, 0.0], [1.0, 0.0], [-1.0, 0.0]]), w.__setitem__(4, [1.0, 1.0, 2.0])),
     "points", 4),  # balanced, but two points coincide
    (lambda p, w: p.__setitem__((3, 0, 1), np.inf), "points", None),
])
def test_a_support_batch_refuses_what_one_support_would_merge_or_drop(change, field, index):
    """A batch keeps every point as given (row j of an answer is support j), so a zero
    weight or two coincident points are refused, not merged; non-finite points too."""
    points, weights = random_balanced_tripods(np.random.default_rng(SEED), 12, 1.0)
    change(points, weights)
    with pytest.raises(InvalidInput) as err:
        SupportBatch.create(points, weights, (0.0, 0.0))
    assert err.value.field == field
    if index is not None:
        assert f"support {index}:" in err.value.reason


def test_balancing_weights_are_the_linear_solve():
    """Cramer's rule against numpy's LU solve of [1 1 1; x; y] p = (1, 0, 0) (3.3.3), on
    seeded tripods: the same weights to rounding, the same tripods kept."""
    rng = np.random.default_rng(SEED + 21)
    rel = rng.uniform(-1.0, 1.0, (20_000, 3, 2))
    rel[:5, 2] = rel[:5, 0] + 2.0 * (rel[:5, 1] - rel[:5, 0])  # collinear feet: no solution
    p, ok = balancing_weights(rel, 1e-12)
    a = np.stack([np.ones(rel.shape[:2]), rel[..., 0], rel[..., 1]], axis=1)
    want_ok = np.abs(np.linalg.det(a)) > 1e-12
    assert np.array_equal(ok, want_ok) and not ok[:5].any()
    want = np.linalg.solve(a[ok], np.tile([1.0, 0.0, 0.0], (int(ok.sum()), 1))[..., None])[..., 0]
    scale = np.maximum(1.0, np.abs(want).max(axis=1, keepdims=True))
    assert np.max(np.abs(p - want) / scale) < 1e-9
    assert np.array_equal(p >= 0.0, want >= 0.0)
    assert np.allclose(np.einsum("bk,bki->bi", p, rel[ok]), 0.0, atol=1e-9)
