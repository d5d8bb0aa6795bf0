"""A feeder design validated by simulated parts (issue 13, issue 24; book 5.4, 1.8.6, 7.1):
random parts (a balanced tripod inside the outline, a uniform orientation, mu_c drawn over
the interval, the entry position across the lane) through the designed fences, batched by
solver/feeder/simulate.py.

On a belt the parts meet the placed fences one after the other in the world frame and then
the gate, if any. Every part is counted once: accepted in an accepted band, accepted outside
every accepted band (a defect: the design promised otherwise), rejected by the gate (returned
to the start: a success of a gate design), or failed: passed a fence untouched, left one still
turning (without a gate; with one the gate judges it), crossed a side of the belt, or did not
finish (jammed, stalled, step or time limit).
Without a belt each fence runs in its own frame (issue 13's validation, kept for the
sequence-only design).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from models.core.footprint import Footprint
from models.core.support import random_balanced_tripods
from models.feeder.arcs import Arcs
from models.feeder.fence import Fence
from models.feeder.gate import Gate, extent
from solver.core.budget import Budget
from solver.feeder.placement import Placement
from solver.feeder.simulate import BeltRun, FenceSegment, simulate_belt_batch, simulate_fence_batch

VALIDATION_MU_VALUES = 5
"""mu_c values, evenly over the interval, among which each validation part draws its own."""
VALIDATION_SLACK = 1e-6
"""Radians: a simulated final orientation this close to a promised band counts as in it."""
VALIDATION_EXAMPLES = 3
"""Validation parts on a belt whose runs are kept for the top view."""
ROOT_OVERHANG = 2.0
"""Part radii by which a simulated fence runs on past its root into the side rail."""
TIME_LIMITED = "time_limit"
"""The status of a simulated run the budget stopped (solver/feeder/simulate.py)."""
ENTRY_CLEARANCE = 0.05
"""Parts enter a belt with their CM this many part radii more than a radius above the
first fence's root (so the outline is clear of every fence)."""


@dataclass(frozen=True)
class Validation:
    """Simulated parts through the design (module docstring): ``in_band`` accepted in an
    accepted band, ``outside`` accepted elsewhere, ``rejected`` by the gate, and the
    failures: ``unflushed`` (left a fence still turning, without a gate), ``missed`` (passed a
    fence untouched, on a belt only), ``off_belt`` (crossed a side), ``unfinished`` (jammed,
    stalled, met two fences at once or ran out of steps). Each part is counted once;
    ``unflushed_gated`` says how many of those the gate judged had left a fence still turning.
    ``parts`` is the parts asked for; ``cut`` of them were stopped by the time limit before
    they ended and count as no outcome (the shares are of the parts simulated to their end).
    ``on_belt``: the placed fences in the world frame; ``examples``: the first few parts'
    runs (for the top view)."""

    parts: int
    in_band: int
    outside: int
    unflushed: int
    unfinished: int
    solve_time_s: float
    missed: int = 0
    on_belt: bool = False
    off_belt: int = 0
    rejected: int = 0
    unflushed_gated: int = 0  # with a gate: parts that left a fence still turning and were judged by it
    cut: int = 0  # stopped by the time limit before they ended: no outcome
    examples: tuple[BeltRun, ...] = ()

    @property
    def simulated(self) -> int:
        """Parts simulated to their end (the others were cut by the time limit)."""
        return self.parts - self.cut

    @property
    def rate(self) -> float:
        """Of the parts that ended accepted, the share in an accepted band."""
        done = self.in_band + self.outside
        return self.in_band / done if done else math.nan

    @property
    def failed(self) -> int:
        return self.unflushed + self.unfinished + self.missed + self.off_belt

    @property
    def succeeded(self) -> float:
        """The share of parts that ended as the design promised: accepted in band, or
        rejected by the gate."""
        return (self.in_band + self.rejected) / self.simulated if self.simulated else math.nan

    @property
    def yield_per_pass(self) -> float:
        """The share of parts accepted in an accepted band."""
        return self.in_band / self.simulated if self.simulated else math.nan


def _random_parts(part: Footprint, n: int, mu_c: tuple[float, float], seed: int
                  ) -> tuple[list[tuple[np.ndarray, np.ndarray]], np.ndarray, np.ndarray, np.random.Generator]:
    rng = np.random.default_rng(seed)
    body, wts = random_balanced_tripods(rng, n, part.circumradius, footprint=part)  # CM at the origin
    lo, hi = mu_c
    mus = np.linspace(lo, hi, VALIDATION_MU_VALUES) if hi > lo else np.array([lo])
    mu_of = mus[rng.integers(0, len(mus), n)]
    theta = rng.uniform(-math.pi, math.pi, n)
    return [(body[i], wts[i]) for i in range(n)], mu_of, theta, rng


