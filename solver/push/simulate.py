"""Whole pushes simulated with the forward solver, to check the gross-motion bounds of
models/push/gross_motion.py (book 4.2-4.4) on known supports.

Two problems, in the frames of models/push/gross_motion.py (the world frame of the scenes built
here is the book's: the pusher moves along +x):

* **Fence alignment** (3.4, 4.3): a fence with face angle alpha advances along +x and
  touches the part at a vertex at distance c from the CM; the part turns clockwise until
  the edge leaving that vertex lies flush (beta = beta_final). Support points lie in the
  circumscribing disk of radius a.
* **Disk encounter** (4.4): a point moving along +x on the line y = 0 meets a disk of
  radius a (support inside it) with collision parameter beta_initial and pushes it aside
  until beta = pi/2, when the disk is left tangent to the path.

Each problem has two simulators:

* ``simulate_*``: one support, stepped in the push distance x with a fixed step. Each step
  is a midpoint (RK2) step of the pose: the forward solver gives the twist per unit push
  (CM velocity, rotation) at the current pose, the pose is moved half a step by that
  twist's exact rigid motion (rotation about the COR), the contact geometry is rebuilt
  and solved again, and the full step uses the midpoint twist. After every (half) step
  the contact is re-imposed (the vertex put back on the fence line along its normal; the
  disk put back at distance a from the pusher point along the line of centres), which
  removes the O(step^2) drift without changing the motion to first order. The end
  (flush edge, or beta = pi/2) is located by linear interpolation inside the last step.
* ``simulate_*_batch``: many supports at once, stepped in beta instead of x. For the
  fence, the part's orientation is a function of beta alone (the vertex stays on the
  fence), so every support is at the same orientation for a given beta and one batched
  forward solve per beta node gives dbeta/dx = -omega for all of them; x is the integral
  of -1/omega (composite Simpson). For the disk, beta fixes the contact geometry for all
  supports but each disk has its own rotation xi, so (xi, x) are integrated with RK4 in
  beta, using dx/dbeta = -a cos(beta) / v_y(CM) (from a sin beta = y_pusher - y_CM, the
  geometry of (4.10), not (4.12)) and dxi/dbeta = -omega dx/dbeta.

The batch versions are reformulations of the same motion (valid while beta increases,
i.e. the part turns clockwise, which Mason's rule guarantees here); the tests check that
both agree and that both converge in their step. The single-support simulators step on the
simulation core (:mod:`solver.sim.stepper`, :mod:`solver.sim.kinematics`,
:mod:`solver.sim.contacts`).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from models.core.errors import InvalidInput
from models.push.gross_bounds import encounter_scene, fence_scene
from solver.core.errors import SolverError
from solver.core.tolerances import SOLVER_DEFAULT, SolverTolerances
from solver.motion.forward import BatchResult, solve_forward_batch
from solver.sim.contacts import at_distance, onto_line
from solver.sim.kinematics import rotate_batch, rotation
from solver.sim.stepper import MotionOracle, march, midpoint_step

HALF_PI = 0.5 * math.pi

ENDING_BETA_GAP = 1e-9
"""A disk whose collision parameter at a step's midpoint is within this of pi/2 is leaving
the pusher: the step keeps its start's twist (an Euler step locates the end)."""

END_BETA_GAP = 1e-12
"""The encounter ends when beta reaches pi/2 - END_BETA_GAP (the end is then placed at
pi/2 by interpolation)."""


@dataclass(frozen=True)
class PushSimulation:
    """One simulated push: ``push`` is the pusher travel until the end event, ``rotation``
    the part's clockwise rotation over it (rad). ``beta``/``x`` are the trajectory at the
    step ends, ``modes`` counts the forward solver's modes over all solves and
    ``max_kkt`` is its largest KKT residual; ``not_optimal`` counts solves that did not
    report status optimal."""

    push: float
    rotation: float
    steps: int
    step: float
    beta: np.ndarray
    x: np.ndarray
    modes: dict
    max_kkt: float
    not_optimal: int
    solve_time_s: float

    @property
    def status(self) -> str:
        """"completed": a simulation that did not reach its end event raises instead."""
        return "completed"

    @property
    def complete(self) -> bool:
        return True

    @property
    def message(self) -> str:
        return (f"pushed {self.push:.6g} in {self.steps} steps of {self.step:.3g}; {self.not_optimal} of "
                f"{sum(self.modes.values())} forward solves not optimal")


