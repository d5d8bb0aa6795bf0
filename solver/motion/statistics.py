"""CORs of random supports: figure 3-5 (tripod CORs for mu_c = 0), figure 7-2 (histogram
along the sticking line for a large mu_c, 7.7), and the uniform-pressure COR (figure 7-1).

These are statistics of a *model* of pressure distributions (uniform random tripods, as in
the book), not properties of the COR locus, which is about possibility (7.7).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.core.mpp import perp
from models.core.scene import PushScene
from models.core.support import random_balanced_tripods, uniform_disk_support, uniform_polygon_support
from solver.core.budget import UNLIMITED, Budget
from solver.core.tolerances import SOLVER_DEFAULT, SolverTolerances
from solver.motion.forward import BatchResult, ForwardResult, solve_forward, solve_forward_batch

HISTOGRAM_ULPS_PER_BIN = 64
"""The narrowest histogram bin, in units in the last place of the range's largest |edge|:
numpy refuses bins its floating point cannot tell apart."""


@dataclass(frozen=True)
class TripodSample:
    """CORs (world, NaN rows for translations) of ``n`` random tripods, and their solve.
    ``solve_time_s``: seconds to draw and solve them; ``status`` and ``complete`` are the
    batch's (every tripod converged)."""

    points: np.ndarray
    weights: np.ndarray
    batch: BatchResult
    seed: int
    solve_time_s: float

    @property
    def status(self) -> str:
        return self.batch.status

    @property
    def complete(self) -> bool:
        return self.batch.complete

    @property
    def message(self) -> str:
        return f"{len(self.weights)} random tripods (seed {self.seed}): {self.batch.message}"


def tripod_sample(
    scene: PushScene,
    n: int,
    seed: int,
    mu_c: float = 0.0,
    footprint: Footprint | None = None,
    tol: SolverTolerances = SOLVER_DEFAULT,
) -> TripodSample:
    """Random tripods on the disk (or footprint) as in 3.3.3, solved in one batch."""
    if n < 1:
        raise InvalidInput("n_tripods", "must be at least 1")
    if footprint is not None and not np.allclose(footprint.center_of_mass, scene.center_of_mass):
        raise InvalidInput("footprint", "its centre of mass differs from the scene's")
    t0 = time.perf_counter()
    rng = np.random.default_rng(seed)
    pts, wts = random_balanced_tripods(rng, n, scene.disk_radius, scene.center_of_mass, footprint)
    batch = solve_forward_batch(scene, pts, wts, mu_c=mu_c, tol=tol, check_centroid=False)
    return TripodSample(points=pts, weights=wts, batch=batch, seed=seed, solve_time_s=time.perf_counter() - t0)


@dataclass(frozen=True)
class StickingHistogram:
    """Figure 7-2: where tripod CORs fall along the sticking line (4.1.2).

    Positions are signed distances from the contact point along J p (the book's "up",
    perpendicular to the push), in world length units. ``counts`` over ``edges``;
    ``sticking_fraction`` of tripods that stick; CORs of slipping tripods are off the line
    and are not counted; ``outside_range`` sticking CORs beyond the edges. ``n_converged``:
    tripods whose forward solve converged (all of them for a ``complete`` histogram).
    """

    edges: np.ndarray
    counts: np.ndarray
    sticking_fraction: float
    outside_range: int
    n_tripods: int
    solve_time_s: float
    n_converged: int

    @property
    def status(self) -> str:
        """"optimal" when every tripod's solve converged, else "not_converged"."""
        return "optimal" if self.n_converged == self.n_tripods else "not_converged"

    @property
    def complete(self) -> bool:
        return self.status == "optimal"

    @property
    def message(self) -> str:
        return (f"{self.n_tripods} tripods, {100.0 * self.sticking_fraction:.3g}% sticking, "
                f"{self.outside_range} sticking CORs outside the range; {self.n_converged} converged")


def histogram_range(pos: np.ndarray, bins: int, disk_radius: float,
                    span: tuple[float, float] | None = None) -> tuple[float, float]:
    """The range of the sticking-line histogram: ``span``, or the 1st to 99th percentile of
    ``pos`` (one disk radius when they coincide). A range floating point cannot split into
    ``bins`` distinct bins (at a small scale far from 0: a 1e-12 disk, positions equal to 15
    digits) is widened about its middle, or refused when it is the caller's span."""
    if span is None:
        lo, hi = (float(v) for v in np.percentile(pos, [1, 99])) if pos.size else (-disk_radius, disk_radius)
    else:
        lo, hi = (float(v) for v in span)
        if not hi > lo:
            raise InvalidInput("span", "must be an increasing pair")
    scale = max(abs(lo), abs(hi))
    least = bins * HISTOGRAM_ULPS_PER_BIN * np.spacing(scale)
    if hi - lo >= least:
        return lo, hi
    if span is not None:
        raise InvalidInput("span", f"is too narrow at its position for {bins} bins: floating point cannot tell their "
                                   f"edges apart (at least {least:.3g} wide)")
    mid, half = 0.5 * (lo + hi), 0.5 * max(disk_radius, least)
    return mid - half, mid + half


