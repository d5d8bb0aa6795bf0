"""SVG picture of a COR locus, drawn with matplotlib's object-oriented API.

Only ``matplotlib.figure.Figure`` and the SVG canvas are used: no pyplot (global state,
not thread safe) and no Agg. Each call builds and discards its own figure, so concurrent
requests share nothing but matplotlib's font cache.

The view is a square about the centre of mass, equal aspect. It always shows the disk,
the workpiece, the contact and r_min; it shows the whole locus when its tip is within
:data:`MAX_TIP_IN_VIEW` disk radii, and otherwise clips the view and points an arrow
at the tip, labelled with its distance (r_tip reaches 1e14 a when the line of force
nearly passes through the CM).

Far from the origin (relative to the view) everything is drawn relative to the centre
of mass (axes "x - x_cm", "y - y_cm"), and in units of a power of ten when the view is
very small or very large, so that a part of
size 1e-9 at coordinates 1e9 still draws correctly. Lines are clipped to the view here
rather than by matplotlib, so the SVG never holds far-away coordinates.
"""

from __future__ import annotations

import io
import math

import numpy as np
from matplotlib.backends.backend_svg import FigureCanvasSVG
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, FancyArrowPatch
from matplotlib.patches import Polygon as PolygonPatch

from models.locus.cor_disk import DiskCorLocus
from service.convert import PreparedPush
from service.errors import NonFiniteResult

MAX_TIP_IN_VIEW = 6.0
"""Largest r_tip / a for which the whole locus is drawn; beyond it the view is clipped."""
VIEW_MARGIN = 1.15
"""Half-width of the view / distance of the farthest point that must be visible."""
FIGSIZE_IN = 6.4
ORIGIN_SHIFT_RATIO = 1e3
"""Draw relative to the CM when |CM| exceeds this many view half-widths."""
MIN_DRAWABLE_HALF_WIDTH = 1e-300
"""Narrower views (subnormal sizes) have no representable unit 10^k: refused (HTTP 422)."""
PLAIN_UNITS = (1e-3, 1e4)
"""Views of half-width in this range are drawn in the client's units, others in 10^k."""

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


