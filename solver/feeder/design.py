"""Designing a parts feeder end to end (issue 13; book 5.3, 5.4, 1.8.6): the baseline push
plan of a frictionless pusher for the same part (models/feeder/pushplan.py), the maps of the
candidate fences, the shortest design by the breadth-first search of
models/feeder/design_graph.py (optionally proven again by CP-SAT, solver/feeder/design_cpsat.py),
and its validation by simulation: random parts (support, orientation, mu_c in the interval)
through the designed fences (solver/feeder/simulate.py, batched), each of which must end in the
promised bands. Under a budget: past the deadline the answer says how far it got (maps
made, depth proven, the design if one was found, the parts simulated).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from models.core.footprint import Footprint
from models.core.support import random_balanced_tripods
from models.feeder.arcs import Arcs
from models.feeder.design_graph import (
    DESIGN_DEFAULT,
    Design,
    DesignGraph,
    DesignTolerances,
    Progress,
    SearchResult,
    search_design,
)
from models.feeder.fence import DEFAULT, FeederTolerances, Fence, FenceMap, fence_map
from models.feeder.layout import CLEARANCE_RADII, SPACING_RADII, BeltLayout, check_belt, lay_out
from models.feeder.maps import ConfigurationMap, sequence
from models.feeder.pushplan import PushPlan, plan_pushes
from solver.core.budget import UNLIMITED, Budget
from solver.core.errors import TimeLimitReached
from solver.feeder.design_cpsat import CpSatDesign, shortest_design_cpsat
from solver.feeder.simulate import BeltRun, FenceSegment, simulate_belt_batch, simulate_fence_batch

VALIDATION_MU_VALUES = 5
"""mu_c values, evenly over the interval, among which each validation part draws its own."""
VALIDATION_SLACK = 1e-6
"""Radians: a simulated final orientation this close to a promised band counts as in it."""
VALIDATION_EXAMPLES = 3
"""Validation parts on a belt whose runs are kept for the top view."""
ENTRY_CLEARANCE = 0.05
"""Parts enter a belt with their CM this many part radii more than a radius above the
first fence's root (so the outline is clear of every fence)."""


@dataclass(frozen=True)
class BeltSpec:
    """The belt a design is placed on (models/feeder/layout.py), lengths in the part's units;
    None for ``clearance``, ``spacing`` and ``entry_x`` takes a tenth of the part's radius, its
    diameter, and the first fence's root side."""

    width: float
    clearance: float | None = None
    spacing: float | None = None
    entry_x: float | None = None

    def gaps(self, part_radius: float) -> tuple[float, float]:
        """(clearance, spacing), the defaults filled in."""
        a = part_radius
        return (CLEARANCE_RADII * a if self.clearance is None else self.clearance,
                SPACING_RADII * a if self.spacing is None else self.spacing)


@dataclass(frozen=True)
class PlacedCheck:
    """A placed fence's reach, whether a part may pass its free end untouched (reach 0: it
    arrives beside or past the end, as after a fence on the same side), and the measure
    (radians) of the orientations arriving at it that its reach may not align."""

    reach: float
    may_miss: bool
    unaligned_arriving: float


@dataclass(frozen=True)
class FeederDesignProblem:
    """The part, the candidate fences (|angle| from ``angle_min`` to ``angle_max`` in steps
    of ``angle_step``, radians, on both sides of the belt), mu_c (a value or an interval),
    the deepest design sought, whether consecutive fences alternate sides, whether CP-SAT
    proves the depth again, and how many simulated parts validate the design (seeded)."""

    part: Footprint
    angle_min: float
    angle_max: float
    angle_step: float
    mu_c: tuple[float, float]
    max_depth: int = 8
    alternate: bool = True
    prove_with_cp_sat: bool = False
    validation_parts: int = 0
    seed: int = 0
    belt: BeltSpec | None = None
    tol: FeederTolerances = DEFAULT
    design_tol: DesignTolerances = DESIGN_DEFAULT

    def angles(self) -> list[float]:
        n = int(angle_count(self.angle_min, self.angle_max, self.angle_step))
        mags = [self.angle_min + i * self.angle_step for i in range(n)]
        return [s * g for s in (1.0, -1.0) for g in mags]


