"""SVG picture of a COR sketch (book 4.1, figure 4-3), matplotlib object API only.

As in :mod:`service.common.svg`: no pyplot, one throw-away ``Figure`` on an SVG canvas per
call; a square view about the centre of mass with equal aspect; drawn relative to the CM
and in units of 10^k when the coordinates demand it; polygons and lines clipped to the
view here, so the SVG never holds far-away coordinates (loci reach 1e14 a when a force
line nearly passes through the CM).

What is drawn (the book's conventions): the disk (and the polygon, if one was given), the
CM, the contact with the push arrow and the friction cone, the sticking line and the edge
normal line through the contact, the two elementary loci {COR}_(alpha+-nu) in outline, the
down- and up-slipping loci shaded in two colours, the sticking locus bold, the tip line
dashed with its estimate of the sticking locus's far end; a legend, and the sketch letter
in the title. Parts farther than :data:`MAX_IN_VIEW` disk radii do not widen the view;
their extent is given in the legend.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, FancyArrowPatch, Wedge
from matplotlib.patches import Polygon as PolygonPatch

from models.locus.cor_disk import TipLine
from models.sketch.disk_sketch import CorSketch
from service.api.sketch.convert import IMPLICATION_TEXT, is_translation
from service.common.scene import PreparedPush
from service.common.svg import (
    FIGSIZE_IN,
    SquareView,
    clip_line_to_box,
    clip_polygon_to_box,
    new_figure,
    svg_bytes,
)

MAX_IN_VIEW = 6.0
"""Points farther than this many disk radii from the CM do not widen the view."""
LEGEND_WIDTH_IN = 3.0
"""Extra figure width for the legend, right of the picture."""
CONE_RADIUS_REL = 0.55
"""Length of the friction cone's sides, in disk radii."""

COLORS = {
    "disk": "#555555",
    "workpiece": "#1f5fa8",
    "plus": "#d07a12",
    "minus": "#7b1fa2",
    "down": "#2e86de",
    "up": "#e74c3c",
    "sticking": "#111111",
    "sticking_line": "#888888",
    "normal": "#2a9d3c",
    "cone": "#f1c40f",
    "push": "#c0392b",
    "tip_line": "#00838f",
}


def _clip_segment(a: np.ndarray, b: np.ndarray, lo: np.ndarray, hi: np.ndarray):
    """The part of the segment a-b inside the box [lo, hi], or None."""
    d = b - a
    n = float(np.hypot(*d))
    if n == 0.0:
        return np.vstack([a, b]) if np.all(lo <= a) and np.all(a <= hi) else None
    seg = clip_line_to_box(a, d / n, lo, hi)
    if seg is None:
        return None
    t = np.clip((seg - a) @ (d / n), 0.0, n)
    if not t[1] - t[0] > 0.0:
        return None
    return a + np.outer(t, d / n)


def _arrow_along(ax, start: np.ndarray, direction: np.ndarray, lo: np.ndarray, hi: np.ndarray, color: str) -> None:
    """An arrow along the ray start + t direction, near where it leaves the view: points at
    something off the picture."""
    seg = clip_line_to_box(start, direction, lo, hi)
    if seg is None:
        return
    end = seg[1]
    begin = end - 0.25 * (end - seg[0])
    ax.add_patch(FancyArrowPatch(tuple(begin), tuple(end), arrowstyle="-|>", mutation_scale=16, color=color,
                                 linewidth=2.0, zorder=6, gid="sticking-locus-off-picture"))


def sketch_title(prep: PreparedPush, sk: CorSketch) -> str:
    of = " (circumscribing disk)" if prep.footprint is not None else ""
    head = f"μc = {sk.mu_c:.4g}, ν = {math.degrees(sk.nu):.4g}°, sense {sk.sense}{of}"
    if is_translation(sk):
        return f"COR sketch: none, the part translates (COR at infinity)\n{head}"
    if sk.sketch is None:
        return f"COR sketch: matches none of the nine of figure 4-6\n{head}"
    mirror = " (mirrored)" if sk.mirrored else ""
    return f"COR sketch {sk.sketch}{mirror}: {IMPLICATION_TEXT[sk.implication]}\n{head}"


def _sketch_view(prep: PreparedPush, sk: CorSketch) -> SquareView:
    """A square about the CM holding the disk, the contact, the footprint and whatever of
    the sketch lies within MAX_IN_VIEW disk radii."""
    scene = prep.scene
    a_world = scene.disk_radius
    cm_world = np.asarray(scene.center_of_mass, dtype=float)
    reach = MAX_IN_VIEW * a_world

    def rel(points) -> np.ndarray:
        return np.atleast_2d(np.asarray(points, dtype=float)) - cm_world

    must_see = [np.array([[a_world, a_world]]), rel(scene.contact_point)]
    if prep.footprint is not None:
        must_see.append(rel(prep.footprint.vertices))
    optional = [sk.plus.tip, sk.minus.tip, sk.tip_line_low, *sk.down_slipping, *sk.up_slipping]
    if sk.sticking is not None:
        optional += [sk.sticking.low, sk.sticking.high]
    for loc in (sk.plus, sk.minus):
        if loc.boundary is not None:
            optional.append(loc.boundary)
    for pts in optional:
        if pts is None or len(pts) == 0:
            continue
        r = rel(pts)
        near = r[np.hypot(r[:, 0], r[:, 1]) <= reach]
        if len(near):
            must_see.append(near)
    return SquareView.around(must_see, cm_world)


