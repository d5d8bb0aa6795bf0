"""The COR sketch of a disk-bounded part pushed with pusher friction (book 4.1).

With friction mu_c between pusher and part the pusher's force lies in the friction cone
of half-angle nu = atan(mu_c) about the edge normal n (4.1, (4.1)). Every possible COR is
consistent with the force that produces it (4.1.3-4.1.4):

* slipping: the force is on a cone edge, d+ = (n + mu_c alpha)/|.| or d- = (n - mu_c
  alpha)/|.|, and the motion is the frictionless one for that force: the COR lies in the
  elementary locus {COR}_{alpha+-nu} of the scene whose edge is turned by +-nu (its
  normal is d+-). Friction on the part points along the pusher's slip relative to it, so
  the d+ edge goes with the part's contact moving *down* relative to the pusher (along
  -J p, the book's "down" when the push is drawn along +x) and d- with *up*;
* sticking: the COR is on the sticking line, through c perpendicular to p (4.1.2.1), and
  the force anywhere in the cone: the sticking locus is the union over phi in [-nu, nu] of
  {COR}_phi intersected with the sticking line (4.1.4).

Kinematic consistency, for a COR r: the contact keeps up with the pusher, n . v(c) = n . p,
so omega = -sin(alpha) / (alpha . (c - r)) (3.3) with the TRUE edge normal, and the part's
contact moves relative to the pusher by (v(c) - p) . J p = omega (c - r) . p. A COR of
{COR}_d rotates the part with that locus's sense, sign(omega) = -sign(m_d), m_d = alpha_d . c,
so r must lie where -sin(alpha)/(alpha . (c - r)) has that sign. Both conditions are
half-planes, bounded by the edge-normal line through c and by the sticking line (figure 4-2):

    down-slipping locus = {COR}_+ ∩ {sign(m_+) alpha.(c - r) > 0} ∩ {sign(m_+)(c - r).p > 0}
    up-slipping locus   = {COR}_- ∩ {sign(m_-) alpha.(c - r) > 0} ∩ {-sign(m_-)(c - r).p > 0}

and on the sticking line (c - r parallel to J p) sticking needs sign((c - r) . J p) =
sign(m_phi).

Elementary configurations (4.1.5) of each locus against the sticking line: *wrapped* when
its sense is not the part's (Mason's rule, 1.6.2) or it is a translation; otherwise *pure
slipping* when it misses the sticking line, *same-sided split* when it crosses it with its
tip on the CM's side, *opposite-sided split* with the tip across. As alpha decreases a
locus runs through P -> S -> O -> W, and {COR}_{alpha+nu} is never later than
{COR}_{alpha-nu}; the nine sketches (4.1.6, figure 4-6, whose drawing is missing from the
text) are the pairs (config of {COR}_{alpha+nu}, config of {COR}_{alpha-nu}) in that order,
except (W, W). Reconstructed from the text's statements about them:

    a = (P, P) must slip up          b = (P, S), d = (P, O)  stick or slip up
    c = (S, S), e = (S, O), f = (O, O)  anything             g = (P, W)  must stick
    h = (S, W), i = (O, W)  stick or slip down

(g: "sweeping from the pure slipping locus to the wrapped locus"; i: "the tip of
{COR}_{alpha+nu} is left of the sticking line", i.e. opposite-sided, (4.17).) Mirror images
(contact on the other side, the other sense of rotation, 4.1.6) swap the roles of the two
loci and of up and down: a pair out of order is the mirror image of the ordered one (for
equal configurations the CM's zone decides, see :func:`cor_sketch`); the sketch reports the
letter of its canonical image and whether it is mirrored. The modes a sketch allows are also computed directly from which of its
three loci are non-empty.

The elementary loci are the exact analytic disk loci of models/locus/cor_disk.py. The sticking
locus is found here by the book's own construction -- a sweep of phi over the cone, each
{COR}_phi intersected with the sticking line, refined at the extremes by golden-section
search -- which is exact up to the boundary polygons' resolution; solver/sketch/sticking.py
solves the same question as a convex feasibility problem in the pressure distribution.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from models.core.errors import InvalidInput
from models.core.mpp import mason_sense, perp
from models.core.scene import PushScene
from models.locus.cor_disk import DiskCorLocus, disk_boundaries, disk_cor_locus

Configuration = str  # "pure_slipping" | "same_sided_split" | "opposite_sided_split" | "wrapped"
CONFIG_ORDER = ("pure_slipping", "same_sided_split", "opposite_sided_split", "wrapped")
_SHORT = {"pure_slipping": "P", "same_sided_split": "S", "opposite_sided_split": "O", "wrapped": "W"}

SKETCHES = {
    ("P", "P"): "a", ("P", "S"): "b", ("S", "S"): "c",
    ("P", "O"): "d", ("S", "O"): "e", ("O", "O"): "f",
    ("P", "W"): "g", ("S", "W"): "h", ("O", "W"): "i",
}
"""Sketch letter (figure 4-6) of (config of {COR}_{alpha+nu}, config of {COR}_{alpha-nu})."""

IMPLICATIONS = {
    "a": "must_slip_up", "b": "stick_or_slip_up", "d": "stick_or_slip_up",
    "c": "anything", "e": "anything", "f": "anything",
    "g": "must_stick", "h": "stick_or_slip_down", "i": "stick_or_slip_down",
}
"""What each sketch implies (4.1.6), for the canonical (unmirrored) orientation."""

IMPLIED_MODES = {
    "must_slip_up": ("slipping_up",),
    "must_slip_down": ("slipping_down",),
    "stick_or_slip_up": ("sticking", "slipping_up"),
    "stick_or_slip_down": ("sticking", "slipping_down"),
    "must_stick": ("sticking",),
    "anything": ("sticking", "slipping_up", "slipping_down"),
}
"""The modes each implication allows."""

SWEEP_POINTS = 33
"""Force angles of the coarse sweep over the cone (then refined by golden section)."""

GOLDEN_STEPS = 40
"""Golden-section steps refining each extreme of the sticking locus over phi."""


@dataclass(frozen=True)
class ElementaryLocus:
    """{COR}_{alpha +- nu}: the frictionless locus for force direction ``force`` (world unit
    vector), its boundary (world, closed CCW polygon; None for a translation), tip,
    configuration, and its moment-arm sign (the sign of alpha_d . c)."""

    label: str
    force: np.ndarray
    boundary: np.ndarray | None
    tip: np.ndarray | None
    moment_sign: int
    configuration: Configuration
    crosses_sticking_line: bool
    tip_on_cm_side: bool | None


@dataclass(frozen=True)
class StickingLocus:
    """The sticking locus: the segment of the sticking line between positions ``t_low`` and
    ``t_high`` (signed distances from c along J p), with its end points (world) and the
    force angles phi (relative to n, CCW) that produce each end (None when the ends come
    from the exact feasibility problem of solver/sketch/sticking.py, which has no single angle)."""

    t_low: float
    t_high: float
    low: np.ndarray
    high: np.ndarray
    phi_low: float | None
    phi_high: float | None


@dataclass(frozen=True)
class CorSketch:
    """The COR sketch (4.1). Polygons are world-frame lists of vertices (possibly several
    pieces per locus). ``allowed_modes`` are the modes whose loci are non-empty."""

    mu_c: float
    nu: float
    sense: str
    sticking_line_point: np.ndarray
    sticking_line_direction: np.ndarray
    edge_normal_direction: np.ndarray
    plus: ElementaryLocus
    minus: ElementaryLocus
    down_slipping: tuple[np.ndarray, ...]
    up_slipping: tuple[np.ndarray, ...]
    sticking: StickingLocus | None
    tip_line_low: np.ndarray | None
    tip_line_t: float | None
    tip_line_error: float | None
    sketch: str | None  # None: the loci match none of the nine sketches of figure 4-6
    mirrored: bool
    implication: str | None
    allowed_modes: tuple[str, ...]


def force_scene(scene: PushScene, phi: float) -> tuple[PushScene, int]:
    """The frictionless scene whose force is n turned by ``phi`` (CCW, radians): the same
    contact with the edge turned by phi (4.1, {COR}_phi), and the sign of that force's
    moment arm alpha_d . c (0 for a translation).

    The frictionless locus depends on the force line and the contact only, not on the
    push direction (p only scales the rotation rate, (3.3)), so the turned scene pushes
    along its own normal d: no grazing case arises even where a wide cone's edge points
    away from the actual push.
    """
    d = np.array([
        math.cos(phi) * scene.normal[0] - math.sin(phi) * scene.normal[1],
        math.sin(phi) * scene.normal[0] + math.cos(phi) * scene.normal[1],
    ])
    turned = PushScene.create(
        scene.disk_radius, scene.contact_point, scene.edge_angle + phi, math.atan2(d[1], d[0]),
        scene.center_of_mass, scene.tolerances,
    )
    if turned.is_translation:
        return turned, 0
    return turned, (1 if turned.moment_arm > 0.0 else -1)


def clip_half_plane(poly: np.ndarray, normal: np.ndarray, offset: float) -> np.ndarray:
    """Sutherland-Hodgman: the part of a closed polygon with normal . x > offset (each
    vertex inside kept, then the crossing of its edge to the next when the edge crosses;
    all edges at once)."""
    if poly is None or len(poly) == 0:
        return np.empty((0, 2))
    s = poly @ normal - offset
    inside = s > 0.0
    nxt = np.roll(np.arange(len(poly)), -1)
    crossing = inside != inside[nxt]
    t = np.where(crossing, s / np.where(crossing, s - s[nxt], 1.0), 0.0)
    cut = poly + t[:, None] * (poly[nxt] - poly)
    both = np.stack([poly, cut], axis=1).reshape(-1, 2)
    keep = np.stack([inside, crossing], axis=1).reshape(-1)
    return both[keep] if keep.any() else np.empty((0, 2))


def _line_intervals(poly: np.ndarray, origin: np.ndarray, direction: np.ndarray) -> list[tuple[float, float]]:
    """Intervals of t where origin + t direction is inside the closed polygon (even-odd)."""
    rel = poly - origin
    nrm = perp(direction)
    s = rel @ nrm
    i = np.flatnonzero((s > 0.0) != (np.roll(s, -1) > 0.0))  # edges i -> i + 1 the line crosses
    j = (i + 1) % len(poly)
    u = s[i] / (s[i] - s[j])
    p = rel[i] + u[:, None] * (rel[j] - rel[i])
    ts = np.sort(p[:, 0] * direction[0] + p[:, 1] * direction[1]).tolist()
    return [(ts[k], ts[k + 1]) for k in range(0, len(ts) - 1, 2)]


def _locus(scene: PushScene, phi: float, n_points: int) -> tuple[int, PushScene, DiskCorLocus | None]:
    """(moment sign of the turned force, its analytic locus or None for a translation)."""
    sc, m_sign = force_scene(scene, phi)
    if m_sign == 0:
        return 0, sc, None
    return m_sign, sc, disk_cor_locus(sc, outputs=["tip", "boundary"], n_points=n_points)


def sticking_spans(scene: PushScene, phis: Sequence[float], n_points: int) -> list[tuple[float, float] | None]:
    """At each force angle phi, the part of the sticking line inside {COR}_phi where
    sticking is consistent with that locus's sense: (t_min, t_max) or None; the loci's
    boundaries solved at once (models/locus/cor_disk.py, disk_boundaries)."""
    turned = [force_scene(scene, float(phi)) for phi in phis]
    bounded = [i for i, (_, m_sign) in enumerate(turned) if m_sign != 0]
    out: list[tuple[float, float] | None] = [None] * len(turned)
    c = scene.contact_point
    jp = perp(scene.push_hat)
    for i, boundary in zip(bounded, disk_boundaries([turned[i][0] for i in bounded], n_points)):
        sgn = float(turned[i][1])
        spans = []
        for lo, hi in _line_intervals(boundary, c, jp):
            # r = c + t J p: (c - r) . J p = -t must have the sign of m_phi.
            if sgn > 0.0:
                lo, hi = lo, min(hi, 0.0)
            else:
                lo, hi = max(lo, 0.0), hi
            if hi > lo:
                spans.append((lo, hi))
        if spans:
            out[i] = (min(s[0] for s in spans), max(s[1] for s in spans))
    return out


Spans = Callable[[PushScene, Sequence[float], int], list[tuple[float, float] | None]]
"""The sticking sweep's question at many force angles, :func:`sticking_spans`'s signature:
the solver passes its compiled twin (solver/sketch/sweep.py), the same answers to rounding."""


def _golden(evaluate: Callable[[list[int], list[float]], list[float]], brackets: Sequence[tuple[float, float]],
            steps: int) -> list[float]:
    """Argmin of each f_k on its bracket [lo, hi] by golden section (f_k unimodal near the
    bracket), the searches in lockstep: ``evaluate(ks, xs)`` gives f_k(x) for each pair,
    so each step's points are evaluated together."""
    g = (math.sqrt(5.0) - 1.0) / 2.0
    lo = [b[0] for b in brackets]
    hi = [b[1] for b in brackets]
    ks = list(range(len(brackets)))
    x1 = [hi[k] - g * (hi[k] - lo[k]) for k in ks]
    x2 = [lo[k] + g * (hi[k] - lo[k]) for k in ks]
    both = evaluate(ks + ks, x1 + x2)
    f1, f2 = both[:len(ks)], both[len(ks):]
    for _ in range(steps):
        lower = [f1[k] <= f2[k] for k in ks]
        for k in ks:
            if lower[k]:
                hi[k], x2[k], f2[k] = x2[k], x1[k], f1[k]
                x1[k] = hi[k] - g * (hi[k] - lo[k])
            else:
                lo[k], x1[k], f1[k] = x1[k], x2[k], f2[k]
                x2[k] = lo[k] + g * (hi[k] - lo[k])
        new = evaluate(ks, [x1[k] if lower[k] else x2[k] for k in ks])
        for k in ks:
            if lower[k]:
                f1[k] = new[k]
            else:
                f2[k] = new[k]
    return [x1[k] if f1[k] <= f2[k] else x2[k] for k in ks]


