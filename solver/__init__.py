"""The solver layer's public entry points, and nothing else.

Each workflow takes one problem object and a :class:`Budget` and returns a result that
implements :class:`Outcome` (status, complete, solve_time_s, message); the service calls
only these (import-linter contract ``solver-public``). The lower-level computations below
them are public too, for tests, benchmarks and library users. docs/architecture.md
describes the folders.
"""

from solver.core.backends import BACKENDS, close_ledger, open_ledger
from solver.core.budget import UNLIMITED, Budget
from solver.core.errors import BackendNotFound, Infeasible, NotConverged, SolverError, TimeLimitReached
from solver.core.outcome import Outcome
from solver.core.parallel import ParallelRun, RayPool, parallel_map, release_ray
from solver.core.store import ResultStore
from solver.core.tolerances import SOLVER_DEFAULT, SOLVER_FAST, SOLVER_HIGH_ACCURACY, SolverTolerances
from solver.feeder.catalogue import FeederCatalogueProblem, FeederCatalogueResult, feeder_catalogue
from solver.feeder.design import (
    BeltSpec,
    FeederDesignProblem,
    FeederDesignResult,
    Relaxation,
    angle_count,
    feeder_design,
)
from solver.feeder.part_bound import PartBoundCost, PartBoundSettings
from solver.feeder.simulate import (
    DEFAULT_FENCE_LENGTH_RADII,
    BeltRun,
    FeederSimSettings,
    FenceEvent,
    FenceRun,
    FenceSegment,
    simulate_belt_batch,
    simulate_fence,
)
from solver.feeder.workflow import (
    FeederMapProblem,
    FeederMapResult,
    FeederSimProblem,
    FeederSimResult,
    feeder_map,
    feeder_simulate,
)
from solver.kernels import KERNEL_MODULES
from solver.locus.certified_locus import (
    CertifiedDiskBoundary,
    CertifiedPolygonBoundary,
    certified_disk_boundary,
    certified_polygon_boundary,
)
from solver.locus.cor_locus import LocusProblem, LocusResult, cor_locus
from solver.locus.membership import MembershipProblem, MembershipResult, decide_membership, membership
from solver.motion.forward import BatchResult, ForwardResult, solve_forward, solve_forward_batch
from solver.motion.solve import Impact, MotionProblem, MotionResult, UniformPressure, solve_motion
from solver.motion.statistics import HistogramQuery, TripodStatistics, TripodStatisticsProblem, tripod_statistics
from solver.motion.tripod_search import ExtremeCorResult, extreme_cor_search
from solver.particle.solve import ParticleProblem, ParticleSolution, mpp_particle
from solver.push.align import AlignProblem, AlignResult, AlignStage, Slip, align, below_line_of_motion
from solver.push.bounds import ENCOUNTER_SKETCH_COST, SKETCH_COST, Bound, QuasiStaticQuery
from solver.push.disk_encounter import DiskEncounterProblem, DiskEncounterResult, disk_encounter
from solver.push.simulate import (
    BatchSimulation,
    PushSimulation,
    simulate_disk_encounter,
    simulate_disk_encounter_batch,
    simulate_fence_alignment,
    simulate_fence_alignment_batch,
)
from solver.scenes.analyze import analyze_scene
from solver.scenes.problem import Answer, ModeVerdict, Question, SceneAnalysis, SceneProblem, Tried
from solver.sketch.certified_sketch import CertifiedSketch, certified_sketch
from solver.sketch.cor_sketch import SketchProblem, SketchResult, cor_sketch
from solver.sketch.sticking import StickingResult, sticking_feasibility
from solver.sketch.sticking_locus import LocusEnd, StickingLocus, sticking_locus
from solver.spiral.critical_radius import (
    CriticalRadii,
    CriticalRadiusProblem,
    CriticalRadiusTable,
    critical_radii,
    critical_radius_table,
)
from solver.spiral.plan import PathQuery, SimulationQuery, SpiralPlan, SpiralProblem, plan_spiral
from solver.spiral.schedule import SpiralSchedule, spiral_schedule
from solver.spiral.simulate import SpiralBatch, SpiralRun, simulate_spiral, simulate_spiral_batch, spiral_check