def _clip_polygon_to_box(points: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
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


def _clip_line_to_box(point: np.ndarray, direction: np.ndarray, lo: np.ndarray, hi: np.ndarray):
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


def _title(prep: PreparedPush, locus: DiskCorLocus) -> str:
    a = prep.scene.disk_radius
    head = f"COR locus: a = {a:.4g}, |α·c| = {locus.moment_arm:.4g}"
    if locus.kind == "translation":
        return f"{head}, pure translation (COR at infinity)"
    return f"{head}, sense {locus.sense}"


def _axis_label(name: str, origin: float, unit_exp: int) -> str:
    if origin == 0.0:
        return name if unit_exp == 0 else f"{name} × 1e{-unit_exp}"
    label = f"{name} − ({origin:.6g})"
    return label if unit_exp == 0 else f"({label}) × 1e{-unit_exp}"


def build_figure(prep: PreparedPush, locus: DiskCorLocus) -> Figure:
    """The picture of ``locus`` (computed with every output) on a new SVG-canvas figure."""
    scene = prep.scene
    a_world = scene.disk_radius
    cm_world = np.asarray(scene.center_of_mass, dtype=float)

    # ---- view box: a square about the CM, sized in world units first -----------------
    def rel(point) -> np.ndarray:
        return np.asarray(point, dtype=float) - cm_world

    must_see = [np.array([a_world, a_world]), rel(scene.contact_point)]
    if prep.footprint is not None:
        must_see.extend(rel(prep.footprint.vertices))
    tip_in_view = locus.tip is not None and locus.tip.distance <= MAX_TIP_IN_VIEW * a_world
    if tip_in_view and locus.boundary is not None:
        must_see.extend(rel(locus.boundary))
    if tip_in_view:
        must_see.append(rel(locus.tip.point))
    if locus.tip_line is not None and locus.tip_line.distance <= MAX_TIP_IN_VIEW * a_world:
        must_see.append(rel(locus.tip_line.point))
    half_world, unit_exp, scale, origin = _view_frame(must_see, cm_world)

    def P(point) -> np.ndarray:
        """World point(s) -> drawing coordinates (from ``origin``, in 10^unit_exp)."""
        return (np.asarray(point, dtype=float) - origin) / scale

    a = a_world / scale
    cm = P(cm_world)
    contact = P(scene.contact_point)
    half = half_world / scale
    lo, hi = cm - half, cm + half
    line_lo, line_hi = lo - 0.05 * half, hi + 0.05 * half

    fig = Figure(figsize=(FIGSIZE_IN, FIGSIZE_IN))
    FigureCanvasSVG(fig)
    ax = fig.add_subplot()
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal", adjustable="box")
    ax.grid(True, linewidth=0.3, alpha=0.5)
    handles = []

    def line(point, direction, **style):
        seg = _clip_line_to_box(np.asarray(point, float), np.asarray(direction, float), line_lo, line_hi)
        if seg is None:
            return Line2D([], [], **style)  # legend entry only
        (h,) = ax.plot(seg[:, 0], seg[:, 1], **style)
        return h

    # ---- the locus ------------------------------------------------------------------
    if locus.boundary is not None:
        ring = _clip_polygon_to_box(P(locus.boundary), line_lo, line_hi)
        if len(ring) >= 3:
            patch = PolygonPatch(
                ring, closed=True, facecolor=COLORS["locus_fill"], edgecolor=COLORS["locus_edge"],
                alpha=0.6, linewidth=1.0, label="COR locus", zorder=1,
            )
            ax.add_patch(patch)
            handles.append(patch)

    # ---- workpiece ------------------------------------------------------------------
    disk = Circle(tuple(cm), a, fill=False, edgecolor=COLORS["disk"], linestyle="--", linewidth=1.0,
                  label=f"disk (a = {a_world:.4g})", zorder=2)
    ax.add_patch(disk)
    handles.append(disk)
    if prep.footprint is not None:
        poly = PolygonPatch(P(prep.footprint.vertices), closed=True, facecolor=COLORS["workpiece"],
                            alpha=0.15, edgecolor=COLORS["workpiece"], linewidth=1.2,
                            label="workpiece", zorder=2)
        ax.add_patch(poly)
        handles.append(poly)
    (h,) = ax.plot(*cm, marker="+", color="black", markersize=12, markeredgewidth=1.5,
                   linestyle="none", label="centre of mass", zorder=5)
    handles.append(h)

    # ---- pusher: edge line and line of pushing through the contact -------------------
    edge_dir = np.array([math.cos(scene.edge_angle), math.sin(scene.edge_angle)])
    handles.append(line(contact, edge_dir, color=COLORS["edge"], linewidth=1.2, label="pushed edge", zorder=3))
    p = np.asarray(scene.push_hat, dtype=float)
    line(contact, p, color=COLORS["push"], linewidth=0.8, linestyle=":", zorder=3)
    ax.add_patch(FancyArrowPatch(tuple(contact - 0.6 * a * p), tuple(contact), arrowstyle="-|>",
                                 mutation_scale=14, color=COLORS["push"], linewidth=1.5, zorder=4))
    handles.append(Line2D([], [], color=COLORS["push"], linestyle=":", marker=">",
                          label="line of pushing"))
    (h,) = ax.plot(*contact, marker="o", color=COLORS["push"], markersize=6, linestyle="none",
                   label="contact", zorder=5)
    handles.append(h)

    # ---- tip, tip line, r_min ----------------------------------------------------------
    if locus.tip_line is not None:
        tl = locus.tip_line
        handles.append(line(P(tl.point), tl.direction, color=COLORS["tip"], linewidth=0.8,
                            linestyle="-.", label="tip line", zorder=3))
    if locus.tip is not None:
        if tip_in_view:
            (h,) = ax.plot(*P(locus.tip.point), marker="^", color=COLORS["tip"], markersize=8,
                           linestyle="none", label=f"tip (r_tip = {locus.tip.distance:.4g})", zorder=6)
            handles.append(h)
        else:
            axis = np.asarray(locus.axis, dtype=float)
            reach = half / max(abs(axis[0]), abs(axis[1]))  # distance to the view's edge
            start, end = cm + 0.55 * reach * axis, cm + 0.95 * reach * axis
            ax.add_patch(FancyArrowPatch(tuple(start), tuple(end), arrowstyle="-|>", mutation_scale=16,
                                         color=COLORS["tip"], linewidth=1.5, zorder=6))
            ax.annotate(f"tip off picture\nr_tip = {locus.tip.distance:.4g}", xy=tuple(start),
                        ha="center", va="center", fontsize=8, color=COLORS["tip"], zorder=7,
                        bbox=dict(boxstyle="round", facecolor="white", alpha=0.8, linewidth=0.5))
            handles.append(Line2D([], [], color=COLORS["tip"], marker=">",
                                  label=f"to tip (r_tip = {locus.tip.distance:.4g})"))
    if locus.r_min is not None:
        (h,) = ax.plot(*P(locus.r_min.point), marker="s", color=COLORS["r_min"], markersize=6,
                       linestyle="none", label=f"r_min = {locus.r_min.distance:.4g}", zorder=6)
        handles.append(h)
    if locus.kind == "translation":
        d = np.asarray(locus.translation_direction, dtype=float)
        ax.add_patch(FancyArrowPatch(tuple(cm), tuple(cm + 0.8 * a * d), arrowstyle="-|>",
                                     mutation_scale=18, color=COLORS["tip"], linewidth=2.0, zorder=6))
        handles.append(Line2D([], [], color=COLORS["tip"], marker=">", linewidth=2.0,
                              label="pure translation"))

    ax.set_title(_title(prep, locus), fontsize=10)
    ax.set_xlabel(_axis_label("x", float(origin[0]), unit_exp))
    ax.set_ylabel(_axis_label("y", float(origin[1]), unit_exp))
    ax.legend(handles=handles, loc="upper left", fontsize=7, framealpha=0.85)
    fig.tight_layout()
    return fig


def _view_frame(must_see, cm_world: np.ndarray) -> tuple[float, int, float, np.ndarray]:
    """Half-width of the view (world units) around the CM holding every point of
    ``must_see`` (offsets from the CM), the drawing unit 10^unit_exp -- the client's own
    unless the view is very small or very large -- its scale, and the drawing origin: the
    world's, unless the CM is so far away relative to the view that plotting world
    coordinates would lose precision; then the CM."""
    half_world = VIEW_MARGIN * max(float(np.max(np.abs(p))) for p in must_see)
    if not half_world >= MIN_DRAWABLE_HALF_WIDTH:
        raise NonFiniteResult("the picture's scale (a view narrower than 1e-300)")
    unit_exp = 0
    if not PLAIN_UNITS[0] <= half_world <= PLAIN_UNITS[1]:
        unit_exp = int(math.floor(math.log10(half_world)))
    scale = 10.0**unit_exp
    far = float(np.max(np.abs(cm_world))) > ORIGIN_SHIFT_RATIO * half_world
    origin = cm_world if far else np.zeros(2)
    return half_world, unit_exp, scale, origin


def render_locus_svg(prep: PreparedPush, locus: DiskCorLocus) -> bytes:
    """The picture of ``locus`` as SVG bytes (text drawn as paths, no external fonts)."""
    fig = build_figure(prep, locus)
    buf = io.BytesIO()
    fig.savefig(buf, format="svg", metadata={"Title": _title(prep, locus), "Date": None})
    return buf.getvalue()