def sweep_angles(scene: PushScene, nu: float) -> np.ndarray:
    """Force angles of the coarse sweep: uniform over [-nu, nu], plus, when the cone holds
    the force line through the CM (angle phi0), angles crowding geometrically towards phi0
    from both sides: there the loci {COR}_phi grow like a^2/|alpha_phi . c| and reach the
    sticking line far away, over a range of phi too narrow for a uniform sweep."""
    phis = [np.linspace(-nu, nu, SWEEP_POINTS)]
    c = scene.contact_rel
    if float(np.linalg.norm(c)) > 0.0:
        n = scene.normal
        for d in (c, -c):
            phi0 = math.atan2(n[0] * d[1] - n[1] * d[0], float(n @ d))
            if -nu < phi0 < nu:
                offs = np.geomspace(1e-9, 2.0 * nu, SWEEP_POINTS)
                phis.append(np.clip(np.concatenate([phi0 - offs, phi0 + offs]), -nu, nu))
    out = np.unique(np.concatenate(phis))
    return out


def sticking_locus_sweep(scene: PushScene, mu_c: float, n_points: int = 1024,
                         spans: Spans = sticking_spans) -> StickingLocus | None:
    """The sticking locus by the book's construction (4.1.4): sweep phi over [-nu, nu],
    intersect each {COR}_phi with the sticking line, take the union; the two extremes are
    refined by golden-section search over phi around the best coarse angle. ``spans``
    answers each angle's question (:data:`Spans`)."""
    nu = math.atan(mu_c)
    phis = sweep_angles(scene, nu)
    found = spans(scene, [float(ph) for ph in phis], n_points)
    coarse = {i: s for i, s in enumerate(found) if s is not None}
    have = list(coarse)
    if not have:
        return None
    big = 1e300

    def low_and_neg_high(ks: list[int], xs: list[float]) -> list[float]:
        """f_0 = the span's low end, f_1 = minus its high end (big where there is none)."""
        found = spans(scene, xs, n_points)
        return [big if s is None else (s[0] if k == 0 else -s[1]) for k, s in zip(ks, found)]

    def bracket(i: int) -> tuple[float, float]:
        return float(phis[max(i - 1, 0)]), float(phis[min(i + 1, len(phis) - 1)])

    i_lo = min(have, key=lambda i: coarse[i][0])
    i_hi = max(have, key=lambda i: coarse[i][1])
    p_lo, p_hi = _golden(low_and_neg_high, [bracket(i_lo), bracket(i_hi)], GOLDEN_STEPS)
    t_lo, neg_t_hi = low_and_neg_high([0, 1], [p_lo, p_hi])
    t_hi = -neg_t_hi
    if not t_lo <= coarse[i_lo][0]:
        t_lo, p_lo = coarse[i_lo][0], float(phis[i_lo])
    if not t_hi >= coarse[i_hi][1]:
        t_hi, p_hi = coarse[i_hi][1], float(phis[i_hi])
    c = scene.contact_point
    jp = perp(scene.push_hat)
    return StickingLocus(t_lo, t_hi, c + t_lo * jp, c + t_hi * jp, p_lo, p_hi)


