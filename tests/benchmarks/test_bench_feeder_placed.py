"""Benchmark (not a test): feeder designs searched as placed on a belt (issue 24;
solver/feeder/design.py with a belt; book 5.3-5.4, 1.8.6, 7.1).

Writes its sections of docs/benchmarks.md: the ten benchmark parts at mu_c 0.25 and over
[0.2, 0.3] on a belt 20 part radii wide, candidates 20..70 degrees in 5 degree steps on both
sides, a gate allowed when fences alone cannot: the design, its belt, its guaranteed yield,
and 1000 simulated parts on the placed belt; then the design time of the pentagon against
the candidate step and the width of the mu_c interval. Run with
`pytest tests/benchmarks/test_bench_feeder_placed.py --run-benchmarks`."""

from __future__ import annotations

import dataclasses
import math
import os
import platform
import time

import pytest

from models.feeder.fence import feeder_part
from models.feeder.gate import GateSpec
from models.feeder.placed import Goal
from solver import BeltSpec, FeederDesignProblem, feeder_design
from tests.benchmarks._docs import write_section
from tests.benchmarks.test_bench_feeder_design import ALL_PARTS

pytestmark = pytest.mark.benchmark

SEED = 20261127
BELT_RADII = 20.0
VALIDATION = 1000
MU_CASES = ((0.25, 0.25), (0.2, 0.3))


def problem(name: str, mu: tuple[float, float], step_deg: float = 5.0, validation: int = VALIDATION) -> FeederDesignProblem:
    v, cm = ALL_PARTS[name]
    part = feeder_part(v, cm)
    return FeederDesignProblem(part, math.radians(20), math.radians(70), math.radians(step_deg), mu, max_depth=8,
                               alternate=False, validation_parts=validation, seed=SEED,
                               belt=BeltSpec(BELT_RADII * part.circumradius), gate=GateSpec())


def fences_text(res) -> str:
    return " ".join(f"{math.degrees(res.maps[f].fence.angle):+.0f}" for f in res.design.fences)


def row(name: str, mu: tuple[float, float]) -> str:
    res = feeder_design(problem(name, mu))
    t = res.timings
    a = res.maps[0].part.circumradius
    mu_txt = f"{mu[0]:g}" if mu[0] == mu[1] else f"{mu[0]:g}–{mu[1]:g}"
    times = (f"{t.get('maps', 0):.1f} / {t.get('reach_profiles', 0):.1f} / {t.get('search', 0):.2f} / "
             f"{t.get('validation', 0):.0f}")
    d = res.design
    if d is None:
        s = res.placed_search
        why = "exhausted" if s.exhausted else f"none to {s.depth_proven} fences"
        if res.fences_only_exhausted is not None:
            alone = "exhausted" if res.fences_only_exhausted else "none to 8 fences"
            why = f"fences alone: {alone}; with a gate: {why}"
        refused = ", ".join(f"{k} {v}" for k, v in s.refused.items() if v)
        return f"| {name} | {mu_txt} | – | none ({why}; steps refused: {refused}) | – | – | – | – | – | – | {times} |"
    pl = res.placement
    v = res.validation
    binding = sorted({b for bs in pl.binding for b in bs})
    gate = "–" if d.gate is None else (f"{d.gate.feature} {'≤' if d.gate.rule == 'at_most' else '≥'} "
                                       f"{d.gate.threshold / a:.3f} a (±{d.gate.margin / a:.3f} a)")
    sides = "".join("R" if pl_f.side == "right" else "L" for pl_f in pl.fences)
    sim = (f"{v.in_band} / {v.rejected} / {v.outside} / {v.failed}")
    return (f"| {name} | {mu_txt} | {len(d.fences)} | {fences_text(res)} ({sides}) | {gate} | "
            f"{pl.length / a:.1f} ({', '.join(binding)}) | {100 * d.guaranteed_yield:.2f} | "
            f"{1 / d.guaranteed_yield:.2f} | {sim} | {100 * v.succeeded:.1f} | {times} |")


def best_gate(name: str, mu: tuple[float, float]) -> str:
    """For a part without a design: the best gate design at any guaranteed yield (no
    validation)."""
    base = problem(name, mu, validation=0)
    res = feeder_design(dataclasses.replace(base, gate=GateSpec(min_yield=0.01)))
    d = res.design
    mu_txt = f"{mu[0]:g}" if mu[0] == mu[1] else f"{mu[0]:g}–{mu[1]:g}"
    if d is None:
        return f"{name} at μ_c {mu_txt}: no gate design of any yield up to 4 fences either"
    return (f"{name} at μ_c {mu_txt}: the best gate design at any yield has {len(d.fences)} fence(s) "
            f"({fences_text(res)}) and guarantees {100 * d.guaranteed_yield:.1f} %, below the 25 % asked")


