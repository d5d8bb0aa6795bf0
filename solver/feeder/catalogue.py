"""A catalogue of parts, one design request: every part's feeder design (5.3-5.4) and its
validation by simulated parts, in parallel on Ray (:mod:`solver.core.parallel`), each
exactly what :func:`solver.feeder.design.feeder_design` answers for that part alone.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass

from models.core.footprint import Footprint
from solver.core.budget import UNLIMITED, Budget
from solver.core.parallel import ParallelRun, RayPool, parallel_map
from solver.feeder.design import FeederDesignProblem, FeederDesignResult, feeder_design


@dataclass(frozen=True)
class FeederCatalogueProblem:
    """``parts`` (body frame, as :func:`models.feeder.fence.feeder_part` makes them), the one
    ``design`` request applied to each (its own ``part`` is replaced), and where to run
    (``pool``)."""

    parts: tuple[Footprint, ...]
    design: FeederDesignProblem
    pool: RayPool = RayPool()

    def problems(self) -> list[FeederDesignProblem]:
        return [dataclasses.replace(self.design, part=part) for part in self.parts]


@dataclass(frozen=True)
class FeederCatalogueResult:
    """Each part's design result (None: not finished by the deadline), where they ran
    (``run``: backend, CPUs, nodes) and the time."""

    problem: FeederCatalogueProblem
    designs: tuple[FeederDesignResult | None, ...]
    run: ParallelRun
    solve_time_s: float

    @property
    def complete(self) -> bool:
        return all(d is not None and d.status == "ok" for d in self.designs)

    @property
    def status(self) -> str:
        """"complete" (every part's design finished) or "time_limit"."""
        return "complete" if self.complete else "time_limit"

    @property
    def message(self) -> str:
        done = sum(d is not None and d.status == "ok" for d in self.designs)
        return f"{done} of {len(self.designs)} designs finished ({self.run.backend}, {self.run.cpus} CPUs)"


def design_until(problem: FeederDesignProblem, ends_at: float | None) -> FeederDesignResult:
    """One part's design with the time left until ``ends_at`` (wall clock), where a Ray
    task runs it."""
    return feeder_design(problem, Budget.of(None if ends_at is None else ends_at - time.time()))


def feeder_catalogue(problem: FeederCatalogueProblem, budget: Budget = UNLIMITED) -> FeederCatalogueResult:
    """Every part's design, in parallel on ``problem.pool`` within ``budget``."""
    t0 = time.perf_counter()
    run = parallel_map(design_until, problem.problems(), problem.pool, budget)
    return FeederCatalogueResult(problem, run.results, run, time.perf_counter() - t0)
