"""Spiral localization, the pure part (models/spiral/graph.py; book 4.5): schedules on a grid
of radii, the safe-revolution DAG and its shortest paths."""

from __future__ import annotations

import itertools

import numpy as np

from models.spiral.critical import (
    critical_envelope,
)
from models.spiral.graph import arc_costs, greedy_on_graph, schedule_graph, schedule_grid, shortest_path_potentials
from models.spiral.path import (
    revolution_length,
)
from tests.models.spiral.synthetic import synthetic_envelope
from tests.scenes import SEED

# ------------------------------------------------------------------ grid schedules


def test_schedule_graph_arcs_are_exactly_the_safe_steps():
    """Brute force on a small grid: an arc i -> j iff x_i - x_j <= D(x_j) and >= min_step
    (up to one ulp towards safety)."""
    env = synthetic_envelope()
    x = schedule_grid(env, 8.0, 2.0, spacing=0.07)
    for ms, cap in ((None, None), (0.2, None), (None, 0.3), (0.1, 0.5)):
        g = schedule_graph(env, x, min_step=ms, max_step=cap)
        arcs = set(zip(g.tails.tolist(), g.heads.tolist()))
        D = env.d_star(x, cap)
        for i, j in itertools.product(range(x.size), repeat=2):
            if j >= i:
                continue
            step = x[i] - x[j]
            ok = step <= D[j] and (ms is None or step >= ms)
            if abs(step - D[j]) < 1e-12 or (ms is not None and abs(step - ms) < 1e-12):
                continue  # within rounding of the boundary
            assert ((i, j) in arcs) == ok


def test_greedy_on_a_grid_is_the_shortest_path():
    """Without a minimum step greedy is optimal on any grid, for revolutions and for path
    length (models/spiral/path.py): compared with the exact DAG shortest path (integer costs)
    over random tables and grids; the potentials certify it (reduced costs >= 0)."""
    rng = np.random.default_rng(SEED)
    base = synthetic_envelope()
    for trial in range(6):
        noisy = base.radii * (1.0 + 0.05 * rng.uniform(size=base.radii.size))
        env = critical_envelope(base.betas, noisy, 1.0)
        cap = None if trial % 2 == 0 else 0.35
        x = schedule_grid(env, 25.0, 2.6, resolution=int(rng.integers(2, 9)), max_step=cap)
        g = schedule_graph(env, x, max_step=cap)
        path = greedy_on_graph(g)
        assert path is not None
        for obj in ("revolutions", "length"):
            unit = 1.0 if obj == "revolutions" else 1e-7
            c = arc_costs(g, obj, unit)
            pot = shortest_path_potentials(g, c)
            rc = c + pot[g.tails] - pot[g.heads]
            assert rc[pot[g.tails] >= 0].min() >= 0
            if obj == "revolutions":
                assert pot[0] == path.size - 1
            else:
                L = sum(revolution_length(x[i], x[j])[0] for i, j in zip(path[:-1], path[1:]))
                assert abs(L / unit - pot[0]) <= 0.5 * (path.size - 1) + 1


def test_minimum_step_can_defeat_greedy():
    """With a minimum step greedy may get stuck (its last step would be too short) while
    another schedule reaches the target: why solver/spiral/schedule.py solves the shortest path."""
    env = synthetic_envelope()
    found = False
    for target in np.linspace(5.0, 8.0, 61):
        x = schedule_grid(env, 12.0, float(target), spacing=0.05)
        g = schedule_graph(env, x, min_step=0.5)
        pot = shortest_path_potentials(g, arc_costs(g, "revolutions", 1.0))
        if greedy_on_graph(g) is None and pot[0] >= 0:
            found = True
            break
    assert found
