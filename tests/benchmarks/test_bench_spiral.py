"""Benchmark (not a test): spiral localization of a disk (models/spiral/,
solver/spiral/critical_radius.py; book 4.5).

Writes the section "Spiral localization (4.5)" of docs/benchmarks.md: r*(beta) tables by
the exact sticking locus, the book's sweep and the tip line (build time, agreement),
b_inf against (4.25), a/r* on the grid of figure 4-19, the schedule from b_1 = 100 a by the
recursion (4.26) and on OR-Tools (time, revolutions, certificate), the tip line's error
against the exact schedule, and the exponent of figure 4-21. Run with `make bench` or
`pytest tests/benchmarks --run-benchmarks`."""

from __future__ import annotations

import math
import platform
import statistics
import time

import numpy as np
import pytest

from models.core.tolerances import SpiralTolerances
from models.spiral.critical import limiting_radius, tip_line_envelope
from models.spiral.path import fastest_spiral, power_law_fit, spiral_polyline
from solver.core.budget import Budget
from solver.spiral.critical_radius import (
    BetaGrid,
    beta_grid,
    critical_radius,
    critical_radius_table,
    kink_beta,
    limiting_radius_check,
    sketch_change_beta,
)
from solver.spiral.schedule import spiral_schedule
from tests.benchmarks._docs import write_section

pytestmark = pytest.mark.benchmark

HALF_PI = 0.5 * math.pi
B1 = 100.0
TAIL = SpiralTolerances(max_revolutions=5000)


def p95(xs):
    return float(np.percentile(xs, 95))


def revs_to(rec, r):
    """Revolutions of a recursion until b_n <= r (None if never)."""
    hit = np.nonzero(rec.radii <= r)[0]
    return None if hit.size == 0 else int(hit[0]) + 1


def fmt(x, spec=".4f"):
    return "-" if x is None else format(x, spec)


