"""The motion of a pushed workpiece for known pressure distributions: one support, a batch
of supports, or a modelled uniform pressure (book 3.2-3.3.3, 4.1, figure 7-1), with the
impact-limit COR (7.1) of a single body. One problem in, one result out.

A batch is solved by the batched Newton back end, one batch per support size
(:func:`solver.motion.forward.solve_forward_batch`), or, with the conic and
interior-point back ends, one support after the other
(:func:`solver.motion.forward.solve_forward`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.core.inertia import (
    disk_radius_of_gyration,
    impact_cor,
    impact_cor_distance,
    polygon_radius_of_gyration,
    support_radius_of_gyration,
)
from models.core.scene import PushScene
from models.core.support import Support, SupportBatch
from solver.core.budget import UNLIMITED, Budget
from solver.core.errors import BackendNotFound
from solver.core.tolerances import SOLVER_DEFAULT, SolverTolerances
from solver.motion.forward import (
    METHODS,
    BatchResult,
    ForwardResult,
    solve_forward,
    solve_forward_batch,
)
from solver.motion.statistics import uniform_pressure_cor


@dataclass(frozen=True)
class UniformPressure:
    """Uniform pressure (figure 7-1) on ``footprint``, or on the scene's disk when None,
    discretised with ``resolution`` rings (disk) or sub-divisions per triangle (polygon)."""

    footprint: Footprint | None
    resolution: int


@dataclass(frozen=True)
class MotionProblem:
    """The push ``scene`` with pusher friction ``mu_c`` on exactly one of: ``support`` (one
    motion), ``supports`` (a batch, one motion each), ``batch`` (supports of one size as
    arrays, solved by "newton" as one batch) or ``pressure``; solved by ``method``
    ("newton", "cvxpy" or "casadi")."""

    scene: PushScene
    support: Support | None = None
    supports: tuple[Support, ...] | None = None
    pressure: UniformPressure | None = None
    batch: SupportBatch | None = None
    mu_c: float = 0.0
    method: str = "newton"
    tol: SolverTolerances = SOLVER_DEFAULT

    def __post_init__(self) -> None:
        if sum(x is not None for x in (self.support, self.supports, self.pressure, self.batch)) != 1:
            raise InvalidInput("support", "give exactly one of support, supports, batch or pressure")
        if self.batch is not None and self.method != "newton":
            raise InvalidInput("method", "a columnar batch is solved by newton only")
        if self.supports is not None and not self.supports:
            raise InvalidInput("supports", "must hold at least one support")
        if self.method not in METHODS:
            raise BackendNotFound("method", self.method, METHODS)

    @property
    def kind(self) -> str:
        """"support", "supports", "batch" or "pressure"."""
        if self.batch is not None:
            return "batch"
        return "support" if self.support is not None else ("supports" if self.supports is not None else "pressure")


@dataclass(frozen=True)
class Impact:
    """The impact-limit COR (7.1) of a body with radius of gyration ``radius_of_gyration``
    about the CM (``source``: "support", "uniform_disk" or "uniform_polygon"); ``cor`` None
    for a pure translation."""

    cor: np.ndarray | None
    distance: float | None
    radius_of_gyration: float
    source: str


@dataclass(frozen=True)
class BatchGroup:
    """The Newton batch of the supports ``indices`` (all of one size) and its result
    (row j is support ``indices[j]``)."""

    indices: tuple[int, ...]
    result: BatchResult


@dataclass(frozen=True)
class MotionResult:
    """The motions of a :class:`MotionProblem`.

    ``motion``: the one motion of a support or a pressure; ``motions``: one per support of
    a batch solved one by one (cvxpy, casadi); ``groups``: the Newton batches of a batch.
    ``impact``: (7.1) for a support or a pressure (None for a batch, or when the whole
    support is at the CM)."""

    problem: MotionProblem
    motion: ForwardResult | None
    motions: tuple[ForwardResult, ...] | None
    groups: tuple[BatchGroup, ...] | None
    impact: Impact | None
    solve_time_s: float

    @property
    def n_motions(self) -> int:
        if self.groups is not None:
            return sum(len(g.indices) for g in self.groups)
        return len(self.motions) if self.motions is not None else 1

    @property
    def n_optimal(self) -> int:
        if self.groups is not None:
            return sum(int(np.sum(g.result.converged)) for g in self.groups)
        done = self.motions if self.motions is not None else (self.motion,)
        return sum(m.status == "optimal" for m in done)

    @property
    def status(self) -> str:
        """"optimal" when every motion is, else "not_converged"."""
        return "optimal" if self.n_optimal == self.n_motions else "not_converged"

    @property
    def complete(self) -> bool:
        return True

    @property
    def message(self) -> str:
        return f"{self.n_optimal} of {self.n_motions} motions optimal ({self.problem.kind}, {self.problem.method})"


def _impact(scene: PushScene, rho: float, source: str) -> Impact | None:
    """(7.1) with the radius of gyration ``rho``; rho may exceed a by rounding only (a is
    at least the support's extent), so it is capped at a. None when rho = 0 (all the mass
    at the CM: no rotational inertia, (7.1) is undefined)."""
    if not rho > 0.0:
        return None
    rho = min(rho, scene.disk_radius)
    return Impact(impact_cor(scene, rho), impact_cor_distance(scene, rho), rho, source)


def solve_motion(problem: MotionProblem, budget: Budget = UNLIMITED) -> MotionResult:
    """The motions of ``problem`` (module docstring). The solves are not time-limited:
    their size is bounded by the caller (``budget`` is accepted for uniformity)."""
    scene, mu_c, method, tol = problem.scene, float(problem.mu_c), problem.method, problem.tol
    motion = motions = groups = impact = None
    if problem.pressure is not None:
        pr = problem.pressure
        motion = uniform_pressure_cor(scene, pr.footprint, resolution=pr.resolution, mu_c=mu_c, method=method, tol=tol)
        if pr.footprint is None:
            impact = _impact(scene, disk_radius_of_gyration(scene.disk_radius), "uniform_disk")
        else:
            impact = _impact(scene, polygon_radius_of_gyration(pr.footprint), "uniform_polygon")
        solve_s = motion.solve_time_s
    elif problem.support is not None:
        motion = solve_forward(scene, problem.support, mu_c=mu_c, method=method, tol=tol)
        rho = support_radius_of_gyration(problem.support.points, problem.support.weights)
        impact = _impact(scene, rho, "support")
        solve_s = motion.solve_time_s
    elif problem.batch is not None:
        b = problem.batch
        result = solve_forward_batch(scene, b.points, b.weights, mu_c=mu_c, tol=tol, check_centroid=False)
        groups = (BatchGroup(tuple(range(len(b))), result),)
        solve_s = result.solve_time_s
    elif method != "newton":
        out = []
        for i, support in enumerate(problem.supports):
            try:
                out.append(solve_forward(scene, support, mu_c=mu_c, method=method, tol=tol))
            except InvalidInput as exc:
                if exc.field != "support":
                    raise
                raise InvalidInput(f"supports.{i}", exc.reason) from exc  # the problem's supports[i]
        motions = tuple(out)
        solve_s = sum(m.solve_time_s for m in motions)
    else:
        by_size: dict[int, list[int]] = {}
        for i, support in enumerate(problem.supports):
            by_size.setdefault(len(support.points), []).append(i)
        found = []
        for idx in by_size.values():
            pts = np.stack([problem.supports[i].points for i in idx])
            wts = np.stack([problem.supports[i].weights for i in idx])
            found.append(BatchGroup(tuple(idx), solve_forward_batch(scene, pts, wts, mu_c=mu_c, tol=tol,
                                                                     check_centroid=False)))
        groups = tuple(found)
        solve_s = sum(g.result.solve_time_s for g in groups)
    return MotionResult(problem, motion, motions, groups, impact, solve_s)
