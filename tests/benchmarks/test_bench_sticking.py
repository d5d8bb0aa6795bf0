"""Benchmark (not a test): the exact sticking locus (solver/sketch/sticking_locus.py; book 4.1.4,
3.3.11.1, 6.3).

Writes its section of docs/benchmarks.md: the time of one sticking-feasibility query
(inside, outside, at a certified bracket end; certified and grid-only), of a whole
sticking locus (scan, bisection, certified brackets of every end) for disks and polygons,
the tip line's error against the exact lower end for several mu_c, and speed against the
bracket width. Run with `make bench` or `pytest tests/benchmarks --run-benchmarks`."""

from __future__ import annotations

import dataclasses
import math
import platform
import statistics
import time

import numpy as np
import pytest

from models.core.footprint import Footprint
from models.core.scene import PushScene
from solver.core.tolerances import SOLVER_DEFAULT
from solver.sketch.sticking import sticking_feasibility, sticking_point
from solver.sketch.sticking_locus import sticking_locus
from tests.benchmarks._docs import write_section

pytestmark = pytest.mark.benchmark

SEED = 20261122
SQUARE = Footprint.create([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]])
L_SHAPE = Footprint.create([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]])
U_SHAPE = Footprint.create([[0, 0], [3, 0], [3, 2], [2, 2], [2, 0.6], [1, 0.6], [1, 2], [0, 2]])
AL = math.radians(70)


def scenes():
    """(name, scene, footprint, mu_c)."""
    near = PushScene.create(1.0, [-0.9, 0.3], AL, 0.0)
    oblique = PushScene.create(1.0, [-0.2064, -0.8692], 5.5226, 3.0127)
    book63 = PushScene.create(1.25, [-1.25 * math.sin(AL), 1.25 * math.cos(AL)], AL, 0.0)
    far = PushScene.create(1.0, [-0.26447305, -0.69623092], 6.224765398562094, 1.2190980200659878)
    square = PushScene.create(SQUARE.circumradius, [-0.5, 0.2], math.radians(80), 0.0)
    lsh = PushScene.create(L_SHAPE.circumradius, [0.5, 0.0], 0.0, math.pi / 2 + 0.3, L_SHAPE.center_of_mass)
    ush = PushScene.create(
        U_SHAPE.circumradius, [0.0, 0.29439040855770426], -math.pi / 2, 2.1405943745008185, U_SHAPE.center_of_mass
    )
    return [
        ("disk, near translation", near, None, 0.5),
        ("disk, oblique", oblique, None, 0.5),
        ("disk, book 6.3", book63, None, 0.5),
        ("disk, far locus", far, None, 0.5),
        ("square", square, SQUARE, 0.5),
        ("L shape", lsh, L_SHAPE, 0.6),
        ("U shape", ush, U_SHAPE, 0.3),
    ]


def p95(xs):
    return float(np.percentile(xs, 95))


def timed(fn, *args, **kwargs):
    t0 = time.perf_counter()
    out = fn(*args, **kwargs)
    return time.perf_counter() - t0, out


