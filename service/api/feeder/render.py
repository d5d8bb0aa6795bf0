"""SVG pictures of the feeder (book ch. 5), matplotlib object API only.

As in :mod:`service.common.svg`: no pyplot, one throw-away ``Figure`` on an SVG canvas per
call, text drawn as paths, no date, so equal inputs give equal bytes.

* :func:`render_maps_svg` -- figure 1-8 for each fence and, for a sequence, figure 5-2's
  product beside them: initial orientation across, final orientation up (degrees), each
  band B_j over its kernel K_j shaded, the initial orientations that may jam hatched and
  those the map does not bound (a reach too short) tinted; outlines of the part at eight
  orientations along the bottom, as in figure 1-8.
* :func:`render_runs_svg` -- a top view of each fence's run (figure 1-9's motion, one
  panel per fence, in the fence's frame: its free end E at the origin, the belt moving
  down): the fence, the path of the centre of mass, and outlines of the part at evenly
  spaced steps, the first and the last bold.
* :func:`render_belt_svg` -- a top view of placed fences (figure 1-9): the belt's sides
  when known, every fence from its root to its free end, and each part's whole path
  through them with outlines along it; also the first panel of a design's picture when
  the design was laid out on a belt.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from matplotlib.patches import Polygon as PolygonPatch
from matplotlib.patches import Rectangle

from models.core.footprint import Footprint
from models.feeder.arcs import TWO_PI, Arcs
from models.feeder.fence import FenceMap, rotation
from models.feeder.maps import ConfigurationMap
from service.common.svg import COLORS as LOCUS_COLORS
from service.common.svg import FIGSIZE_IN, SquareView, axis_label, clip_polygon_to_box, new_figure, svg_bytes
from service.errors import NonFiniteResult
from solver import FenceRun, FenceSegment

PANEL_IN = 0.8 * FIGSIZE_IN
"""Width of one map panel, inches."""
OUTLINE_STRIP_DEG = 50.0
"""Height of the strip of part outlines under a map, in the map's degrees."""
OUTLINE_HALF_DEG = 18.0
"""Half the size of an outline there (the part's circumscribing radius), degrees."""
OUTLINE_ORIENTATIONS = 8
"""Outlines drawn under a map, at evenly spaced orientations."""
RUN_OUTLINES = 9
"""Outlines of the part drawn along a run (evenly over its steps, first and last included)."""
BELT_OUTLINES = 14
"""Outlines of the part drawn along its whole path over a belt."""

COLORS = {
    "band": LOCUS_COLORS["workpiece"],
    "jam": LOCUS_COLORS["disk"],
    "unaligned": LOCUS_COLORS["push"],
    "outline": LOCUS_COLORS["disk"],
    "fence": LOCUS_COLORS["edge"],
    "path": LOCUS_COLORS["locus_edge"],
    "part": LOCUS_COLORS["workpiece"],
    "belt": "0.45",
    "gate": "0.2",
}
PATH_COLORS = (LOCUS_COLORS["workpiece"], LOCUS_COLORS["push"], LOCUS_COLORS["disk"], LOCUS_COLORS["locus_edge"])
"""One per part on a belt's top view, in turn."""


@dataclass(frozen=True)
class BeltPicture:
    """What a belt's top view shows: each fence as (root, free end) in the world frame, the
    belt's width (None: sides not drawn), and each part's runs through the fences in order."""

    fences: Sequence[tuple[np.ndarray, np.ndarray]]
    width: float | None
    parts: Sequence[Sequence[FenceRun]]
    gate_y: float | None = None  # a reject gate across the belt there (None: no gate)


def degree_spans(arcs: Arcs) -> list[tuple[float, float]]:
    """The arcs as (start, width) in degrees within [0, 360], an arc across 0 split in two."""
    out = []
    for s, w in arcs.arcs:
        if not (math.isfinite(s) and math.isfinite(w)):
            raise NonFiniteResult("an orientation arc")
        s = s % TWO_PI
        first = min(w, TWO_PI - s)
        out.append((math.degrees(s), math.degrees(first)))
        if w > first:
            out.append((0.0, math.degrees(w - first)))
    return out


