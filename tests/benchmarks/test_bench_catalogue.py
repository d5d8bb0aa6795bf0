"""Benchmark (not a test): a feeder catalogue (issue 27) in process and on a local Ray of 1
and 2 CPUs, on this machine: the time of each, the speed-up, and whether every part's design
and validation are identical to the in-process run. Writes its section of
docs/benchmarks.md."""

from __future__ import annotations

import math
import os
import time

import pytest

from models.feeder.fence import feeder_part
from solver import FeederCatalogueProblem, FeederDesignProblem, RayPool, feeder_catalogue, release_ray
from tests.benchmarks._docs import write_section

pytestmark = pytest.mark.benchmark

OUTLINES = [
    [[0, 0], [3, 0], [3.5, 1.5], [1.5, 2.5], [-0.5, 1.2]],
    [[0, 0], [2, 0], [2, 0.6], [0.6, 0.6], [0.6, 2], [0, 2]],
    [[0, 0], [2, 0], [0.4, 1.5]],
    [[0, 0], [2.5, 0], [2.5, 1], [0, 1]],
    [[0, 0], [3, 0], [2.2, 1.2], [0.5, 1.4]],
    [[0, 0], [2, 0.3], [2.4, 1.6], [0.9, 2.2], [-0.3, 1.1]],
]


def centroid(outline):
    from models.core.footprint import Footprint

    return Footprint.create(outline, None).center_of_mass


PARTS = tuple(feeder_part(v, centroid(v)) for v in OUTLINES)
TEMPLATE = FeederDesignProblem(PARTS[0], math.radians(10), math.radians(80), math.radians(5), (0.25, 0.25),
                               max_depth=8, alternate=False, validation_parts=20, seed=1)


def summary(result):
    return [(d.design, d.validation.in_band) for d in result.designs]


def test_catalogue_speed_up():
    rows = []
    reference = None
    for workers in (0, 1, 2):
        pool = RayPool(workers=workers)
        if workers:  # start the local Ray first: its start-up is not the catalogue's
            feeder_catalogue(FeederCatalogueProblem(PARTS[:1], TEMPLATE, pool))
        t0 = time.perf_counter()
        result = feeder_catalogue(FeederCatalogueProblem(PARTS, TEMPLATE, pool))
        elapsed = time.perf_counter() - t0
        release_ray()
        if reference is None:
            reference = summary(result)
        rows.append((workers, result.run.backend, elapsed, summary(result) == reference, result.complete))
        print(rows[-1])
    base = rows[0][2]
    lines = [
        f"Measured {time.strftime('%Y-%m-%d')} on this machine ({os.cpu_count()} cores, nothing else running) by "
        f"`tests/benchmarks/test_bench_catalogue.py`: {len(PARTS)} parts, each designed (candidates 10..80 degrees "
        "in 5 degree steps, mu_c 0.25, same side allowed) and validated by 20 simulated parts; a local Ray started "
        "before the clock starts (its start-up is 2-4 s).",
        "",
        "| where | time (s) | speed-up | designs and validations identical to in process |",
        "|---|---|---|---|",
    ]
    for workers, backend, elapsed, same, complete in rows:
        where = "in process" if workers == 0 else f"local Ray, {workers} CPU{'s' if workers > 1 else ''}"
        lines.append(f"| {where} | {elapsed:.1f} | {base / elapsed:.2f}x | {'yes' if same and complete else 'NO'} |")
    write_section("Feeder catalogue on Ray (issue 27)", lines)