def tip_line_estimate(scene: PushScene) -> float | None:
    """The book's approximation of the sticking locus's far end (4.1.4): where the tip line
    (3.3.11.1: the line r . c_hat = -a^2/|c|) meets the sticking line, as t along J p.
    None when they are parallel or the contact is at the CM."""
    c = scene.contact_rel
    cn = float(np.linalg.norm(c))
    if cn == 0.0:
        return None
    c_hat = c / cn
    jp = perp(scene.push_hat)
    den = float(jp @ c_hat)
    if abs(den) < 1e-15:
        return None
    a = scene.disk_radius
    return -(cn * cn + a * a) / (cn * den)


def disk_elementary_locus(scene: PushScene, sigma: float, mu_c: float, sense: str, n_points: int) -> ElementaryLocus:
    """{COR}_{alpha + sigma nu} of the scene's disk: the analytic locus (3.30, 3.35) of the
    force-turned scene, classified (:func:`classify_locus`)."""
    nu = math.atan(mu_c)
    m_sign, sc, loc = _locus(scene, sigma * nu, n_points)
    return classify_locus(scene, sigma, mu_c, sense, m_sign,
                          None if loc is None else loc.boundary, None if loc is None or loc.tip is None else loc.tip.point)


def classify_locus(
    scene: PushScene, sigma: float, mu_c: float, sense: str, m_sign: int,
    boundary: np.ndarray | None, tip: np.ndarray | None,
) -> ElementaryLocus:
    """{COR}_{alpha + sigma nu} with the given boundary (world, closed polygon; None for a
    translation) and tip: its elementary configuration (4.1.5) against the sticking line.
    Wrapped when its own sense (the sign ``m_sign`` of its moment arm) is not the part's
    ``sense`` (Mason's rule with the cone, 1.6.2)."""
    label = "alpha_plus_nu" if sigma > 0 else "alpha_minus_nu"
    force = (scene.normal + sigma * mu_c * scene.alpha_hat) / math.hypot(1.0, mu_c)
    own_sense = {1: "cw", -1: "ccw", 0: "none"}[m_sign]
    if boundary is None or own_sense != sense:
        return ElementaryLocus(label, force, boundary, tip, m_sign, "wrapped", False, None)
    if tip is None:
        raise InvalidInput("tip", "a locus boundary needs its tip")
    c = scene.contact_point
    jp = perp(scene.push_hat)
    crosses = bool(_line_intervals(boundary, c, jp))
    def side(x: np.ndarray) -> float:  # sign of the side of the sticking line
        return float((x - c) @ scene.push_hat)

    tip_same = bool(np.sign(side(tip)) == np.sign(side(scene.center_of_mass)))
    if not crosses:
        config = "pure_slipping"
    else:
        config = "same_sided_split" if tip_same else "opposite_sided_split"
    return ElementaryLocus(label, force, boundary, tip, m_sign, config, crosses, tip_same)


