"""SVG pictures of the spiral localization of a disk (book 4.5), matplotlib object API only.

As in :mod:`service.common.svg`: no pyplot, one throw-away ``Figure`` on an SVG canvas per
call, text drawn as paths (the strings survive as XML comments), ``Date`` metadata left
out so equal inputs give equal bytes. Non-finite input raises
:class:`service.errors.NonFiniteResult` (HTTP 422) instead of drawing garbage.

* :func:`render_critical_radius_svg` -- figure 4-19: a / r*(beta) against beta / pi, one
  line per :class:`CriticalCurve` (its tip-line approximation 2a / sin beta dashed in the
  same colour, a / b_inf as a marker at beta / pi = 1/2, certified table points filled,
  uncertified open). Only ratios are plotted, so any absolute scale draws the same.
* :func:`render_schedule_svg` -- two panels: the pusher's path about the spiral's centre
  with the circles b_1, target and b_inf (equal aspect; drawn relative to the centre and
  in units of 10^k exactly like the COR locus, via :func:`service.common.svg.view_frame`; long
  polylines decimated by :func:`decimate_polyline`), and figure 4-21: (b_n - b_inf) / a
  against the revolution n on log-log axes, with a power-law fit C n^-k and the tip-line
  schedule for comparison.
"""

from __future__ import annotations

import heapq
import math
from dataclasses import dataclass

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle

from service.common.numbers import finite
from service.common.svg import COLORS as LOCUS_COLORS
from service.common.svg import FIGSIZE_IN, SquareView, new_figure, svg_bytes
from service.errors import NonFiniteResult

MAX_PATH_POINTS = 4000
"""Most vertices of the pusher's path that go into the SVG (:func:`decimate_polyline`)."""
DECIMATE_CHUNKS = 64
"""The path is first cut into this many equal index ranges (bounds the decimation's cost)."""
DECIMATE_REL_TOL = 1e-4
"""Decimation stops early once every dropped vertex is this close (relative to the
path's extent) to the kept polyline: well below a pixel."""
MAX_REVOLUTION_CIRCLES = 60
"""Without a path, at most this many revolutions are drawn as thin circles."""

CURVE_COLORS = (
    LOCUS_COLORS["workpiece"],
    LOCUS_COLORS["locus_edge"],
    LOCUS_COLORS["edge"],
    LOCUS_COLORS["push"],
    LOCUS_COLORS["tip"],
    LOCUS_COLORS["r_min"],
    LOCUS_COLORS["disk"],
    "#b8860b",
)
"""One colour per curve of figure 4-19 (cycled), the palette of :mod:`service.common.svg`."""

COLORS = {
    "path": LOCUS_COLORS["workpiece"],
    "b_1": LOCUS_COLORS["disk"],
    "target": LOCUS_COLORS["edge"],
    "b_inf": LOCUS_COLORS["push"],
    "b_floor": "#888888",
    "schedule": LOCUS_COLORS["workpiece"],
    "fit": LOCUS_COLORS["locus_edge"],
    "tip_line": LOCUS_COLORS["tip"],
    "centre": "black",
}


@dataclass(frozen=True)
class CriticalCurve:
    """One curve of figure 4-19. ``betas`` (radians) and ``radii`` r*(beta) (length units,
    same shape); ``a`` the disk radius; ``tip_line`` the tip-line radii 2a / sin beta at
    the same betas (dashed); ``b_inf`` the limiting radius (a marker at beta = pi/2);
    ``certified`` a boolean per point (filled marker if true, open if false; no markers
    when None). The legend reads "mu_c = <mu_c>", followed by ``label`` when it is not
    empty and does not already name mu_c."""

    label: str
    mu_c: float
    betas: np.ndarray
    radii: np.ndarray
    a: float
    tip_line: np.ndarray | None = None
    b_inf: float | None = None
    certified: np.ndarray | None = None


# --------------------------------------------------------------------------------------
# Checks


