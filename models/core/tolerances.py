"""Named numerical tolerances, passed in explicitly; never bare literals in code bodies."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol


@dataclass(frozen=True)
class Tolerances:
    """Tolerances of the analytic COR-locus computations (all relative, dimensionless).

    Attributes:
        root_rtol: relative width in log(r) at which the root solve of the outer
            boundary (3.35) stops.
        root_max_iter: iteration cap of that root solve (a safeguarded bisection/secant
            hybrid needs about 10 for ``root_rtol=1e-14``; the cap only guards bugs).
        translation_rel: |alpha . c| / a at or below which the line of force is taken to
            pass through the centre of mass, so the push is a pure translation (3.3.11.1).
        grazing_sin: |sin| of the angle between push direction and edge at or below
            which the pusher slides along the edge instead of pushing it (3.3).
        polygon_area_rel: polygon area / (bounding-box diagonal)^2 at or below which a
            footprint is degenerate (collinear vertices).
        boundary_residual_rel: largest accepted residual of the boundary equations
            (3.29)/(3.35), relative to the disk radius; a larger one is reported as a
            numerical failure instead of a wrong locus.
        max_relative_moment_arm: largest |alpha . c| / a accepted. The locus is then inside
            the disk and no longer changes visibly, while powers of the ratio in (3.33) would
            overflow; a scene beyond it is refused as an input error.
    """

    root_rtol: float = 1e-14
    root_max_iter: int = 200
    translation_rel: float = 1e-14
    grazing_sin: float = 1e-9
    polygon_area_rel: float = 1e-12
    boundary_residual_rel: float = 1e-9
    max_relative_moment_arm: float = 1e12

    @classmethod
    def default(cls) -> "Tolerances":
        return DEFAULT

    @classmethod
    def high_accuracy(cls) -> "Tolerances":
        return HIGH_ACCURACY

    @classmethod
    def fast(cls) -> "Tolerances":
        return FAST


DEFAULT = Tolerances()
HIGH_ACCURACY = Tolerances(root_rtol=4e-16, boundary_residual_rel=1e-11)
FAST = Tolerances(root_rtol=1e-9, boundary_residual_rel=1e-6)


@dataclass(frozen=True)
class SpiralTolerances:
    """Named tolerances of the spiral computations (lengths relative to the disk radius a).

    Attributes:
        grazing_delta: pi/2 - beta of the last table point and of the numerical limit
            beta -> pi/2 (4.5.4): exactly pi/2 is a grazing touch with no pushing force.
        stall_step_rel: the recursion (4.26) stops as "stalled" once a revolution would
            shrink the radius by at most stall_step_rel * a.
        max_revolutions: cap on the revolutions of the recursion.
        arc_nodes: Gauss-Legendre nodes of the arc length of one revolution (half as many
            give its error estimate).
        monotone_rel: an increase of the table r*_{k+1} > r*_k (1 + monotone_rel) is
            reported as a violation of monotonicity.
        length_unit_rel: the integer cost unit of path lengths on the OR-Tools graph,
            relative to a (the rounding of a schedule's length is at most half a unit per
            revolution).
        tie_break_unit_rel: the (coarser) length unit of the tie-break of the "revolutions"
            objective: among the schedules with the fewest revolutions the shortest is
            taken, to this unit (relative to a).
        graph_safe_ulps: how many ulps a radius of the recursion may be raised so that its
            step is also safe in the schedule graph's rounding-proof test (the two differ
            by rounding only).
    """

    grazing_delta: float = 1e-6
    stall_step_rel: float = 1e-12
    max_revolutions: int = 100_000
    arc_nodes: int = 16
    monotone_rel: float = 1e-9
    length_unit_rel: float = 1e-7
    tie_break_unit_rel: float = 1e-4
    graph_safe_ulps: int = 64

    @classmethod
    def default(cls) -> "SpiralTolerances":
        return SPIRAL_DEFAULT

    @classmethod
    def fast(cls) -> "SpiralTolerances":
        return SPIRAL_FAST

    @classmethod
    def high_accuracy(cls) -> "SpiralTolerances":
        return SPIRAL_HIGH_ACCURACY


SPIRAL_DEFAULT = SpiralTolerances()
SPIRAL_FAST = SpiralTolerances(grazing_delta=1e-5, stall_step_rel=1e-10, max_revolutions=10_000, arc_nodes=8,
                               length_unit_rel=1e-6)
SPIRAL_HIGH_ACCURACY = SpiralTolerances(grazing_delta=1e-7, stall_step_rel=1e-14, arc_nodes=32, length_unit_rel=1e-9)


class CentroidTolerance(Protocol):
    """Anything that names the centroid tolerance of a support (book 3.1.5):
    :class:`SupportTolerances` here, or the optimisation engine's tolerances."""

    @property
    def centroid_rel(self) -> float: ...


@dataclass(frozen=True)
class SupportTolerances:
    """Tolerance of a discrete pressure distribution (:class:`models.core.support.Support`).

    Attributes:
        centroid_rel: largest |weighted centroid - CM| / L accepted for a given support
            (L the support's size), 3.1.5.
    """

    centroid_rel: float = 1e-9


SUPPORT_DEFAULT = SupportTolerances()