def _slipping_piece(scene: PushScene, locus: ElementaryLocus, sigma: float) -> tuple[np.ndarray, ...]:
    if locus.configuration == "wrapped" or locus.boundary is None:
        return ()
    c = scene.contact_point
    sgn = float(locus.moment_sign)
    # sign(m) alpha . (c - r) > 0  <=>  (-sign(m) alpha) . r > -sign(m) alpha . c
    piece = clip_half_plane(locus.boundary, -sgn * scene.alpha_hat, float(-sgn * scene.alpha_hat @ c))
    # sigma sign(m) (c - r) . p > 0  <=>  (-sigma sign(m) p) . r > -sigma sign(m) p . c
    k = sigma * sgn
    piece = clip_half_plane(piece, -k * scene.push_hat, float(-k * scene.push_hat @ c))
    return (piece,) if len(piece) >= 3 else ()


def disk_cor_sketch(scene: PushScene, mu_c: float, n_points: int = 512, sweep_points: int | None = None,
                    spans: Spans = sticking_spans) -> CorSketch:
    """The COR sketch of ``scene`` with pusher friction ``mu_c`` (book 4.1): elementary loci
    with ``n_points`` boundary points, the sticking sweep's loci with ``sweep_points``
    (default max(n_points, 1024): the sticking ends are where the sketch is most sensitive),
    each answered by ``spans`` (:data:`Spans`)."""
    check_mu_c(mu_c)
    sense = sketch_sense(scene, mu_c)
    plus = disk_elementary_locus(scene, 1.0, mu_c, sense, n_points)
    minus = disk_elementary_locus(scene, -1.0, mu_c, sense, n_points)
    sweep_n = max(n_points, 1024) if sweep_points is None else sweep_points
    stick = sticking_locus_sweep(scene, mu_c, sweep_n, spans) if sense != "none" else None
    return assemble_sketch(scene, mu_c, sense, plus, minus, stick)