def test_spiral_benchmark():
    lines = [
        f"`models/spiral/`, `solver/spiral/critical_radius.py`; {platform.machine()}, Python {platform.python_version()}, one core. "
        "Disk radius a = 1; r* is the distance from the pusher line to the lower end of the sticking locus "
        "(4.5.3); exact = the outside end of the certified bracket (solver/sketch/sticking.py), sweep = the book's "
        "force-angle sweep with 1024-point loci (models/sketch/disk_sketch.py), tip line = 2a/sin(beta) (4.13).",
        "",
    ]

    # ---------------------------------------------------------------- tables
    tables = {}
    grids = {}
    for mu, kw in ((0.25, BetaGrid(n_low=20, n_mid=14, n_grazing=40)), (1.0, BetaGrid(n_low=14, n_mid=10, n_grazing=16))):
        t0 = time.perf_counter()
        kink = kink_beta(1.0, mu)
        t_kink = time.perf_counter() - t0
        grid = beta_grid(1.0, B1, 1e-6, refine=(kink, sketch_change_beta(mu)), grid=kw)
        grids[mu] = (grid, kink, t_kink)
        for method in ("exact", "sweep", "tip_line"):
            tables[(mu, method)] = critical_radius_table(1.0, mu, method, betas=grid)
    lines += [
        "r*(beta) tables on the default kind of grid for b_1 = 100 a (geometric from beta = 0.018, uniform",
        "in the middle, geometric in pi/2 - beta down to 1e-6, refined around the rim crossing and the",
        "sketch change (4.17)); times per point and in total; the kink search (12 sweeps of 256-point",
        "loci) is extra. *max |exact - sweep|* uses the exact midpoint.",
        "",
        "| mu_c | points | kink beta (s) | method | total (s) | per point median / p95 (s) | certified | "
        "max bracket / a | max abs(exact - sweep) / a | max abs(tip - exact) / a |",
        "|---:|---:|---|---|---:|---|---:|---:|---:|---:|",
    ]
    for mu in (0.25, 1.0):
        grid, kink, t_kink = grids[mu]
        ex, sw, tp = (tables[(mu, m)] for m in ("exact", "sweep", "tip_line"))
        d_sw = float(np.max(np.abs(ex.midpoints - sw.radii)))
        d_tp = float(np.max(np.abs(tp.radii - ex.radii)))
        for t in (ex, sw, tp):
            cert = f"{int(t.certified.sum())}/{t.n_done}" if t.method == "exact" else "-"
            wid = f"{np.nanmax(t.widths):.1e}" if t.method == "exact" else "-"
            lines.append(
                f"| {mu:g} | {grid.size} | {fmt(kink, '.4f')} ({t_kink:.1f}) | {t.method} | {t.solve_time_s:.1f} | "
                f"{statistics.median(t.times):.3f} / {p95(t.times):.3f} | {cert} | {wid} | "
                f"{d_sw:.1e} | {d_tp:.3f} |"
            )
    assert tables[(0.25, "exact")].certified.all()

    # ---------------------------------------------------------------- figure 4-19 and b_inf
    lines += [
        "",
        "a / r*(beta) at the abscissae of figure 4-19 (beta / pi), exact; the last column is the",
        "grazing limit pi/2 - 1e-6 against (4.25). The tip line gives 1/(2 / sin beta) for every mu_c.",
        "",
        "| mu_c | 0.05 | 0.1 | 0.2 | 0.3 | 0.4 | 0.45 | grazing: a/r* | (4.25): a/b_inf |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for mu in (0.1, 0.25, 0.5, 1.0, 2.0):
        vals = [1.0 / critical_radius(1.0, f * math.pi, mu, "exact").radius for f in (0.05, 0.1, 0.2, 0.3, 0.4, 0.45)]
        graz = critical_radius(1.0, HALF_PI - 1e-6, mu, "exact").radius
        lines.append(f"| {mu:g} | " + " | ".join(f"{v:.4f}" for v in vals)
                     + f" | {1.0 / graz:.6f} | {1.0 / limiting_radius(1.0, mu):.6f} |")
    tip = [1.0 / (2.0 / math.sin(f * math.pi)) for f in (0.05, 0.1, 0.2, 0.3, 0.4, 0.45)]
    lines.append("| tip line | " + " | ".join(f"{v:.4f}" for v in tip) + " | 0.500000 | - |")
    lines += [
        "",
        "b_inf: r*(pi/2 - 1e-6) against (4.25) b_inf = a(1 + mu_c) (mu_c <= 1), 2a (mu_c >= 1). Exact: the",
        "safe outside end; the tip line's limit is 2a for every mu_c. mu_c = 0.01: the default 96-probe",
        "scan of the sticking line misses the ~0.02 a long locus; critical_radius rescans with 384 probes.",
        "",
        "| mu_c | (4.25) | exact | exact - (4.25) | time (s) | sweep | sweep - (4.25) | tip line - (4.25) |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for mu in (0.01, 0.1, 0.25, 0.5, 1.0, 2.0, 5.0):
        ce = limiting_radius_check(1.0, mu, "exact")
        cs = limiting_radius_check(1.0, mu, "sweep")
        closed = ce.closed_form
        lines.append(
            f"| {mu:g} | {closed:.4f} | {fmt(ce.numeric, '.7f')} | {fmt(ce.difference, '+.1e')} | {ce.solve_time_s:.2f} | "
            f"{fmt(cs.numeric, '.7f')} | {fmt(cs.difference, '+.1e')} | {2.0 - closed:+.4f} |"
        )
        assert ce.certified and abs(ce.difference) < 1e-5

    # ---------------------------------------------------------------- schedules
    lines += [
        "",
        f"The fastest spiral from b_1 = {B1:g} a (4.26) for mu_c = 0.25 on the exact table above: the",
        "recursion (exact least safe radius per step) and the shortest path on OR-Tools (min cost flow on",
        "an adaptive grid with `resolution` radii per safe step, or a uniform one; CP-SAT on a small",
        "grid). *Certified*: shortest-path potentials give a dual bound equal to the objective. The grid",
        "optimum equals the greedy on the same grid (proved in models/spiral/path.py) and lies above the",
        "continuous recursion by the grid's rounding. The revolutions objective breaks ties by length",
        "(to 1e-4 a), so it returns the greedy schedule; *greedy on grid* gives its revolutions.",
        "",
        "| target / a | method | grid | nodes | arcs | time (s) | status | revolutions | path length / a | "
        "greedy on grid | recursion revs | certified |",
        "|---:|---|---|---:|---:|---:|---|---:|---:|---:|---:|---|",
    ]
    env = tables[(0.25, "exact")].envelope
    for target in (3.0, 1.5, 1.3):
        t0 = time.perf_counter()
        rec = fastest_spiral(env, B1, target)
        t_rec = time.perf_counter() - t0
        lines.append(f"| {target:g} | recursion (4.26) | - | - | - | {t_rec:.4f} | {rec.stop_reason} | "
                     f"{rec.revolutions} | {rec.path_length:.2f} | - | {rec.revolutions} | - |")
        runs = [("min cost flow", dict(resolution=16), "adaptive 16"), ("min cost flow", dict(resolution=64), "adaptive 64"),
                ("min cost flow, length", dict(resolution=16, objective="length"), "adaptive 16")]
        if target == 3.0:
            runs.append(("min cost flow", dict(spacing=0.01), "uniform 0.01"))
            runs.append(("CP-SAT", dict(resolution=2, backend="cp_sat", budget=Budget.of(60.0)), "adaptive 2"))
        for name, kw, gname in runs:
            s = spiral_schedule(env, B1, target, **kw)
            lines.append(
                f"| {target:g} | {name} | {gname} | {s.n_nodes} | {s.n_arcs} | {s.total_time_s:.3f} | {s.solver_status} | "
                f"{s.revolutions} | {fmt(s.path_length, '.2f')} | {s.greedy_revolutions} | {s.recursion.revolutions} | "
                f"{s.certificate.certified if s.certificate else '-'} |"
            )
            assert s.solver_status == "OPTIMAL" and s.certificate.certified
            if s.objective == "revolutions":
                assert s.revolutions == s.greedy_revolutions

    rec = fastest_spiral(env, B1, 1.3)
    polys = []
    for m in (64, 256, 1024):
        t0 = time.perf_counter()
        pl = spiral_polyline(rec.radii, points_per_revolution=m)
        polys.append(f"{m}: {pl.points.shape[0]} points, deviation <= {pl.max_chord_deviation:.2e} a, "
                     f"{1e3 * (time.perf_counter() - t0):.1f} ms")
    lines += [
        "",
        f"The pusher polyline of the recursion's {rec.revolutions} revolutions to 1.3 a (points per revolution: "
        "points, bound on the distance between path and chords, time): " + "; ".join(polys) + ".",
    ]

    # ---------------------------------------------------------------- tip line vs exact schedule
    lines += [
        "",
        f"The tip-line approximation against the exact schedule (recursion (4.26) from b_1 = {B1:g} a on the",
        "same beta grid). *Floor*: the smallest radius with a guarantee (the table's b_inf). *Unsafe",
        "revolutions*: tip-line steps b_(n-1) - b_n larger than the exact d*(b_n), i.e. revolutions on",
        "which the disk may be pushed out. *max |b_n diff|* over the revolutions both schedules make",
        "before the tip line stalls.",
        "",
        "| mu_c | table | floor / a | revs to 10 a | revs to 3 a | revs to 2.1 a | revs to b_inf + 0.05 a | "
        "unsafe revolutions | max abs(b_n diff) / a |",
        "|---:|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for mu in (0.25, 1.0):
        ex_env = tables[(mu, "exact")].envelope
        tp_env = tip_line_envelope(1.0, grids[mu][0])
        binf = limiting_radius(1.0, mu)
        r_ex = fastest_spiral(ex_env, B1, tol=TAIL)
        r_tp = fastest_spiral(tp_env, B1, tol=TAIL)
        n = min(r_ex.revolutions, r_tp.revolutions)
        diff = float(np.max(np.abs(r_ex.radii[:n] - r_tp.radii[:n])))
        unsafe = int(np.sum(r_tp.steps > ex_env.d_star(r_tp.radii[1:])))
        for name, rec, envx in (("exact", r_ex, ex_env), ("tip line", r_tp, tp_env)):
            lines.append(
                f"| {mu:g} | {name} | {envx.b_floor:.6f} | {revs_to(rec, 10.0)} | {revs_to(rec, 3.0)} | "
                f"{revs_to(rec, 2.1)} | {revs_to(rec, binf + 0.05)} | {unsafe if name == 'tip line' else '-'} | "
                f"{diff:.3f} |"
            )

    # ---------------------------------------------------------------- figure 4-21
    t0 = time.perf_counter()
    dense_grid = beta_grid(1.0, B1, 1e-6, refine=(grids[0.25][1], sketch_change_beta(0.25)),
                           grid=BetaGrid(n_low=40, n_mid=30, n_grazing=110))
    dense = critical_radius_table(1.0, 0.25, "sweep", betas=dense_grid)
    t_dense = time.perf_counter() - t0
    lines += [
        "",
        "Figure 4-21 (mu_c = 0.25, b_1 = 100 a): least squares of log(b_n - b_inf) = log C - k log n over",
        "ranges of n (b_inf = 1.25 a from (4.25)); the book reads k ~ 1.6. *exact*: the table above;",
        f"*dense sweep*: {dense_grid.size} points ({t_dense:.0f} s), 1024-point loci. Local slopes are",
        "-d log e / d log n between consecutive revolutions (the staircase of a finite table shows as spread).",
        "",
        "| table | n range | k | C | rms residual (log) | local slopes min / max |",
        "|---|---|---:|---:|---:|---|",
    ]
    fits = {}
    for name, envx in (("exact", env), ("dense sweep", dense.envelope)):
        rec = fastest_spiral(envx, B1, tol=TAIL)
        for lo, hi in ((10, 100), (100, 1000), (150, 1500), (200, 2000), (1000, 5000)):
            f = power_law_fit(rec.radii, 1.25, lo, hi)
            fits[(name, lo)] = f.exponent
            lines.append(f"| {name} | {lo}-{hi} | {f.exponent:.3f} | {f.coefficient:.3g} | {f.rms_residual:.3f} | "
                         f"{f.local_exponent_range[0]:.2f} / {f.local_exponent_range[1]:.2f} |")
        e = rec.radii - 1.25
        lines.append(f"| {name} | b_n - b_inf at n = 100, 200, 500, 1000, 5000 | "
                     + ", ".join(f"{e[n - 1]:.3g}" for n in (100, 200, 500, 1000, 5000)) + " | | | |")
    lines += [
        "",
        "Near grazing r* - b_inf ~ c (pi/2 - beta) with c ~ 1.30 for mu_c = 0.25 (sweep: 1.22 at",
        "pi/2 - beta = 0.1, 1.30 at 1e-3), while d = a(1 - sin beta) ~ a (pi/2 - beta)^2 / 2 (4.24), so",
        "the recursion becomes e_(n-1) - e_n ~ e_n^2 / (2 c^2): e_n ~ 2 c^2 / n, k -> 1. The book's",
        "1.6 is the slope over the first few hundred revolutions, where the ~110 revolutions of the",
        "linear phase (steps of almost a) still bend the log-log curve. At mu_c = 1, r* - 2a is",
        "quadratic in pi/2 - beta (~2 (pi/2 - beta)^2): e_n falls geometrically, no power law.",
    ]
    write_section("Spiral localization (4.5)", lines)
    assert 1.0 < fits[("dense sweep", 1000)] < 1.3
