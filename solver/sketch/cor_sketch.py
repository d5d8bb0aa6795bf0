"""The COR sketch of a push with pusher friction (book 4.1), analytic or certified: one
problem in, one result out.

Method "analytic": :func:`models.sketch.disk_sketch.cor_sketch`, the disk's analytic loci and
the book's sweep of the force over the cone (4.1.4); a polygon is bounded by its
circumscribing disk (3.1.8). Method "certified":
:func:`solver.sketch.certified_sketch.certified_sketch`, every piece certified by the
minimum-power engine (with a footprint, the polygon's own sketch), within the budget; one
not whole (the time limit, or a piece not certified) answers the disk's analytic sketch,
which bounds the polygon's (7.5), beside its certification report, never a verdict drawn
from the pieces finished.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

from models.core.footprint import Footprint
from models.core.scene import PushScene
from models.locus.cor_disk import TipLine, disk_cor_locus
from models.sketch.disk_sketch import CorSketch, disk_cor_sketch
from solver.core.budget import UNLIMITED, Budget
from solver.core.errors import BackendNotFound
from solver.core.tolerances import SOLVER_DEFAULT, SolverTolerances
from solver.sketch.certified_sketch import (
    DEFAULT_RAYS,
    CertifiedSketch,
    certified_sketch,
)
from solver.sketch.sweep import sticking_spans

SKETCH_METHODS = ("analytic", "certified")


@dataclass(frozen=True)
class SketchProblem:
    """A push with pusher friction ``mu_c`` and what to compute of its sketch.

    ``footprint``: the polygon sketched by method "certified" (method "analytic" sketches
    the scene's disk). ``n_points``: boundary points of each analytic elementary locus;
    ``n_rays``: rays per traced locus of a certified polygon. ``with_tip_line``: also the
    frictionless locus's tip line of the scene (3.3.11.1), for a picture."""

    scene: PushScene
    mu_c: float
    footprint: Footprint | None = None
    method: str = "analytic"
    n_points: int = 512
    n_rays: int = DEFAULT_RAYS
    with_tip_line: bool = False
    tol: SolverTolerances = SOLVER_DEFAULT

    def __post_init__(self) -> None:
        if self.method not in SKETCH_METHODS:
            raise BackendNotFound("method", self.method, SKETCH_METHODS)


@dataclass(frozen=True)
class SketchResult:
    """The sketch (the certified one when whole, else the disk's), the certification report
    of method "certified" (else None) and, when asked for, the tip line."""

    problem: SketchProblem
    sketch: CorSketch
    certified: CertifiedSketch | None
    tip_line: TipLine | None
    solve_time_s: float

    @property
    def complete(self) -> bool:
        return self.certified is None or self.certified.complete

    @property
    def bounded(self) -> bool:
        """A certified sketch not whole: the sketch answered is the (circumscribing) disk's."""
        return self.certified is not None and not self.certified.complete

    @property
    def status(self) -> str:
        """"analytic", "certified" (every piece certified) or "incomplete"."""
        if self.certified is None:
            return "analytic"
        return "certified" if self.certified.complete else "incomplete"

    @property
    def message(self) -> str:
        head = f"sketch {self.sketch.sketch or 'none'} ({self.problem.method})"
        return head if self.certified is None else f"{head}: {self.certified.message}"


def cor_sketch(problem: SketchProblem, budget: Budget = UNLIMITED) -> SketchResult:
    """The COR sketch of ``problem`` (module docstring); ``budget`` bounds a certified one."""
    t0 = time.perf_counter()
    certified = None
    if problem.method == "certified":
        certified = certified_sketch(problem.scene, problem.mu_c, footprint=problem.footprint, n_rays=problem.n_rays,
                                     n_points=problem.n_points, tol=problem.tol, budget=budget)
    if certified is not None and certified.complete:
        sk = certified.sketch
    else:  # analytic; or a certified one not whole: the (circumscribing) disk's sketch bounds it (7.5)
        sk = disk_cor_sketch(problem.scene, problem.mu_c, n_points=problem.n_points, spans=sticking_spans)
    tip_line = disk_cor_locus(problem.scene, outputs=["tip_line"]).tip_line if problem.with_tip_line else None
    return SketchResult(problem, sk, certified, tip_line, time.perf_counter() - t0)