def _finite_array(values, what: str, ndim: int | None = None) -> np.ndarray:
    arr = np.asarray(values, dtype=float)
    if ndim is not None and arr.ndim != ndim:
        raise ValueError(f"{what}: expected a {ndim}-d array, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise NonFiniteResult(what)
    return arr


def _positive_length(value, what: str) -> float:
    x = finite(value, what)
    if not x > 0.0:
        raise ValueError(f"{what} must be positive, got {x!r}")
    return x


def _ratio(num, den: float, what: str) -> np.ndarray:
    """num / den, refused when it over- or underflows to something non-finite."""
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        out = np.asarray(num, dtype=float) / den
    if not np.all(np.isfinite(out)):
        raise NonFiniteResult(what)
    return out


# --------------------------------------------------------------------------------------
# Polyline decimation


def _segment_deviation(pts: np.ndarray, i: int, j: int):
    """(largest distance, its index) of the vertices strictly between i and j from the
    segment pts[i]-pts[j]; None when there are none."""
    if j - i < 2:
        return None
    a, b = pts[i], pts[j]
    p = pts[i + 1 : j] - a
    d = b - a
    l2 = float(d @ d)
    if l2 > 0.0:
        t = np.clip((p @ d) / l2, 0.0, 1.0)
        p = p - t[:, None] * d
    dist2 = np.einsum("ij,ij->i", p, p)
    k = int(np.argmax(dist2))
    return math.sqrt(float(dist2[k])), i + 1 + k


def decimate_polyline(points, max_points: int = MAX_PATH_POINTS, rel_tol: float = DECIMATE_REL_TOL) -> np.ndarray:
    """At most ``max_points`` vertices of the polyline ``points`` (N, 2), in order, always
    including the first and the last (see :func:`decimation_indices`). Polylines of at
    most ``max_points`` vertices come back unchanged."""
    pts = np.asarray(points, dtype=float)
    return pts[decimation_indices(pts, max_points, rel_tol)]


def decimation_indices(points, max_points: int = MAX_PATH_POINTS, rel_tol: float = DECIMATE_REL_TOL) -> np.ndarray:
    """Ascending indices of the vertices of the polyline ``points`` (N, 2) to keep: at
    most ``max_points`` (at least 2), always 0 and N - 1. A progressive Ramer-Douglas-
    Peucker: keep splitting the piece whose dropped vertex lies farthest from it, until the
    budget is spent or every dropped vertex is within ``rel_tol`` times the polyline's
    extent (well below a pixel). The polyline is first cut into :data:`DECIMATE_CHUNKS`
    equal index ranges, so the cost stays ~ N log N even for a spiral (whose first chord
    is a poor split). All indices when N <= ``max_points``."""
    pts = np.asarray(points, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise ValueError(f"a polyline is an (N, 2) array, got shape {pts.shape}")
    n = len(pts)
    max_points = max(int(max_points), 2)
    if n <= max_points:
        return np.arange(n)
    extent = float(np.max(np.ptp(pts, axis=0)))
    if not extent > 0.0:  # every vertex at the same place
        return np.array([0, n - 1])
    tol = rel_tol * extent
    n_chunks = max(1, min(DECIMATE_CHUNKS, (max_points - 1) // 4))
    breaks = np.unique(np.linspace(0, n - 1, n_chunks + 1).round().astype(int))
    keep = set(int(b) for b in breaks)
    heap: list[tuple[float, int, int, int]] = []

    def push(i: int, j: int) -> None:
        dev = _segment_deviation(pts, i, j)
        if dev is not None and dev[0] > tol:
            heapq.heappush(heap, (-dev[0], i, j, dev[1]))

    for i, j in zip(breaks[:-1], breaks[1:]):
        push(int(i), int(j))
    while heap and len(keep) < max_points:
        _, i, j, k = heapq.heappop(heap)
        keep.add(k)
        push(i, k)
        push(k, j)
    return np.fromiter(sorted(keep), dtype=int)


# --------------------------------------------------------------------------------------
# Figure 4-19


def _curve_label(c: CriticalCurve) -> str:
    head = f"mu_c = {float(c.mu_c):.4g}"
    label = (c.label or "").strip()
    if not label:
        return head
    if "mu_c" in label or "μ" in label:
        return label
    return f"{head} ({label})"


def build_critical_radius_figure(curves: list[CriticalCurve], title: str) -> Figure:
    """Figure 4-19 on a new SVG-canvas figure (see :func:`render_critical_radius_svg`)."""
    fig = new_figure(FIGSIZE_IN + 1.2, FIGSIZE_IN * 0.8)
    ax = fig.add_subplot()
    ax.grid(True, linewidth=0.3, alpha=0.5)
    handles: list = []
    x_lo, x_hi, y_hi = 0.0, 0.5, 0.0
    any_tip = any_binf = any_cert = False

    for idx, c in enumerate(curves):
        color = CURVE_COLORS[idx % len(CURVE_COLORS)]
        what = f"curve {idx} ({_curve_label(c)})"
        a = _positive_length(c.a, f"{what}: the disk radius a")
        finite(c.mu_c, f"{what}: mu_c")
        betas = _finite_array(c.betas, f"{what}: beta", ndim=1)
        radii = _finite_array(c.radii, f"{what}: r*", ndim=1)
        if betas.shape != radii.shape:
            raise ValueError(f"{what}: {betas.size} betas but {radii.size} radii")
        x = betas / math.pi
        y = _ratio(a, radii, f"{what}: a / r*")
        if x.size:
            x_lo, x_hi = min(x_lo, float(x.min())), max(x_hi, float(x.max()))
            y_hi = max(y_hi, float(y.max()))
        (h,) = ax.plot(x, y, color=color, linewidth=1.4, label=_curve_label(c), zorder=3, gid=f"critical-{idx}")
        handles.append(h)

        if c.certified is not None:
            cert = np.asarray(c.certified, dtype=bool)
            if cert.shape != x.shape:
                raise ValueError(f"{what}: {cert.size} certified flags for {x.size} points")
            style = dict(marker="o", markersize=3.2, linestyle="none", color=color, zorder=4)
            if np.any(cert):
                ax.plot(x[cert], y[cert], gid=f"certified-{idx}", **style)
            if np.any(~cert):
                ax.plot(x[~cert], y[~cert], markerfacecolor="white", gid=f"uncertified-{idx}", **style)
            any_cert = True

        if c.tip_line is not None:
            tip = _finite_array(c.tip_line, f"{what}: the tip-line radii", ndim=1)
            if tip.shape != x.shape:
                raise ValueError(f"{what}: {tip.size} tip-line radii for {x.size} points")
            yt = _ratio(a, tip, f"{what}: a / (2a / sin beta)")
            if yt.size:
                y_hi = max(y_hi, float(yt.max()))
            ax.plot(x, yt, color=color, linewidth=1.0, linestyle="--", zorder=2, gid=f"tip-line-{idx}")
            any_tip = True

        if c.b_inf is not None:
            b_inf = _positive_length(c.b_inf, f"{what}: b_inf")
            yb = float(_ratio(a, b_inf, f"{what}: a / b_inf"))
            y_hi = max(y_hi, yb)
            ax.plot([0.5], [yb], marker="D", markersize=7, color=color, markeredgecolor="black",
                    markeredgewidth=0.6, linestyle="none", zorder=5, clip_on=False, gid=f"b-inf-{idx}")
            any_binf = True

    if any_tip:
        handles.append(Line2D([], [], color="#555555", linestyle="--", linewidth=1.0,
                              label="tip line, r* = 2a / sin beta"))
    if any_binf:
        handles.append(Line2D([], [], color="#cccccc", marker="D", markeredgecolor="black", linestyle="none",
                              label="a / b_inf at beta = pi / 2"))
    if any_cert:
        handles.append(Line2D([], [], color="#555555", marker="o", markersize=4, linestyle="none",
                              label="certified point"))
        handles.append(Line2D([], [], color="#555555", marker="o", markersize=4, markerfacecolor="white",
                              linestyle="none", label="not certified"))
    if not curves:
        ax.text(0.5, 0.5, "no curves", transform=ax.transAxes, ha="center", va="center", color="#888888")

    ax.set_xlim(x_lo, x_hi)
    ax.set_ylim(0.0, 1.08 * y_hi if y_hi > 0.0 else 1.0)
    ax.set_xlabel("beta / pi")
    ax.set_ylabel("a / r*")
    ax.set_title(title, fontsize=10)
    if handles:
        legend = ax.legend(handles=handles, loc="upper left", fontsize=7, framealpha=0.85)
        legend.set_gid("legend")
    fig.tight_layout()
    return fig


def _svg_text(fig: Figure, title: str) -> str:
    return svg_bytes(fig, " ".join(title.split())).decode("utf-8")


def render_critical_radius_svg(curves: list[CriticalCurve], title: str) -> str:
    """Figure 4-19 as SVG text: a / r*(beta) against beta / pi (x from 0 to 1/2, widened
    only if some beta lies outside [0, pi/2]), one solid line per curve, the tip line
    dashed in the same colour, a / b_inf as a diamond at beta / pi = 1/2, certified points
    filled and uncertified open. Raises NonFiniteResult on a NaN or infinite input (also
    an infinite tip-line radius, e.g. at beta = 0) or a ratio that overflows."""
    return _svg_text(build_critical_radius_figure(list(curves), title), title)


# --------------------------------------------------------------------------------------
# The schedule: the pusher's path, and figure 4-21


def _power_label(k: float) -> str:
    return f"n^-{k:.3g}" if k >= 0.0 else f"n^+{-k:.3g}"


@dataclass(frozen=True)
class _Schedule:
    """The checked inputs of the schedule's picture (finite, of the right shapes)."""

    b: np.ndarray
    a: float
    b_inf: float
    b_floor: float
    centre: np.ndarray
    target: float | None
    path: np.ndarray | None
    tip: np.ndarray | None
    fit: tuple[float, float, int, int] | None


def _checked_schedule(radii, a, b_inf, b_floor, path_points, centre, target, fit, tip_line_radii) -> _Schedule:
    """The inputs checked in the order the picture takes them (the first bad one is named)."""
    b = _finite_array(radii, "the schedule's radii", ndim=1)
    if b.size == 0:
        raise ValueError("the schedule needs at least one radius")
    a = _positive_length(a, "the disk radius a")
    b_inf = finite(b_inf, "b_inf")
    b_floor = finite(b_floor, "the table's floor b_floor")
    c_world = _finite_array(centre, "the spiral's centre", ndim=1)
    if c_world.shape != (2,):
        raise ValueError(f"the centre is a point (2,), got shape {c_world.shape}")
    if target is not None:
        target = finite(target, "the target radius")
    path = None
    if path_points is not None:
        path = _finite_array(path_points, "the pusher's path", ndim=2)
        if path.shape[1] != 2:
            raise ValueError(f"the path is an (N, 2) array, got shape {path.shape}")
    tip = None if tip_line_radii is None else _finite_array(tip_line_radii, "the tip-line schedule's radii", ndim=1)
    checked_fit = None
    if fit is not None:
        k_fit, c_fit, n_min, n_max = fit
        checked_fit = (finite(k_fit, "the fit's exponent k"), finite(c_fit, "the fit's coefficient C"),
                       int(n_min), int(n_max))
    return _Schedule(b=b, a=a, b_inf=b_inf, b_floor=b_floor, centre=c_world, target=target, path=path, tip=tip,
                     fit=checked_fit)


@dataclass(frozen=True)
class _Approach:
    """The right panel's data, ratios only (every scale draws the same): (b_n - b_inf) / a,
    the floor's and the target's, the tip-line schedule's."""

    dev: np.ndarray
    floor_rel: float
    target_rel: float | None
    tip_dev: np.ndarray | None

    @classmethod
    def of(cls, sch: _Schedule) -> _Approach:
        a, b_inf = sch.a, sch.b_inf
        return cls(dev=_ratio(sch.b - b_inf, a, "(b_n - b_inf) / a"),
                   floor_rel=float(_ratio(sch.b_floor - b_inf, a, "(b_floor - b_inf) / a")),
                   target_rel=None if sch.target is None else float(_ratio(sch.target - b_inf, a,
                                                                             "(target - b_inf) / a")),
                   tip_dev=None if sch.tip is None else _ratio(sch.tip - b_inf, a, "(tip-line b_n - b_inf) / a"))


def _draw_path_panel(ax, sch: _Schedule) -> None:
    """Left: the pusher's path (or its revolutions as circles) with b_1, the target and b_inf,
    in a square about the centre, as the COR locus picture."""
    b, a, b_inf, target, path = sch.b, sch.a, sch.b_inf, sch.target, sch.path
    b_1 = float(b[0])
    reach = [abs(b_1), abs(b_inf)] + ([abs(target)] if target is not None else [])
    must_see = [np.array([max(reach), max(reach)])]
    if path is not None and len(path):
        must_see.append(path - sch.centre)
    view = SquareView.around(must_see, sch.centre)
    scale, cen = view.scale, view.centre
    view.frame(ax)
    handles: list = []
    if path is not None and len(path):
        drawn = decimate_polyline(view.to_drawing(path))
        note = "" if len(drawn) == len(path) else f", {len(drawn)} of {len(path)} points drawn"
        (h,) = ax.plot(drawn[:, 0], drawn[:, 1], color=COLORS["path"], linewidth=0.6, zorder=2,
                       label=f"pusher path ({len(b)} revolutions{note})", gid="pusher-path")
        handles.append(h)
        ax.plot(*drawn[0], marker="o", markersize=4, color=COLORS["path"], linestyle="none", zorder=4,
                gid="path-start")
    else:
        pick = np.unique(np.linspace(0, b.size - 1, min(b.size, MAX_REVOLUTION_CIRCLES)).round().astype(int))
        style = dict(fill=False, edgecolor=COLORS["path"], linewidth=0.4, alpha=0.7, zorder=2)
        for i in pick:
            if b[i] > 0.0:
                ax.add_patch(Circle(tuple(cen), b[i] / scale, gid=f"revolution-{i + 1}", **style))
        shown = "" if len(pick) == b.size else f", {len(pick)} drawn"
        handles.append(Line2D([], [], color=COLORS["path"], linewidth=0.6,
                              label=f"revolutions b_n ({b.size}{shown})"))

    def circle(radius: float | None, key: str, label: str, **style) -> None:
        if radius is None:
            return
        if radius > 0.0:
            patch = Circle(tuple(cen), radius / scale, fill=False, edgecolor=COLORS[key], zorder=3,
                           gid=f"circle-{key.replace('_', '-')}", **style)
            ax.add_patch(patch)
        handles.append(Line2D([], [], color=COLORS[key], label=label, **style))

    circle(b_1, "b_1", f"b_1 = {b_1:.4g}", linestyle="--", linewidth=1.2)
    if target is not None:
        circle(target, "target", f"target = {target:.4g}", linestyle="--", linewidth=1.2)
    circle(b_inf, "b_inf", f"b_inf = {b_inf:.4g} = {b_inf / a:.4g} a", linestyle="--", linewidth=1.2)
    (h,) = ax.plot(*cen, marker="+", color=COLORS["centre"], markersize=10, markeredgewidth=1.3,
                   linestyle="none", zorder=5, label="centre", gid="centre")
    handles.append(h)
    ax.set_title(f"pusher path (a = {a:.4g}, b_floor = {sch.b_floor:.4g})", fontsize=9)
    legend = ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=2,
                       fontsize=7, framealpha=0.85)
    legend.set_gid("legend-path")


def _draw_approach_panel(ax2, sch: _Schedule, data: _Approach) -> None:
    """Right: figure 4-21, (b_n - b_inf) / a against n on log-log axes, with the tip-line
    schedule, the fit, the target and the floor."""
    b, a = sch.b, sch.a
    n = np.arange(1, b.size + 1, dtype=float)
    dev, floor_rel, target_rel, tip_dev = data.dev, data.floor_rel, data.target_rel, data.tip_dev
    ax2.set_xscale("log")
    ax2.set_yscale("log")
    ax2.grid(True, which="both", linewidth=0.3, alpha=0.5)
    handles2: list = []
    xs: list[np.ndarray] = []
    ys: list[np.ndarray] = []
    pos = dev > 0.0
    if np.any(pos):
        marker = "o" if pos.sum() <= 60 else None
        (h,) = ax2.plot(n[pos], dev[pos], color=COLORS["schedule"], linewidth=1.3, marker=marker, markersize=3,
                        zorder=3, label="(b_n - b_inf) / a", gid="schedule")
        handles2.append(h)
        xs.append(n[pos])
        ys.append(dev[pos])
    else:
        handles2.append(Line2D([], [], color=COLORS["schedule"], label="(b_n - b_inf) / a: none above b_inf"))
    if tip_dev is not None:
        tpos = tip_dev > 0.0
        nt = np.arange(1, tip_dev.size + 1, dtype=float)
        if np.any(tpos):
            (h,) = ax2.plot(nt[tpos], tip_dev[tpos], color=COLORS["tip_line"], linewidth=1.1, linestyle="--",
                            zorder=2, label=f"tip-line schedule ({tip_dev.size} revolutions)",
                            gid="tip-line-schedule")
            handles2.append(h)
            xs.append(nt[tpos])
            ys.append(tip_dev[tpos])
    if sch.fit is not None:
        handles2.append(_draw_fit(ax2, sch.fit, a, xs, ys))
    for value, key, text in ((target_rel, "target", "target"), (floor_rel, "b_floor", "table floor b_floor")):
        if value is not None and value > 0.0:
            h = ax2.axhline(value, color=COLORS[key], linestyle=":", linewidth=1.0, zorder=1,
                            label=f"{text}: {value:.3g} a above b_inf", gid=f"level-{key.replace('_', '-')}")
            handles2.append(h)
            ys.append(np.array([value]))
    if xs:
        x_all, y_all = np.concatenate(xs), np.concatenate(ys)
        x_hi = max(float(x_all.max()), 2.0)
        ax2.set_xlim(0.8, 1.25 * x_hi)
        y_lo, y_hi = float(y_all.min()), float(y_all.max())
        if y_hi <= y_lo * 1.0001:
            y_lo, y_hi = y_lo / 10.0, y_hi * 10.0
        ax2.set_ylim(y_lo / 1.5, y_hi * 1.5)
    else:
        ax2.set_xlim(0.8, 1.25 * max(float(b.size), 2.0))
        ax2.set_ylim(1e-3, 1e1)
        ax2.text(0.5, 0.5, "every b_n is at or below b_inf", transform=ax2.transAxes, ha="center",
                 va="center", color="#888888", fontsize=9)
    ax2.set_xlabel("revolution n")
    ax2.set_ylabel("(b_n - b_inf) / a")
    ax2.set_title("figure 4-21: approach to b_inf", fontsize=9)
    legend2 = ax2.legend(handles=handles2, loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=1,
                         fontsize=7, framealpha=0.85)
    legend2.set_gid("legend-schedule")


def _draw_fit(ax2, fit: tuple[float, float, int, int], a: float, xs: list, ys: list):
    """The power-law fit's line (its legend handle; what it draws joins ``xs``, ``ys``)."""
    k_fit, c_fit, n_min, n_max = fit
    label = f"fit (b_n - b_inf) = {c_fit:.3g} {_power_label(k_fit)}, n in [{n_min}, {n_max}]"
    lo_n, hi_n = max(min(n_min, n_max), 1), max(n_min, n_max, 1)
    nf = np.geomspace(lo_n, hi_n, 64) if hi_n > lo_n else np.array([float(lo_n)])
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        yf = c_fit * nf ** (-k_fit) / a
    ok = np.isfinite(yf) & (yf > 0.0)
    if not np.any(ok):
        return Line2D([], [], color=COLORS["fit"], linestyle="-.", label=f"{label} (not drawable)")
    (h,) = ax2.plot(nf[ok], yf[ok], color=COLORS["fit"], linewidth=1.6, linestyle="-.",
                    marker="s" if ok.sum() == 1 else None, zorder=4, label=label, gid="fit")
    xs.append(nf[ok])
    ys.append(yf[ok])
    return h


def build_schedule_figure(radii, a: float, b_inf: float, b_floor: float, path_points, centre, target,
                          fit, title: str, tip_line_radii=None) -> Figure:
    """The two panels on a new SVG-canvas figure (see :func:`render_schedule_svg`)."""
    sch = _checked_schedule(radii, a, b_inf, b_floor, path_points, centre, target, fit, tip_line_radii)
    data = _Approach.of(sch)
    fig = new_figure(2.0 * FIGSIZE_IN, FIGSIZE_IN)
    ax, ax2 = fig.subplots(1, 2)
    _draw_path_panel(ax, sch)
    _draw_approach_panel(ax2, sch, data)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig


def render_schedule_svg(radii: np.ndarray, a: float, b_inf: float, b_floor: float,
                        path_points: np.ndarray | None, centre: np.ndarray, target: float | None,
                        fit: tuple[float, float, int, int] | None, title: str,
                        tip_line_radii: np.ndarray | None = None) -> str:
    """The schedule as SVG text, two panels side by side.

    Left: the pusher's path ``path_points`` (world coordinates, (M, 2); decimated to at
    most :data:`MAX_PATH_POINTS` vertices, first and last kept), with dashed circles of
    radius b_1 = ``radii[0]``, ``target`` (if given) and ``b_inf`` about ``centre``; equal
    aspect, drawn relative to the centre when it is far away and in units of 10^k for very
    small or large views (axis labels say so). Without a path, the revolutions b_n are
    drawn as thin circles (at most :data:`MAX_REVOLUTION_CIRCLES`).

    Right (figure 4-21): (b_n - b_inf) / a against n = 1..N on log-log axes (values <= 0
    skipped); ``fit`` = (k, C, n_min, n_max) means b_n - b_inf = C n^-k in length units
    (C is a length), drawn divided by a over [n_min, n_max]; ``tip_line_radii`` (the
    tip-line schedule's b_n) dashed, also minus b_inf and over a; ``target`` and
    ``b_floor`` as horizontal dotted levels when above b_inf.

    Raises NonFiniteResult on NaN or infinite input (or a ratio that overflows), and
    ValueError on wrongly shaped arrays or a non-positive ``a``."""
    fig = build_schedule_figure(radii, a, b_inf, b_floor, path_points, centre, target, fit, title,
                                tip_line_radii)
    return _svg_text(fig, title)
