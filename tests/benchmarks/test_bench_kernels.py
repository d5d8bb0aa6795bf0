"""Benchmark (not a test): which kernel technology (issue 36.1), measured on one piece of
work: the frictionless forward solve of 100,000 seeded tripods (book 3.2-3.3.3).

* plain arrays: solver/motion/newton.py, vectorised over the batch (the reference);
* numba: solver/kernels/forward.py, a support at a time, the whole solve (vertex test,
  Newton with its line search, kink escapes, the mode logic of 4.1 and the answer's
  quantities);
* CasADi's code generation: the same problem written as CasADi expressions, C generated
  for the batch (``Function.map``) and compiled with ``gcc -O2``. CasADi expressions have
  no loops or early exits, so what is generated is a *reduced* solve: the three vertex tests
  and eight plain Newton steps in the constraint plane (no line search), the answer picked
  with ``if_else``; it does less work than the others and is not always converged (the
  share within 1e-8 of the reference is given).

One core, seeded, best of three. Writes its section of docs/benchmarks.md."""

from __future__ import annotations

import platform
import shutil
import subprocess
import time

import numpy as np
import pytest

from models.core.support import random_balanced_tripods
from solver.core.tolerances import SOLVER_DEFAULT as TOL
from solver.motion import newton
from solver.motion.forward import solve_forward_batch
from tests.benchmarks._docs import write_section
from tests.scenes import SEED, scene_for_mu

pytestmark = pytest.mark.benchmark

N = 100_000
NEWTON_STEPS = 8
"""Plain Newton steps of the reduced CasADi solve."""


def best_of(fn, n=3):
    times, out = [], None
    for _ in range(n):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def reduced_casadi_solve():
    """The reduced solve of one tripod as a CasADi Function of z = (w (6), p (3), a (3), q)."""
    import casadi as ca

    z = ca.SX.sym("z", 13)
    wx, wy, pw, a, q = z[0:6:2], z[1:6:2], z[6:9], z[9:12], z[12]
    best_x, best_v = ca.SX.zeros(3), ca.SX(1e300)
    for j in range(3):
        den = a[0] * wy[j] - a[1] * wx[j] + a[2]
        om = q / den
        gx = gy = gw = 0
        for i in range(3):
            if i == j:
                continue
            ux, uy = -om * (wy[i] - wy[j]), om * (wx[i] - wx[j])
            r = ca.sqrt(ux * ux + uy * uy)
            gx, gy, gw = gx + pw[i] * ux / r, gy + pw[i] * uy / r, gw + pw[i] * (uy * wx[i] - ux * wy[i]) / r
        lam = (-wy[j] * gx + wx[j] * gy - gw) / -den
        viol = ca.fmax(ca.sqrt((lam * a[0] - gx) ** 2 + (lam * a[1] - gy) ** 2) - pw[j], 0)
        better = viol < best_v
        best_x = ca.if_else(better, ca.vertcat(om * wy[j], -om * wx[j], om), best_x)
        best_v = ca.if_else(better, viol, best_v)
    y = ca.SX.sym("y", 2)
    a2 = ca.dot(a, a)
    an = a / ca.sqrt(a2)
    n1 = ca.cross(an, ca.vertcat(1, 0, 0))
    n1 = n1 / ca.norm_2(n1)
    n2 = ca.cross(an, n1)
    x = a * q / a2 + y[0] * n1 + y[1] * n2
    f = sum(pw[i] * ca.sqrt((x[0] - x[2] * wy[i]) ** 2 + (x[1] + x[2] * wx[i]) ** 2) for i in range(3))
    step = ca.Function("step", [y, z], [y - ca.solve(ca.hessian(f, y)[0], ca.gradient(f, y))])
    yy = ca.SX.zeros(2)
    for _ in range(NEWTON_STEPS):
        yy = step(yy, z)
    xn = a * q / a2 + yy[0] * n1 + yy[1] * n2
    return ca.Function("tripod", [z], [ca.if_else(best_v <= TOL.kkt, best_x, xn)])


