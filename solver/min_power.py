"""The COR of a workpiece on a known support, by the minimum power principle (book 2, 3.2).

For a frictionless pusher (mu_c = 0) the workpiece's motion per unit advance of the
pusher is the planar twist (v, omega) that minimises the frictional power (3.6)-(3.7),
sum_i P_i |v + omega z x w_i|, subject to the contact constraint n . v(c) = n . p (3.3):
a second-order cone programme in the twist. It is solved here with cvxpy + Clarabel and
serves as the independent check of the closed forms of chapter 3.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass

import cvxpy as cp
import numpy as np

from models.errors import InvalidInput
from models.scene import PushScene
from solver.errors import SolverError


@dataclass(frozen=True)
class ForwardSolution:
    """Motion of the workpiece per unit push, world frame.

    ``cor`` is None for a pure translation (|omega| below ``translation_omega`` times the
    support's inverse size). ``power`` is the dissipated power per unit push divided by
    mu_s * total weight (3.7). ``gap`` is the duality gap |power - lambda sin(alpha)| with
    lambda the contact force (the contact constraint's multiplier).
    """

    status: str
    cor: np.ndarray | None
    velocity_cm: np.ndarray
    omega: float
    power: float
    contact_force: float
    gap: float
    solve_time_s: float


def solve_cor(
    scene: PushScene,
    points,
    weights,
    eps_abs: float = 1e-10,
    eps_rel: float = 1e-10,
    translation_omega: float = 1e-12,
) -> ForwardSolution:
    """COR for the support ``points`` (world frame, (k, 2)) with ``weights`` (>= 0).

    The weights are normalised; their centroid must be the scene's CM (3.1.5) to within
    ``eps_rel`` of the support's size, else InvalidInput.
    """
    w = np.asarray(points, dtype=float).reshape(-1, 2)
    p = np.asarray(weights, dtype=float).reshape(-1)
    if p.shape[0] != w.shape[0] or np.any(p < 0.0) or p.sum() <= 0.0:
        raise InvalidInput("weights", "need one non-negative weight per point, not all zero")
    p = p / p.sum()
    rel = w - scene.center_of_mass
    size = max(float(np.max(np.linalg.norm(rel, axis=1))), scene.disk_radius)
    if np.linalg.norm(p @ rel) > 1e3 * eps_rel * size:
        raise InvalidInput("weights", "the weighted centroid of the support is not the centre of mass")
    v = cp.Variable(2)
    om = cp.Variable()
    # velocity of support point i: v + om * z x rel_i = v + om * (-y_i, x_i)
    perp_rel = np.column_stack([-rel[:, 1], rel[:, 0]])
    terms = [p[i] * cp.norm(v + om * perp_rel[i], 2) for i in range(len(p)) if p[i] > 0.0]
    c = scene.contact_rel
    n = scene.normal
    contact = n @ v + om * (n @ np.array([-c[1], c[0]])) == scene.sin_alpha
    prob = cp.Problem(cp.Minimize(cp.sum(cp.hstack(terms))), [contact])
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings():
            # An inaccurate solve is reported through ``status``, not a warning.
            warnings.simplefilter("ignore", UserWarning)
            prob.solve(solver=cp.CLARABEL, tol_gap_abs=eps_abs, tol_gap_rel=eps_rel, tol_feas=eps_abs)
    except cp.error.SolverError as exc:  # pragma: no cover - depends on the back end
        raise SolverError(f"Clarabel failed on the minimum-power problem: {exc}") from exc
    elapsed = time.perf_counter() - t0
    if prob.status not in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE):
        raise SolverError(f"minimum-power problem ended with status {prob.status}")
    # Dual of min sum_i P_i |A_i x| s.t. n . v(c) = sin(alpha) is max lambda sin(alpha):
    # lambda, the multiplier of the contact constraint, is the normal contact force.
    # cvxpy's sign convention for equality multipliers makes it -lambda.
    force = -float(np.asarray(contact.dual_value, dtype=float).reshape(-1)[0])
    gap = abs(float(prob.value) - force * scene.sin_alpha)
    vv = np.asarray(v.value, dtype=float)
    omega = float(om.value)
    if abs(omega) * size <= translation_omega * max(1.0, float(np.linalg.norm(vv))):
        cor = None
    else:
        cor = scene.center_of_mass + np.array([-vv[1] / omega, vv[0] / omega])
    return ForwardSolution(
        status=str(prob.status),
        cor=cor,
        velocity_cm=vv,
        omega=omega,
        power=float(prob.value),
        contact_force=force,
        gap=gap,
        solve_time_s=elapsed,
    )