ANGLE_GRID_SLACK = 1e-9
"""Steps of the candidate angles: a range this close to a whole number of steps is one."""


def angle_count(angle_min: float, angle_max: float, angle_step: float) -> float:
    """How many |angle| candidates the range and step give (inf when too many to count)."""
    steps = (angle_max - angle_min) / angle_step + ANGLE_GRID_SLACK
    return math.floor(steps) + 1 if math.isfinite(steps) else math.inf


@dataclass(frozen=True)
class Validation:
    """Simulated parts through the design: how many ran to the end, ended in the promised
    bands, left a fence without an edge flush (a fence too short for them: outside the
    maps' assumption), passed a fence untouched (``missed``, on a belt only), or did not
    finish (jammed, stalled, step limit, time limit, two fences at once). ``on_belt``: the
    parts ran through the placed fences one after the other (world frame, from the entry
    lane), not each fence in its own frame; then ``off_belt`` counts the parts whose
    outline crossed a side of the belt somewhere (no side walls are simulated), and
    ``examples`` keeps the first few parts' runs (for the top view)."""

    parts: int
    in_band: int
    outside: int
    unflushed: int
    unfinished: int
    solve_time_s: float
    missed: int = 0
    on_belt: bool = False
    off_belt: int = 0
    examples: tuple[BeltRun, ...] = ()

    @property
    def rate(self) -> float:
        done = self.in_band + self.outside
        return self.in_band / done if done else math.nan


@dataclass(frozen=True)
class FeederDesignResult:
    maps: tuple[FenceMap, ...]  # the candidates' maps made
    search: SearchResult | None
    cp_sat: CpSatDesign | None
    final_set: Arcs | None  # the orientations the design leaves the part in
    product: ConfigurationMap | None  # the map of the design's fences (5.4, 5.5)
    validation: Validation | None
    baseline: PushPlan | None  # Goldberg's frictionless push plan for the same part, for comparison
    layout: BeltLayout | None  # the design placed on the belt, when one was given
    placed: tuple[PlacedCheck, ...]  # per placed fence
    status: str  # "ok" | "time_limit"
    solve_time_s: float
    timings: dict[str, float] = field(default_factory=dict)
    progress: Progress | None = None

    @property
    def design(self) -> Design | None:
        return None if self.search is None else self.search.design

    @property
    def complete(self) -> bool:
        return self.status == "ok"

    @property
    def realizable(self) -> bool | None:
        """On its belt no fence may be missed and every arriving orientation is aligned
        (None: not laid out)."""
        if self.layout is None:
            return None
        return all(not c.may_miss and c.unaligned_arriving == 0.0 for c in self.placed)

    @property
    def message(self) -> str:
        if self.search is None:
            got = self.progress.depth_proven if self.progress is not None else 0
            return (f"stopped after {len(self.maps)} candidate maps; no design shorter than {got + 1} fences "
                    "exists among them" if got else f"stopped after {len(self.maps)} candidate maps")
        if self.design is None:
            return ("no design exists with these fences" if self.search.exhausted else
                    f"no design of {self.search.depth_proven} fences or fewer")
        return (f"a design of {len(self.design.fences)} fences, none shorter "
                f"(searched {self.search.nodes} nodes)")