@pytest.mark.skipif(shutil.which("gcc") is None, reason="CasADi's generated C needs gcc")
def test_kernel_technologies(tmp_path):
    import casadi as ca

    scene = scene_for_mu(0.3)
    rng = np.random.default_rng(SEED)
    pts, wts = random_balanced_tripods(rng, N, scene.disk_radius, scene.center_of_mass, None)
    w_rel = pts - scene.center_of_mass
    p = wts / wts.sum(axis=1, keepdims=True)
    ell = np.maximum(np.hypot(w_rel[..., 0], w_rel[..., 1]).max(axis=1), np.hypot(*scene.contact_rel))
    w_n, c_n = w_rel / ell[:, None, None], scene.contact_rel / ell[:, None]
    rows = np.zeros((N, 1, 3))
    rows[:, 0, :2] = scene.normal
    rows[:, 0, 2] = -c_n[:, 1] * scene.normal[0] + c_n[:, 0] * scene.normal[1]
    q = np.ones((N, 1))

    t_numpy, ref = best_of(lambda: newton.solve_batch(w_n, p, rows, q, TOL.kkt, TOL.max_newton_iter))
    solve_forward_batch(scene, pts[:100], wts[:100], check_centroid=False)
    t_numba, got = best_of(lambda: solve_forward_batch(scene, pts, wts, check_centroid=False))
    mapped = reduced_casadi_solve().map(N, "serial")
    t0 = time.perf_counter()
    mapped.generate("tripods.c", {"with_header": False})
    shutil.move("tripods.c", tmp_path / "tripods.c")
    subprocess.run(["gcc", "-O2", "-fPIC", "-shared", str(tmp_path / "tripods.c"), "-o", str(tmp_path / "t.so"),
                    "-lm"], check=True)
    t_build = time.perf_counter() - t0
    ext = ca.external(mapped.name(), str(tmp_path / "t.so"))
    z = np.concatenate([w_n.reshape(N, 6), p, rows[:, 0, :], q], axis=1).T
    t_casadi, x = best_of(lambda: np.asarray(ext(z)).T)
    close = float(np.mean(np.abs(x - ref.x).max(axis=1) < 1e-8))
    assert np.all(got.converged)

    write_section("Kernel technology (issue 36)", [
        f"`tests/benchmarks/test_bench_kernels.py`, seed {SEED}, {N:,} tripods drawn as in 3.3.3, frictionless, "
        f"Python {platform.python_version()}, one core of the 2-core x86_64 machine, idle, best of 3. The same "
        "work three ways (the module docstring says what each does); µs per tripod.",
        "",
        "| technology | µs per tripod | what it computes |",
        "|---|---:|---|",
        f"| plain arrays (numpy, solver/motion/newton.py) | {1e6 * t_numpy / N:.2f} | the whole solve, vectorised "
        "over the batch |",
        f"| numba (solver/kernels/forward.py) | {1e6 * t_numba / N:.2f} | the whole solve and the answer's "
        "quantities, a support at a time |",
        f"| CasADi, generated C (gcc -O2) | {1e6 * t_casadi / N:.2f} | a reduced solve (no line search, "
        f"{NEWTON_STEPS} Newton steps): {100 * close:.1f} % of the tripods within 1e-8 of the reference; "
        f"generated and compiled in {t_build:.1f} s |",
        "",
        "numba is chosen: the fastest here though it does the whole solve, and the only one of the three that "
        "writes the simulator's loop (events, contacts switching, early exits) as it reads; CasADi's expressions "
        "have no loops or branches that end a computation early, so its generated code must evaluate every "
        "branch. Its costs: llvmlite (about 160 MB stripped) in the venv and the image, and a compile of about "
        "45 s whenever a kernel changes, paid by `python -m solver.kernels` at set-up and in the image's build, "
        "never by a request (solver/kernels/__init__.py).",
    ])
