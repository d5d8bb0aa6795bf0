"""Shared tables of the spiral tests: six exact points and sweeps at mu_c = 0.25."""

from __future__ import annotations

import math

import pytest

from solver.spiral.critical_radius import BetaGrid, beta_grid, critical_radius_table

HALF_PI = 0.5 * math.pi
BETAS = (0.3, 0.8, 1.15, 1.4, 1.55, HALF_PI - 1e-6)


@pytest.fixture(scope="module")
def exact_025():
    return critical_radius_table(1.0, 0.25, "exact", betas=BETAS)


@pytest.fixture(scope="module")
def sweep_025():
    return critical_radius_table(1.0, 0.25, "sweep", betas=BETAS)


@pytest.fixture(scope="module")
def dense_sweep_025():
    """A sweep table fine enough for the recursion from b_1 = 100 a (figure 4-21), with
    256-point loci (error ~2e-4 a) to stay fast."""
    grid = beta_grid(1.0, 100.0, grazing_delta=1e-4, grid=BetaGrid(n_low=14, n_mid=8, n_grazing=26))
    return critical_radius_table(1.0, 0.25, "sweep", betas=grid, sweep_points=256)
