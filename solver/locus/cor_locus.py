"""The COR locus of a push, analytic or certified: one problem in, one result out.

:func:`locus` computes the closed forms of the frictionless disk locus (book 3.3,
:func:`models.locus.cor_disk.disk_cor_locus`) and, with method "certified", certified
brackets of the boundary by minimum-power membership queries (3.3.13, 7.5): of the
analytic disk boundary (:func:`solver.locus.certified_locus.certified_disk_boundary`), or
of the polygon footprint's own locus
(:func:`solver.locus.certified_locus.certified_polygon_boundary`). The certificates stop
when the budget runs out; the result says how far they got (``complete``).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

from models.core.footprint import Footprint
from models.core.scene import PushScene
from models.locus.cor_disk import OUTPUTS, DiskCorLocus, disk_cor_locus
from solver.core.budget import UNLIMITED, Budget
from solver.core.errors import BackendNotFound
from solver.core.tolerances import SOLVER_DEFAULT, SolverTolerances
from solver.locus.certified_locus import (
    CertifiedDiskBoundary,
    CertifiedPolygonBoundary,
    certified_disk_boundary,
    certified_polygon_boundary,
)

LOCUS_METHODS = ("analytic", "certified")


@dataclass(frozen=True)
class LocusProblem:
    """A push and what to compute of its COR locus.

    ``footprint``: the polygon whose locus is certified (method "certified"); the analytic
    locus is always that of the scene's disk (for a polygon its circumscribing disk, 3.1.8,
    whose locus contains the polygon's, 7.5). ``outputs``: the parts of the analytic locus
    (:data:`models.locus.cor_disk.OUTPUTS`); ``n_points`` its boundary points.
    ``n_certified``: boundary points (disk) or rays (polygon) to certify."""

    scene: PushScene
    footprint: Footprint | None = None
    outputs: tuple[str, ...] = OUTPUTS
    n_points: int = 256
    method: str = "analytic"
    n_certified: int = 64
    tol: SolverTolerances = SOLVER_DEFAULT

    def __post_init__(self) -> None:
        if self.method not in LOCUS_METHODS:
            raise BackendNotFound("method", self.method, LOCUS_METHODS)


@dataclass(frozen=True)
class LocusResult:
    """The analytic locus and, for method "certified", the certified brackets.

    ``certified`` is None for method "analytic" and for a translation (nothing to
    certify). ``n_requested`` / ``n_done``: certified points or rays asked for and examined
    before the budget ran out. ``notes``: remarks for the caller (what was not certified
    and why)."""

    problem: LocusProblem
    analytic: DiskCorLocus
    certified: CertifiedDiskBoundary | CertifiedPolygonBoundary | None
    n_requested: int
    n_done: int
    notes: tuple[str, ...]
    solve_time_s: float

    @property
    def complete(self) -> bool:
        return self.n_done == self.n_requested

    @property
    def status(self) -> str:
        """"analytic", "certified" (every point or ray examined) or "time_limited"."""
        if self.problem.method == "analytic":
            return "analytic"
        return "certified" if self.complete else "time_limited"

    @property
    def message(self) -> str:
        head = f"{self.analytic.kind} locus ({self.problem.method})"
        return "; ".join((head, *self.notes))


def cor_locus(problem: LocusProblem, budget: Budget = UNLIMITED) -> LocusResult:
    """The COR locus of ``problem`` (module docstring); the certificates stop once
    ``budget`` has expired (at least one point or ray is always examined)."""
    t0 = time.perf_counter()
    scene = problem.scene
    analytic = disk_cor_locus(scene, outputs=problem.outputs, n_points=problem.n_points)
    certified = None
    notes: list[str] = []
    n_requested = n_done = 0
    if problem.method == "certified":
        if scene.is_translation:
            notes.append("method certified: nothing to certify, the push translates the part (COR at infinity)")
        elif problem.footprint is None:
            certified = certified_disk_boundary(scene, n_points=problem.n_certified, tol=problem.tol, budget=budget)
            n_requested, n_done = len(certified.boundary), len(certified.pairs)
        else:
            certified = certified_polygon_boundary(scene, problem.footprint, n_rays=problem.n_certified,
                                                   tol=problem.tol, budget=budget)
            n_requested, n_done = problem.n_certified, len(certified.rays)
        if n_done < n_requested:
            limit = "the time limit" if budget.limit_s is None else f"time limit {budget.limit_s:g} s"
            what = "points" if problem.footprint is None else "rays"
            notes.append(f"method certified: {limit} reached after {n_done} of {n_requested} {what}")
    return LocusResult(problem, analytic, certified, n_requested, n_done, tuple(notes), time.perf_counter() - t0)
