"""What the SVG pictures share: figure setup, the view frame, clipping and colours.

Only ``matplotlib.figure.Figure`` and the SVG canvas are used: no pyplot (global state,
not thread safe) and no Agg. Each picture builds and discards its own figure, so
concurrent requests share nothing but matplotlib's font cache.

Far from the origin (relative to the view) a picture is drawn relative to a centre (axes
"x - x_cm", "y - y_cm"), and in units of a power of ten when the view is very small or
very large (:func:`view_frame`), so that a part of size 1e-9 at coordinates 1e9 still
draws correctly. Lines are clipped to the view here rather than by matplotlib
(:func:`clip_polygon_to_box`, :func:`clip_line_to_box`), so the SVG never holds far-away
coordinates.
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass

import matplotlib
import numpy as np
from matplotlib.backends.backend_svg import FigureCanvasSVG
from matplotlib.figure import Figure

from service.errors import NonFiniteResult

VIEW_MARGIN = 1.15
"""Half-width of the view / distance of the farthest point that must be visible."""
FIGSIZE_IN = 6.4
"""Height (and, for a single square panel, width) of a picture, inches."""
ORIGIN_SHIFT_RATIO = 1e3
"""Draw relative to the centre when |centre| exceeds this many view half-widths."""
MIN_DRAWABLE_HALF_WIDTH = 1e-300
"""Narrower views (subnormal sizes) have no representable unit 10^k: refused (HTTP 422)."""
PLAIN_UNITS = (1e-3, 1e4)
"""Views of half-width in this range are drawn in the client's units, others in 10^k."""
LINE_MARGIN_REL = 0.05
"""Lines and polygons are clipped to the view widened by this fraction of its half-width
(so that they run off the picture's edge instead of stopping at it)."""

COLORS = {
    "disk": "#555555",
    "workpiece": "#1f5fa8",
    "locus_fill": "#f6c98e",
    "locus_edge": "#d07a12",
    "edge": "#2a9d3c",
    "push": "#c0392b",
    "tip": "#7b1fa2",
    "r_min": "#00838f",
}
"""The colours of the COR locus picture; the other pictures take theirs from these."""


def new_figure(width_in: float, height_in: float) -> Figure:
    """A new figure on its own SVG canvas."""
    fig = Figure(figsize=(width_in, height_in))
    FigureCanvasSVG(fig)
    return fig


SVG_HASH_SALT = "peshkin-service"
"""Salt of the ids matplotlib gives clip paths in an SVG: fixed, so that one request always
draws the same bytes (set once at import, never changed per request)."""
matplotlib.rcParams["svg.hashsalt"] = SVG_HASH_SALT


def svg_bytes(fig: Figure, title: str) -> bytes:
    """The figure as SVG bytes (text drawn as paths, no external fonts, no date)."""
    buf = io.BytesIO()
    fig.savefig(buf, format="svg", metadata={"Title": title, "Date": None})
    return buf.getvalue()


