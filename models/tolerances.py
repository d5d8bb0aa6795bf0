"""Named numerical tolerances, passed in explicitly; never bare literals in code bodies."""

from __future__ import annotations

from dataclasses import dataclass


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
