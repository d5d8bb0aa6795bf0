"""SVG picture of a COR locus (:mod:`service.common.svg` sets up the figure and the view).

The view is a square about the centre of mass, equal aspect. It always shows the disk,
the workpiece, the contact and r_min; it shows the whole locus when its tip is within
:data:`MAX_TIP_IN_VIEW` disk radii, and otherwise clips the view and points an arrow
at the tip, labelled with its distance (r_tip reaches 1e14 a when the line of force
nearly passes through the CM).
"""

from __future__ import annotations

import math

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, FancyArrowPatch
from matplotlib.patches import Polygon as PolygonPatch

from models.locus.cor_disk import DiskCorLocus
from service.common.scene import PreparedPush
from service.common.svg import (
    COLORS,
    FIGSIZE_IN,
    SquareView,
    clip_line_to_box,
    clip_polygon_to_box,
    new_figure,
    svg_bytes,
)

MAX_TIP_IN_VIEW = 6.0
"""Largest r_tip / a for which the whole locus is drawn; beyond it the view is clipped."""


def _title(prep: PreparedPush, locus: DiskCorLocus) -> str:
    a = prep.scene.disk_radius
    head = f"COR locus: a = {a:.4g}, |α·c| = {locus.moment_arm:.4g}"
    if locus.kind == "translation":
        return f"{head}, pure translation (COR at infinity)"
    return f"{head}, sense {locus.sense}"


def _locus_view(prep: PreparedPush, locus: DiskCorLocus, tip_in_view: bool) -> SquareView:
    """A square about the CM, sized in world units first: the disk, the contact, the
    footprint, and the locus, its tip and the tip line when the tip is near enough."""
    scene = prep.scene
    a_world = scene.disk_radius
    cm_world = np.asarray(scene.center_of_mass, dtype=float)

    def rel(point) -> np.ndarray:
        return np.asarray(point, dtype=float) - cm_world

    must_see = [np.array([a_world, a_world]), rel(scene.contact_point)]
    if prep.footprint is not None:
        must_see.extend(rel(prep.footprint.vertices))
    if tip_in_view and locus.boundary is not None:
        must_see.extend(rel(locus.boundary))
    if tip_in_view:
        must_see.append(rel(locus.tip.point))
    if locus.tip_line is not None and locus.tip_line.distance <= MAX_TIP_IN_VIEW * a_world:
        must_see.append(rel(locus.tip_line.point))
    return SquareView.around(must_see, cm_world)


def _draw_tip(ax, tip, axis: np.ndarray, view: SquareView, tip_in_view: bool):
    """The tip, or an arrow toward it when it is off the picture; its legend handle."""
    if tip_in_view:
        (h,) = ax.plot(*view.to_drawing(tip.point), marker="^", color=COLORS["tip"], markersize=8,
                       linestyle="none", label=f"tip (r_tip = {tip.distance:.4g})", zorder=6)
        return h
    cm = view.centre
    reach = view.half / max(abs(axis[0]), abs(axis[1]))  # distance to the view's edge
    start, end = cm + 0.55 * reach * axis, cm + 0.95 * reach * axis
    ax.add_patch(FancyArrowPatch(tuple(start), tuple(end), arrowstyle="-|>", mutation_scale=16,
                                 color=COLORS["tip"], linewidth=1.5, zorder=6))
    ax.annotate(f"tip off picture\nr_tip = {tip.distance:.4g}", xy=tuple(start),
                ha="center", va="center", fontsize=8, color=COLORS["tip"], zorder=7,
                bbox=dict(boxstyle="round", facecolor="white", alpha=0.8, linewidth=0.5))
    return Line2D([], [], color=COLORS["tip"], marker=">", label=f"to tip (r_tip = {tip.distance:.4g})")


def build_figure(prep: PreparedPush, locus: DiskCorLocus) -> Figure:
    """The picture of ``locus`` (computed with every output) on a new SVG-canvas figure."""
    scene = prep.scene
    a_world = scene.disk_radius
    tip_in_view = locus.tip is not None and locus.tip.distance <= MAX_TIP_IN_VIEW * a_world
    view = _locus_view(prep, locus, tip_in_view)
    P = view.to_drawing
    a = a_world / view.scale
    cm = view.centre
    contact = P(scene.contact_point)
    line_lo, line_hi = view.clip_box

    fig = new_figure(FIGSIZE_IN, FIGSIZE_IN)
    ax = fig.add_subplot()
    view.frame(ax)
    handles = []

    def line(point, direction, **style):
        seg = clip_line_to_box(np.asarray(point, float), np.asarray(direction, float), line_lo, line_hi)
        if seg is None:
            return Line2D([], [], **style)  # legend entry only
        (h,) = ax.plot(seg[:, 0], seg[:, 1], **style)
        return h

    # ---- the locus ------------------------------------------------------------------
    if locus.boundary is not None:
        ring = clip_polygon_to_box(P(locus.boundary), line_lo, line_hi)
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
        handles.append(_draw_tip(ax, locus.tip, np.asarray(locus.axis, dtype=float), view, tip_in_view))
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
    ax.legend(handles=handles, loc="upper left", fontsize=7, framealpha=0.85)
    fig.tight_layout()
    return fig


def render_locus_svg(prep: PreparedPush, locus: DiskCorLocus) -> bytes:
    """The picture of ``locus`` as SVG bytes (text drawn as paths, no external fonts)."""
    return svg_bytes(build_figure(prep, locus), _title(prep, locus))