def check_mu_c(mu_c: float) -> None:
    if not (math.isfinite(mu_c) and mu_c > 0.0):
        raise InvalidInput("mu_c", "must be a positive finite number (mu_c = 0 is the frictionless locus)")


def sketch_sense(scene: PushScene, mu_c: float) -> str:
    """The part's sense of rotation by Mason's rule with the friction cone (1.6.2)."""
    return mason_sense(scene.contact_rel, scene.normal, scene.push_hat, mu_c)


def assemble_sketch(
    scene: PushScene, mu_c: float, sense: str, plus: ElementaryLocus, minus: ElementaryLocus,
    stick: StickingLocus | None,
) -> CorSketch:
    """The sketch (4.1.3-4.1.6) from its two elementary loci (:func:`classify_locus`) and
    its sticking locus, however they were computed (analytic disk loci and the sweep here;
    certified polygon loci and the exact sticking locus in solver/sketch/certified_sketch.py):
    the slipping loci, the tip-line estimate, the letter of figure 4-6 and the modes."""
    nu = math.atan(mu_c)
    down = _slipping_piece(scene, plus, 1.0)
    up = _slipping_piece(scene, minus, -1.0)
    t_tip = tip_line_estimate(scene)
    tip_point = tip_err = None
    if t_tip is not None:
        tip_point = scene.contact_point + t_tip * perp(scene.push_hat)
        if stick is not None:
            tip_err = min(abs(t_tip - stick.t_low), abs(t_tip - stick.t_high))
    # Canonical orientation (the book's figures): {COR}_{alpha+nu} is not later than
    # {COR}_{alpha-nu} in the order P < S < O < W; the mirror image swaps the roles of the
    # two loci and of up and down. When both have the same configuration the order cannot
    # tell: then the sketch is canonical when the CM lies in the up-slipping zone, where
    # the book's pure-slipping loci lie: omega_n(CM) (c - CM) . p = -sin(alpha)/m (c . p) > 0.
    pair = (_SHORT[plus.configuration], _SHORT[minus.configuration])
    rank = {k: i for i, k in enumerate("PSOW")}
    if pair[0] != pair[1]:
        mirrored = rank[pair[0]] > rank[pair[1]]
    else:
        mirrored = (1.0 if scene.moment_arm > 0.0 else -1.0) * float(scene.contact_rel @ scene.push_hat) > 0.0
    if mirrored:
        pair = (pair[1], pair[0])
    letter = SKETCHES.get(pair)
    implication = None if letter is None else IMPLICATIONS[letter]
    if mirrored and implication is not None:
        implication = implication.replace("up", "@").replace("down", "up").replace("@", "down")
    modes = []
    if stick is not None:
        modes.append("sticking")
    if up:
        modes.append("slipping_up")
    if down:
        modes.append("slipping_down")
    if implication is not None and set(modes) != set(IMPLIED_MODES[implication]):
        # The loci do not match the book's sketch of this letter (e.g. a cone edge pointing
        # back against the push, which the book's figures never show): no letter.
        letter = implication = None
    return CorSketch(
        mu_c=mu_c,
        nu=nu,
        sense=sense,
        sticking_line_point=scene.contact_point.copy(),
        sticking_line_direction=perp(scene.push_hat),
        edge_normal_direction=scene.normal.copy(),
        plus=plus,
        minus=minus,
        down_slipping=down,
        up_slipping=up,
        sticking=stick,
        tip_line_low=tip_point,
        tip_line_t=t_tip,
        tip_line_error=tip_err,
        sketch=letter,
        mirrored=mirrored,
        implication=implication,
        allowed_modes=tuple(modes),
    )