def test_bench_feeder_placed():
    only = os.environ.get("BENCH_PARTS")
    names = [n for n in ALL_PARTS if only is None or n in only.split(",")]
    rows = []
    nothing = []
    t0 = time.perf_counter()
    for name in names:
        for mu in MU_CASES:
            rows.append(row(name, mu))
            print(rows[-1], flush=True)
            if "| none (" in rows[-1]:
                nothing.append(best_gate(name, mu))
    lines = [
        f"`tests/benchmarks/test_bench_feeder_placed.py`, seed {SEED}, {platform.python_version()}, one core of a "
        f"2-core machine (the other mostly idle), {time.perf_counter() - t0:.0f} s in all. Belt {BELT_RADII:g} part radii "
        "wide (clearance 0.1 a, spacing 2 a, parts entering with the CM anywhere within 0.5 a of a lane beside the "
        "right side), candidates 20°…70° in 5° steps "
        "on both sides, sides free (same-side runs where the width allows), depth up to 8, a fences-only design "
        "needs a guaranteed yield of 99.5 %; when none exists up to that depth a reject gate is allowed (either "
        "silhouette extent, margin 0.005 a, guaranteed yield at least 25 %: fewer fences, then the higher yield).",
        "",
        "Columns: fences; the design (γ in degrees, R/L the side each hangs from); the gate (feature, rule, "
        "threshold, margin); the shortest belt for it (part radii, from the first root to the last free end or the "
        "gate) and what keeps it from being shorter; the guaranteed yield per pass from the maps (%) and the "
        "passes a part takes at most on average (1 / yield); 1000 simulated parts on the placed belt (random "
        "orientation, balanced tripod, μ_c over the interval): accepted in the accepted band / rejected by the "
        "gate / accepted outside it / failed (missed a fence, left one still turning, left the belt, or did not "
        "finish); the share that ended as promised (%); seconds for the maps / reach profiles / search / "
        "validation.",
        "",
        "| part | μ_c | fences | design (γ, deg) | gate | belt (a) | guaranteed (%) | passes | in band / rejected / "
        "outside / failed | as promised (%) | s |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
        *rows,
        "",
        "Where no design is returned: " + ("; ".join(nothing) if nothing else "none") + ".",
    ]
    write_section("Feeder designs searched as placed (issue 24, book 5.3-5.4, 1.8.6, 7.1)", lines)


def test_bench_feeder_placed_time():
    """Design time of the pentagon (maps, reach profiles, search, placement; no validation)."""
    rows = []
    for step in (10.0, 5.0, 2.5):
        for mu in ((0.25, 0.25), (0.22, 0.28), (0.2, 0.3)):
            best = math.inf
            res = None
            for _ in range(2):
                t = time.perf_counter()
                res = feeder_design(problem("pentagon", mu, step, validation=0))
                best = min(best, time.perf_counter() - t)
            t = res.timings
            d = res.design
            what = "–" if d is None else f"{len(d.fences)}{'' if d.gate is None else ' + gate'}"
            rows.append(f"| {step:g}° | {len(res.maps)} | {mu[1] - mu[0]:.2f} | {t['maps']:.2f} | "
                        f"{t['reach_profiles']:.2f} | {t['search']:.2f} | {1e3 * t.get('layout', 0):.0f} | "
                        f"{best:.2f} | {what} |")
            print(rows[-1], flush=True)
    lines = [
        f"`tests/benchmarks/test_bench_feeder_placed.py::test_bench_feeder_placed_time`, {platform.python_version()}, "
        "one core of an otherwise idle 2-core machine, best of 2. The pentagon on the belt above, the design without validation: "
        "candidate maps, reach profiles (phase 6 for every reach at once), the placed search (fences only, then with "
        "a gate), and the placement's linear programme.",
        "",
        "| step | candidates | μ_c width | maps s | profiles s | search s | layout ms | total s | design |",
        "|---|---|---|---|---|---|---|---|---|",
        *rows,
    ]
    write_section("Feeder design time on a belt (issue 24)", lines)


GOAL_CASES = (
    # (part, input edge against a guide, side, tolerance in degrees)
    ("near-symmetric", 0, "either", 40.0),
    ("rectangle", 0, "either", 40.0),
    ("pentagon", 0, "either", 40.0),
)


def test_bench_feeder_placed_goal():
    """Goals a user states: an edge against a guide, either way round."""
    rows = []
    for name, edge, side, tol_deg in GOAL_CASES:
        base = problem(name, (0.25, 0.25))
        part = base.part
        j = part.hull_edge_of_input(edge)
        goal = Goal.edge_against_guide(part, j, side, math.radians(tol_deg))
        t = time.perf_counter()
        res = feeder_design(dataclasses.replace(base, goal=goal))
        dt = time.perf_counter() - t
        d, v = res.design, res.validation
        if d is None:
            rows.append(f"| {name} | {edge} ({side}, ±{tol_deg:g}°) | none | – | – | – | {dt:.0f} |")
            continue
        gate = "–" if d.gate is None else f"{d.gate.feature} {d.gate.rule}"
        rows.append(f"| {name} | {edge} ({side}, ±{tol_deg:g}°) | {fences_text(res)} | {gate} | "
                    f"{100 * d.guaranteed_yield:.2f} | {v.in_band} / {v.rejected} / {v.outside} / {v.failed} | {dt:.0f} |")
        print(rows[-1], flush=True)
    lines = [
        "The same belt and candidates, μ_c = 0.25, with a goal the user states instead of one band: edge 0 of the "
        "outline as given (from vertex 0 to vertex 1) along the belt against a guide on either side, within the "
        f"tolerance; {VALIDATION} simulated parts each (accepted in the goal / rejected / accepted outside / failed); "
        "seconds for the whole request.",
        "",
        "| part | edge (side, tolerance) | design (γ, deg) | gate | guaranteed (%) | simulated | s |",
        "|---|---|---|---|---|---|---|",
        *rows,
    ]
    write_section("Feeder designs for a goal the user states (issue 24)", lines)