ENTRY_POINTS = (
    align,
    disk_encounter,
    cor_locus,
    cor_sketch,
    decide_membership,
    solve_motion,
    tripod_statistics,
    mpp_particle,
    plan_spiral,
    critical_radii,
    feeder_map,
    feeder_simulate,
    feeder_design,
    feeder_catalogue,
    analyze_scene,
)
"""The workflows the service calls: each ``(problem, budget) -> Outcome``."""

__all__ = [
    "FeederCatalogueProblem",
    "FeederCatalogueResult",
    "feeder_catalogue",
    "ParallelRun",
    "RayPool",
    "parallel_map",
    "release_ray",
    "analyze_scene",
    "Answer",
    "ModeVerdict",
    "Question",
    "SceneAnalysis",
    "SceneProblem",
    "Tried",
    "BACKENDS",
    "close_ledger",
    "open_ledger",
    "BeltSpec",
    "angle_count",
    "DEFAULT_FENCE_LENGTH_RADII",
    "ENTRY_POINTS",
    "KERNEL_MODULES",
    "FeederDesignProblem",
    "FeederDesignResult",
    "Relaxation",
    "FeederMapProblem",
    "FeederMapResult",
    "FeederSimProblem",
    "FeederSimResult",
    "PartBoundCost",
    "PartBoundSettings",
    "FeederSimSettings",
    "FenceEvent",
    "FenceRun",
    "FenceSegment",
    "BeltRun",
    "feeder_design",
    "feeder_map",
    "feeder_simulate",
    "simulate_fence",
    "simulate_belt_batch",
    "UNLIMITED",
    "Budget",
    "BackendNotFound",
    "Infeasible",
    "NotConverged",
    "SolverError",
    "TimeLimitReached",
    "Outcome",
    "ResultStore",
    "SOLVER_DEFAULT",
    "SOLVER_FAST",
    "SOLVER_HIGH_ACCURACY",
    "SolverTolerances",
    "AlignProblem",
    "AlignResult",
    "AlignStage",
    "Slip",
    "align",
    "below_line_of_motion",
    "SKETCH_COST",
    "ENCOUNTER_SKETCH_COST",
    "Bound",
    "QuasiStaticQuery",
    "DiskEncounterProblem",
    "DiskEncounterResult",
    "disk_encounter",
    "CertifiedDiskBoundary",
    "CertifiedPolygonBoundary",
    "certified_disk_boundary",
    "certified_polygon_boundary",
    "CertifiedSketch",
    "certified_sketch",
    "LocusProblem",
    "LocusResult",
    "cor_locus",
    "MembershipProblem",
    "MembershipResult",
    "decide_membership",
    "membership",
    "SketchProblem",
    "SketchResult",
    "cor_sketch",
    "StickingResult",
    "sticking_feasibility",
    "LocusEnd",
    "StickingLocus",
    "sticking_locus",
    "BatchResult",
    "ForwardResult",
    "solve_forward",
    "solve_forward_batch",
    "ParticleProblem",
    "ParticleSolution",
    "mpp_particle",
    "Impact",
    "MotionProblem",
    "MotionResult",
    "UniformPressure",
    "solve_motion",
    "HistogramQuery",
    "TripodStatistics",
    "TripodStatisticsProblem",
    "tripod_statistics",
    "BatchSimulation",
    "PushSimulation",
    "simulate_disk_encounter",
    "simulate_disk_encounter_batch",
    "simulate_fence_alignment",
    "simulate_fence_alignment_batch",
    "SpiralBatch",
    "SpiralRun",
    "simulate_spiral",
    "simulate_spiral_batch",
    "spiral_check",
    "ExtremeCorResult",
    "extreme_cor_search",
    "CriticalRadii",
    "CriticalRadiusProblem",
    "CriticalRadiusTable",
    "critical_radii",
    "critical_radius_table",
    "PathQuery",
    "SimulationQuery",
    "SpiralPlan",
    "SpiralProblem",
    "plan_spiral",
    "SpiralSchedule",
    "spiral_schedule",
]
