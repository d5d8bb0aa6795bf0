"""Contacts of a simulated push (solver/sim/contacts.py; book 3.4, 4.3-4.5): the contact
search finds every dip deeper than the graze depth at any sampling (against the closed-form
crossing of a line and a circle), re-imposed contacts satisfy their constraint exactly, the
regula falsi finds an event's root, and the crossing fraction interpolates linearly."""

from __future__ import annotations

import math

import numpy as np
import pytest

from solver.sim.contacts import at_distance, crossing_fraction, first_dip, gap_to_disk, onto_line, regula_falsi
from solver.spiral import simulate as ss

A = 1.0


def cross(u, v) -> float:
    return float(u[0] * v[1] - u[1] * v[0])


@pytest.mark.parametrize("depth", [1e-3, 5e-9])
def test_contact_search_finds_shallow_dips_at_any_sampling(depth):
    """The pusher runs along y = 0 past a disk whose top is ``depth`` above the line; the
    sampling step (5 a) is far wider than the dip (2 sqrt(2 a depth) ~ 1e-4 a)."""
    path = ss.polyline_path([[-20.0, 0.0], [20.0, 0.0]], centre=(0.0, -1e6))
    cm = np.array([0.37, -(A - depth)])
    s = ss.SpiralSimSettings(sample=5.0)
    u, _ = first_dip(path, cm, A, 0.0, s.sample, s.graze_depth, s.root_tol, s.max_bisections)
    expect = 20.0 + 0.37 - math.sqrt(A * A - (A - depth) ** 2)
    assert u == pytest.approx(expect, abs=1e-9)
    # Shallower than the graze depth: a touch, not a contact.
    shallow = np.array([0.37, -(A - 0.5 * s.graze_depth * A)])
    assert first_dip(path, shallow, A, 0.0, s.sample, s.graze_depth, s.root_tol, s.max_bisections)[0] is None


def test_re_imposed_contacts_hold_exactly():
    """A vertex put back on a fence line lies on it; a disk put back at its radius from the
    pusher point lies at that distance, along the old line of centres (4.3, 4.4)."""
    rng = np.random.default_rng(7)
    for _ in range(20):
        cm, vertex = rng.normal(size=2), rng.normal(size=2)
        ang = rng.uniform(0, 2 * math.pi)
        n = np.array([math.cos(ang), math.sin(ang)])
        level = float(rng.normal())
        moved = onto_line(cm, vertex, n, level)
        assert float(n @ (vertex + moved - cm)) == pytest.approx(level, abs=1e-14)
        assert abs(cross(moved - cm, n)) < 1e-14  # moved along the normal
        pusher = rng.normal(size=2)
        kept = at_distance(cm, pusher, 2.5)
        assert np.hypot(*(kept - pusher)) == pytest.approx(2.5, rel=1e-15)
        assert abs(cross(kept - pusher, cm - pusher)) < 1e-12


def test_regula_falsi_and_crossing_fraction():
    """The Illinois iteration finds the root of a convex event within its tolerance and
    returns the last trial's payload; linear interpolation places a level in a step."""
    calls = []

    def trial(h):
        calls.append(h)
        return 1.0 - h * h, ("payload", h)

    h, payload = regula_falsi(trial, 0.0, 1.0, 3.0, -8.0, 1e-12, 60)
    assert h == pytest.approx(1.0, abs=1e-12) and payload == ("payload", h) and len(calls) < 60
    assert crossing_fraction(0.2, 0.6, 0.5) == pytest.approx(0.75)


def test_gap_to_disk_is_signed():
    path = ss.polyline_path([[-2.0, 0.0], [2.0, 0.0]])
    assert float(gap_to_disk(path, np.array([0.0, 0.5]), A, 2.0)) == pytest.approx(-0.5)
    assert float(gap_to_disk(path, np.array([0.0, 3.0]), A, 2.0)) == pytest.approx(2.0)
