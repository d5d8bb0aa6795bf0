"""Synthetic tables of critical radii for the spiral's pure tests: a stand-in for r*(beta)
with the real one's shape (the solver's tests use real ones)."""

from __future__ import annotations

import math

import numpy as np

from models.spiral.critical import critical_envelope

HALF_PI = 0.5 * math.pi


def synthetic_r_star(beta, mu=0.25):
    """A stand-in for r*(beta) with the real one's shape (solver tests): ~2/beta near 0,
    b_inf = 1 + mu at pi/2, decreasing."""
    beta = np.asarray(beta, dtype=float)
    return 2.0 / np.sin(beta) - (1.0 - mu) * np.sin(beta) ** 8


def synthetic_envelope(n=60, mu=0.25, a=1.0):
    betas = np.unique(np.concatenate([np.geomspace(0.015, 0.5, n // 3), np.linspace(0.5, HALF_PI - 0.1, n // 3),
                                      HALF_PI - np.geomspace(0.1, 1e-6, n // 3)]))
    return critical_envelope(betas, a * synthetic_r_star(betas, mu), a)
