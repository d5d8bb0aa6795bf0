"""The spiral-localization pictures (service/api/spiral/render.py): figure 4-19 (a / r* against
beta / pi) and the schedule (pusher path + figure 4-21), on synthetic numpy data."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from service.api.spiral.render import (
    MAX_PATH_POINTS,
    CriticalCurve,
    decimate_polyline,
    decimation_indices,
    render_critical_radius_svg,
    render_schedule_svg,
)
from service.errors import NonFiniteResult

SVG = "{http://www.w3.org/2000/svg}"
BETAS = np.linspace(0.05, 0.5 * math.pi - 1e-3, 60)
N = np.arange(1, 120, dtype=float)
B_INF = 1.25
RADII = B_INF + 100.0 / N**1.5  # b_n in units of a = 1
TIP = 2.0 + 100.0 / N


def curve(mu_c: float, a: float = 1.0, **kw) -> CriticalCurve:
    b_inf = a * (1.0 + min(mu_c, 1.0))
    r = b_inf + 1.3 * (2.0 * a / np.sin(BETAS) - 2.0 * a)
    kw.setdefault("tip_line", 2.0 * a / np.sin(BETAS))
    kw.setdefault("b_inf", b_inf)
    kw.setdefault("certified", np.arange(BETAS.size) % 4 != 0)
    return CriticalCurve(label=kw.pop("label", "exact"), mu_c=mu_c, betas=BETAS, radii=r, a=a, **kw)


def spiral_points(radii: np.ndarray, n_points: int, centre=(0.0, 0.0)) -> np.ndarray:
    """A polyline through the revolutions, radius linear in the angle."""
    turns = np.linspace(0.0, radii.size - 1, n_points)
    rho = np.interp(turns, np.arange(radii.size), radii)
    th = 2.0 * math.pi * turns
    return np.c_[rho * np.cos(th), rho * np.sin(th)] + np.asarray(centre)


def schedule(scale: float = 1.0, centre=(0.0, 0.0), path_n: int | None = 5000, **kw) -> str:
    args = dict(
        radii=scale * RADII, a=scale, b_inf=scale * B_INF, b_floor=scale * (B_INF + 1e-4),
        path_points=None if path_n is None else spiral_points(scale * RADII, path_n, centre),
        centre=np.asarray(centre, dtype=float), target=scale * 2.0, fit=(1.5, scale * 100.0, 10, 119),
        title="fastest spiral, mu_c = 0.25", tip_line_radii=scale * TIP,
    )
    args.update(kw)
    return render_schedule_svg(**args)


def drawn_paths(svg: str) -> int:
    """<path> elements outside <defs> (glyph outlines live in <defs>, and depend on the
    digits of the tick and legend labels)."""
    root = ET.fromstring(svg)
    in_defs = {id(e) for d in root.iter(f"{SVG}defs") for e in d.iter()}
    return sum(1 for e in root.iter(f"{SVG}path") if id(e) not in in_defs)


def gids(svg: str) -> set[str]:
    return {e.get("id") for e in ET.fromstring(svg).iter() if e.get("id")}


# --------------------------------------------------------------------------------------
# Figure 4-19


def test_critical_radius_svg_labels_and_elements():
    svg = render_critical_radius_svg([curve(0.0), curve(0.25), curve(1.0, label="")], "Figure 4-19")
    root = ET.fromstring(svg)
    assert root.tag == f"{SVG}svg"
    for text in ("beta / pi", "a / r*", "mu_c = 0 (exact)", "mu_c = 0.25 (exact)", "mu_c = 1",
                 "tip line", "a / b_inf", "certified point", "not certified", "Figure 4-19"):
        assert text in svg, text
    ids = gids(svg)
    for i in range(3):
        assert {f"critical-{i}", f"tip-line-{i}", f"b-inf-{i}", f"certified-{i}", f"uncertified-{i}"} <= ids


def test_critical_radius_optional_parts_and_empty():
    c = CriticalCurve(label="mu_c = 0.5 sweep", mu_c=0.5, betas=BETAS, radii=2.0 / np.sin(BETAS), a=1.0)
    svg = render_critical_radius_svg([c], "bare")
    ids = gids(svg)
    assert "critical-0" in ids and not ids & {"tip-line-0", "b-inf-0", "certified-0"}
    assert "mu_c = 0.5 sweep" in svg and "mu_c = 0.5 (" not in svg  # the label already names mu_c
    ET.fromstring(render_critical_radius_svg([], "nothing"))


@pytest.mark.parametrize("field", ["radii", "betas", "tip_line", "b_inf", "a", "mu_c"])
def test_critical_radius_rejects_non_finite(field):
    c = curve(0.25)
    bad = {"radii": np.where(BETAS > 1.0, np.nan, c.radii), "betas": np.append(BETAS[:-1], np.inf),
           "tip_line": np.append(c.tip_line[:-1], np.inf), "b_inf": math.nan, "a": math.inf, "mu_c": math.nan}
    kw = {k: getattr(c, k) for k in ("label", "mu_c", "betas", "radii", "a", "tip_line", "b_inf", "certified")}
    kw[field] = bad[field]
    with pytest.raises(NonFiniteResult):
        render_critical_radius_svg([curve(0.0), CriticalCurve(**kw)], "bad")


def test_critical_radius_ratio_overflow_is_non_finite():
    c = CriticalCurve(label="", mu_c=0.25, betas=BETAS, radii=np.full(BETAS.size, 1e-300), a=1e300)
    with pytest.raises(NonFiniteResult):
        render_critical_radius_svg([c], "overflow")


def test_critical_radius_scale_invariant():
    counts = [drawn_paths(render_critical_radius_svg([curve(0.25, a=s), curve(1.0, a=s)], "scale"))
              for s in (1e-6, 1.0, 1e6)]
    assert counts[0] == counts[1] == counts[2]


# --------------------------------------------------------------------------------------
# The schedule


@pytest.mark.slow
def test_schedule_svg_labels_and_elements():
    svg = schedule()
    ET.fromstring(svg)
    for text in ("revolution n", "(b_n - b_inf) / a", "n^-1.5", "b_1 = 101.2", "target = 2", "b_inf = 1.25",
                 "tip-line schedule", "pusher path", "centre", "fastest spiral, mu_c = 0.25"):
        assert text in svg, text
    assert {"pusher-path", "path-start", "circle-b-1", "circle-target", "circle-b-inf", "centre", "schedule",
            "fit", "tip-line-schedule", "level-target", "level-b-floor"} <= gids(svg)


@pytest.mark.parametrize("field", ["radii", "path_points", "centre", "target", "fit", "a", "b_inf", "b_floor",
                                   "tip_line_radii"])
def test_schedule_rejects_non_finite(field):
    path = spiral_points(RADII, 500)
    path[250, 1] = np.nan
    bad = {"radii": np.append(RADII[:-1], np.nan), "path_points": path, "centre": np.array([0.0, np.inf]),
           "target": math.nan, "fit": (math.nan, 100.0, 10, 119), "a": math.nan, "b_inf": -math.inf,
           "b_floor": math.nan, "tip_line_radii": np.append(TIP[:-1], np.inf)}
    with pytest.raises(NonFiniteResult):
        schedule(path_n=500, **{field: bad[field]})


@pytest.mark.slow
@pytest.mark.parametrize("centre", [(0.0, 0.0), (3.0, -2.0)])
def test_schedule_scale_invariant(centre):
    svgs = {s: schedule(scale=s, centre=(s * centre[0], s * centre[1]), path_n=3000) for s in (1e-6, 1.0, 1e6)}
    counts = {s: drawn_paths(svg) for s, svg in svgs.items()}
    assert counts[1e-6] == counts[1.0] == counts[1e6], counts
    assert "x × 1e4" in svgs[1e-6] and "x × 1e-8" in svgs[1e6]  # drawn in units of 10^k (view ~1.2e2 a)
    assert "n^-1.5" in svgs[1e-6] and "n^-1.5" in svgs[1e6]


@pytest.mark.slow
def test_schedule_far_centre_drawn_relative_to_it():
    c = np.array([1e9, -1e9])
    svg = schedule(scale=1e-3, centre=c, path_n=2000)
    assert "x − (1e+09)" in svg and "y − (-1e+09)" in svg
    assert "pusher-path" in gids(svg)


@pytest.mark.slow
def test_schedule_large_polyline_is_decimated():
    """A 100,000-point path is drawn with at most MAX_PATH_POINTS points (the rendering's
    cost is bounded by that, not timed: the suite runs on busy machines too)."""
    path = spiral_points(RADII, 100_000)
    svg = schedule(path_points=path)
    assert f"{MAX_PATH_POINTS} of 100000 points drawn" in svg


@pytest.mark.slow
def test_schedule_degenerate_inputs():
    # a single radius, no path, no target, no fit, no tip line
    one = render_schedule_svg(np.array([3.0]), 1.0, 1.25, 1.25, None, np.zeros(2), None, None, "one")
    ids = gids(one)
    assert {"circle-b-1", "circle-b-inf", "schedule", "revolution-1"} <= ids and "circle-target" not in ids
    # every radius at b_inf: nothing to plot on log axes, said in words
    flat = render_schedule_svg(np.full(5, 1.25), 1.0, 1.25, 1.25, None, np.zeros(2), 1.25, (1.0, 0.0, 1, 5), "flat")
    assert "every b_n is at or below b_inf" in flat and "none above b_inf" in flat
    assert "schedule" not in gids(flat)
    # many revolutions without a path: a bounded number of circles
    many = render_schedule_svg(B_INF + 100.0 / np.arange(1, 20001) ** 1.5, 1.0, B_INF, B_INF, None,
                               np.zeros(2), None, (1.5, 100.0, 7, 7), "many")
    assert sum(1 for i in gids(many) if i.startswith("revolution-")) <= 60
    assert "fit" in gids(many)
    # a path with every point at the centre, and a two-point path
    for path in (np.zeros((10, 2)), np.array([[101.25, 0.0], [2.0, 0.0]])):
        assert "pusher-path" in gids(schedule(path_points=path))


def test_schedule_shape_errors():
    with pytest.raises(ValueError):
        schedule(radii=np.array([]))
    with pytest.raises(ValueError):
        schedule(path_points=np.zeros((10, 3)))
    with pytest.raises(ValueError):
        schedule(a=0.0)


# --------------------------------------------------------------------------------------
# Decimation


def test_decimation_keeps_ends_budget_and_shape():
    pts = spiral_points(RADII, 100_000)
    idx = decimation_indices(pts)
    assert idx[0] == 0 and idx[-1] == len(pts) - 1
    assert len(idx) <= MAX_PATH_POINTS and np.all(np.diff(idx) > 0)
    out = decimate_polyline(pts)
    assert np.array_equal(out[0], pts[0]) and np.array_equal(out[-1], pts[-1])
    # every dropped vertex is close to the kept segment that spans it
    seg = np.clip(np.searchsorted(idx, np.arange(len(pts)), side="right") - 1, 0, len(idx) - 2)
    a, b = pts[idx[seg]], pts[idx[seg + 1]]
    d = b - a
    t = np.clip(np.einsum("ij,ij->i", pts - a, d) / np.einsum("ij,ij->i", d, d), 0.0, 1.0)
    dev = np.hypot(*(pts - a - t[:, None] * d).T)
    assert dev.max() < 2e-3 * np.ptp(pts[:, 0])  # well under a pixel of a 6 inch panel


def test_decimation_small_and_degenerate():
    pts = np.random.default_rng(0).normal(size=(50, 2))
    assert np.array_equal(decimate_polyline(pts), pts)
    same = np.ones((10_000, 2))
    assert np.array_equal(decimation_indices(same), [0, 9_999])
    line = np.c_[np.linspace(0.0, 1.0, 10_000), np.zeros(10_000)]
    assert np.array_equal(decimation_indices(line, max_points=100)[[0, -1]], [0, 9_999])
    assert len(decimation_indices(line, max_points=100)) <= 100
    # a straight line needs only its ends and the forced chunk breaks
    assert len(decimation_indices(line)) <= 70