def test_sticking_locus_benchmark():
    # warm-up: compile the restricted masters
    warm = scenes()[0]
    sticking_locus(warm[1], warm[3], scan_points=16, seed_tripods=0)

    lines = [
        f"`solver/sketch/sticking.py`, `solver/sketch/sticking_locus.py`; {platform.machine()}, Python {platform.python_version()}, one core. "
        "Positions s are along J p from the contact (world units), a = disk radius or circumradius.",
        "",
        "Whole sticking locus (`sticking_locus`, default settings: 96 scan probes, 256 seed tripods,",
        f"every end bracketed to boundary_bracket L = {SOLVER_DEFAULT.boundary_bracket:g} L by a witness",
        "(re-verified forward) and a branch-and-bound dual). *Tip-line error* = exact end on the tip",
        "line's side - where the tip line meets the sticking line (3.3.11.1), / a; negative = the exact",
        "end lies beyond the tip line (the book's \"dip\").",
        "",
        "| scene | mu_c | time (s) | queries | intervals | lower s / a | upper s / a | ends | max width / L | tip-line error / a |",
        "|---|---:|---:|---:|---:|---:|---:|---|---:|---:|",
    ]
    loci = {}
    times = []
    for name, sc, fp, mu in scenes():
        loc = sticking_locus(sc, mu, footprint=fp, seed=SEED)
        loci[name] = loc
        times.append(loc.solve_time_s)
        a = loc.length_scale
        ends = [e for iv in loc.intervals for e in (iv.lower, iv.upper)]
        statuses = ",".join(sorted({e.status for e in ends}))
        width = max(e.width for e in ends) / a
        tip = loc.tip_line
        tip_err = "-" if tip.error is None else f"{tip.error / a:+.4f}"
        lines.append(
            f"| {name} | {mu:g} | {loc.solve_time_s:.2f} | {loc.n_queries} | {len(loc.intervals)} | "
            f"{loc.lower.position / a:.5f} | {loc.upper.position / a:.5f} | {statuses} | {width:.1e} | {tip_err} |"
        )
    b63 = loci["disk, book 6.3"]
    a63 = 1.25
    lines += [
        "",
        f"Book 6.3 (disk a = 1.25 in, fence at 70 degrees, mu_c = 0.5, contact on the rim): the tip line meets "
        f"the sticking line at y = {b63.tip_line.point[1] / a63:.4f} a (the book: -5.51 a); the exact lower end is "
        f"y = {b63.lower.point[1] / a63:.4f} a, the upper end y = {b63.upper.point[1] / a63:.4f} a (y from the CM).",
        "",
        "One query (`sticking_feasibility`, cold, no warm start), times in ms: *inside* at 16 points spread",
        "over the interior of the locus (witness, + forward re-verification), *outside* 1e-3 L beyond",
        "either end (certified dual, and grid pricing only), *at the end*: the two certified bracket",
        "ends (inside and outside, within boundary_bracket L of the end).",
        "",
        "| scene | inside median | inside p95 | inside + forward | outside certified | outside grid | at the end (in / out) |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    q_in_all = []
    for name, sc, fp, mu in scenes():
        loc = loci[name]
        ell = loc.length_scale
        pts_in = []
        for iv in loc.intervals:
            lo, hi = iv.lower.feasible_position, iv.upper.feasible_position
            pts_in += list(np.linspace(lo, hi, 18)[1:-1][:: max(1, len(loc.intervals))])
        t_in = [timed(sticking_feasibility, sc, sticking_point(sc, s), mu, footprint=fp, verify_witness=False)[0]
                for s in pts_in[:16]]
        t_inf = [timed(sticking_feasibility, sc, sticking_point(sc, s), mu, footprint=fp)[0] for s in pts_in[:16:4]]
        outs = [loc.lower.position - 1e-3 * ell, loc.upper.position + 1e-3 * ell]
        t_out = [timed(sticking_feasibility, sc, sticking_point(sc, s), mu, footprint=fp, verify_witness=False)[0]
                 for s in outs]
        t_grid = [timed(sticking_feasibility, sc, sticking_point(sc, s), mu, footprint=fp, certify=False)[0]
                  for s in outs]
        e_in = [timed(sticking_feasibility, sc, sticking_point(sc, e.feasible_position), mu, footprint=fp,
                      verify_witness=False)[0] for e in (loc.lower, loc.upper)]
        e_out = [timed(sticking_feasibility, sc, sticking_point(sc, e.infeasible_position), mu, footprint=fp)[0]
                 for e in (loc.lower, loc.upper) if e.infeasible_position is not None]
        q_in_all += t_in
        lines.append(
            f"| {name} | {1e3 * statistics.median(t_in):.1f} | {1e3 * p95(t_in):.1f} | "
            f"{1e3 * statistics.median(t_inf):.1f} | {1e3 * statistics.median(t_out):.1f} | "
            f"{1e3 * statistics.median(t_grid):.1f} | {1e3 * statistics.median(e_in):.1f} / "
            f"{1e3 * statistics.median(e_out):.1f} |"
        )
    lines += [
        "",
        "The tip line against the exact lower end (disk, contact (-0.9, 0.3) a, edge at 70 degrees, push",
        "along +x; and the book's 6.3 geometry): the tip line's crossing does not depend on mu_c; the",
        "exact end does, through the cone (the locus grows with mu_c until the cone holds every force",
        "angle whose locus reaches the line).",
        "",
        "| scene | mu_c | tip line s / a | exact lower s / a | error / a | upper s / a | time (s) |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    for name, sc in (("near translation", scenes()[0][1]), ("book 6.3", scenes()[2][1])):
        for mu in (0.05, 0.1, 0.2, 0.3, 0.5, 1.0, math.inf):
            loc = sticking_locus(sc, mu, seed=SEED)
            a = loc.length_scale
            tip = loc.tip_line.position / a
            if loc.status == "found":
                err = "-" if loc.tip_line.error is None else f"{loc.tip_line.error / a:+.5f}"
                lines.append(
                    f"| {name} | {mu:g} | {tip:.5f} | {loc.lower.position / a:.5f} | {err} | "
                    f"{loc.upper.position / a:.5f} | {loc.solve_time_s:.2f} |"
                )
            else:
                lines.append(f"| {name} | {mu:g} | {tip:.5f} | ({loc.status}) | - | - | {loc.solve_time_s:.2f} |")
    lines += [
        "",
        "Speed against the bracket width (disk, near translation, mu_c = 0.5): the certified error",
        "of each end is at most half the width.",
        "",
        "| boundary_bracket | time (s) | queries | max width / L |",
        "|---:|---:|---:|---:|",
    ]
    sc = scenes()[0][1]
    for bracket in (1e-3, 1e-4, 1e-6, 1e-8):
        tol = dataclasses.replace(SOLVER_DEFAULT, boundary_bracket=bracket)
        loc = sticking_locus(sc, 0.5, tol=tol, seed=SEED)
        width = max(e.width for e in (loc.lower, loc.upper)) / loc.length_scale
        lines.append(f"| {bracket:g} | {loc.solve_time_s:.2f} | {loc.n_queries} | {width:.1e} |")
    write_section("Exact sticking locus (book 4.1.4, 3.3.11.1, 6.3)", lines)
    assert statistics.median(q_in_all) < 0.2
    assert max(times) < 60.0
