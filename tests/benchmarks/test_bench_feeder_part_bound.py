"""Benchmark (not a test): the configuration map of one fence bounded by the part's own loci
against the disk's (solver/feeder/part_bound.py; book 5.1, 7.5), side by side, with
simulated parts in both, and the part bound's search settings against its error and cost.

Writes its section of docs/benchmarks.md. Run with
`pytest tests/benchmarks/test_bench_feeder_part_bound.py --run-benchmarks`."""

from __future__ import annotations

import math
import platform
import statistics
import time

import numpy as np
import pytest

from models.feeder.fence import Fence, fence_map, flush_orientation
from solver.feeder.part_bound import PART_DEFAULT, PART_DIPODS, PART_FINE, PartBoundSettings, PartLoci
from solver.feeder.simulate import simulate_fence_batch
from tests.benchmarks._docs import write_section
from tests.benchmarks.test_bench_feeder import SIM_FENCES  # the same fences as the simulations there
from tests.feeder_cases import PARTS, part, random_encounter

pytestmark = pytest.mark.benchmark

SEED = 20261126
RUNS = 40
SLACK = 1e-6


def own_map(the_part, fence, settings):
    loci = PartLoci(the_part, fence, settings)
    t0 = time.perf_counter()
    fm = fence_map(the_part, fence, own_rate=loci.rate_for)
    return fm, time.perf_counter() - t0, loci.cost


def b_gaps(the_part, fence, fm, encounters, runs):
    """Per band with outcomes: the least turn off the end that a simulated part made, less
    the band's B (degrees; >= 0 inside), and whether every outcome lies in the map."""
    least: dict[int, float] = {}
    inside = True
    for enc, run in zip(encounters, runs):
        if run.status != "left":
            continue
        inside &= fm.map.allows(enc.theta, run.theta_final, SLACK)
        for j, kernel in zip(fm.final_edges, fm.map.kernels):
            turn = fence.sign * math.remainder(run.theta_final - flush_orientation(the_part, j, fence.angle),
                                               2.0 * math.pi)
            if kernel.contains(enc.theta) and -SLACK <= turn <= 0.5 * math.pi:
                least[j] = min(least.get(j, math.inf), turn)
    gaps = [math.degrees(least[t.edge] - t.least) for t in fm.turns if t.edge in least]
    return gaps, inside


def gap(values):
    return f"{min(values):.1f}" if values else "–"


def side_by_side_rows(rng):
    rows = []
    totals = {"runs": 0, "inside_disk": 0, "inside_part": 0, "disk_s": 0.0, "part_s": 0.0}
    for name in PARTS:
        the_part = part(name)
        for deg, mu in SIM_FENCES:
            fence = Fence.create(math.radians(deg), mu)
            t0 = time.perf_counter()
            disk = fence_map(the_part, fence)
            t_disk = time.perf_counter() - t0
            own, t_own, cost = own_map(the_part, fence, PART_DEFAULT)
            encounters = [random_encounter(rng, name) for _ in range(RUNS)]
            runs = simulate_fence_batch(the_part, fence, mu, [(e.body, e.weights) for e in encounters],
                                        [e.theta for e in encounters])
            gap_d, in_d = b_gaps(the_part, fence, disk, encounters, runs)
            gap_p, in_p = b_gaps(the_part, fence, own, encounters, runs)
            left = sum(r.status == "left" for r in runs)
            width_d = statistics.mean(math.degrees(t.most - t.least) for t in disk.turns)
            width_p = statistics.mean(math.degrees(t.most - t.least) for t in own.turns)
            narrower = [math.degrees(b.least - a.least) for a, b in zip(disk.turns, own.turns)]
            rows.append(f"| {name} | {deg:+.0f}° | {mu:g} | {1e3 * t_disk:.0f} | {t_own:.1f} | "
                        f"{cost.rays_bracketed}/{cost.rays} | {width_d:.1f} → {width_p:.1f} | "
                        f"{min(narrower):.2f}–{max(narrower):.2f} | {left} | "
                        f"{'all' if in_d else 'NOT all'} / {'all' if in_p else 'NOT all'} | "
                        f"{gap(gap_d)} / {gap(gap_p)} |")
            totals["runs"] += left
            totals["inside_disk"] += left if in_d else 0
            totals["inside_part"] += left if in_p else 0
            totals["disk_s"] += t_disk
            totals["part_s"] += t_own
    return rows, totals


