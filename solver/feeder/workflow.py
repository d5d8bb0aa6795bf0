"""What a feeder request asks for, end to end (issue 12; book 5.1, 5.2, 6.4-6.6).

* :func:`feeder_map`: the configuration map of each fence of a sequence (models/feeder/fence.py,
  bounded with the circumscribing disk), their product (5.1, 5.4, 5.5), and optionally its
  boolean matrix on an orientation grid.
* :func:`feeder_simulate`: one part with one known support through the fences in order
  (solver/sim/feeder.py), the final orientation of each fence the initial one of the next,
  and whether each outcome lies in its fence's map.

Both run under a budget: past the deadline they return what was finished, marked
incomplete (status "time_limit").
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from models.feeder.fence import DEFAULT, FeederTolerances, Fence, FenceMap, Part, fence_map
from models.feeder.maps import ConfigurationMap, sequence
from solver.core.budget import UNLIMITED, Budget
from solver.core.errors import TimeLimitReached
from solver.sim.feeder import DEFAULT_SIM, FeederSimSettings, FenceRun, simulate_fence

MAP_SLACK = 1e-6
"""Radians: a simulated final orientation this close to a band counts as in it."""


@dataclass(frozen=True)
class FeederMapProblem:
    """The part, the fences in the order the part meets them, and the grid (cells of the
    circle; 0: no matrix) of the product's boolean matrix."""

    part: Part
    fences: tuple[Fence, ...]
    resolution: int = 0
    tol: FeederTolerances = DEFAULT


@dataclass(frozen=True)
class FeederMapResult:
    maps: tuple[FenceMap, ...]  # the fences finished, in order
    product: ConfigurationMap | None  # of all fences (None unless every map was made)
    matrix: np.ndarray | None
    status: str  # "ok" | "time_limit"
    solve_time_s: float
    message: str

    @property
    def complete(self) -> bool:
        return self.status == "ok"


def feeder_map(problem: FeederMapProblem, budget: Budget = UNLIMITED) -> FeederMapResult:
    t0 = time.perf_counter()
    maps: list[FenceMap] = []
    try:
        for i, fence in enumerate(problem.fences):
            budget.checkpoint(f"the map of fence {i}")
            maps.append(fence_map(problem.part, fence, problem.tol, checkpoint=budget.checkpoint))
        budget.checkpoint("the product of the maps")
    except TimeLimitReached as exc:
        return FeederMapResult(tuple(maps), None, None, "time_limit", time.perf_counter() - t0,
                               f"{len(maps)} of {len(problem.fences)} fence maps made: {exc}")
    product = sequence([m.map for m in maps])
    matrix = product.matrix(problem.resolution) if problem.resolution > 0 else None
    n = len(maps)
    return FeederMapResult(tuple(maps), product, matrix, "ok", time.perf_counter() - t0,
                           f"{n} fence map{'s' if n > 1 else ''} and {'their product' if n > 1 else 'its matrix'} "
                           "bounded with the circumscribing disk")


@dataclass(frozen=True)
class FeederSimProblem:
    """One part with a known support (points relative to the CM in the part's frame,
    weights) at ``theta_initial``, through ``fences`` (each with the mu_c it has)."""

    part: Part
    fences: tuple[tuple[Fence, float], ...]
    support_points: np.ndarray
    weights: np.ndarray
    theta_initial: float
    fence_length: float | None = None
    settings: FeederSimSettings = DEFAULT_SIM
    check_map: bool = True


@dataclass(frozen=True)
class FeederSimResult:
    runs: tuple[FenceRun, ...]  # the fences the part met, in order
    in_map: tuple[bool | None, ...]  # each outcome in its fence's map (None: not checked)
    theta_final: float | None
    status: str  # the last run's: "left" | "missed" | "jammed" | "step_limit" | "stalled" | "time_limit"
    solve_time_s: float
    message: str
    notes: tuple[str, ...] = field(default=())

    @property
    def complete(self) -> bool:
        return len(self.runs) > 0 and all(r.complete for r in self.runs) and (
            self.status == "jammed" or self.theta_final is not None)


def feeder_simulate(problem: FeederSimProblem, budget: Budget = UNLIMITED) -> FeederSimResult:
    t0 = time.perf_counter()
    runs: list[FenceRun] = []
    in_map: list[bool | None] = []
    theta = problem.theta_initial
    status = "time_limit"
    for i, (fence, mu_c) in enumerate(problem.fences):
        run = simulate_fence(problem.part, fence, mu_c, problem.support_points, problem.weights, theta,
                             fence_length=problem.fence_length, settings=problem.settings, budget=budget)
        runs.append(run)
        status = run.status
        final = run.theta_final
        verdict: bool | None = None
        if problem.check_map and run.status == "jammed":
            verdict = fence_map(problem.part, fence).map.jam.contains(theta)
        elif problem.check_map and run.status == "left":  # the maps assume a contact: not for "missed"
            verdict = fence_map(problem.part, fence).map.allows(theta, final, MAP_SLACK)
        in_map.append(verdict)
        if final is None:
            break
        theta = final
    done = len(runs) == len(problem.fences) and runs[-1].theta_final is not None
    n = len(problem.fences)
    message = (f"left all {n} fence{'s' if n > 1 else ''}" if done else
               f"stopped at fence {len(runs) - 1} of {n}: {runs[-1].message}")
    return FeederSimResult(tuple(runs), tuple(in_map), theta if done else None, status, time.perf_counter() - t0, message)