@dataclass(frozen=True)
class BatchSimulation:
    """Many supports simulated together (stepped in beta). ``push``, ``rotation`` (B,);
    ``beta_nodes`` (N,) the betas solved at; ``rate`` (N, B) dx/dbeta there;
    ``rotation_rate`` (N, B) dxi/dbeta; ``cor`` (N, B, 2) the CORs in the problem's frame
    (NaN for translations); ``mode`` (N, B) indices into BatchResult.MODES; ``converged``
    is True if every forward solve converged."""

    push: np.ndarray
    rotation: np.ndarray
    beta_nodes: np.ndarray
    rate: np.ndarray
    rotation_rate: np.ndarray
    cor: np.ndarray
    mode: np.ndarray
    converged: bool
    max_kkt: float
    solve_time_s: float
    evaluations: int = field(default=0)

    @property
    def status(self) -> str:
        return "converged" if self.converged else "not_converged"

    @property
    def complete(self) -> bool:
        """Every forward solve converged."""
        return self.converged

    @property
    def message(self) -> str:
        return (f"{self.push.size} supports over {self.beta_nodes.size} beta nodes ({self.evaluations} batched "
                f"solves); {'all' if self.converged else 'not all'} converged, max KKT {self.max_kkt:.2g}")


def _check_batch(points, weights):
    w = np.asarray(points, dtype=float)
    p = np.asarray(weights, dtype=float)
    if w.ndim == 2:
        w, p = w[None], p.reshape(1, -1)
    if w.ndim != 3 or w.shape[2] != 2 or p.shape != w.shape[:2]:
        raise InvalidInput("points", "need support points (B, k, 2) relative to the CM and weights (B, k)")
    return w, p


# ---------------------------------------------------------------------------------------
# Fence alignment (3.4, 4.3)
# ---------------------------------------------------------------------------------------


def _fence_checks(a, c, alpha, beta_initial, beta_final):
    if not (a > 0 and 0 < c <= a * (1 + 1e-12)):
        raise InvalidInput("contact_distance", "need 0 < c <= a (the vertex is inside the circumscribing disk)")
    if not (0 < alpha < math.pi):
        raise InvalidInput("alpha", "must lie in (0, pi)")
    if not (0 < beta_initial < beta_final < math.pi - alpha):
        raise InvalidInput("beta_final", "need 0 < beta_initial < beta_final < pi - alpha")


def simulate_fence_alignment_batch(
    points,
    weights,
    a: float,
    c: float,
    alpha: float,
    beta_initial: float,
    beta_final: float,
    mu_c: float,
    n_steps: int = 128,
    tol: SolverTolerances = SOLVER_DEFAULT,
) -> BatchSimulation:
    """Push needed by each support to turn the part from beta_initial to beta_final.

    ``points`` (B, k, 2) are the supports relative to the CM with the part at beta_initial;
    at beta they are turned clockwise by beta - beta_initial. x = int -1/omega dbeta by
    composite Simpson on ``n_steps`` (even) intervals.
    """
    _fence_checks(a, c, alpha, beta_initial, beta_final)
    w, p = _check_batch(points, weights)
    n = int(n_steps) + (int(n_steps) % 2)
    betas = np.linspace(beta_initial, beta_final, n + 1)
    b_count = w.shape[0]
    rate = np.empty((n + 1, b_count))
    cor = np.empty((n + 1, b_count, 2))
    mode = np.empty((n + 1, b_count), dtype=int)
    converged = True
    max_kkt = 0.0
    t0 = time.perf_counter()
    for j, beta in enumerate(betas):
        scene = fence_scene(a, c, alpha, float(beta))
        res: BatchResult = solve_forward_batch(scene, rotate_batch(w, -(beta - beta_initial)), p, mu_c, tol)
        if np.any(res.omega >= 0.0):
            raise SolverError(f"a support did not turn clockwise at beta = {beta:.6g} (Mason's rule says it must)")
        rate[j] = -1.0 / res.omega
        cor[j] = res.cor
        mode[j] = res.mode
        converged &= bool(np.all(res.converged))
        max_kkt = max(max_kkt, float(np.max(res.kkt_residual)))
    elapsed = time.perf_counter() - t0
    h = (beta_final - beta_initial) / n
    simpson = np.ones(n + 1)
    simpson[1:-1:2] = 4.0
    simpson[2:-1:2] = 2.0
    push = (h / 3.0) * (simpson @ rate)
    return BatchSimulation(
        push=push,
        rotation=np.full(b_count, beta_final - beta_initial),
        beta_nodes=betas,
        rate=rate,
        rotation_rate=np.ones_like(rate),
        cor=cor,
        mode=mode,
        converged=converged,
        max_kkt=max_kkt,
        solve_time_s=elapsed,
        evaluations=n + 1,
    )


