"""The fence simulator's step against the error of its final orientation, shared by the
benchmarks that report it (test_bench_feeder.py in degrees with the solves,
test_bench_speed_error.py in radians with the time)."""

from __future__ import annotations

import math
import statistics
import time
from dataclasses import dataclass

import numpy as np

from models.feeder.fence import Fence
from solver.feeder.simulate import FeederSimSettings, simulate_fence
from tests.feeder_cases import Encounter, random_encounter

REFERENCE_STEP = 0.0025
STEPS = (0.005, 0.01, 0.02, 0.05)


@dataclass(frozen=True)
class StepResult:
    worst_error: float  # radians, the largest over the cases
    mean_solves: float
    mean_time_s: float  # per run


def step_cases(rng: np.random.Generator) -> list[tuple[Encounter, Fence, float, float]]:
    """Eight runs: four parts, gamma = 0.7 with mu_c 0.25 and gamma = -0.9 with mu_c 0.15,
    each with its final orientation at REFERENCE_STEP."""
    cases = []
    for name in ("pentagon", "square", "L-shape", "right triangle"):
        enc = random_encounter(rng, name)
        for gamma, mu in ((0.7, 0.25), (-0.9, 0.15)):
            fence = Fence.create(gamma, mu)
            ref = simulate_fence(enc.part, fence, mu, enc.body, enc.weights, enc.theta,
                                 settings=FeederSimSettings(step=REFERENCE_STEP)).theta_final
            cases.append((enc, fence, mu, ref))
    return cases


def step_sweep(cases: list[tuple[Encounter, Fence, float, float]], steps=STEPS) -> dict[float, StepResult]:
    out = {}
    for step in steps:
        errors, solves, times = [], [], []
        for enc, fence, mu, ref in cases:
            t0 = time.perf_counter()
            run = simulate_fence(enc.part, fence, mu, enc.body, enc.weights, enc.theta,
                                 settings=FeederSimSettings(step=step))
            times.append(time.perf_counter() - t0)
            errors.append(abs(math.remainder(run.theta_final - ref, 2 * math.pi)))
            solves.append(run.counts.solves)
        out[step] = StepResult(max(errors), statistics.mean(solves), statistics.mean(times))
    return out
