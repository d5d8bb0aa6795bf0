"""Tripod statistics (3.3.3 figure 3-5, 7.7 figure 7-2) and uniform pressure (7.5, figure 7-1)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.core.mpp import perp
from solver.core.outcome import Outcome
from solver.core.tolerances import SolverTolerances
from solver.motion.statistics import (
    HistogramQuery,
    TripodStatisticsProblem,
    histogram_range,
    sticking_line_histogram,
    tripod_sample,
    tripod_statistics,
    uniform_pressure_cor,
)
from tests.scenes import SEED, scene_for_mu


def test_sample_is_reproducible_and_seeded():
    sc = scene_for_mu(0.3)
    a = tripod_sample(sc, 500, seed=SEED)
    b = tripod_sample(sc, 500, seed=SEED)
    c = tripod_sample(sc, 500, seed=SEED + 1)
    assert np.array_equal(a.points, b.points) and np.allclose(a.batch.cor, b.batch.cor, equal_nan=True)
    assert not np.array_equal(a.points, c.points)
    # 3.3.3: every tripod has non-negative weights and its centroid at the CM.
    assert np.all(a.weights >= 0.0)
    assert np.abs(np.einsum("bk,bki->bi", a.weights, a.points)).max() < 1e-12


def test_histogram_counts_sticking_cors_on_the_sticking_line():
    """7.7: with a large mu_c the CORs collapse onto the sticking line (4.1.2); the
    histogram counts each sticking COR once, and is symmetric in nothing in particular but
    must account for every sticking tripod."""
    sc = scene_for_mu(0.3)
    h = sticking_line_histogram(sc, 4000, seed=SEED, mu_c=1e6, bins=40)
    assert 0.5 < h.sticking_fraction <= 1.0
    assert h.counts.sum() + h.outside_range == round(h.sticking_fraction * h.n_tripods)
    # Cross-check by hand: positions along J p of the sticking CORs.
    s = tripod_sample(sc, 4000, seed=SEED, mu_c=1e6)
    stick = s.batch.mode == 1
    pos = (s.batch.cor[stick] - sc.contact_point) @ perp(sc.push_hat)
    assert np.allclose((s.batch.cor[stick] - sc.contact_point) @ sc.push_hat, 0.0, atol=1e-9)
    counts, _ = np.histogram(pos, bins=h.edges)
    assert np.array_equal(counts, h.counts)


def test_histogram_rejects_bad_input():
    sc = scene_for_mu(0.3)
    with pytest.raises(InvalidInput):
        sticking_line_histogram(sc, 10, seed=1, bins=0)
    with pytest.raises(InvalidInput):
        sticking_line_histogram(sc, 10, seed=1, span=(1.0, 0.0))
    with pytest.raises(InvalidInput):
        tripod_sample(sc, 0, seed=1)


def test_uniform_square_cor_matches_a_finer_discretisation_and_symmetry():
    """Uniform pressure on a square (figure 3-6 shape): pushing at the middle of a side
    straight on is a translation; an off-centre push turns it, converging with resolution."""
    sq = Footprint.create([[-1, -1], [1, -1], [1, 1], [-1, 1]])
    import models.core.scene as ms

    straight = ms.PushScene.create(math.sqrt(2), (-1.0, 0.0), math.pi / 2, 0.0)
    r = uniform_pressure_cor(straight, sq, resolution=8)
    assert r.cor is None
    off = ms.PushScene.create(math.sqrt(2), (-1.0, 0.4), math.pi / 2, 0.0)
    cors = [uniform_pressure_cor(off, sq, resolution=n).cor for n in (4, 8, 16)]
    assert np.linalg.norm(cors[2] - cors[1]) < 0.5 * np.linalg.norm(cors[1] - cors[0])
    # Mirror symmetry: the contact mirrored across the x axis mirrors the COR, up to the
    # discretisation (the triangulation of the square is not itself mirror symmetric).
    mirror = ms.PushScene.create(math.sqrt(2), (-1.0, -0.4), math.pi / 2, 0.0)
    cm = uniform_pressure_cor(mirror, sq, resolution=16).cor
    assert np.allclose(cm, [cors[2][0], -cors[2][1]], atol=4.0 * np.linalg.norm(cors[2] - cors[1]))


def test_sample_and_histogram_are_outcomes():
    """3.3.3 / 7.7: a sample and a histogram are complete when every tripod converged."""
    sc = scene_for_mu(0.3)
    s = tripod_sample(sc, 200, seed=SEED, mu_c=0.5)
    assert isinstance(s, Outcome) and s.status == "optimal" and s.complete
    assert s.solve_time_s >= s.batch.solve_time_s > 0.0
    assert s.message == f"200 random tripods (seed {SEED}): 200 of 200 supports converged"
    h = sticking_line_histogram(sc, 200, seed=SEED, mu_c=1e6, bins=10)
    assert isinstance(h, Outcome) and h.complete and h.n_converged == 200
    never = SolverTolerances(kkt_accept=-1.0)  # no residual is accepted
    assert not tripod_sample(sc, 50, seed=SEED, tol=never).complete
    bad = sticking_line_histogram(sc, 50, seed=SEED, mu_c=1e6, bins=10, tol=never)
    assert bad.status == "not_converged" and not bad.complete and bad.n_converged == 0
def test_tripod_statistics_in_one_call_figures_3_5_and_7_2():
    sc = scene_for_mu(0.3)
    problem = TripodStatisticsProblem(sc, 300, SEED, histogram=HistogramQuery(mu_c=1e6, bins=20))
    res = tripod_statistics(problem)
    want = tripod_sample(sc, 300, seed=SEED)
    assert np.allclose(res.sample.batch.cor, want.batch.cor, equal_nan=True)
    h = sticking_line_histogram(sc, 300, seed=SEED, mu_c=1e6, bins=20)
    assert np.array_equal(res.histogram.counts, h.counts) and np.array_equal(res.histogram.edges, h.edges)
    assert isinstance(res, Outcome) and res.complete and res.status == "optimal"
    assert tripod_statistics(TripodStatisticsProblem(sc, 10, SEED)).histogram is None


def test_a_histogram_range_floating_point_cannot_split_is_widened_or_refused_7_7():
    """Issue 25: at a small scale far from 0 the percentiles of the sticking positions can
    coincide to 15 digits; numpy then cannot make the bins (a 500 before). Figure 7-2's
    histogram widens such a range about its middle to a disk radius, and refuses such a
    span given by the caller (422 at span)."""
    a = 1e-12
    pos = np.array([1.0, 1.0 + 4e-16, 1.0 + 8e-16]) * 1e3 * a
    lo, hi = histogram_range(pos, 50, a)
    assert lo < pos.min() and hi > pos.max() and math.isclose(hi - lo, a, rel_tol=1e-3)
    counts, _ = np.histogram(pos, bins=50, range=(lo, hi))
    assert counts.sum() == 3
    with pytest.raises(InvalidInput) as err:
        histogram_range(pos, 50, a, span=(float(pos[0]), float(pos[2])))
    assert err.value.field == "span"
    assert histogram_range(pos, 50, a, span=(0.0, 2e-9)) == (0.0, 2e-9)  # a range numpy can split is kept