def simulate_fence_alignment(
    points,
    weights,
    a: float,
    c: float,
    alpha: float,
    beta_initial: float,
    beta_final: float,
    mu_c: float,
    step: float = 1e-3,
    method: str = "newton",
    max_steps: int = 200_000,
    tol: SolverTolerances = SOLVER_DEFAULT,
) -> PushSimulation:
    """One support pushed by a fence, stepped in x (``step`` in units of a).

    The vertex starts at the origin on the fence line (through the origin along alpha_hat
    at x = 0); the CM at c (cos beta_i, -sin beta_i) from it; ``points`` (k, 2) are the
    support relative to the CM at that pose. The fence at push x is the line
    n . P = x sin alpha, n = (sin alpha, -cos alpha). Ends when the part has turned until
    beta = beta_final (the edge flush).
    """
    _fence_checks(a, c, alpha, beta_initial, beta_final)
    body = np.asarray(points, dtype=float).reshape(-1, 2)
    wts = np.asarray(weights, dtype=float).reshape(-1)
    n_hat = np.array([math.sin(alpha), -math.cos(alpha)])
    vertex_body = c * np.array([-math.cos(beta_initial), math.sin(beta_initial)])
    h = float(step) * a
    oracle = MotionOracle(body, wts, a, mu_c, method, tol)

    def beta_of(x, cm, theta):
        d = -(rotation(theta) @ vertex_body)  # vertex -> CM
        return math.atan2(-d[1], d[0])

    def constrain(cm, theta, x):
        return onto_line(cm, cm + rotation(theta) @ vertex_body, n_hat, x * math.sin(alpha))

    def twist(x, cm, theta, start=None):
        tw = oracle.twist(cm, theta, cm + rotation(theta) @ vertex_body, alpha, 0.0)
        if tw.omega >= 0.0:
            raise SolverError("the part did not turn clockwise (Mason's rule says it must)")
        return tw

    def step_once(x, cm, theta):
        return midpoint_step(cm, theta, x, h, twist(x, cm, theta), twist, constrain)

    t0 = time.perf_counter()
    run = march(-vertex_body.copy(), 0.0, h, step_once, beta_of, beta_final, max_steps,  # vertex at the origin
                "the edge did not come flush")
    c = oracle.counts
    return PushSimulation(
        push=run.u_end, rotation=beta_final - beta_initial, steps=run.steps, step=h, beta=run.monitor, x=run.u,
        modes=dict(c.modes), max_kkt=c.max_kkt, not_optimal=c.not_optimal, solve_time_s=time.perf_counter() - t0,
    )


# ---------------------------------------------------------------------------------------
# A disk pushed aside by a point (4.4)
# ---------------------------------------------------------------------------------------


def _check_disk(a, beta_initial):
    if not a > 0:
        raise InvalidInput("disk_radius", "must be positive")
    if not 0 < beta_initial < HALF_PI:
        raise InvalidInput("beta_initial", "must lie in (0, pi/2)")


