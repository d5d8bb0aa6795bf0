"""Benchmark (not a test): configuration maps of one fence and the fence simulator
(models/feeder/fence.py, solver/feeder/simulate.py; book 5.1, 5.2, 6.4-6.6).

Writes its section of docs/benchmarks.md: the map's time against the extreme-B
integration's steps and the error of its band edges against FINE; the boolean matrix's
time against the orientation resolution; simulated parts per second, how many outcomes
fall inside their maps, and how much of each band they fill; the batched simulator's
throughput. Run with
`pytest tests/benchmarks/test_bench_feeder.py --run-benchmarks`."""

from __future__ import annotations

import math
import platform
import time

import numpy as np
import pytest

from models.feeder.arcs import ccw_distance
from models.feeder.fence import FINE, FeederTolerances, Fence, fence_map
from solver.feeder.simulate import simulate_fence, simulate_fence_batch
from tests.benchmarks._docs import write_section
from tests.benchmarks._sim_steps import step_cases, step_sweep
from tests.benchmarks._timing import timed
from tests.feeder_cases import PARTS, part, random_encounter

pytestmark = pytest.mark.benchmark

SEED = 20261124
FENCES = ((40.0, (0.25, 0.25)), (-55.0, (0.15, 0.15)), (30.0, (0.1, 0.3)))
SIM_FENCES = ((40.0, 0.25), (-55.0, 0.15), (24.0, 0.43))  # the last 3 % above the friction angle
RUNS = 20
SLACK = 1e-6


def map_rows():
    rows = []
    pent = part("pentagon")
    for deg, mu in FENCES:
        fence = Fence.create(math.radians(deg), mu)
        ref = fence_map(pent, fence, FINE)
        t_fine, _ = timed(lambda: fence_map(pent, fence, FINE), repeat=1)
        for steps in (8, 16, 32):
            tol = FeederTolerances(endpoint_steps=steps)
            t, got = timed(lambda: fence_map(pent, fence, tol), repeat=5)
            err = [math.degrees(g.least - r.least) for g, r in zip(got.turns, ref.turns)]
            rows.append(f"| {deg:+.0f}° | {mu[0]:g}–{mu[1]:g} | {steps} | {1e3 * t:.0f} | "
                        f"{min(err):+.3f} / {max(err):+.3f} | {1e3 * t_fine:.0f} |")
    return rows


def matrix_rows():
    cmap = fence_map(part("pentagon"), Fence.create(math.radians(40.0), 0.25)).map
    rows = []
    for n in (90, 360, 1440):
        t, m = timed(lambda: cmap.matrix(n), repeat=5)
        rows.append(f"| {360 / n:g}° ({n}) | {1e3 * t:.2f} | {int(m.sum())} |")
    return rows


def sim_rows(rng):
    rows = []
    totals = {"runs": 0, "inside": 0, "time": 0.0, "batch_time": 0.0, "solves": 0}
    for name in PARTS:
        the_part = part(name)
        for deg, mu in SIM_FENCES:
            fence = Fence.create(math.radians(deg), mu)
            cmap = fence_map(the_part, fence).map
            where: dict[int, list[float]] = {}
            inside = jams = cut = 0
            t_sim = 0.0
            solves = 0
            encounters = [random_encounter(rng, name) for _ in range(RUNS)]
            t0 = time.perf_counter()
            batch = simulate_fence_batch(the_part, fence, mu, [(e.body, e.weights) for e in encounters],
                                         [e.theta for e in encounters])
            t_batch = time.perf_counter() - t0
            for enc, twin in zip(encounters, batch):
                t0 = time.perf_counter()
                run = simulate_fence(the_part, fence, mu, enc.body, enc.weights, enc.theta)
                t_sim += time.perf_counter() - t0
                assert twin.status == run.status and twin.theta_final == run.theta_final
                solves += run.counts.solves
                if run.status == "jammed":
                    jams += 1
                    inside += cmap.jam.contains(enc.theta)
                    continue
                if run.status != "left":
                    cut += 1
                    continue
                ok = cmap.allows(enc.theta, run.theta_final, SLACK)
                inside += ok
                for j, (band, kernel) in enumerate(zip(cmap.bands, cmap.kernels)):
                    if kernel.contains(enc.theta) and band.contains(run.theta_final, SLACK):
                        s, w = band.arcs[0]
                        d = ccw_distance(s - SLACK, run.theta_final) - SLACK
                        where.setdefault(j, []).append(d / w if w > 0 else 0.0)
            spans = [f"{min(v):.2f}–{max(v):.2f}" for _, v in sorted(where.items()) if len(v) >= 2]
            rows.append(f"| {name} | {deg:+.0f}° | {mu:g} | {RUNS} | {inside} | {jams} | {cut} | "
                        f"{RUNS / t_sim:.1f} | {RUNS / t_batch:.1f} | {solves / RUNS:.0f} | {', '.join(spans) or '–'} |")
            totals["runs"] += RUNS
            totals["inside"] += inside
            totals["time"] += t_sim
            totals["batch_time"] += t_batch
            totals["solves"] += solves
    return rows, totals