@dataclass
class _Canvas:
    """The axes, the view and the legend's handles of one picture."""

    ax: object
    view: SquareView
    handles: list = field(default_factory=list)

    def line(self, point, direction, gid, **style):
        """An infinite line clipped to the picture (a legend entry only when it misses it)."""
        line_lo, line_hi = self.view.clip_box
        seg = clip_line_to_box(np.asarray(point, float), np.asarray(direction, float), line_lo, line_hi)
        if seg is None:
            return Line2D([], [], **style)
        (h,) = self.ax.plot(seg[:, 0], seg[:, 1], gid=gid, **style)
        return h

    def polygon(self, points, gid, **style) -> None:
        line_lo, line_hi = self.view.clip_box
        ring = clip_polygon_to_box(self.view.to_drawing(points), line_lo, line_hi)
        if len(ring) >= 3:
            self.ax.add_patch(PolygonPatch(ring, closed=True, gid=gid, **style))


def _draw_loci(c: _Canvas, sk: CorSketch) -> None:
    """The slipping loci (shaded) and the elementary loci (outline)."""
    for polys, key, name in ((sk.down_slipping, "down", "down-slipping locus"),
                             (sk.up_slipping, "up", "up-slipping locus")):
        style = dict(facecolor=COLORS[key], edgecolor="none", alpha=0.35, zorder=1)
        for i, poly in enumerate(polys):
            c.polygon(poly, f"{key}-slipping-{i}", **style)
        label = name if polys else f"{name} (empty)"
        c.handles.append(PolygonPatch(np.zeros((3, 2)), label=label, **style))
    for loc, key, name in ((sk.plus, "plus", "{COR}_(α+ν)"), (sk.minus, "minus", "{COR}_(α−ν)")):
        style = dict(fill=False, edgecolor=COLORS[key], linewidth=1.1, zorder=2)
        if loc.boundary is not None:
            c.polygon(loc.boundary, f"locus-{key}", **style)
            label = f"{name}: {loc.configuration.replace('_', ' ')}"
        else:
            label = f"{name}: translation (wrapped)"
        c.handles.append(PolygonPatch(np.zeros((3, 2)), label=label, **style))


def _draw_workpiece(c: _Canvas, prep: PreparedPush) -> None:
    """The disk, the footprint and the CM."""
    a_world = prep.scene.disk_radius
    disk = Circle(tuple(c.view.centre), a_world / c.view.scale, fill=False, edgecolor=COLORS["disk"],
                  linestyle="--", linewidth=1.0, label=f"disk (a = {a_world:.4g})", zorder=3, gid="disk")
    c.ax.add_patch(disk)
    c.handles.append(disk)
    if prep.footprint is not None:
        poly = PolygonPatch(c.view.to_drawing(prep.footprint.vertices), closed=True, facecolor=COLORS["workpiece"],
                            alpha=0.12, edgecolor=COLORS["workpiece"], linewidth=1.2,
                            label="workpiece", zorder=3, gid="workpiece")
        c.ax.add_patch(poly)
        c.handles.append(poly)
    (h,) = c.ax.plot(*c.view.centre, marker="+", color="black", markersize=12, markeredgewidth=1.5,
                     linestyle="none", label="centre of mass", zorder=6, gid="center-of-mass")
    c.handles.append(h)


def _draw_sticking(c: _Canvas, sk: CorSketch, contact: np.ndarray, jp: np.ndarray) -> None:
    """The sticking locus (bold, or an arrow toward it when it is off the picture) and the
    tip-line estimate of its end."""
    P = c.view.to_drawing
    line_lo, line_hi = c.view.clip_box
    if sk.sticking is not None:
        s = sk.sticking
        seg = _clip_segment(P(s.low), P(s.high), line_lo, line_hi)
        style = dict(color=COLORS["sticking"], linewidth=3.2, solid_capstyle="butt", zorder=5)
        label = f"sticking locus, t ∈ [{s.t_low:.4g}, {s.t_high:.4g}]"
        if seg is not None:
            (h,) = c.ax.plot(seg[:, 0], seg[:, 1], label=label, gid="sticking-locus", **style)
        else:
            h = Line2D([], [], label=f"{label} (off picture)", **style)
            _arrow_along(c.ax, contact, jp if s.t_low > 0.0 else -jp, c.view.lo, c.view.hi, COLORS["sticking"])
        c.handles.append(h)
    else:
        c.handles.append(Line2D([], [], color=COLORS["sticking"], linewidth=3.2, label="sticking locus (empty)"))
    if sk.tip_line_low is not None:
        pt = P(sk.tip_line_low)
        label = f"tip-line estimate, t = {sk.tip_line_t:.4g}"
        if np.all(line_lo <= pt) and np.all(pt <= line_hi):
            (h,) = c.ax.plot(*pt, marker="x", color=COLORS["tip_line"], markersize=8, markeredgewidth=1.8,
                             linestyle="none", label=label, zorder=6, gid="tip-line-estimate")
        else:
            h = Line2D([], [], marker="x", color=COLORS["tip_line"], linestyle="none", label=f"{label} (off picture)")
        c.handles.append(h)