def clip_polygon_to_box(points: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Sutherland-Hodgman clip of a closed polygon (N, 2) to the box [lo, hi]; keeps far
    away vertices (up to 1e14 a) out of the SVG. Vectorised per box side."""
    poly = np.asarray(points, dtype=float)
    for axis in (0, 1):
        for bound, keep_le in ((hi[axis], True), (lo[axis], False)):
            if len(poly) == 0:
                return poly
            nxt = np.roll(poly, -1, axis=0)
            inside = poly[:, axis] <= bound if keep_le else poly[:, axis] >= bound
            inside_next = np.roll(inside, -1)
            crossing = inside != inside_next
            denom = nxt[:, axis] - poly[:, axis]
            t = np.where(crossing, (bound - poly[:, axis]) / np.where(crossing, denom, 1.0), 0.0)
            cross_pt = poly + t[:, None] * (nxt - poly)
            cross_pt[:, axis] = bound
            # Emit, for each edge p -> q: p if inside, then the crossing if the edge crosses.
            pieces = np.stack([poly, cross_pt], axis=1)  # (N, 2, 2)
            mask = np.stack([inside, crossing], axis=1)  # (N, 2)
            poly = pieces[mask]
    return poly


def clip_line_to_box(point: np.ndarray, direction: np.ndarray, lo: np.ndarray, hi: np.ndarray):
    """The segment of the line point + t direction inside the box [lo, hi] (Liang-Barsky),
    or None when the line misses the box."""
    t0, t1 = -math.inf, math.inf
    for k in (0, 1):
        d = float(direction[k])
        if d == 0.0:
            if not lo[k] <= point[k] <= hi[k]:
                return None
            continue
        ta, tb = (lo[k] - point[k]) / d, (hi[k] - point[k]) / d
        t0, t1 = max(t0, min(ta, tb)), min(t1, max(ta, tb))
    if not t0 < t1:
        return None
    return np.vstack([point + t0 * direction, point + t1 * direction])


def axis_label(name: str, origin: float, unit_exp: int) -> str:
    """The label of an axis drawn from ``origin`` in units of 10^unit_exp."""
    if origin == 0.0:
        return name if unit_exp == 0 else f"{name} × 1e{-unit_exp}"
    label = f"{name} − ({origin:.6g})"
    return label if unit_exp == 0 else f"({label}) × 1e{-unit_exp}"


def view_frame(must_see, centre_world: np.ndarray) -> tuple[float, int, float, np.ndarray]:
    """Half-width of the view (world units) around ``centre_world`` holding every point of
    ``must_see`` (offsets from the centre), the drawing unit 10^unit_exp -- the client's own
    unless the view is very small or very large -- its scale, and the drawing origin: the
    world's, unless the centre is so far away relative to the view that plotting world
    coordinates would lose precision; then the centre."""
    half_world = VIEW_MARGIN * max(float(np.max(np.abs(p))) for p in must_see)
    if not half_world >= MIN_DRAWABLE_HALF_WIDTH:
        raise NonFiniteResult("the picture's scale (a view narrower than 1e-300)")
    unit_exp = 0
    if not PLAIN_UNITS[0] <= half_world <= PLAIN_UNITS[1]:
        unit_exp = int(math.floor(math.log10(half_world)))
    scale = 10.0**unit_exp
    far = float(np.max(np.abs(centre_world))) > ORIGIN_SHIFT_RATIO * half_world
    origin = centre_world if far else np.zeros(2)
    return half_world, unit_exp, scale, origin


@dataclass(frozen=True)
class SquareView:
    """A square view of half-width ``half_world`` (world units) about ``centre_world``,
    drawn from ``origin`` in units of ``scale`` = 10^``unit_exp`` (:func:`view_frame`).
    The properties are in drawing coordinates."""

    centre_world: np.ndarray
    half_world: float
    unit_exp: int
    scale: float
    origin: np.ndarray

    @classmethod
    def around(cls, must_see, centre_world) -> SquareView:
        """The view about ``centre_world`` holding every point of ``must_see`` (offsets
        from the centre, world units)."""
        centre = np.asarray(centre_world, dtype=float)
        half_world, unit_exp, scale, origin = view_frame(must_see, centre)
        return cls(centre, half_world, unit_exp, scale, origin)

    def to_drawing(self, points) -> np.ndarray:
        """World point(s) -> drawing coordinates."""
        return (np.asarray(points, dtype=float) - self.origin) / self.scale

    @property
    def centre(self) -> np.ndarray:
        return self.to_drawing(self.centre_world)

    @property
    def half(self) -> float:
        return self.half_world / self.scale

    @property
    def lo(self) -> np.ndarray:
        return self.centre - self.half

    @property
    def hi(self) -> np.ndarray:
        return self.centre + self.half

    @property
    def clip_box(self) -> tuple[np.ndarray, np.ndarray]:
        """The box lines and polygons are clipped to (:data:`LINE_MARGIN_REL`)."""
        margin = LINE_MARGIN_REL * self.half
        return self.lo - margin, self.hi + margin

    def frame(self, ax) -> None:
        """Limits, equal aspect, grid and axis labels of ``ax`` for this view."""
        lo, hi = self.lo, self.hi
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_aspect("equal", adjustable="box")
        ax.grid(True, linewidth=0.3, alpha=0.5)
        ax.set_xlabel(axis_label("x", float(self.origin[0]), self.unit_exp))
        ax.set_ylabel(axis_label("y", float(self.origin[1]), self.unit_exp))
