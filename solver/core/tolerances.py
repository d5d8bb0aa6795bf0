"""Named tolerances of the optimisation engine, passed in explicitly; never bare
literals in code bodies. (The closed forms' tolerances are :mod:`models.core.tolerances`.)"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class SolverTolerances:
    """Tolerances of the minimum-power engine (forward solves, membership, certificates).

    All are dimensionless: lengths are divided by the size L of the support or footprint,
    forces and powers by the total weight (times mu_s), so the values mean the same at
    every scale.

    Attributes:
        kkt: KKT residual the Newton iteration drives to: the norm of the projected
            gradient of the power (smooth optimum) or the excess of the subgradient
            multiplier over the weight (COR on a support point).
        kkt_accept: KKT residual at or below which any back end's answer is reported
            optimal (IPOPT's and Clarabel's own answers reach ~1e-10 to 1e-12).
        max_newton_iter: iteration cap of the batched Newton solver.
        translation_omega: |omega| L / |v| at or below which a motion is a translation
            (COR at infinity).
        centroid_rel: largest |weighted centroid - CM| / L accepted for a given support.
        conic_gap: absolute and relative gap / feasibility tolerance handed to Clarabel.
        conic_ktratio: Clarabel's tolerance on the ratio kappa/tau of its homogeneous
            embedding for the forward cone programme (its default 1e-6 stops early on
            badly scaled supports).
        casadi_tol: IPOPT's tol for the CasADi paths.
        nlp_feasibility: largest constraint violation of an IPOPT tripod-search optimum
            that counts as feasible; weights below it are dropped.
        membership_residual: L1 residual of the membership equations at or below which a
            witness support is accepted (candidate COR inside the locus).
        witness_cor_rel: largest |forward COR of the witness - r| / L for a witness to be
            re-verified by the forward solver.
        certificate_margin: certified dual margin above which a candidate COR is outside.
        pricing_tol: column generation stops once no point of the footprint has a reduced
            cost below -pricing_tol, or below -(residual - membership_residual) when the
            residual is smaller than that (:func:`solver.certify.colgen.pricing_threshold`).
        max_cg_iter: cap on column-generation rounds of one membership query.
        max_bnb_intervals: cap on the intervals of one branch-and-bound lower bound.
        boundary_bracket: width |r_out - r_in| / L of the certified bracket around a
            boundary point of a certified locus.
        max_cor_distance_rel: farthest candidate COR, |r - CM| / L, a membership query
            takes (beyond, its rows lose every digit; the query is refused naming it).
    """

    kkt: float = 1e-10
    kkt_accept: float = 1e-9
    max_newton_iter: int = 80
    translation_omega: float = 1e-12
    centroid_rel: float = 1e-9
    conic_gap: float = 1e-11
    conic_ktratio: float = 1e-12
    casadi_tol: float = 1e-12
    nlp_feasibility: float = 1e-8
    membership_residual: float = 1e-12
    witness_cor_rel: float = 1e-6
    certificate_margin: float = 1e-9
    pricing_tol: float = 1e-10
    max_cg_iter: int = 40
    max_bnb_intervals: int = 200_000
    boundary_bracket: float = 1e-6
    max_cor_distance_rel: float = 1e12


SOLVER_DEFAULT = SolverTolerances()
SOLVER_HIGH_ACCURACY = SolverTolerances(kkt=1e-12, kkt_accept=1e-11, membership_residual=1e-13, boundary_bracket=1e-8)
SOLVER_FAST = SolverTolerances(kkt=1e-8, kkt_accept=1e-7, membership_residual=1e-6, boundary_bracket=1e-4, max_cg_iter=20)
