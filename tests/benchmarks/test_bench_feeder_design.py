"""Benchmark (not a test): designing feeders (solver/feeder/design.py; book 5.3, 5.4).

Writes its section of docs/benchmarks.md: for six parts, the shortest design with fences
alternating sides and without, the breadth-first search against CP-SAT (time, the depth
each proves), and simulated parts through each design; then the time against the step of
the candidate angles and against the width of the mu_c interval. Run with
`pytest tests/benchmarks/test_bench_feeder_design.py --run-benchmarks`."""

from __future__ import annotations

import math
import platform

import pytest

from models.feeder.fence import feeder_part
from solver import FeederDesignProblem, feeder_design
from tests.benchmarks._docs import write_section
from tests.feeder_cases import PARTS

pytestmark = pytest.mark.benchmark

SEED = 20261126
VALIDATION = 100


EXTRA_PARTS = {
    # four more outlines for the comparison with the push baseline (CM: the plate's centroid,
    # except pentagon 2: a CM inside it)
    "scalene triangle": ([[0, 0], [3, 0], [0.8, 1.6]], [1.2667, 0.5333]),
    "trapezoid": ([[0, 0], [4, 0], [3, 1.5], [1, 1.5]], [2.0, 0.6667]),
    "long rectangle": ([[0, 0], [6, 0], [6, 1], [0, 1]], [3.0, 0.5]),
    "pentagon 2": ([[0, 0], [2.5, -0.3], [3.2, 1.2], [1.4, 2.2], [-0.4, 1.4]], [1.3, 0.8]),
}
ALL_PARTS = {**PARTS, **EXTRA_PARTS}


def problem(name, step_deg=5.0, mu=(0.25, 0.25), alternate=True, validation=0, cp_sat=True, max_depth=10):
    v, cm = ALL_PARTS[name]
    return FeederDesignProblem(feeder_part(v, cm), math.radians(20), math.radians(70), math.radians(step_deg), mu,
                               max_depth=max_depth, alternate=alternate, prove_with_cp_sat=cp_sat,
                               validation_parts=validation, seed=SEED)


def describe(res):
    d = res.design
    if d is None:
        return "none (exhausted)" if res.search.exhausted else f"none to {res.search.depth_proven}"
    return " ".join(f"{math.degrees(res.maps[f].fence.angle):+.0f}" for f in d.fences)


def part_rows():
    rows = []
    for name in PARTS:
        for alternate in (True, False):
            res = feeder_design(problem(name, alternate=alternate, validation=VALIDATION))
            t = res.timings
            d = res.design
            v = res.validation
            val = "–" if v is None else f"{v.in_band}/{v.parts} ({v.outside} out, {v.unflushed} unflushed)"
            cp = res.cp_sat
            rows.append(
                f"| {name} | {'yes' if alternate else 'no'} | {'–' if d is None else len(d.fences)} | {describe(res)} | "
                f"{'–' if d is None else f'{math.degrees(d.margin):.2f}'} | {1e3 * t['maps']:.0f} | "
                f"{1e3 * t['search']:.0f} | {res.search.nodes} / {res.search.pruned} | "
                f"{1e3 * t['cp_sat']:.0f} | {cp.depth_proven} | {val} |")
    return rows


def baseline_rows():
    rows = []
    for name in ALL_PARTS:
        res = feeder_design(problem(name, alternate=False, cp_sat=False))
        alt = feeder_design(problem(name, alternate=True, cp_sat=False))
        plan = res.baseline
        t = res.timings
        pushes = "–" if plan.alphas is None else str(1 + len(plan.alphas))
        tol = "–" if plan.alphas is None or not plan.alphas else f"{math.degrees(plan.tolerance):.2f}"
        d, da = res.design, alt.design
        rows.append(f"| {name} | {pushes} | {tol} | {1e3 * plan.solve_time_s:.1f} | "
                    f"{'–' if d is None else len(d.fences)} | {'–' if da is None else len(da.fences)} | "
                    f"{1e3 * (t['maps'] + t['search']):.0f} |")
    return rows


def step_rows():
    rows = []
    for step in (10.0, 5.0, 2.5, 1.0):
        res = feeder_design(problem("pentagon", step_deg=step, alternate=False))
        t = res.timings
        d = res.design
        rows.append(f"| {step:g}° | {len(res.maps)} | {1e3 * t['maps']:.0f} | {1e3 * t['search']:.0f} | "
                    f"{1e3 * t['cp_sat']:.0f} | {'–' if d is None else len(d.fences)} |")
    return rows


def mu_rows():
    rows = []
    for mu in ((0.25, 0.25), (0.22, 0.28), (0.2, 0.3), (0.15, 0.35)):
        res = feeder_design(problem("pentagon", mu=mu, alternate=False))
        t = res.timings
        d = res.design
        rows.append(f"| {mu[0]:g}–{mu[1]:g} | {1e3 * t['maps']:.0f} | {1e3 * t['search']:.0f} | "
                    f"{1e3 * t['cp_sat']:.0f} | {'–' if d is None else len(d.fences)} | "
                    f"{'–' if d is None else f'{math.degrees(d.margin):.2f}'} |")
    return rows


def test_bench_feeder_design():
    p_rows = part_rows()
    b_rows = baseline_rows()
    s_rows = step_rows()
    m_rows = mu_rows()
    lines = [
        f"`tests/benchmarks/test_bench_feeder_design.py`, seed {SEED}, {platform.python_version()}, one core. "
        "Candidate fences at |γ| = 20°…70° (step 5°, both sides: 22 maps), μ_c = 0.25, depth up to 10. These are "
        "fence sequences without a belt (each fence met in its own frame, as the request without `belt` answers); "
        "on a belt the design is searched as placed (issue 24's section below), and these sequences mostly cannot "
        "be built there.",
        "",
        "Per part: the fewest fences (alternating sides or not), the design (fence angles in order), its "
        "margin (1.8.6), the time of the candidates' maps, of the breadth-first search (nodes made / pruned) "
        f"and of CP-SAT proving the same depth (the depth each proves impossible agrees), and {VALIDATION} "
        "simulated parts (random tripod, orientation) through the design: in the final band / simulated.",
        "",
        "| part | alternate | fences | design (γ, deg) | margin (deg) | maps ms | search ms | nodes | "
        "CP-SAT ms | proven | validation |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
        *p_rows,
        "",
        "The baseline users would otherwise pick (Goldberg 1993): a frictionless single pusher, its push "
        "function and shortest plan (`models/feeder/pushplan.py`; pushes, the least tolerance of its turns, "
        "planning time) against the fence design on a belt with μ_c = 0.25 (fences without and with "
        "alternating sides; time of maps and search). – : none (for fences: none to depth 10 or none at "
        "any depth).",
        "",
        "| part | pushes | push tolerance (deg) | plan ms | fences | fences alternating | design ms |",
        "|---|---|---|---|---|---|---|",
        *b_rows,
        "",
        "The pentagon (not alternating) against the step of the candidate angles:",
        "",
        "| step | candidates | maps ms | search ms | CP-SAT ms | fences |",
        "|---|---|---|---|---|---|",
        *s_rows,
        "",
        "The pentagon (step 5°, not alternating) against the width of the μ_c interval (a design for "
        "every μ_c in it):",
        "",
        "| μ_c | maps ms | search ms | CP-SAT ms | fences | margin (deg) |",
        "|---|---|---|---|---|---|",
        *m_rows,
    ]
    write_section("Feeder design (issue 13, book 5.3-5.4)", lines)
