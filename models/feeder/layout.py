"""A feeder's fences placed on a real belt (book 1.8.6, 5.4, figure 1-9): where each fence
hangs, how long it is, and how far it reaches beyond the point where the part meets it.

World frame as in models/feeder/fence.py: the belt, of width W, runs in -y between the
sides x = -W/2 and x = +W/2. A fence at angle gamma hangs from the side sgn(gamma) W/2 (its
root) and runs down the belt, along -sgn(gamma) (cos gamma, sin gamma), across W - g, where
the gap g at its free end E lets the part pass (g = part diameter 2a plus ``clearance``);
its length is (W - g) / cos gamma and it drops (W - g) tan |gamma| along the belt. The next
fence's root lies ``spacing`` below the previous free end.

Reach (phase 6 of models/feeder/fence.py). A part leaves a fence at its free end, its CM
within a of E's x; it meets the next fence where that fence crosses its path, somewhere
within 2a of that x (the hull's extent either way). The reach is the distance along the
next fence from the least favourable such point to its free end. Fences that alternate
sides catch the part near their root (a long reach); a fence on the same side as the one
before catches it near its own free end (a short reach: the map then bounds little). The
first fence sees parts arriving in the lane ``entry_x`` (their CM's x, default a from the
first fence's root side).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from models.core.errors import InvalidInput


@dataclass(frozen=True)
class PlacedFence:
    """One fence on the belt: its angle and side, root and free end (world), length, the
    reach beyond the part's least favourable first contact (0 when the part may arrive past
    its end), and, when a design placed it, the reach its arriving orientations need (part
    units; None otherwise)."""

    angle: float
    side: str
    root: np.ndarray
    end: np.ndarray
    length: float
    reach: float
    reach_needed: float | None = None


@dataclass(frozen=True)
class BeltLayout:
    """The fences placed, the belt's width, the gap at each free end, and the lane (x of
    the CM) in which parts arrive at the first fence."""

    belt_width: float
    gap: float
    fences: tuple[PlacedFence, ...]
    entry_x: float

    @property
    def belt_length(self) -> float:
        """From the first fence's root to the last fence's free end, along the belt."""
        if not self.fences:
            return 0.0
        return float(self.fences[0].root[1] - self.fences[-1].end[1])


def reach_from(angle: float, end_x: float, x_lo: float, x_hi: float) -> float:
    """Distance along a fence at ``angle`` with free end at x = end_x from the least
    favourable first contact at x in [x_lo, x_hi] to the end (0 if it may lie past it)."""
    sign = 1.0 if angle > 0.0 else -1.0
    # the fence runs from its root toward -sign in x: points past the end have (x - end_x) * sign < 0
    nearest = min((x - end_x) * sign for x in (x_lo, x_hi))
    return max(nearest, 0.0) / math.cos(angle)


CLEARANCE_RADII = 0.1
"""The default extra gap at a fence's free end, in part radii."""
SPACING_RADII = 2.0
"""The default spacing from a fence's free end to the next root, in part radii."""


def check_belt(part_radius: float, belt_width: float, clearance: float, spacing: float,
               entry_x: float | None = None) -> None:
    """Refuse a belt the fences cannot be placed on: too narrow for the part to pass a free
    end, a negative or non-finite spacing or clearance, a lane off the belt."""
    gap = 2.0 * float(part_radius) + float(clearance)
    if not (math.isfinite(belt_width) and belt_width > gap):
        raise InvalidInput("belt_width", f"must exceed the part's diameter plus the clearance ({gap:.6g})")
    if not (math.isfinite(spacing) and spacing >= 0.0) or not (math.isfinite(clearance) and clearance >= 0.0):
        raise InvalidInput("spacing", "spacing and clearance must be finite and >= 0")
    if entry_x is not None and not abs(entry_x) <= 0.5 * belt_width:
        raise InvalidInput("entry_x", "must lie on the belt, |entry_x| <= width / 2")


def lay_out(angles: Sequence[float], part_radius: float, belt_width: float, clearance: float,
            spacing: float, entry_x: float | None = None) -> BeltLayout:
    """Place the fences (module docstring)."""
    check_belt(part_radius, belt_width, clearance, spacing, entry_x)
    a = float(part_radius)
    w = float(belt_width)
    gap = 2.0 * a + float(clearance)
    placed: list[PlacedFence] = []
    y = 0.0
    across = w - gap
    prev_end_x = None
    lane = math.nan
    for gamma in angles:
        sign = 1.0 if gamma > 0.0 else -1.0
        root = np.array([sign * 0.5 * w, y])
        end = root + np.array([-sign * across, -across * math.tan(abs(gamma))])
        if prev_end_x is None:
            lane = (sign * (0.5 * w - a)) if entry_x is None else float(entry_x)
            x_lo, x_hi = lane - a, lane + a  # the hull's extent about the lane
        else:
            x_lo, x_hi = prev_end_x - 2.0 * a, prev_end_x + 2.0 * a
        placed.append(PlacedFence(float(gamma), "right" if sign > 0 else "left", root, end,
                                  across / math.cos(gamma), reach_from(float(gamma), float(end[0]), x_lo, x_hi)))
        prev_end_x = float(end[0])
        y = float(end[1]) - spacing
    return BeltLayout(w, gap, tuple(placed), lane)