def settings_rows():
    rows = []
    pent = part("pentagon")
    for deg, mu in ((40.0, 0.25), (-55.0, 0.15)):
        fence = Fence.create(math.radians(deg), mu)
        ref, t_ref, c_ref = own_map(pent, fence, PART_FINE)
        disk = fence_map(pent, fence)
        err = [math.degrees(a.least - r.least) for a, r in zip(disk.turns, ref.turns)]
        rows.append(f"| {deg:+.0f}° | disk | – | – | {min(err):+.2f} / {max(err):+.2f} | – |")
        for label, s in (("dipods only, 17 contacts (not a bound)", PART_DIPODS),
                         ("cheap: 5 contacts, climbs of 2 rays", PartBoundSettings(contacts=5, turns=1, refine_levels=0, max_rays_per_aim=2)),
                         ("default: 5 contacts, climbs of ≤ 8 rays", PART_DEFAULT)):
            got, t, cost = own_map(pent, fence, s)
            err = [math.degrees(g.least - r.least) for g, r in zip(got.turns, ref.turns)]
            rows.append(f"| {deg:+.0f}° | {label} | {t:.1f} | {cost.rays} | {min(err):+.2f} / {max(err):+.2f} | "
                        f"{t_ref:.0f} |")
    return rows


def test_bench_feeder_part_bound():
    rng = np.random.default_rng(SEED)
    s_rows = settings_rows()
    rows, tot = side_by_side_rows(rng)
    lines = [
        f"`tests/benchmarks/test_bench_feeder_part_bound.py`, seed {SEED}, {platform.python_version()}, one core. "
        "The same fences and parts as the simulations above; the part's own bound with its default search "
        "(5 contacts per edge and μ_c, 360 dipods each, and from the dipod that bounds the slip at each of 2 turns a "
        "climb along the exact locus by certified rays a degree apart while the slip rises, at most 8 rays).",
        "",
        "Side by side: map time (disk ms, part s), rays certified / traced, the mean band width (A − B, "
        "degrees) with the disk → with the part, how much later B is per band with the part (degrees), "
        f"{RUNS} simulated parts each (random tripods in the outline, random initial orientations): how many "
        "left the fence, whether all lie in the disk's / the part's map, and the least gap over the bands "
        "between B and the nearest outcome (degrees, disk / part: how far each bound is from what was seen).",
        "",
        "| part | γ | μ_c | disk ms | part s | rays | band width | B later by | left | inside | B gap |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
        *rows,
        "",
        f"{tot['inside_part']} of {tot['runs']} outcomes inside the part-bounded maps, {tot['inside_disk']} inside "
        f"the disk's; the part maps took {tot['part_s']:.0f} s against {tot['disk_s']:.2f} s for the disk "
        f"({tot['part_s'] / tot['disk_s']:.0f} times).",
        "",
        "The search's settings against its error (the pentagon; B − B_FINE per band, least / most, "
        "degrees; FINE: 9 contacts, 1440 dipods, 3 turns, climbs by half a degree then a quarter, at most 16 "
        "rays; negative is the "
        "safe side, a wider band):",
        "",
        "| γ | bound | s | rays | B − B_FINE (deg) | FINE s |",
        "|---|---|---|---|---|---|",
        *s_rows,
    ]
    write_section("The part's own bound against the disk (issue 12, book 5.1, 7.5)", lines)
    assert tot["inside_part"] == tot["runs"]
