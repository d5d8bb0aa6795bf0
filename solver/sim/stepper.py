"""Stepping a pushed part: the instantaneous motion from the forward minimum-power solver
(book 3.7, 4.1) and a midpoint scheme on the pose, with the contact re-imposed after every
(half) step; a march to an event. A scenario (a fence aligning a part, a point pushing a
disk aside, a spiral herding a disk; next, a part meeting the fences of a belt) supplies

* the contact at a pose (:class:`MotionOracle.twist`: contact point, the pushed edge's
  angle, the push direction);
* the re-imposition of the contact (``constrain``, from :mod:`solver.sim.contacts`);
* the quantity whose crossing ends the motion (``monitor``, for :func:`march`) or its own
  event location (:func:`solver.sim.contacts.regula_falsi`).

:class:`SolveCounts` says what ran: forward solves, their modes, the largest KKT residual,
the solves that were not optimal, the largest angle of the contact force from the normal.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from models.core.scene import PushScene
from models.core.support import Support
from solver.core.budget import UNLIMITED, Budget
from solver.core.errors import NotConverged
from solver.core.tolerances import SOLVER_DEFAULT, SolverTolerances
from solver.motion.forward import ForwardResult, solve_forward
from solver.sim.contacts import crossing_fraction
from solver.sim.kinematics import Twist, advance, body_to_world

Constrain = Callable[[np.ndarray, float, float], np.ndarray]
"""(cm, theta, u) -> cm with the contact re-imposed at parameter u."""

TwistAt = Callable[[float, np.ndarray, float, Twist], Twist]
"""(u, cm, theta, twist at the step's start) -> the twist at that pose (the midpoint's)."""


@dataclass
class SolveCounts:
    """What the forward solves of a run did (the run reports it; nothing is counted that did
    not run)."""

    solves: int = 0
    not_optimal: int = 0
    modes: Counter[str] = field(default_factory=Counter)
    max_kkt: float = 0.0
    max_force_angle: float = 0.0

    def record(self, res: ForwardResult, scene: PushScene) -> None:
        self.record_values(res.mode, res.kkt_residual, res.status == "optimal", res.contact_force, scene)

    def record_values(self, mode: str, kkt: float, optimal: bool, force: np.ndarray, scene: PushScene) -> None:
        """One solve's mode, KKT residual, whether it was optimal, and its contact force (a
        single solve, or one row of a batched one)."""
        self.solves += 1
        self.modes[mode] += 1
        self.max_kkt = max(self.max_kkt, float(kkt))
        self.not_optimal += not optimal
        fn = float(force @ scene.normal)
        ft = float(force @ scene.alpha_hat)
        self.max_force_angle = max(self.max_force_angle, math.atan2(abs(ft), fn))


class MotionOracle:
    """The motion per unit push of a part with a known support (``body_points`` (k, 2)
    relative to the CM in the body frame, ``weights``) in a disk of radius ``a``, pushed
    with contact friction ``mu_c``: the forward solve at each pose (3.7, 4.1), counted in
    ``counts``. The budget is checked before every solve (TimeLimitReached)."""

    def __init__(self, body_points: np.ndarray, weights: np.ndarray, a: float, mu_c: float,
                 method: str = "newton", tol: SolverTolerances = SOLVER_DEFAULT, budget: Budget = UNLIMITED):
        self.body = np.asarray(body_points, dtype=float).reshape(-1, 2)
        self.weights = np.asarray(weights, dtype=float).reshape(-1)
        self.a, self.mu_c, self.method, self.tol, self.budget = a, mu_c, method, tol, budget
        self.counts = SolveCounts()

    def solve(self, cm: np.ndarray, theta: float, contact: np.ndarray, edge_angle: float,
              push_direction: float) -> tuple[ForwardResult, PushScene]:
        """The forward solve at the pose, with the pushed edge at ``edge_angle`` and the
        push along ``push_direction`` (radians, world)."""
        self.budget.checkpoint("a forward solve")
        scene = PushScene.create(self.a, contact, edge_angle, push_direction, cm)
        support = Support.create(body_to_world(cm, theta, self.body), self.weights, cm, self.tol)
        res = solve_forward(scene, support, self.mu_c, method=self.method, tol=self.tol)
        self.counts.record(res, scene)
        return res, scene

    def twist(self, cm: np.ndarray, theta: float, contact: np.ndarray, edge_angle: float,
              push_direction: float) -> Twist:
        res, _ = self.solve(cm, theta, contact, edge_angle, push_direction)
        return Twist(res.velocity_cm, res.omega, cm.copy())


def midpoint_step(cm: np.ndarray, theta: float, u: float, h: float, start: Twist, twist_at: TwistAt,
                  constrain: Constrain) -> tuple[np.ndarray, float]:
    """One midpoint (RK2) step of length h in the push parameter u: half a step with the
    twist at the start, the contact re-imposed, the twist there, the full step with it from
    the start, the contact re-imposed (error O(h^2) per unit push)."""
    c_h, th_h = advance(cm, theta, start, 0.5 * h)
    c_h = constrain(c_h, th_h, u + 0.5 * h)
    mid = twist_at(u + 0.5 * h, c_h, th_h, start)
    c_n, th_n = advance(cm, theta, mid, h)
    return constrain(c_n, th_n, u + h), th_n


@dataclass(frozen=True)
class March:
    """A motion stepped until its monitor reached the target: ``u_end`` where it did
    (interpolated inside the last step), ``fraction`` of the last step taken, the poses at
    the last step's start and end, ``steps``, and the trajectory ``u``, ``monitor`` at
    every step end (the last entry is the target at ``u_end``)."""

    u_end: float
    fraction: float
    before: tuple[np.ndarray, float]
    after: tuple[np.ndarray, float]
    steps: int
    u: np.ndarray
    monitor: np.ndarray


def march(cm: np.ndarray, theta: float, h: float, step: Callable[[float, np.ndarray, float], tuple[np.ndarray, float]],
          monitor: Callable[[float, np.ndarray, float], float], target: float, max_steps: int,
          what: str, reached_at: float | None = None) -> March:
    """Step (``step(u, cm, theta)`` -> the pose after a step of h) from u = 0 until
    ``monitor(u, cm, theta)`` (increasing) reaches ``reached_at`` (default ``target``); the
    crossing of ``target`` is placed by :func:`solver.sim.contacts.crossing_fraction`.
    NotConverged after ``max_steps`` steps (``what`` names the event)."""
    reached = target if reached_at is None else reached_at
    u = 0.0
    value = monitor(u, cm, theta)
    us, values = [u], [value]
    for k in range(1, max_steps + 1):
        cm_n, th_n = step(u, cm, theta)
        value_n = monitor(u + h, cm_n, th_n)
        if value_n >= reached:
            frac = crossing_fraction(value, value_n, target)
            us.append(u + frac * h)
            values.append(target)
            return March(u + frac * h, frac, (cm, theta), (cm_n, th_n), k, np.array(us), np.array(values))
        cm, theta, u, value = cm_n, th_n, u + h, value_n
        us.append(u)
        values.append(value)
    raise NotConverged(f"{what} within {max_steps} steps")