def _draw_map(ax, cmap: ConfigurationMap, hull_unit: np.ndarray, label: str) -> None:
    for band, kernel in zip(cmap.bands, cmap.kernels):
        for ks, kw in degree_spans(kernel):
            for bs, bw in degree_spans(band):
                # a band narrower than a pixel still shows: its rectangle is outlined
                ax.add_patch(Rectangle((ks, bs), kw, bw, facecolor=COLORS["band"], edgecolor=COLORS["band"],
                                       linewidth=0.6, alpha=0.85))
    for s, w in degree_spans(cmap.jam):
        ax.add_patch(Rectangle((s, 0.0), w, 360.0, facecolor="none", edgecolor=COLORS["jam"], hatch="//",
                               linewidth=0.0))
    for s, w in degree_spans(cmap.unaligned):
        ax.add_patch(Rectangle((s, 0.0), w, 360.0, facecolor=COLORS["unaligned"], edgecolor="none", alpha=0.25))
    for i in range(OUTLINE_ORIENTATIONS):
        theta = TWO_PI * (i + 0.5) / OUTLINE_ORIENTATIONS
        pts = (rotation(theta) @ hull_unit.T).T * OUTLINE_HALF_DEG
        pts = pts + np.array([math.degrees(theta), -0.5 * OUTLINE_STRIP_DEG])
        ax.add_patch(PolygonPatch(pts, closed=True, facecolor="none", edgecolor=COLORS["outline"], linewidth=0.8))
    ax.axhline(0.0, color="black", linewidth=0.6)
    ax.set_xlim(0.0, 360.0)
    ax.set_ylim(-OUTLINE_STRIP_DEG, 360.0)
    ax.set_aspect("equal")
    ticks = np.arange(0.0, 361.0, 90.0)
    ax.set_xticks(ticks)
    ax.set_yticks(ticks)
    ax.set_xlabel("initial orientation θ_i (deg)")
    ax.set_ylabel("final orientation θ_f (deg)")
    ax.set_title(label, fontsize=9)


def map_label(fm: FenceMap) -> str:
    f = fm.fence
    mu = f"μ_c = {f.mu_low:g}" if f.mu_high <= f.mu_low else f"μ_c ∈ [{f.mu_low:g}, {f.mu_high:g}]"
    return f"fence γ = {math.degrees(f.angle):+.1f}°, {mu}"


def render_maps_svg(part: Footprint, maps: Sequence[FenceMap], product: ConfigurationMap | None, title: str,
                    belt: BeltPicture | None = None) -> str:
    """Figure 1-8 per fence, and the product (figure 5-2) when there are several, after the
    belt's top view (figure 1-9) when given; SVG text."""
    panels = [(map_label(fm), fm.map) for fm in maps]
    if product is not None and len(maps) > 1:
        panels.append((f"product of the {len(maps)} fences (5.4, 5.5)", product))
    if not panels:
        raise ValueError("no map to draw")
    hull_unit = part.hull / part.circumradius
    if not np.all(np.isfinite(hull_unit)):
        raise NonFiniteResult("the part's outline")
    extra = 0 if belt is None else 1
    fig = new_figure(PANEL_IN * (len(panels) + extra), PANEL_IN * 1.1)
    axes = fig.subplots(1, len(panels) + extra, squeeze=False)[0]
    if belt is not None:
        _draw_belt(axes[0], part, belt, "the design on the belt (figure 1-9)")
    for ax, (label, cmap) in zip(axes[extra:], panels):
        _draw_map(ax, cmap, hull_unit, label)
    handles = [Rectangle((0, 0), 1, 1, facecolor=COLORS["band"], alpha=0.85, label="band B_j over kernel K_j"),
               Rectangle((0, 0), 1, 1, facecolor="none", edgecolor=COLORS["jam"], hatch="//", label="may jam (6.4)"),
               Rectangle((0, 0), 1, 1, facecolor=COLORS["unaligned"], alpha=0.25,
                         label="not bounded: reach too short (1.8.6)")]
    fig.legend(handles=handles, loc="lower center", ncol=3, fontsize=8, frameon=False)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout(rect=(0.0, 0.05, 1.0, 0.95))
    return svg_bytes(fig, " ".join(title.split())).decode("utf-8")


def _outlines(part: Footprint, cms: np.ndarray, thetas: np.ndarray, count: int) -> list[np.ndarray]:
    """The part's outline at ``count`` poses evenly over a path, its first and last included."""
    idx = np.unique(np.linspace(0, len(cms) - 1, min(count, len(cms))).round().astype(int))
    return [cms[k] + (rotation(float(thetas[k])) @ part.hull.T).T for k in idx]


def _draw_outlines(ax, view: SquareView, outlines: list[np.ndarray], color, box: tuple[np.ndarray, np.ndarray],
                   widths: tuple[float, float]) -> None:
    """Outlines along a path clipped to ``box``, the first and the last filled and bold."""
    for k, outline in enumerate(outlines):
        poly = clip_polygon_to_box(view.to_drawing(outline), *box)
        if len(poly) < 3:
            continue
        bold = k in (0, len(outlines) - 1)
        ax.add_patch(PolygonPatch(poly, closed=True, facecolor=color if bold else "none", alpha=0.35 if bold else 1.0,
                                  edgecolor=color, linewidth=widths[0] if bold else widths[1]))