def _validate(problem: FeederDesignProblem, fences: list[Fence], final: Arcs, layout: BeltLayout | None,
              budget: Budget) -> Validation:
    t0 = time.perf_counter()
    rng = np.random.default_rng(problem.seed)
    part = problem.part
    n = problem.validation_parts
    body, wts = random_balanced_tripods(rng, n, part.circumradius, footprint=part)  # CM at the origin
    lo, hi = problem.mu_c
    mus = np.linspace(lo, hi, VALIDATION_MU_VALUES) if hi > lo else np.array([lo])
    mu_of = mus[rng.integers(0, len(mus), n)]
    theta = rng.uniform(-math.pi, math.pi, n)
    supports = [(body[i], wts[i]) for i in range(n)]
    if layout is None:
        finished, unflushed = _through_each_fence(part, fences, mu_of, supports, theta, budget)
        missed = off_belt = np.zeros(n, dtype=bool)
        examples: tuple[BeltRun, ...] = ()
    else:
        segs = [FenceSegment.create(f, p.end, p.length) for f, p in zip(fences, layout.fences)]
        start = np.array([layout.entry_x, float(layout.fences[0].root[1]) + part.circumradius * (1.0 + ENTRY_CLEARANCE)])
        runs = simulate_belt_batch(part, segs, mu_of, supports, theta, np.tile(start, (n, 1)), budget=budget)
        finished = np.array([r.status == "left" for r in runs], dtype=bool)
        missed = np.array([r.missed for r in runs], dtype=bool)
        unflushed = np.array([not r.flushed for r in runs], dtype=bool)
        off_belt = np.array([_leaves_belt(part, r, 0.5 * layout.belt_width) for r in runs], dtype=bool)
        theta = np.array([math.nan if r.theta_final is None else r.theta_final for r in runs])
        examples = tuple(runs[:VALIDATION_EXAMPLES])
    ok = finished & ~unflushed & ~missed
    in_band = int(sum(final.contains(float(theta[i]), VALIDATION_SLACK) for i in np.nonzero(ok)[0]))
    return Validation(parts=n, in_band=in_band, outside=int(ok.sum()) - in_band,
                      unflushed=int((finished & unflushed & ~missed).sum()), unfinished=int((~finished).sum()),
                      solve_time_s=time.perf_counter() - t0, missed=int((finished & missed).sum()),
                      on_belt=layout is not None, off_belt=int(off_belt.sum()), examples=examples)


def _through_each_fence(part: Footprint, fences: list[Fence], mu_of: np.ndarray, supports: list[tuple[np.ndarray, np.ndarray]],
                        theta: np.ndarray, budget: Budget) -> tuple[np.ndarray, np.ndarray]:
    """Each fence in its own frame (the part meets it at 0.7 of a 40-radius fence), the final
    orientation of one the initial of the next: (finished, unflushed) per part; ``theta``
    is updated in place."""
    n = len(supports)
    finished = np.ones(n, dtype=bool)
    unflushed = np.zeros(n, dtype=bool)
    for fence in fences:
        ids = np.nonzero(finished)[0]
        runs = simulate_fence_batch(part, fence, mu_of[ids], [supports[i] for i in ids], theta[ids], budget=budget)
        for i, run in zip(ids, runs):
            if run.status != "left" or run.theta_final is None:
                finished[i] = False
                continue
            unflushed[i] |= not run.flushed
            theta[i] = run.theta_final
    return finished, unflushed


def _leaves_belt(part: Footprint, run: BeltRun, half_width: float) -> bool:
    """Whether the part's outline crossed x = +-half_width at any recorded pose."""
    for r in run.runs:
        c, s_ = np.cos(r.thetas)[:, None], np.sin(r.thetas)[:, None]
        x = r.cms[:, 0][:, None] + c * part.hull[:, 0][None, :] - s_ * part.hull[:, 1][None, :]
        if np.any(np.abs(x) > half_width):
            return True
    return False


