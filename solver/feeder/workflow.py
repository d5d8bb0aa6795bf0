"""What a feeder request asks for, end to end (issue 12; book 5.1, 5.2, 6.4-6.6).

* :func:`feeder_map`: the configuration map of each fence of a sequence (models/feeder/fence.py,
  bounded with the circumscribing disk, or on request the part's own loci), their product (5.1, 5.4, 5.5), and optionally its
  boolean matrix on an orientation grid.
* :func:`feeder_simulate`: one part with one known support through the fences in order
  (solver/feeder/simulate.py), the final orientation of each fence the initial one of the next,
  and whether each outcome lies in its fence's map. Fences are either each in its own
  frame (the part placed above it), or segments placed in the world frame of a belt, met
  one after the other from a start pose (a fence passed untouched is "missed").

Both run under a budget: past the deadline they return what was finished, marked
incomplete (status "time_limit").
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.feeder.fence import DEFAULT, FeederTolerances, Fence, FenceMap, fence_map
from models.feeder.maps import ConfigurationMap, sequence
from solver.core.budget import UNLIMITED, Budget
from solver.core.errors import TimeLimitReached
from solver.feeder.part_bound import PART_DEFAULT, PartBoundCost, PartBoundSettings, PartLoci
from solver.feeder.simulate import (
    DEFAULT_SIM,
    FeederSimSettings,
    FenceRun,
    FenceSegment,
    own_frame_segment,
    simulate_belt_batch,
    simulate_fence,
)
from solver.locus.disk_rings import disk_boundaries

MAP_SLACK = 1e-6
"""Radians: a simulated final orientation this close to a band counts as in it."""


BOUNDS = ("disk", "part")
"""What bounds the turns off a fence's end: the part's circumscribing disk (analytic loci,
cheap), or the part's own loci as well (solver/feeder/part_bound.py, tighter, far dearer)."""


@dataclass(frozen=True)
class FeederMapProblem:
    """The part, the fences in the order the part meets them, the grid (cells of the
    circle; 0: no matrix) of the product's boolean matrix, and the bound (BOUNDS)."""

    part: Footprint
    fences: tuple[Fence, ...]
    resolution: int = 0
    tol: FeederTolerances = DEFAULT
    bound: str = "disk"
    part_bound: PartBoundSettings = PART_DEFAULT

    def __post_init__(self) -> None:
        if self.bound not in BOUNDS:
            raise InvalidInput("bound", f"must be one of {list(BOUNDS)}")


@dataclass(frozen=True)
class FeederMapResult:
    maps: tuple[FenceMap, ...]  # the fences finished, in order
    product: ConfigurationMap | None  # of all fences (None unless every map was made)
    matrix: np.ndarray | None
    status: str  # "ok" | "time_limit"
    solve_time_s: float
    message: str
    bound: str = "disk"
    part_bound_costs: tuple[PartBoundCost, ...] = ()  # per fence searched, with bound "part"

    @property
    def complete(self) -> bool:
        return self.status == "ok"


def feeder_map(problem: FeederMapProblem, budget: Budget = UNLIMITED) -> FeederMapResult:
    t0 = time.perf_counter()
    maps: list[FenceMap] = []
    costs: list[PartBoundCost] = []
    try:
        for i, fence in enumerate(problem.fences):
            budget.checkpoint(f"the map of fence {i}")
            own = None
            if problem.bound == "part":
                own = PartLoci(problem.part, fence, problem.part_bound, budget.checkpoint)
            try:
                maps.append(fence_map(problem.part, fence, problem.tol, checkpoint=budget.checkpoint,
                                      own_rate=None if own is None else own.rate_for, boundaries=disk_boundaries))
            finally:
                if own is not None:
                    costs.append(own.cost)
        budget.checkpoint("the product of the maps")
    except TimeLimitReached as exc:
        return FeederMapResult(tuple(maps), None, None, "time_limit", time.perf_counter() - t0,
                               f"{len(maps)} of {len(problem.fences)} fence maps made: {exc}", problem.bound,
                               tuple(costs))
    product = sequence([m.map for m in maps])
    matrix = product.matrix(problem.resolution) if problem.resolution > 0 else None
    n = len(maps)
    how = ("bounded with the circumscribing disk" if problem.bound == "disk" else
           "with the turns off the end bounded by the part's own loci (the reach by the disk; interpolated "
           "between traced rays and contacts, so measured, not proven: within about 1 degree of a finer search, "
           "docs/benchmarks.md)")
    return FeederMapResult(tuple(maps), product, matrix, "ok", time.perf_counter() - t0,
                           f"{n} fence map{'s' if n > 1 else ''} and {'their product' if n > 1 else 'its matrix'} "
                           f"{how}", problem.bound, tuple(costs))


