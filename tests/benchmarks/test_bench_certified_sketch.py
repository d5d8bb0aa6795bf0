"""Benchmark (not a test): certified COR sketches (solver/sketch/certified_sketch.py; book 4.1,
3.3.13, 7.5).

Writes its section of docs/benchmarks.md: the time of a polygon's own sketch against the
number of rays per traced locus, its sticking segment against the circumscribing disk's
(how much the polygon's own sketch sharpens the disk bound), and the time of a disk sketch
with exact sticking ends against the analytic sweep. Run with
`pytest tests/benchmarks --run-benchmarks`."""

from __future__ import annotations

import math
import platform
import time

import numpy as np
import pytest

from models.core.footprint import Footprint
from models.core.scene import PushScene
from models.sketch.disk_sketch import disk_cor_sketch
from solver.sketch.certified_sketch import certified_sketch
from tests.benchmarks._docs import write_section

pytestmark = pytest.mark.benchmark

RECT = Footprint.create([[-1.5, -0.4], [1.5, -0.4], [1.5, 0.4], [-1.5, 0.4]])
L_SHAPE = Footprint.create([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]])


def cases():
    """(name, scene, footprint, mu_c)."""
    return [
        ("rectangle, short side (must stick)", PushScene.create(
            RECT.circumradius, [-1.5, 0.18766172], math.pi / 2, -0.4635935760943159, RECT.center_of_mass), RECT, 0.3),
        ("rectangle, long side", PushScene.create(
            RECT.circumradius, [-0.6, -0.4], 0.3, math.pi / 2, RECT.center_of_mass), RECT, 0.5),
        ("L shape", PushScene.create(
            L_SHAPE.circumradius, [0.5, 0.0], 0.0, math.pi / 2 + 0.3, L_SHAPE.center_of_mass), L_SHAPE, 0.6),
    ]


def test_bench_certified_sketch():
    lines = [
        f"Machine: {platform.machine()}, Python {platform.python_version()}; one core, in-process. "
        "A polygon's own sketch: the exact sticking locus on the footprint plus {COR}_(alpha+-nu) traced "
        "with certified brackets along `n_rays` rays (wrapped loci are not traced). "
        "'disk t range' is the circumscribing disk's sticking segment (models.sketch.disk_sketch), 'polygon t "
        "range' the polygon's (certified); both along J p from the contact.",
        "",
        "| scene | mu_c | n_rays | time (s) | complete | disk sketch | polygon sketch | disk t range | polygon t range |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for name, sc, fp, mu in cases():
        disk = disk_cor_sketch(sc, mu, n_points=1024)
        for n_rays in (8, 16, 32):
            t0 = time.perf_counter()
            cs = certified_sketch(sc, mu, fp, n_rays=n_rays)
            dt = time.perf_counter() - t0
            st, ds = cs.sketch.sticking, disk.sticking

            def rng(s):
                return "—" if s is None else f"[{s.t_low:.4f}, {s.t_high:.4f}]"

            lines.append(
                f"| {name} | {mu:g} | {n_rays} | {dt:.2f} | {cs.complete} | {disk.sketch or '—'}"
                f"{' (m)' if disk.mirrored else ''} | {cs.sketch.sketch or '—'}{' (m)' if cs.sketch.mirrored else ''} "
                f"| {rng(ds)} | {rng(st)} |"
            )
    lines += ["", "Disk with exact sticking ends against the analytic sweep (a = 1, encounter scene of 4.4):", "",
              "| beta | mu_c | sweep (s) | certified (s) | sweep t_low − exact | sweep t_high − exact |",
              "|---|---|---|---|---|---|"]
    for beta in (0.3, 0.9, 1.4):
        for mu in (0.25, 1.0):
            sc = PushScene.create(1.0, np.array([-math.cos(beta), math.sin(beta)]), 0.5 * math.pi - beta, 0.0)
            t0 = time.perf_counter()
            sw = disk_cor_sketch(sc, mu)
            t_sw = time.perf_counter() - t0
            t0 = time.perf_counter()
            cs = certified_sketch(sc, mu)
            t_cs = time.perf_counter() - t0
            lines.append(
                f"| {beta:g} | {mu:g} | {t_sw:.3f} | {t_cs:.2f} | {sw.sticking.t_low - cs.sketch.sticking.t_low:.1e} "
                f"| {sw.sticking.t_high - cs.sketch.sticking.t_high:.1e} |"
            )
    write_section("Certified COR sketches (4.1 on exact loci)", lines)
