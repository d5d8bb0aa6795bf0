"""Designing a parts feeder end to end (issues 13 and 24; book 5.3, 5.4, 1.8.6, 7.1): the
baseline push plan of a frictionless pusher for the same part (models/feeder/pushplan.py), the
maps of the candidate fences, and the design.

Without a belt, the shortest fence sequence by the breadth-first search of
models/feeder/design_graph.py (optionally proven again by CP-SAT, solver/feeder/design_cpsat.py).
On a belt, the design searched as placed (models/feeder/placed.py): each fence's reach
inside the search, the user's goal, a fences-only design whose guaranteed yield reaches
``min_yield`` if one exists up to ``max_depth``, else a design with a reject gate (when
allowed: fewer fences, then the higher guaranteed yield), placed on the shortest belt
(solver/feeder/placement.py). Then validation by simulated parts (solver/feeder/validate.py).
Under a budget: past the deadline the answer says how far it got (maps made, depth proven,
the design if one was found, the parts simulated).
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
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
from models.feeder.fence import DESIGN, FeederTolerances, Fence, FenceMap, ReachBound, fence_maps, sampled_reach
from models.feeder.gate import GateSpec
from models.feeder.maps import ConfigurationMap, sequence
from models.feeder.placed import Belt, Goal, PlacedDesign, PlacedGraph, PlacedSearchResult, search_placed
from models.feeder.pushplan import PushPlan, plan_pushes
from solver.core.budget import UNLIMITED, Budget
from solver.core.errors import TimeLimitReached
from solver.feeder.design_cpsat import CpSatDesign, shortest_design_cpsat
from solver.feeder.placement import Placement, place
from solver.feeder.validate import Validation, validate_in_own_frames, validate_on_belt
from solver.locus.disk_rings import disk_boundaries

MIN_YIELD = 0.995
"""The default least guaranteed yield per pass of a fences-only design on a belt."""
ENTRY_SPREAD_RADII = 0.5
"""The default half width of the entry lane, in part radii."""
BASELINE_SHARE = 0.1
"""The share of the remaining time the frictionless push-plan baseline may take: it runs
first and is cut (reported so) past it, so it can never sink the design (a regular 64-gon
with an off-centre centre of mass needs over a minute at its third push)."""


@dataclass(frozen=True)
class BeltSpec:
    """The belt a design is placed on (models/feeder/placed.py), lengths in the part's units;
    None for ``clearance``, ``spacing``, ``entry_x`` and ``entry_spread`` takes a tenth of the
    part's radius, its diameter, the lane beside the right side (the first fence hangs there)
    and ENTRY_SPREAD_RADII of the radius; parts enter with their CM within ``entry_spread``
    of ``entry_x``."""

    width: float
    clearance: float | None = None
    spacing: float | None = None
    entry_x: float | None = None
    entry_spread: float | None = None

    def belt(self, part_radius: float) -> Belt:
        spread = ENTRY_SPREAD_RADII * part_radius if self.entry_spread is None else self.entry_spread
        return Belt.create(self.width, part_radius, self.clearance, self.spacing, self.entry_x, spread)


@dataclass(frozen=True)
class FeederDesignProblem:
    """The part, the candidate fences (|angle| from ``angle_min`` to ``angle_max`` in steps
    of ``angle_step``, radians, on both sides of the belt), mu_c (a value or an interval),
    the deepest design sought, whether consecutive fences alternate sides, whether CP-SAT
    proves the depth again (without a belt), how many simulated parts validate the design
    (seeded). On a belt also: the goal (None accepted set: one band per symmetry class), the
    gate allowed (None: fences only; its margin None: MARGIN_RADII of the part's radius), and
    the least guaranteed yield of a fences-only design."""

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
    goal: Goal = Goal()
    gate: GateSpec | None = None
    min_yield: float = MIN_YIELD
    tol: FeederTolerances = DESIGN
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
class Relaxation:
    """What the same search found with one restricting setting lifted, when the request's
    own settings gave no design: ``setting`` ("alternate": sides free instead of alternating;
    "gate": a reject gate allowed, with the defaults), its ``result`` (the design, or none:
    then the setting did not rule one out; None: the time limit cut it)."""

    setting: str
    result: SearchResult | PlacedSearchResult | None  # None: cut by the time limit

    @property
    def design(self) -> Design | PlacedDesign | None:
        return None if self.result is None else self.result.design


@dataclass(frozen=True)
class FeederDesignResult:
    maps: tuple[FenceMap, ...]  # the candidates' maps made
    search: SearchResult | None  # without a belt
    cp_sat: CpSatDesign | None
    final_set: Arcs | None  # the orientations the design may leave the part in
    product: ConfigurationMap | None  # the map of the design's fences (5.4, 5.5)
    validation: Validation | None
    baseline: PushPlan | None  # Goldberg's frictionless push plan for the same part, for comparison
    placed_search: PlacedSearchResult | None  # on a belt
    placement: Placement | None  # the design placed on the belt (the shortest)
    status: str  # "ok" | "time_limit"
    solve_time_s: float
    timings: dict[str, float] = field(default_factory=dict)
    progress: Progress | None = None
    accepted_set: Arcs | None = None  # the accepted bands' orientations (on a belt)
    fences_only_exhausted: bool | None = None  # on a belt with a gate allowed: no fences-only design at any depth
    relaxed: tuple[Relaxation, ...] = ()  # no design: what the search found with a setting lifted

    @property
    def design(self) -> Design | PlacedDesign | None:
        if self.placed_search is not None:
            return self.placed_search.design
        return None if self.search is None else self.search.design

    @property
    def complete(self) -> bool:
        return self.status == "ok"

    @property
    def message(self) -> str:
        v = self.validation
        if v is not None and v.cut:
            return (f"{self._found()}; the time limit stopped {v.cut} of the {v.parts} simulated parts before they "
                    f"ended: the validation is of {v.simulated}")
        return self._found()

    def _found(self) -> str:
        found = self.search if self.placed_search is None else self.placed_search
        if found is None:
            got = self.progress.depth_proven if self.progress is not None else 0
            return (f"stopped after {len(self.maps)} candidate maps; no design shorter than {got + 1} fences "
                    "exists among them" if got else f"stopped after {len(self.maps)} candidate maps")
        if self.design is None:
            head = ("no design exists with these fences" if found.exhausted else
                    f"no design of {found.depth_proven} fences or fewer")
            return "; ".join((head, *(_relaxed_words(r) for r in self.relaxed)))
        return f"{_design_words(self.design)}, none shorter (searched {found.nodes} nodes)"


def _design_words(design: Design | PlacedDesign) -> str:
    """"a design of n fences", or on a belt what it is made of and its guaranteed yield."""
    n = len(design.fences)
    if isinstance(design, PlacedDesign):
        kind = "fences only" if design.gate is None else "fences and a reject gate"
        return f"a placed design of {n} fences ({kind}, guaranteed yield {100 * design.guaranteed_yield:.2f} % per pass)"
    return f"a design of {n} fences"


RELAXED_WORDS = {"alternate": "with alternate false (sides free)", "gate": "with a reject gate allowed"}


def _relaxed_words(r: Relaxation) -> str:
    if r.result is None:
        return f"{RELAXED_WORDS[r.setting]}: not searched, the time limit was reached"
    if r.design is None:
        return f"{RELAXED_WORDS[r.setting]}, none either: that setting did not rule one out"
    return f"{RELAXED_WORDS[r.setting]} the same search finds {_design_words(r.design)}"


MAPS_AT_ONCE = 16
"""Candidate fences whose maps are integrated in lockstep (models/feeder/fence.py,
fence_maps): their disk loci solved together; the deadline is asked between groups."""


def _maps(problem: FeederDesignProblem, budget: Budget, maps: list[FenceMap]) -> None:
    angles = problem.angles()
    for lo in range(0, len(angles), MAPS_AT_ONCE):
        group = angles[lo:lo + MAPS_AT_ONCE]
        budget.checkpoint(f"the maps of the fences at {math.degrees(group[0]):+.1f} to "
                          f"{math.degrees(group[-1]):+.1f} degrees")
        maps += fence_maps(problem.part, [Fence.create(g, problem.mu_c) for g in group], problem.tol,
                           checkpoint=budget.checkpoint, boundaries=disk_boundaries)


def _profiles(problem: FeederDesignProblem, maps: list[FenceMap], budget: Budget) -> list[ReachBound]:
    out = []
    for m in maps:
        budget.checkpoint(f"the reach profile of the fence at {math.degrees(m.fence.angle):+.1f} degrees")
        out.append(sampled_reach(problem.part, m.fence, problem.tol, budget.checkpoint))
    return out


def _jam_held(problem: FeederDesignProblem, angle: float) -> bool:
    """Whether a fence one candidate step shallower than ``angle`` would jam (6.4), whether
    or not the candidates go that low."""
    shallower = abs(angle) - problem.angle_step
    return shallower <= 0.0 or problem.mu_c[1] >= math.tan(shallower)


def _search_placed(problem: FeederDesignProblem, graph: DesignGraph, profiles: list[ReachBound], belt: Belt,
                   budget: Budget, progress: Progress) -> tuple[PlacedSearchResult, bool | None]:
    """Fences only first; with a gate allowed and no fences-only design, the gate designs.
    Returns the result and, when a gate search ran, whether fences alone were exhausted."""
    only = PlacedGraph(graph, profiles, problem.goal, None)
    res = search_placed(only, belt, problem.max_depth, problem.min_yield, problem.alternate, problem.design_tol,
                        budget.checkpoint, progress)
    if res.design is not None or problem.gate is None:
        return res, None
    depth = min(problem.max_depth, problem.gate.max_depth)
    gated = search_placed(PlacedGraph(graph, profiles, problem.goal, problem.gate), belt, depth, problem.min_yield,
                          problem.alternate, problem.design_tol, budget.checkpoint, progress)
    return gated, res.exhausted


def _relax_placed(problem: FeederDesignProblem, graph: DesignGraph, profiles: list[ReachBound], belt: Belt,
                  budget: Budget) -> tuple[Relaxation, ...]:
    """No placed design with the request's settings: the same search with the sides free
    (when they alternated) and with a gate allowed (when none was), each alone, so the
    answer says which setting ruled a design out (issue 35)."""
    lifted = []
    if problem.alternate:
        lifted.append(("alternate", dataclasses.replace(problem, alternate=False)))
    if problem.gate is None:
        lifted.append(("gate", dataclasses.replace(problem, gate=GateSpec())))
    out = []
    for setting, relaxed in lifted:
        try:
            res, _ = _search_placed(relaxed, graph, profiles, belt, budget, Progress())
        except TimeLimitReached:  # the request's own answer stands; this one is said to be cut
            res = None
        out.append(Relaxation(setting, res))
    return tuple(out)


def feeder_design(problem: FeederDesignProblem, budget: Budget = UNLIMITED) -> FeederDesignResult:
    t0 = time.perf_counter()
    # what would fail only after the maps and the search is refused first
    if problem.belt is None and (problem.goal.accepted is not None or problem.gate is not None):
        raise InvalidInput("goal" if problem.goal.accepted is not None else "gate",
                           "needs a belt: goals and gates are for designs placed on one")
    belt = None if problem.belt is None else problem.belt.belt(problem.part.circumradius)
    timings: dict[str, float] = {}
    maps: list[FenceMap] = []
    progress = Progress()
    out: dict = dict(search=None, cp_sat=None, final_set=None, product=None, validation=None, baseline=None,
                     placed_search=None, placement=None, relaxed=())
    extra: dict = {}
    status = "ok"
    try:
        t = time.perf_counter()
        out["baseline"] = plan_pushes(problem.part, problem.max_depth, problem.design_tol,
                                      expired=budget.child(fraction=BASELINE_SHARE).expired)
        timings["push_plan"] = time.perf_counter() - t
        t = time.perf_counter()
        _maps(problem, budget, maps)
        timings["maps"] = time.perf_counter() - t
        t = time.perf_counter()
        graph = DesignGraph.build(problem.part, maps, problem.design_tol, checkpoint=budget.checkpoint)
        if belt is None:
            status = _sequence_design(problem, graph, budget, progress, out, timings, t)
        else:
            _placed_design(problem, graph, belt, budget, progress, out, extra, timings)
    except TimeLimitReached:
        status = "time_limit"
    if out["validation"] is not None and out["validation"].cut:  # some parts never ended: not a complete check
        status = "time_limit"
    return FeederDesignResult(tuple(maps), status=status, solve_time_s=time.perf_counter() - t0, timings=timings,
                              progress=progress, **out, **extra)


def _sequence_design(problem: FeederDesignProblem, graph: DesignGraph, budget: Budget, progress: Progress,
                     out: dict, timings: dict[str, float], t: float) -> str:
    """The fence sequence without a belt (issue 13): search, CP-SAT, validation in own frames."""
    from solver.kernels.search import scan_reached  # compiled: loaded where it runs, not by the web processes

    status = "ok"
    search = out["search"] = search_design(graph, problem.max_depth, problem.alternate, problem.design_tol,
                                           checkpoint=budget.checkpoint, progress=progress, scan=scan_reached)
    timings["search"] = time.perf_counter() - t
    design = search.design
    if design is None and problem.alternate:  # what the same search finds with the sides free
        try:
            free: SearchResult | None = search_design(graph, problem.max_depth, False, problem.design_tol,
                                                      checkpoint=budget.checkpoint, scan=scan_reached)
        except TimeLimitReached:
            free = None
        out["relaxed"] = (Relaxation("alternate", free),)
    if problem.prove_with_cp_sat:
        t = time.perf_counter()
        depth = problem.max_depth if design is None else len(design.fences)
        cp = out["cp_sat"] = shortest_design_cpsat(graph, depth, problem.alternate, budget)
        timings["cp_sat"] = time.perf_counter() - t
        if not cp.complete:
            status = "time_limit"
    if design is not None:
        final = out["final_set"] = graph.occupied_set(design.fences[-1], design.final_bands)
        out["product"] = sequence([graph.maps[f].map for f in design.fences])
        if problem.validation_parts > 0:
            t = time.perf_counter()
            out["validation"] = validate_in_own_frames(problem.part, [graph.maps[f].fence for f in design.fences],
                                                       final, problem.mu_c, problem.validation_parts, problem.seed,
                                                       budget)
            timings["validation"] = time.perf_counter() - t
    return status


def _placed_design(problem: FeederDesignProblem, graph: DesignGraph, belt: Belt, budget: Budget, progress: Progress,
                   out: dict, extra: dict, timings: dict[str, float]) -> None:
    """The design searched as placed, its placement and its validation on the belt."""
    t = time.perf_counter()
    profiles = _profiles(problem, list(graph.maps), budget)
    timings["reach_profiles"] = time.perf_counter() - t
    t = time.perf_counter()
    res, exhausted = _search_placed(problem, graph, profiles, belt, budget, progress)
    out["placed_search"] = res
    extra["fences_only_exhausted"] = exhausted
    timings["search"] = time.perf_counter() - t
    design = res.design
    if design is None:
        out["relaxed"] = _relax_placed(problem, graph, profiles, belt, budget)
        return
    fences = [graph.maps[f].fence for f in design.fences]
    out["final_set"] = graph.occupied_set(design.fences[-1], design.final_bands)
    accepted = extra["accepted_set"] = graph.occupied_set(design.fences[-1], design.accepted_bands)
    # the first fence's unaligned orientations as full columns (5.4); a later fence's slivers
    # (at most design_tol.sliver radians each) are counted in the yield instead (placed.py)
    first = graph.maps[design.fences[0]].map
    placed_maps = [ConfigurationMap(first.bands, first.kernels, first.jam, design.lost)]
    out["product"] = sequence(placed_maps + [graph.maps[f].map for f in design.fences[1:]])
    t = time.perf_counter()
    placement = out["placement"] = place(belt, [f.angle for f in fences], list(design.reaches), design.gate is not None,
                                         [_jam_held(problem, f.angle) for f in fences])
    timings["layout"] = time.perf_counter() - t
    if problem.validation_parts > 0:
        t = time.perf_counter()
        out["validation"] = validate_on_belt(problem.part, fences, placement, accepted, design.gate, problem.mu_c,
                                             problem.validation_parts, problem.seed, budget)
        timings["validation"] = time.perf_counter() - t