def render_runs_svg(part: Footprint, runs: Sequence[FenceRun], segments: Sequence[FenceSegment], title: str) -> str:
    """A top view of each run in its fence's frame (the fence from its end E to its root,
    the belt moving in -y); SVG text."""
    if not runs:
        raise ValueError("no run to draw")
    fig = new_figure(PANEL_IN * len(runs), PANEL_IN * 1.05)
    axes = fig.subplots(1, len(runs), squeeze=False)[0]
    for ax, run, fence_seg, i in zip(axes, runs, segments, range(len(runs))):
        outlines = _outlines(part, run.cms, run.thetas, RUN_OUTLINES)
        pts = np.vstack([*outlines, run.cms, fence_seg.end[None]])
        if not np.all(np.isfinite(pts)):
            raise NonFiniteResult("the part's trajectory")
        centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
        view = SquareView.around([pts - centre], centre)
        lo, hi = view.centre - view.half, view.centre + view.half
        seg = view.to_drawing(np.array([fence_seg.end, fence_seg.root]))
        ax.plot(seg[:, 0], seg[:, 1], color=COLORS["fence"], linewidth=3.0, solid_capstyle="butt", label="fence")
        e = view.to_drawing(fence_seg.end)
        ax.plot([e[0]], [e[1]], marker="o", color=COLORS["fence"], markersize=4)
        path = view.to_drawing(run.cms)
        ax.plot(path[:, 0], path[:, 1], color=COLORS["path"], linewidth=1.0, label="centre of mass")
        _draw_outlines(ax, view, outlines, COLORS["part"], (lo, hi), (1.2, 0.6))
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_aspect("equal")
        ax.set_xlabel(axis_label("x", float(view.origin[0]), view.unit_exp))
        ax.set_ylabel(axis_label("y", float(view.origin[1]), view.unit_exp))
        final = "—" if run.theta_final is None else f"{math.degrees(run.theta_final) % 360.0:.2f}°"
        ax.set_title(f"fence {i}: {run.status}, θ {math.degrees(run.theta_initial) % 360.0:.2f}° → {final}"
                     f"{'' if run.flushed else ' (never flush)'}", fontsize=9)
        ax.legend(loc="upper right", fontsize=7)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout(rect=(0.0, 0.0, 1.0, 0.95))
    return svg_bytes(fig, " ".join(title.split())).decode("utf-8")


def _draw_belt(ax, part: Footprint, belt: BeltPicture, label: str) -> None:
    """The top view of placed fences and the parts' paths through them (world frame)."""
    paths = [[(run.cms, run.thetas) for run in runs] for runs in belt.parts]
    poses = [(np.vstack([c for c, _ in p]), np.concatenate([t for _, t in p])) for p in paths if p]
    ends = np.array([pt for f in belt.fences for pt in f]).reshape(-1, 2)
    if belt.gate_y is not None:  # the gate in view
        ends = np.vstack([ends, [[0.0, belt.gate_y]]])
    outlines = [_outlines(part, cms, thetas, BELT_OUTLINES) for cms, thetas in poses]
    pts = np.vstack([ends, *[c for c, _ in poses], *[o for group in outlines for o in group]])
    if not np.all(np.isfinite(pts)):
        raise NonFiniteResult("the belt's top view")
    centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
    view = SquareView.around([pts - centre], centre)
    if belt.width is not None:
        for x in (-0.5 * belt.width, 0.5 * belt.width):
            side = view.to_drawing(np.array([[x, pts[:, 1].min()], [x, pts[:, 1].max()]]))
            ax.plot(side[:, 0], side[:, 1], color=COLORS["belt"], linewidth=0.8, linestyle="--")
    if belt.gate_y is not None and belt.width is not None:
        line = view.to_drawing(np.array([[-0.5 * belt.width, belt.gate_y], [0.5 * belt.width, belt.gate_y]]))
        ax.plot(line[:, 0], line[:, 1], color=COLORS["gate"], linewidth=1.5, linestyle=":", label="reject gate")
    for i, (root, end) in enumerate(belt.fences):
        seg = view.to_drawing(np.array([root, end]))
        ax.plot(seg[:, 0], seg[:, 1], color=COLORS["fence"], linewidth=3.0, solid_capstyle="butt",
                label="fences" if i == 0 else None)
        ax.plot([seg[1, 0]], [seg[1, 1]], marker="o", color=COLORS["fence"], markersize=3)
        ax.annotate(str(i), seg[0], fontsize=7, xytext=(3, 3), textcoords="offset points")
    for j, ((cms, _), group) in enumerate(zip(poses, outlines)):
        color = PATH_COLORS[j % len(PATH_COLORS)]
        path = view.to_drawing(cms)
        ax.plot(path[:, 0], path[:, 1], color=color, linewidth=0.9, label=f"part {j}")
        _draw_outlines(ax, view, group, color, view.clip_box, (1.0, 0.5))
    view.frame(ax)
    ax.set_title(f"{label}; belt moving down", fontsize=9)
    ax.legend(loc="lower right", fontsize=7)


def render_belt_svg(part: Footprint, belt: BeltPicture, title: str) -> str:
    """A top view of placed fences and the parts' paths through them; SVG text."""
    fig = new_figure(PANEL_IN * 1.2, PANEL_IN * 1.25)
    ax = fig.subplots(1, 1)
    _draw_belt(ax, part, belt, "top view (figure 1-9)")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout(rect=(0.0, 0.0, 1.0, 0.95))
    return svg_bytes(fig, " ".join(title.split())).decode("utf-8")