@dataclass(frozen=True)
class ExtremeCor:
    """The consistent COR farthest along a direction: ``point`` (world), ``value`` =
    direction . point, and ``source``: "sticking", "slipping_up" or "slipping_down"."""

    point: np.ndarray
    value: float
    source: str


def extreme_cor(sketch: CorSketch, direction: ArrayLike) -> ExtremeCor | None:
    """max over all CORs of the sketch of direction . r (4.2: the COR that makes a gross
    motion slowest or fastest, e.g. direction -alpha for the longest push of (4.2)).

    The maximum of a linear function over the sketch is attained at a vertex of a
    slipping-locus polygon or at an end of the sticking segment; None for an empty sketch.
    """
    u = np.asarray(direction, dtype=float)
    u = u / float(np.linalg.norm(u))
    best: ExtremeCor | None = None
    candidates = []
    if sketch.sticking is not None:
        candidates += [(sketch.sticking.low, "sticking"), (sketch.sticking.high, "sticking")]
    for polys, name in ((sketch.up_slipping, "slipping_up"), (sketch.down_slipping, "slipping_down")):
        for poly in polys:
            k = int(np.argmax(poly @ u))
            candidates.append((poly[k], name))
    for point, name in candidates:
        value = float(point @ u)
        if best is None or value > best.value:
            best = ExtremeCor(np.asarray(point, dtype=float).copy(), value, name)
    return best