@dataclass(frozen=True)
class FeederSimProblem:
    """One part with a known support (points relative to the CM in the part's frame,
    weights) at ``theta_initial``, through ``fences`` (each with the mu_c it has). With
    ``placements`` (a free end E, world frame, and a length for each fence) the fences are
    placed and the part starts with its CM at ``start`` (None: above the first fence, as a
    fence alone)."""

    part: Footprint
    fences: tuple[tuple[Fence, float], ...]
    support_points: np.ndarray
    weights: np.ndarray
    theta_initial: float
    fence_length: float | None = None
    settings: FeederSimSettings = DEFAULT_SIM
    check_map: bool = True
    placements: tuple[tuple[np.ndarray, float], ...] | None = None
    start: np.ndarray | None = None


@dataclass(frozen=True)
class FeederSimResult:
    runs: tuple[FenceRun, ...]  # the fences the part met (or passed, on a belt), in order
    segments: tuple[FenceSegment, ...]  # every fence as simulated (its own frame: E at the origin)
    placed: bool  # the fences were placed in the world frame (met one after the other)
    in_map: tuple[bool | None, ...]  # each outcome in its fence's map (None: not checked)
    theta_final: float | None
    status: str  # the last run's: "left" | "missed" | "jammed" | "step_limit" | "stalled" | "overlap" | "time_limit"
    solve_time_s: float
    message: str
    notes: tuple[str, ...] = field(default=())

    @property
    def complete(self) -> bool:
        return len(self.runs) > 0 and all(r.complete for r in self.runs) and (
            self.status == "jammed" or self.theta_final is not None)


def feeder_simulate(problem: FeederSimProblem, budget: Budget = UNLIMITED) -> FeederSimResult:
    t0 = time.perf_counter()
    if problem.placements is None:
        segments = tuple(own_frame_segment(problem.part, fence, problem.fence_length) for fence, _ in problem.fences)
        runs = _each_in_its_frame(problem, budget)
    else:
        if len(problem.placements) != len(problem.fences):
            raise InvalidInput("fences", "need one placement (end, length) per fence")
        segments = tuple(FenceSegment.create(fence, end, length)
                         for (fence, _), (end, length) in zip(problem.fences, problem.placements))
        mus = np.array([[mu for _, mu in problem.fences]])
        (belt,) = simulate_belt_batch(problem.part, list(segments), mus,
                                      [(problem.support_points, problem.weights)], [problem.theta_initial],
                                      None if problem.start is None else problem.start[None], problem.settings,
                                      budget=budget)
        runs = list(belt.runs)
        if problem.start is not None and runs[0].status == "overlap":
            raise InvalidInput("start", "the first fence passes through the part there")
    in_map = [_in_map(problem, fence, run) for (fence, _), run in zip(problem.fences, runs)]
    last = runs[-1]
    done = len(runs) == len(problem.fences) and last.status in ("left", "missed")
    n = len(problem.fences)
    missed = sum(r.status == "missed" for r in runs)
    message = (f"left all {n} fence{'s' if n > 1 else ''}" + (f" ({missed} passed untouched)" if missed else "")
               if done else f"stopped at fence {len(runs) - 1} of {n}: {last.message}")
    return FeederSimResult(tuple(runs), segments, problem.placements is not None, tuple(in_map),
                           float(last.thetas[-1]) if done else None, last.status, time.perf_counter() - t0, message)


def _each_in_its_frame(problem: FeederSimProblem, budget: Budget) -> list[FenceRun]:
    """The fences one by one, each in its own frame: the final orientation of one the
    initial one of the next, until a run does not leave its fence."""
    runs: list[FenceRun] = []
    theta = problem.theta_initial
    for fence, mu_c in problem.fences:
        run = simulate_fence(problem.part, fence, mu_c, problem.support_points, problem.weights, theta,
                             fence_length=problem.fence_length, settings=problem.settings, budget=budget)
        runs.append(run)
        if run.theta_final is None:
            break
        theta = run.theta_final
    return runs


def _in_map(problem: FeederSimProblem, fence: Fence, run: FenceRun) -> bool | None:
    """Whether the run's outcome lies in its fence's map (None: not asked, not finished, or
    the fence was never touched, which the maps do not cover)."""
    if problem.check_map and run.status == "jammed":
        return fence_map(problem.part, fence, boundaries=disk_boundaries).map.jam.contains(run.theta_initial)
    if problem.check_map and run.status == "left" and run.theta_final is not None:
        return fence_map(problem.part, fence, boundaries=disk_boundaries).map.allows(run.theta_initial,
                                                                                   run.theta_final, MAP_SLACK)
    return None
