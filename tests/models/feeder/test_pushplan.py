"""The frictionless push baseline (models/feeder/pushplan.py; Goldberg 1993) against an
independent computation: the radius function descended numerically, orientation by
orientation, through each plan."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.feeder.arcs import TWO_PI
from models.feeder.design_graph import rotational_symmetry
from models.feeder.fence import feeder_part
from models.feeder.pushplan import PushFunction, plan_pushes
from tests.feeder_cases import PARTS, part

STEP = 2e-4
"""Radians per step of the numerical descent of the radius function."""


def descend(hull: np.ndarray, omega: np.ndarray) -> np.ndarray:
    """Each omega moved downhill on r(omega) = max_k v_k . u(omega) in steps of STEP until
    r rises both ways (a frictionless push turns the part toward the nearer minimum)."""
    omega = omega.copy()

    def r(w):
        return np.max(hull[None, :, 0] * np.cos(w)[:, None] + hull[None, :, 1] * np.sin(w)[:, None], axis=1)

    for _ in range(int(2 * math.pi / STEP) + 10):
        here, up, down = r(omega), r(omega + STEP), r(omega - STEP)
        move = np.where(up < here, 1.0, np.where(down < here, -1.0, 0.0))
        if not move.any():
            break
        omega += STEP * move
    return omega


def same_direction(a: np.ndarray, b: np.ndarray, tol: float) -> np.ndarray:
    return np.abs(np.remainder(a - b + math.pi, TWO_PI) - math.pi) <= tol


@pytest.mark.parametrize("name", sorted(PARTS))
def test_the_push_function_is_the_descent_of_the_radius_function(name):
    p = part(name)
    pf = PushFunction.of(p)
    omega = np.random.default_rng(93).uniform(0.0, TWO_PI, 300)
    # within a descent step of a maximum the numerical descent may fall either way
    far = np.array([min(abs(math.remainder(w - mx, TWO_PI)) for mx in pf.maxima) > 2 * STEP for w in omega])
    omega = omega[far]
    assert len(omega) > 290
    got = np.array([pf.stable[pf.index_of(float(w))] for w in omega])
    assert np.all(same_direction(descend(p.hull, omega), got, 2 * STEP))


@pytest.mark.parametrize("name", sorted(PARTS))
def test_every_orientation_ends_where_the_plan_says(name):
    """Random orientations pushed through the plan by the numerical descent all end in its
    final directions (up to the part's symmetry); every part here has a plan."""
    p = part(name)
    pf = PushFunction.of(p)
    plan = plan_pushes(p)
    assert plan.alphas is not None and plan.depth_proven == len(plan.alphas)
    omega = descend(p.hull, np.random.default_rng(94).uniform(0.0, TWO_PI, 300))  # the first push
    for alpha in plan.alphas:
        omega = descend(p.hull, omega + alpha)
    k = rotational_symmetry(p)
    finals = np.array([pf.stable[s] for s in plan.final])
    ok = np.zeros(len(omega), dtype=bool)
    for f in finals:
        for i in range(k):
            ok |= same_direction(omega, np.full_like(omega, f + i * TWO_PI / k), 4 * STEP)
    assert ok.all()


def test_known_plans_a_square_needs_one_push_a_rectangle_two():
    """A square is oriented (up to its quarter-turn symmetry) by any push; a rectangle's
    first push leaves a long or a short edge on the pusher, and a second push turned by
    45 degrees (within its tolerance) brings the long one."""
    assert plan_pushes(part("square")).alphas == ()
    rect = plan_pushes(part("rectangle"))
    assert rect.alphas is not None and len(rect.alphas) == 1
    assert abs(math.remainder(rect.alphas[0], math.pi / 2)) == pytest.approx(math.pi / 4, abs=rect.tolerance)
    tri = feeder_part([[0, 0], [1, 0], [0.5, math.sqrt(3) / 2]], [0.5, math.sqrt(3) / 6])
    assert plan_pushes(tri).alphas == ()  # an equilateral triangle: symmetry of order 3


def regular_64_gon_off_centre():
    """Issue 25: a regular 64-gon with its centre of mass at (0.01, 0); its third push takes
    over a minute to search (each state has thousands of classes of turns)."""
    return feeder_part([(math.cos(2 * math.pi * i / 64), math.sin(2 * math.pi * i / 64)) for i in range(64)],
                       (0.01, 0.0))


def test_the_search_stops_within_a_class_of_turns_once_told_and_says_it_was_cut():
    asked = 0

    def expired() -> bool:  # a work limit, not a clock: the 50th question ends the search
        nonlocal asked
        asked += 1
        return asked >= 50

    plan = plan_pushes(regular_64_gon_off_centre(), max_pushes=8, expired=expired)
    assert asked == 50 and not plan.complete and plan.alphas is None and plan.depth_proven <= 1
    square = plan_pushes(part("square"), expired=lambda: False)
    assert square.complete and square.alphas == ()