def sticking_line_histogram(
    scene: PushScene,
    n: int,
    seed: int,
    mu_c: float = 1e6,
    bins: int = 50,
    span: tuple[float, float] | None = None,
    footprint: Footprint | None = None,
    tol: SolverTolerances = SOLVER_DEFAULT,
) -> StickingHistogram:
    """Histogram of tripod CORs along the sticking line for a large mu_c (7.7)."""
    if bins < 1:
        raise InvalidInput("bins", "must be at least 1")
    t0 = time.perf_counter()
    sample = tripod_sample(scene, n, seed, mu_c=mu_c, footprint=footprint, tol=tol)
    b = sample.batch
    stick = (b.mode == 1) & np.all(np.isfinite(b.cor), axis=1)
    pos = (b.cor[stick] - scene.contact_point) @ perp(scene.push_hat)
    lo, hi = histogram_range(pos, bins, scene.disk_radius, span)
    counts, edges = np.histogram(pos, bins=bins, range=(lo, hi))
    outside = int(np.sum((pos < lo) | (pos > hi)))
    return StickingHistogram(
        edges=edges,
        counts=counts,
        sticking_fraction=float(stick.mean()),
        outside_range=outside,
        n_tripods=n,
        solve_time_s=time.perf_counter() - t0,
        n_converged=int(np.count_nonzero(b.converged)),
    )


def uniform_pressure_cor(
    scene: PushScene,
    footprint: Footprint | None = None,
    resolution: int = 32,
    mu_c: float = 0.0,
    method: str = "newton",
    tol: SolverTolerances = SOLVER_DEFAULT,
) -> ForwardResult:
    """The motion under uniform pressure on the disk or polygon footprint (figure 7-1),
    discretised with ``resolution`` rings (disk) or sub-divisions per triangle (polygon)."""
    if footprint is None:
        support = uniform_disk_support(scene.disk_radius, scene.center_of_mass, rings=resolution)
    else:
        support = uniform_polygon_support(footprint, subdivisions=resolution)
    return solve_forward(scene, support, mu_c=mu_c, method=method, tol=tol)


@dataclass(frozen=True)
class HistogramQuery:
    """Figure 7-2's histogram: the tripods solved again with pusher friction ``mu_c``,
    ``bins`` bins over ``span`` (None: the 1st..99th percentile)."""

    mu_c: float = 1e6
    bins: int = 50
    span: tuple[float, float] | None = None


@dataclass(frozen=True)
class TripodStatisticsProblem:
    """``n_tripods`` random balanced tripods (3.3.3, seeded by ``seed``) on the scene's disk
    or on ``footprint``, solved with pusher friction ``mu_c`` (figure 3-5), and optionally
    the sticking-line histogram (figure 7-2)."""

    scene: PushScene
    n_tripods: int
    seed: int
    mu_c: float = 0.0
    footprint: Footprint | None = None
    histogram: HistogramQuery | None = None
    tol: SolverTolerances = SOLVER_DEFAULT


@dataclass(frozen=True)
class TripodStatistics:
    """The sample of a :class:`TripodStatisticsProblem` and its histogram (None unless
    asked for). ``status``: "optimal" when every tripod's solve converged."""

    problem: TripodStatisticsProblem
    sample: TripodSample
    histogram: StickingHistogram | None
    solve_time_s: float

    @property
    def status(self) -> str:
        return "optimal" if bool(np.all(self.sample.batch.converged)) else "not_converged"

    @property
    def complete(self) -> bool:
        return True

    @property
    def message(self) -> str:
        b = self.sample.batch
        return f"{int(np.sum(b.converged))} of {self.problem.n_tripods} tripods converged"


def tripod_statistics(problem: TripodStatisticsProblem, budget: Budget = UNLIMITED) -> TripodStatistics:
    """The tripod sample of ``problem`` and, if asked, its histogram (figures 3-5, 7-2).
    Not time-limited: the caller bounds the sample's size (``budget`` is accepted for
    uniformity)."""
    p = problem
    sample = tripod_sample(p.scene, p.n_tripods, p.seed, mu_c=p.mu_c, footprint=p.footprint, tol=p.tol)
    solve_s = sample.batch.solve_time_s
    hist = None
    if p.histogram is not None:
        h = p.histogram
        hist = sticking_line_histogram(p.scene, p.n_tripods, p.seed, mu_c=h.mu_c, bins=h.bins, span=h.span,
                                       footprint=p.footprint, tol=p.tol)
        solve_s += hist.solve_time_s
    return TripodStatistics(problem, sample, hist, solve_s)