def _draw_pusher(c: _Canvas, prep: PreparedPush, sk: CorSketch, contact: np.ndarray, n: np.ndarray) -> None:
    """The contact, the push arrow, the friction cone and, for a translation, its arrow."""
    a = prep.scene.disk_radius / c.view.scale
    cm = c.view.centre
    p = np.asarray(prep.scene.push_hat, dtype=float)
    ang_n = math.degrees(math.atan2(n[1], n[0]))
    nu_deg = math.degrees(sk.nu)
    cone = Wedge(tuple(contact), CONE_RADIUS_REL * a, ang_n - nu_deg, ang_n + nu_deg, facecolor=COLORS["cone"],
                 edgecolor="#b7950b", alpha=0.55, linewidth=0.8, zorder=4,
                 label=f"friction cone (ν = {nu_deg:.3g}°)", gid="friction-cone")
    c.ax.add_patch(cone)
    c.handles.append(cone)
    c.ax.add_patch(FancyArrowPatch(tuple(contact - 0.6 * a * p), tuple(contact), arrowstyle="-|>",
                                   mutation_scale=14, color=COLORS["push"], linewidth=1.5, zorder=6,
                                   gid="push-arrow"))
    (h,) = c.ax.plot(*contact, marker="o", color=COLORS["push"], markersize=6, linestyle="none",
                     label="contact and push", zorder=7, gid="contact")
    c.handles.append(h)
    if is_translation(sk):
        c.ax.add_patch(FancyArrowPatch(tuple(cm), tuple(cm + 0.8 * a * p), arrowstyle="-|>", mutation_scale=18,
                                       color=COLORS["sticking"], linewidth=2.0, zorder=6, gid="translation"))
        c.handles.append(Line2D([], [], color=COLORS["sticking"], marker=">", linewidth=2.0,
                                label="translation (COR at infinity)"))


def build_sketch_figure(prep: PreparedPush, sk: CorSketch, tip_line: TipLine | None) -> Figure:
    """The picture of ``sk`` on a new SVG-canvas figure; ``tip_line`` is the frictionless
    locus's tip line of the scene (models.locus.cor_disk), drawn dashed."""
    view = _sketch_view(prep, sk)
    contact = view.to_drawing(prep.scene.contact_point)
    fig = new_figure(FIGSIZE_IN + LEGEND_WIDTH_IN, FIGSIZE_IN)
    c = _Canvas(fig.add_subplot(), view)
    view.frame(c.ax)
    _draw_loci(c, sk)
    _draw_workpiece(c, prep)
    # lines through the contact
    jp = np.asarray(sk.sticking_line_direction, dtype=float)
    n = np.asarray(sk.edge_normal_direction, dtype=float)
    c.handles.append(c.line(contact, jp, "sticking-line", color=COLORS["sticking_line"], linewidth=0.9,
                            label="sticking line", zorder=3))
    c.handles.append(c.line(contact, n, "edge-normal-line", color=COLORS["normal"], linewidth=0.9, linestyle="-.",
                            label="edge normal line", zorder=3))
    if tip_line is not None:
        c.handles.append(c.line(view.to_drawing(tip_line.point), tip_line.direction, "tip-line",
                                color=COLORS["tip_line"], linewidth=0.9, linestyle="--", label="tip line", zorder=3))
    _draw_sticking(c, sk, contact, jp)
    _draw_pusher(c, prep, sk, contact, n)
    c.ax.set_title(sketch_title(prep, sk), fontsize=9)
    legend = c.ax.legend(handles=c.handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0,
                         fontsize=7, framealpha=0.85)
    legend.set_gid("legend")
    fig.tight_layout()
    return fig


def render_sketch_svg(prep: PreparedPush, sk: CorSketch, tip_line: TipLine | None) -> bytes:
    """The picture of ``sk`` as SVG bytes (text drawn as paths, no external fonts)."""
    return svg_bytes(build_sketch_figure(prep, sk, tip_line), sketch_title(prep, sk).replace("\n", "; "))
