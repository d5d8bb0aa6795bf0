"""Stepping a pushed part (solver/sim/stepper.py): the midpoint scheme is second order on a
constrained motion with a known answer, the march places its event by interpolation and
gives up after its step cap, and the motion oracle counts what ran and stops at its budget
(a work limit, tests/budgets.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.support import random_balanced_tripods
from solver.core.errors import NotConverged, TimeLimitReached
from solver.sim.contacts import at_distance
from solver.sim.kinematics import Twist
from solver.sim.stepper import MotionOracle, march, midpoint_step
from tests.budgets import checks_budget
from tests.scenes import SEED


def _circle_run(h):
    """A point kept at distance 1 from the origin and pushed along its tangent: it moves on
    the unit circle at unit speed; after travel 1 it is at angle 1 exactly."""

    def twist(u, cm, theta, start=None):
        t = np.array([-cm[1], cm[0]])
        return Twist(t / np.hypot(*t), 0.0, cm.copy())

    def constrain(cm, theta, u):
        return at_distance(cm, np.zeros(2), 1.0)

    cm, th = np.array([1.0, 0.0]), 0.0
    n = int(round(1.0 / h))
    for k in range(n):
        cm, th = midpoint_step(cm, th, k * h, h, twist(k * h, cm, th), twist, constrain)
    return math.atan2(cm[1], cm[0])


def test_midpoint_steps_with_the_constraint_converge():
    errs = [abs(_circle_run(h) - 1.0) for h in (0.1, 0.05, 0.025)]
    assert errs[0] > errs[1] > errs[2] and errs[2] < 1e-4


def test_march_places_the_event_and_gives_up_at_its_cap():
    def step(u, cm, theta):
        return cm + np.array([0.1, 0.0]), theta

    def monitor(u, cm, theta):
        return float(cm[0])

    run = march(np.zeros(2), 0.0, 0.1, step, monitor, 0.35, 100, "x did not reach 0.35")
    assert run.steps == 4 and run.u_end == pytest.approx(0.35) and run.fraction == pytest.approx(0.5)
    assert run.monitor[-1] == 0.35 and run.u[-1] == pytest.approx(0.35) and len(run.u) == 5
    with pytest.raises(NotConverged, match="x did not reach 5 within 10 steps"):
        march(np.zeros(2), 0.0, 0.1, step, monitor, 5.0, 10, "x did not reach 5")


def test_the_oracle_counts_solves_and_stops_at_its_budget():
    pts, wts = random_balanced_tripods(np.random.default_rng(SEED), 1, 1.0)
    oracle = MotionOracle(pts[0], wts[0], 1.0, 0.3, budget=checks_budget(2))
    cm = np.zeros(2)
    for _ in range(2):
        tw = oracle.twist(cm, 0.0, np.array([-0.9, 0.2]), math.pi / 2, 0.0)
    assert oracle.counts.solves == 2 and sum(oracle.counts.modes.values()) == 2
    assert oracle.counts.not_optimal == 0 and oracle.counts.max_kkt < 1e-9 and tw.omega != 0.0
    assert 0.0 <= oracle.counts.max_force_angle <= math.atan(0.3) + 1e-9
    with pytest.raises(TimeLimitReached):
        oracle.twist(cm, 0.0, np.array([-0.9, 0.2]), math.pi / 2, 0.0)
    assert oracle.counts.solves == 2  # the refused solve is not counted
