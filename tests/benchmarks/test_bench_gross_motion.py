"""Benchmark (not a test): COR sketch (4.1) and gross-motion bounds (4.3, 4.4), the book's
closed forms against the exact bounds from the exact sketch, speed against error.
Writes its section of docs/benchmarks.md."""

from __future__ import annotations

import math
import statistics
import time

import pytest

from models.core.scene import PushScene
from models.push import gross_motion as gm
from models.push.gross_bounds import encounter_bounds_exact, fence_push_bound_exact
from models.sketch.disk_sketch import disk_cor_sketch
from tests.benchmarks._docs import write_section

pytestmark = pytest.mark.benchmark


def timed(fn, repeats=3):
    fn()
    ts = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        ts.append(time.perf_counter() - t0)
    return out, statistics.median(ts)


def test_gross_motion_bounds():
    lines = [
        "COR sketch (`models/sketch/disk_sketch.py`) of the book-like scene (contact (-0.3, -0.9), disk a = 1,",
        "edge at 120 deg, push along +x): time against the boundary resolution, and the sticking",
        "locus's far end against a 4096-point reference.",
        "",
        "| n_points | time (ms) | far end t | error vs 4096 |",
        "|---:|---:|---:|---:|",
    ]
    scene = PushScene.create(1.0, (-0.3, -0.9), math.radians(120), 0.0)
    ref = disk_cor_sketch(scene, 0.5, n_points=4096, sweep_points=4096).sticking.t_high
    for n in (128, 256, 512, 1024):
        sk, t = timed(lambda: disk_cor_sketch(scene, 0.5, n_points=n, sweep_points=n))
        lines.append(f"| {n} | {t * 1e3:.0f} | {sk.sticking.t_high:.6f} | {abs(sk.sticking.t_high - ref):.1e} |")
    lines += [
        "",
        "Longest fence push (4.3), the book's example reconstructed (alpha = 70 deg, c = 0.5746 a,",
        "beta 45 -> 80 deg) and a high-friction scene: the book's closed form (tips and tip line,",
        "corrected (4.6)) against the exact bound (slowest COR of the exact sketch at Gauss-Legendre",
        "nodes); *quad. err.* is the difference to the half-node rule.",
        "",
        "| scene | mu_c | closed form (a) | time (ms) | nodes / points | exact (a) | quad. err. | time (s) | exact - closed |",
        "|---|---:|---:|---:|---|---:|---:|---:|---:|",
    ]
    scenes = [
        ("book 4.3", dict(a=1.0, c=0.5746, alpha=math.radians(70), beta_initial=math.radians(45),
                          beta_final=math.radians(80)), (0.1, 0.25, 1.0)),
        ("alpha 60, c 0.9", dict(a=1.0, c=0.9, alpha=math.radians(60), beta_initial=math.radians(35),
                                 beta_final=math.radians(75)), (1.0,)),
    ]
    for name, geo, mus in scenes:
        for mu in mus:
            closed, t_closed = timed(lambda: gm.fence_push_bound(geo["a"], geo["c"], geo["alpha"],
                                                                  geo["beta_initial"], geo["beta_final"], mu).total, 20)
            for nodes, pts in ((8, 128), (16, 256), (16, 512)):
                t0 = time.perf_counter()
                ex = fence_push_bound_exact(mu_c=mu, n_nodes=nodes, n_points=pts, **geo)
                t = time.perf_counter() - t0
                lines.append(f"| {name} | {mu:g} | {closed:.5f} | {t_closed * 1e3:.2f} | {nodes} / {pts} | "
                             f"{ex.value:.5f} | {ex.quadrature_error:.1e} | {t:.2f} | {ex.value - closed:+.5f} |")
    lines += [
        "",
        "Disk pushed aside by a point (4.4), a = 1: greatest length (4.16) and greatest rotation",
        "(4.18, re-derived: pi/2 - beta_i) against the exact bounds, and the least ones (no closed",
        "form in the book), 16 nodes, 256 points.",
        "",
        "| beta_i (deg) | mu_c | (4.16) | exact max length | exact min length | (4.18) | exact max rotation | exact min rotation | time (s) |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for bi_deg in (30.0, 60.0):
        for mu in (0.5, 5.0):
            bi = math.radians(bi_deg)
            t0 = time.perf_counter()
            b = encounter_bounds_exact(1.0, bi, mu, n_nodes=16, n_points=256)
            t = time.perf_counter() - t0
            lines.append(
                f"| {bi_deg:g} | {mu:g} | {b['length_max'].book_value:.5f} | {b['length_max'].value:.5f} | "
                f"{b['length_min'].value:.5f} | {b['rotation_max'].book_value:.5f} | {b['rotation_max'].value:.5f} | "
                f"{b['rotation_min'].value:.5f} | {t:.2f} |"
            )
    write_section("COR sketch and gross-motion bounds (issue 4, book 4.1-4.4)", lines)