def validate_in_own_frames(part: Footprint, fences: list[Fence], final: Arcs, mu_c: tuple[float, float], n: int,
                           seed: int, budget: Budget) -> Validation:
    """Each fence in its own frame (the part meets it at 0.7 of a 40-radius fence), the final
    orientation of one the initial of the next."""
    t0 = time.perf_counter()
    supports, mu_of, theta, _ = _random_parts(part, n, mu_c, seed)
    finished = np.ones(n, dtype=bool)
    cut = np.zeros(n, dtype=bool)
    unflushed = np.zeros(n, dtype=bool)
    for fence in fences:
        ids = np.nonzero(finished)[0]
        runs = simulate_fence_batch(part, fence, mu_of[ids], [supports[i] for i in ids], theta[ids], budget=budget,
                                    record=0)
        for i, run in zip(ids, runs):
            if run.status != "left" or run.theta_final is None:
                finished[i] = False
                cut[i] = run.status == TIME_LIMITED
                continue
            unflushed[i] |= not run.flushed
            theta[i] = run.theta_final
    ok = finished & ~unflushed
    in_band = int(sum(final.contains(float(theta[i]), VALIDATION_SLACK) for i in np.nonzero(ok)[0]))
    return Validation(parts=n, in_band=in_band, outside=int(ok.sum()) - in_band,
                      unflushed=int((finished & unflushed).sum()), unfinished=int((~finished & ~cut).sum()),
                      cut=int(cut.sum()), solve_time_s=time.perf_counter() - t0)


def validate_on_belt(part: Footprint, fences: list[Fence], placement: Placement, accepted: Arcs, gate: Gate | None,
                     mu_c: tuple[float, float], n: int, seed: int, budget: Budget) -> Validation:
    """The parts through the placed fences and the gate (module docstring)."""
    t0 = time.perf_counter()
    supports, mu_of, theta, rng = _random_parts(part, n, mu_c, seed)
    belt = placement.belt
    # each fence runs on into the side rail it hangs from (not simulated): a part beside the
    # rail meets the fence, never its root end
    segs = [FenceSegment.create(f, p.end, p.length + ROOT_OVERHANG * part.circumradius)
            for f, p in zip(fences, placement.fences)]
    xs = belt.entry_x + rng.uniform(-belt.entry_spread, belt.entry_spread, n)
    y0 = float(placement.fences[0].root[1]) + part.circumradius * (1.0 + ENTRY_CLEARANCE)
    starts = np.column_stack([xs, np.full(n, y0)])
    runs = simulate_belt_batch(part, segs, mu_of, supports, theta, starts, budget=budget, record=VALIDATION_EXAMPLES)
    counts = dict(in_band=0, outside=0, rejected=0, unflushed=0, missed=0, off_belt=0, unfinished=0, cut=0)
    gated = 0
    for run in runs:
        outcome = _outcome(part, run, 0.5 * belt.width, accepted, gate)
        counts[outcome] += 1
        gated += outcome in ("in_band", "outside", "rejected") and gate is not None and not run.flushed
    return Validation(parts=n, solve_time_s=time.perf_counter() - t0, on_belt=True,
                      examples=tuple(runs[:VALIDATION_EXAMPLES]), unflushed_gated=gated, **counts)


def _outcome(part: Footprint, run: BeltRun, half_width: float, accepted: Arcs, gate: Gate | None) -> str:
    """What became of one part (module docstring): the first failure, else what the gate did.
    A part that left a fence still turning fails without a gate; with one, the gate judges
    it like any other (its orientation is then not one the maps bound: the guaranteed yield
    counts it as lost, the gate may still reject it)."""
    if run.status == TIME_LIMITED:
        return "cut"
    if run.status != "left" or run.theta_final is None:
        return "unfinished"
    if run.missed:
        return "missed"
    if gate is None and not run.flushed:
        return "unflushed"
    if _leaves_belt(part, run, half_width):
        return "off_belt"
    theta = run.theta_final
    if gate is not None and not bool(gate.accepts(extent(part, theta, gate.feature)[0])):
        return "rejected"
    return "in_band" if accepted.contains(theta, VALIDATION_SLACK) else "outside"


def _leaves_belt(part: Footprint, run: BeltRun, half_width: float) -> bool:
    """Whether the part's outline crossed x = +-half_width at any pose of its runs."""
    for r in run.runs:
        if r.outline_reach is not None:
            if r.outline_reach > half_width:
                return True
            continue
        c, s_ = np.cos(r.thetas)[:, None], np.sin(r.thetas)[:, None]
        x = r.cms[:, 0][:, None] + c * part.hull[:, 0][None, :] - s_ * part.hull[:, 1][None, :]
        if np.any(np.abs(x) > half_width):
            return True
    return False