def simulate_disk_encounter_batch(
    points,
    weights,
    a: float,
    beta_initial: float,
    mu_c: float,
    n_steps: int = 64,
    end_gap: float = 1e-7,
    grading: float = 2.0,
    tol: SolverTolerances = SOLVER_DEFAULT,
) -> BatchSimulation:
    """Length x and clockwise rotation xi of the encounter for each support, stepped in
    beta by classical RK4 on ``n_steps`` steps from beta_initial to pi/2 - end_gap, plus
    end_gap times the last rates (the scene is grazing at pi/2 itself). The steps are
    uniform in s with beta = pi/2 - (pi/2 - beta_initial) (1 - s)^grading.

    ``points`` (B, k, 2) relative to the disk's CM at first contact.
    """
    _check_disk(a, beta_initial)
    w, p = _check_batch(points, weights)
    b_count = w.shape[0]
    beta_end = HALF_PI - end_gap
    # Steps graded towards pi/2, where the motion changes fastest (sketch i: sticking
    # supports start to slip and the CORs run off to the left).
    s = np.linspace(0.0, 1.0, int(n_steps) + 1)
    mesh = HALF_PI - (HALF_PI - beta_initial) * (1.0 - s) ** grading
    mesh[-1] = beta_end
    mesh = mesh[np.concatenate([[True], np.diff(mesh) > 0.0])]
    rec = {"beta": [], "rate": [], "rrate": [], "cor": [], "mode": [], "conv": True, "kkt": 0.0, "n": 0}

    def rhs(beta, xi, record=False):
        scene = encounter_scene(a, beta)
        res = solve_forward_batch(scene, rotate_batch(w, -xi), p, mu_c, tol)
        vy = res.velocity_cm[:, 1]
        if np.any(vy >= 0.0):
            raise SolverError(f"a disk did not move away from the path at beta = {beta:.6g}")
        dx = -a * math.cos(beta) / vy
        dxi = -res.omega * dx
        rec["conv"] &= bool(np.all(res.converged))
        rec["kkt"] = max(rec["kkt"], float(np.max(res.kkt_residual)))
        rec["n"] += 1
        if record:
            rec["beta"].append(beta)
            rec["rate"].append(dx)
            rec["rrate"].append(dxi)
            rec["cor"].append(res.cor)
            rec["mode"].append(res.mode)
        return dx, dxi

    t0 = time.perf_counter()
    x = np.zeros(b_count)
    xi = np.zeros(b_count)
    for beta, beta_next in zip(mesh[:-1], mesh[1:]):
        h = beta_next - beta
        k1x, k1r = rhs(beta, xi, record=True)
        k2x, k2r = rhs(beta + 0.5 * h, xi + 0.5 * h * k1r)
        k3x, k3r = rhs(beta + 0.5 * h, xi + 0.5 * h * k2r)
        k4x, k4r = rhs(beta + h, xi + h * k3r)
        x = x + (h / 6.0) * (k1x + 2 * k2x + 2 * k3x + k4x)
        xi = xi + (h / 6.0) * (k1r + 2 * k2r + 2 * k3r + k4r)
    lx, lr = rhs(beta_end, xi, record=True)
    x = x + end_gap * lx
    xi = xi + end_gap * lr
    return BatchSimulation(
        push=x,
        rotation=xi,
        beta_nodes=np.array(rec["beta"]),
        rate=np.array(rec["rate"]),
        rotation_rate=np.array(rec["rrate"]),
        cor=np.array(rec["cor"]),
        mode=np.array(rec["mode"]),
        converged=rec["conv"],
        max_kkt=rec["kkt"],
        solve_time_s=time.perf_counter() - t0,
        evaluations=rec["n"],
    )


def simulate_disk_encounter(
    points,
    weights,
    a: float,
    beta_initial: float,
    mu_c: float,
    step: float = 1e-3,
    method: str = "newton",
    max_steps: int = 200_000,
    tol: SolverTolerances = SOLVER_DEFAULT,
) -> PushSimulation:
    """One disk pushed aside by a point, stepped in x (``step`` in units of a).

    The pusher starts at the origin and moves along +x on y = 0; the disk's CM starts at
    a (cos beta_i, -sin beta_i); ``points`` (k, 2) are its support relative to the CM. The
    contact is the pusher point, the pushed edge the disk's tangent there. Ends when beta
    reaches pi/2 (the disk tangent to the path, contact lost).
    """
    _check_disk(a, beta_initial)
    body = np.asarray(points, dtype=float).reshape(-1, 2)
    wts = np.asarray(weights, dtype=float).reshape(-1)
    h = float(step) * a
    oracle = MotionOracle(body, wts, a, mu_c, method, tol)

    def pusher(x):
        return np.array([x, 0.0])

    def beta_of(x, cm, theta):
        d = pusher(x) - cm  # CM -> pusher = a (-cos beta, sin beta)
        return math.atan2(d[1], -d[0])

    def constrain(cm, theta, x):
        return at_distance(cm, pusher(x), a)

    def twist(x, cm, theta, start=None):
        if start is not None and beta_of(x, cm, theta) >= HALF_PI - ENDING_BETA_GAP:
            return start  # contact is being lost within the step: an Euler step locates it
        d = pusher(x) - cm
        return oracle.twist(cm, theta, pusher(x), math.atan2(d[1], d[0]) + HALF_PI, 0.0)

    def step_once(x, cm, theta):
        return midpoint_step(cm, theta, x, h, twist(x, cm, theta), twist, constrain)

    t0 = time.perf_counter()
    cm0 = a * np.array([math.cos(beta_initial), -math.sin(beta_initial)])
    run = march(cm0, 0.0, h, step_once, beta_of, HALF_PI, max_steps, "the disk was not pushed aside",
                reached_at=HALF_PI - END_BETA_GAP)
    theta, theta_n = run.before[1], run.after[1]
    c = oracle.counts
    return PushSimulation(
        push=run.u_end, rotation=-(theta + run.fraction * (theta_n - theta)), steps=run.steps, step=h,
        beta=run.monitor, x=run.u, modes=dict(c.modes), max_kkt=c.max_kkt, not_optimal=c.not_optimal,
        solve_time_s=time.perf_counter() - t0,
    )
