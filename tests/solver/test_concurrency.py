"""Solves on many threads at once give the serial answers (solver/core/threads.py: no
compiled cvxpy problem or CasADi Function is used by two threads at once, and no solve
changes the process-wide warning filters).

Each case is a function of a thread index i that runs a few seeded solves and returns
their answers as one float vector. ``N_THREADS`` threads start together (a barrier) and
each result must equal, bit for bit, the same function run serially: the back ends are
deterministic and answers do not depend on what a thread solved before (Clarabel is never
warm-started). The IPOPT cases run in a child process, so that a crash of the process (as
two threads sharing one IPOPT Function caused) fails the test instead of killing pytest.
Nothing here measures time: a hang guard only (``JOIN_LIMIT_S``), far above any run.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import threading
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from models.core.support import Support, random_balanced_tripods
from solver.core.threads import ignore_inaccurate_solution_warning
from solver.locus.membership import membership
from solver.motion.forward import solve_forward, solve_forward_batch
from solver.particle.solve import solve_particle
from solver.sketch.sticking import sticking_feasibility, sticking_point
from tests.scenes import SEED, scene_for_mu

N_THREADS = 16
"""Threads started together in each case."""

SOLVES_PER_THREAD = 4
"""Seeded problems solved in sequence by each thread (all of one size, so that in the old
code they shared one compiled problem)."""

JOIN_LIMIT_S = 300.0
"""Hang guard: a thread still running after this is a failure (a deadlock), not a timing."""

REPO = Path(__file__).resolve().parents[2]
SCENE = scene_for_mu(0.3)
MU_C = 0.4
STATUSES = ("inside", "outside", "undecided")


def support(i: int, j: int, k: int = 5) -> Support:
    """Seeded random support of k points (centroid moved to the CM), the j-th of thread i."""
    rng = np.random.default_rng([SEED, i, j])
    t = rng.uniform(0.0, 2.0 * math.pi, k)
    w = np.sqrt(rng.uniform(size=k))[:, None] * np.column_stack([np.cos(t), np.sin(t)])
    p = rng.uniform(0.1, 1.0, k)
    p /= p.sum()
    return Support.create(w - p @ w, p, SCENE.center_of_mass)


def forward_case(method: str) -> Callable[[int], np.ndarray]:
    def run(i: int) -> np.ndarray:
        out = []
        for j in range(SOLVES_PER_THREAD):
            r = solve_forward(SCENE, support(i, j), mu_c=MU_C if j % 2 else 0.0, method=method)
            assert r.status == "optimal", (i, j, r.status)
            out.append(np.r_[r.velocity_cm, r.omega, r.contact_force, r.kkt_residual, r.iterations])
        return np.concatenate(out)

    return run


def batch_case(i: int) -> np.ndarray:
    rng = np.random.default_rng([SEED, i])
    pts, wts = random_balanced_tripods(rng, 50, SCENE.disk_radius, SCENE.center_of_mass, None)
    b = solve_forward_batch(SCENE, pts, wts, mu_c=MU_C, check_centroid=False)
    assert np.all(b.converged), i
    return np.concatenate([b.velocity_cm.ravel(), b.omega, b.contact_force.ravel(), b.kkt_residual])


def particle_case(i: int) -> np.ndarray:
    out = []
    for j in range(SOLVES_PER_THREAD):
        sol = solve_particle(1.0 + 0.1 * i, 1.0, 2.0 + 0.05 * j, 0.25 * j)
        out.append([sol.mpp_v_y_numeric, sol.iterations])
    return np.ravel(out)


def membership_case(i: int) -> np.ndarray:
    """The forward COR of a random support (inside) and the point four times as far from
    the CM (outside)."""
    out = []
    for j in range(SOLVES_PER_THREAD // 2):
        cor = solve_forward(SCENE, support(i, j)).cor
        for r in (cor, SCENE.center_of_mass + 4.0 * (cor - SCENE.center_of_mass)):
            res = membership(SCENE, r)
            out.append(np.r_[STATUSES.index(res.status), res.witness_residual, res.witness_weights.sum(),
                             res.dual if res.dual is not None else np.zeros(5)])
    return np.concatenate(out)


def sticking_case(i: int) -> np.ndarray:
    out = []
    for j in range(SOLVES_PER_THREAD):
        res = sticking_feasibility(SCENE, sticking_point(SCENE, -2.0 + 0.25 * i + 0.06 * j), MU_C)
        out.append(np.r_[STATUSES.index(res.status), res.witness_residual, res.contact_force,
                         res.dual if res.dual is not None else np.zeros(6)])
    return np.concatenate(out)


CASES: dict[str, Callable[[int], np.ndarray]] = {
    "newton": forward_case("newton"),
    "cvxpy": forward_case("cvxpy"),
    "casadi": forward_case("casadi"),
    "batch": batch_case,
    "particle": particle_case,
    "membership": membership_case,
    "sticking": sticking_case,
}
IN_CHILD = ("casadi", "particle")
"""Cases that call IPOPT: run in a child process."""


def run_at_once(task: Callable[[int], np.ndarray], n: int = N_THREADS) -> list[object]:
    """task(0..n-1), each on its own thread, all released together; an exception is
    returned in place of its result."""
    barrier = threading.Barrier(n)
    results: list[object] = [None] * n

    def work(i: int) -> None:
        try:
            barrier.wait()
            results[i] = task(i)
        except BaseException as exc:  # reported by the caller
            results[i] = exc

    threads = [threading.Thread(target=work, args=(i,), daemon=True) for i in range(n)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(JOIN_LIMIT_S)
    assert not any(t.is_alive() for t in threads), "a thread hung"
    return results


def print_concurrent(case: str) -> None:
    """Run ``case`` on N_THREADS threads at once and print the results as JSON (float.hex);
    the child process of :func:`concurrent_in_child`."""
    out = []
    for r in run_at_once(CASES[case]):
        out.append(repr(r) if isinstance(r, BaseException) else [float(x).hex() for x in np.asarray(r)])
    print(json.dumps(out))


def concurrent_in_child(case: str) -> list[object]:
    code = f"from tests.solver.test_concurrency import print_concurrent; print_concurrent({case!r})"
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    # -X faulthandler: a native crash (SIGSEGV, SIGABRT, ...) prints every thread's Python stack,
    # the crashing thread's first, to stderr, whose last 20 kB the failure message shows
    proc = subprocess.run([sys.executable, "-X", "faulthandler", "-c", code], cwd=REPO, env=env,
                          capture_output=True, text=True, timeout=JOIN_LIMIT_S)
    assert proc.returncode == 0, f"the child process ended with {proc.returncode}:\n{proc.stderr[-20000:]}"
    rows = json.loads(proc.stdout.strip().splitlines()[-1])
    return [row if isinstance(row, str) else np.array([float.fromhex(x) for x in row]) for row in rows]


@pytest.mark.slow
@pytest.mark.parametrize("case", list(CASES))
def test_concurrent_solves_equal_serial_solves(case):
    """N_THREADS solves at once, each equal (bitwise) to the same solve done serially."""
    ignore_inaccurate_solution_warning()
    filters = set(warnings.filters)
    concurrent = concurrent_in_child(case) if case in IN_CHILD else run_at_once(CASES[case])
    assert set(warnings.filters) == filters
    serial = [CASES[case](i) for i in range(N_THREADS)]
    failures = [r for r in concurrent if not isinstance(r, np.ndarray)]
    assert not failures, failures[:3]
    for i, (got, want) in enumerate(zip(concurrent, serial)):
        assert np.array_equal(got, want), (i, np.max(np.abs(got - want)))