def throughput_rows(rng):
    """Parts per second against the batch's size (pentagon, gamma = 0.7, mu_c = 0.25)."""
    the_part = part("pentagon")
    fence = Fence.create(0.7, 0.25)
    encounters = [random_encounter(rng, "pentagon") for _ in range(200)]
    rows = []
    t0 = time.perf_counter()
    for enc in encounters[:20]:
        simulate_fence(the_part, fence, 0.25, enc.body, enc.weights, enc.theta)
    rows.append(f"| one at a time | {20 / (time.perf_counter() - t0):.1f} |")
    for size in (10, 50, 200):
        t0 = time.perf_counter()
        simulate_fence_batch(the_part, fence, 0.25, [(e.body, e.weights) for e in encounters[:size]],
                             [e.theta for e in encounters[:size]])
        rows.append(f"| batch of {size} | {size / (time.perf_counter() - t0):.1f} |")
    return rows


def step_rows(rng):
    """The final orientation against the step (reference: step 0.0025 a)."""
    sweep = step_sweep(step_cases(rng))
    return [f"| {st:g} a | {math.degrees(r.worst_error):.3f} | {r.mean_solves:.0f} |" for st, r in sweep.items()]


def test_bench_feeder():
    rng = np.random.default_rng(SEED)
    m_rows = map_rows()
    x_rows = matrix_rows()
    s_rows, tot = sim_rows(rng)
    st_rows = step_rows(rng)
    tp_rows = throughput_rows(rng)
    assert tot["inside"] == tot["runs"]
    lines = [
        f"`tests/benchmarks/test_bench_feeder.py`, seed {SEED}, {platform.python_version()}, one core. "
        "The five-sided part is `tests/feeder_cases.py`'s irregular pentagon (figure 1-9's outline is "
        "not in the OCR text).",
        "",
        "Map of one fence with the disk bound (`fence_map`): median of 5 runs; the error of each "
        "band's B edge against FINE (200 arc-length steps, 400 locus points, no margin), least / "
        "most over the bands, after the default margin b_margin = 2e-3 rad (0.11°) (negative: the band is "
        "wider than FINE's, the safe side).",
        "",
        "| γ | μ_c | B steps | map ms | B − B_FINE (deg) | FINE ms |",
        "|---|---|---|---|---|---|",
        *m_rows,
        "",
        "The boolean matrix of a map (`ConfigurationMap.matrix`) against the orientation grid "
        "(the symbolic map does not depend on it):",
        "",
        "| resolution | ms | true cells |",
        "|---|---|---|",
        *x_rows,
        "",
        "Simulated parts (`simulate_fence`, one random balanced tripod in the part and a random "
        "initial orientation per run): inside = final orientation in a band whose kernel holds "
        "the initial one (slack 1e-6 rad), or a jam where the map allows one; cut = step limit or stalled; "
        "fill = where in its band the outcomes fell, from its clockwise end (0) to its "
        "counter-clockwise end (1), per band with two or more outcomes (γ > 0: 0 is B and 1 is A; "
        "γ < 0: 0 is A and 1 is B).",
        "",
        "| part | γ | μ_c | runs | inside | jams | cut | parts/s | batched | solves/part | fill per band |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
        *s_rows,
        "",
        f"All {tot['runs']} outcomes inside their maps; {tot['runs'] / tot['time']:.1f} parts/s overall one at a "
        f"time, {tot['runs'] / tot['batch_time']:.1f} batched ({RUNS} parts per batch, `simulate_fence_batch`: "
        f"the same runs, equal to the last bit), {tot['solves'] / tot['runs']:.0f} forward solves per part.",
        "",
        "Throughput against the batch's size (pentagon, γ = 0.7, μ_c = 0.25; the forward solves of a round "
        "are one Newton batch, what remains is each run's own geometry in Python):",
        "",
        "| runs | parts/s |",
        "|---|---|",
        *tp_rows,
        "",
        "The simulator's step against the error of the final orientation (eight runs: four parts, "
        "γ = 0.7 with μ_c 0.25 and γ = −0.9 with μ_c 0.15, against step 0.0025 a): first order; the "
        "default is 0.02 a.",
        "",
        "| step | worst error (deg) | solves/part |",
        "|---|---|---|",
        *st_rows,
    ]
    write_section("Configuration maps and the fence simulator (issue 12, book 5.1-5.2, 6.4-6.6)", lines)