def _place(problem: FeederDesignProblem, graph: DesignGraph, design: Design,
           budget: Budget) -> tuple[BeltLayout, tuple[PlacedCheck, ...]]:
    """The design on the belt, and for each fence its reach and the orientations arriving
    at it that the reach may not align (phase 6: the map of that fence with its reach)."""
    assert problem.belt is not None
    b = problem.belt
    a = problem.part.circumradius
    fences = [graph.maps[f].fence for f in design.fences]
    layout = lay_out([f.angle for f in fences], a, b.width, *b.gaps(a), b.entry_x)
    checks = []
    arriving = Arcs.circle()
    occ = graph.start[design.fences[0]]
    for i, (f, placed) in enumerate(zip(design.fences, layout.fences)):
        budget.checkpoint(f"the reach of placed fence {i}")
        fence = graph.maps[f].fence
        unaligned = fence_map(problem.part, Fence.create(fence.angle, (fence.mu_low, fence.mu_high),
                                                         reach=placed.reach),
                              problem.tol, checkpoint=budget.checkpoint).map.unaligned
        checks.append(PlacedCheck(placed.reach, placed.reach <= 0.0, _measure_within(unaligned, arriving)))
        if i > 0:  # the bands the part may be in after fence i (a design's steps are never refused)
            step = graph.step(design.fences[i - 1], occ, f)
            assert step is not None
            occ = step[0]
        arriving = graph.occupied_set(f, occ)
    return layout, tuple(checks)


def _measure_within(a: Arcs, b: Arcs) -> float:
    """The measure of a within b (|a| + |b| - |a u b|)."""
    return max(a.measure + b.measure - a.union(b).measure, 0.0)


def feeder_design(problem: FeederDesignProblem, budget: Budget = UNLIMITED) -> FeederDesignResult:
    t0 = time.perf_counter()
    # what would fail only after the maps and the search is refused first
    if problem.belt is not None:
        check_belt(problem.part.circumradius, problem.belt.width, *problem.belt.gaps(problem.part.circumradius),
                   problem.belt.entry_x)
    timings: dict[str, float] = {}
    maps: list[FenceMap] = []
    progress = Progress()
    search = None
    cp = None
    final = None
    product = None
    validation = None
    baseline = None
    layout = None
    placed: tuple[PlacedCheck, ...] = ()
    status = "ok"
    try:
        t = time.perf_counter()
        baseline = plan_pushes(problem.part, problem.max_depth, problem.design_tol, checkpoint=budget.checkpoint)
        timings["push_plan"] = time.perf_counter() - t
        t = time.perf_counter()
        for g in problem.angles():
            budget.checkpoint(f"the map of the fence at {math.degrees(g):+.1f} degrees")
            maps.append(fence_map(problem.part, Fence.create(g, problem.mu_c), problem.tol,
                                  checkpoint=budget.checkpoint))
        timings["maps"] = time.perf_counter() - t
        t = time.perf_counter()
        graph = DesignGraph.build(problem.part, maps, problem.design_tol, checkpoint=budget.checkpoint)
        search = search_design(graph, problem.max_depth, problem.alternate, problem.design_tol,
                               checkpoint=budget.checkpoint, progress=progress)
        timings["search"] = time.perf_counter() - t
        design = search.design
        if problem.prove_with_cp_sat:
            t = time.perf_counter()
            depth = problem.max_depth if design is None else len(design.fences)
            cp = shortest_design_cpsat(graph, depth, problem.alternate, budget)
            timings["cp_sat"] = time.perf_counter() - t
            if not cp.complete:
                status = "time_limit"
        if design is not None:
            final = graph.occupied_set(design.fences[-1], design.final_bands)
            product = sequence([maps[f].map for f in design.fences])
            if problem.belt is not None:
                t = time.perf_counter()
                layout, placed = _place(problem, graph, design, budget)
                timings["layout"] = time.perf_counter() - t
            if problem.validation_parts > 0:
                t = time.perf_counter()
                validation = _validate(problem, [maps[f].fence for f in design.fences], final, layout, budget)
                timings["validation"] = time.perf_counter() - t
    except TimeLimitReached:
        status = "time_limit"
    return FeederDesignResult(tuple(maps), search, cp, final, product, validation, baseline, layout, placed,
                              status, time.perf_counter() - t0, timings, progress)
