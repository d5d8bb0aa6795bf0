"""A part meeting one fence across a conveyor belt: the configuration map of the encounter
(book 5.1, 5.2, 6.4-6.6), bounded with the part's circumscribing disk.

Frames (world, radians, CCW positive). The belt carries the part in -y; fences are
stationary. In the belt's frame the fence is the pusher, moving in +y (push direction
d = (0, 1)) (5.2). ``fence_angle`` gamma is the fence's angle from the x-axis, the
perpendicular to the belt's motion, in (-pi/2, pi/2): the book's "fence angle" of 6.4-6.5
(its experiment's 90 - alpha). A fence with gamma > 0 rises to the right, hangs from the
belt's right side, and the part slides down it to the left; gamma < 0 is its mirror image.
Its face has the normal n = (-sin gamma, cos gamma) (into the part, which comes from +y).

The part: its footprint in the body frame (:func:`feeder_part`, CM at the origin), whose
convex hull h_0..h_{m-1} (CCW) meets the fence; edge j runs from h_j to h_{j+1}, its
direction angle phi_j. Orientation theta turns the body frame
into the world frame.

The phases of one encounter, each derived in docs/mechanics.md ("Chapter 5: a part
meeting a fence") and checked in tests/models/feeder/test_fence.py:

1. First contact: the hull vertex lowest along n. Vertex h_k is in contact for theta in
   [flush_k, flush_{k-1}], where flush_j = gamma - phi_j is the orientation with edge j
   flush on the fence.
2. Sense of rotation: Mason's rule with the friction cone (1.6.2, mpp.mason_sense) at the
   contact, pusher velocity d. Turning in one sense keeps every vote (the CM turns away
   from each ray), so the sense holds until an edge at the vertex is flush: CCW brings
   edge k-1 flush, CW edge k.
3. Sliding or jamming (6.4): a flush part slides along the fence only if
   |tan gamma| > mu_c; otherwise it is carried along the fence and never leaves (jam).
4. Stability of a flush edge (a push function with friction): while it slides flush the
   part translates, so the belt's drag acts through the CM whatever the pressure, and the
   fence's force lies on the friction-cone edge n + mu_c sgn(gamma) t. The edge is stable
   only if that force line through the CM crosses it: with the CM at (u_c, h_c) in the
   edge's frame (from h_j along the edge, height above it), at u_X = u_c - mu_c sgn(gamma) h_c
   in [0, L_j]. Past h_j the part pivots there onto edge j-1; past h_{j+1}, onto edge j+1.
5. Leaving the fence's end (5.1, figure 5-1): when the end E reaches u_X the part turns
   (CCW for gamma > 0) with E a point pusher on the edge. Extreme A: no slip, until the
   edge lies along the belt's motion, a turn of pi/2 - |gamma|. Extreme B: the most slip
   of E toward the edge's upstream end per radian of turn, until E leaves the edge. The
   slip per radian is linear in the COR r: dl/ddelta = (r - c) . J g with
   g = (d . e / d . n_e) n_e - e (e the edge, n_e its inward normal, c the contact), so its
   largest value over all pressure distributions is taken on the frictionless locus of the
   cone edge n_e + mu_c e (the slipping motions toward the upstream end, 4.1), here the
   locus of the circumscribing disk (ch. 3), or 0 when only sticking (or no such slip) is
   possible. The final orientation lies between B and A.
6. Reach (book 1.8.6: "the required length of each fence ... can be easily computed from
   the results of Chapter 4"): the map assumes an edge is flush before the fence's end
   reaches the part. Given the fence's reach beyond the first contact, the orientations
   for which that is not certain are reported (``unaligned``: the map bounds nothing
   there). While a vertex turns on the face, the part's slip toward the end per radian of
   turn is linear in the COR, (r - c) . J g with g as in phase 5 on the face (the same
   contact kinematics, 4.3); slipping toward the end needs the cone edge n + mu_c sgn(gamma) t,
   so its largest value is taken on that force's frictionless disk locus (ch. 3), and
   sticking gives 0. Its integral over the turn to flush (and over the pivots to the edge
   that stays), plus the flush edge's length up to u_X, is the reach needed. Where that
   cone edge passes through the CM the part can slide without turning: the reach needed
   grows without bound toward such an orientation, so no fence aligns every orientation.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.core.mpp import mason_sense, perp
from models.core.scene import PushScene
from models.feeder.arcs import TWO_PI, Arcs, wrap
from models.feeder.maps import ConfigurationMap
from models.locus.cor_disk import Boundaries, disk_boundaries
from models.sketch.disk_sketch import force_scene

PUSH = np.array([0.0, 1.0])
"""The fence's velocity in the belt's frame (unit speed)."""

PUSH_ANGLE = 0.5 * math.pi

BALANCE_SIDE_REL = 1e-9
"""Mason's rule is sampled this far (relative) either side of a mu_c at which a cone edge
passes through the CM, to see the sense on each side."""


@dataclass(frozen=True)
class FeederTolerances:
    """Named tolerances of the fence map.

    Attributes:
        collinear_rel: the CM must lie inside every hull edge by more than this times the
            squared radius (:func:`feeder_part`; the hull itself is the footprint's).
        endpoint_steps: Heun steps of the extreme-B integration along the edge (5.1).
        locus_points: boundary points of each disk locus in that integration.
        grazing_margin: radians short of A at which that integration stops (the edge is
            then nearly along the belt's motion and E barely pushes).
        mu_samples: mu_c values (evenly over an interval) at which extreme B is integrated.
        b_margin: radians taken off B to cover that integration's error (docs/benchmarks.md:
            at the default steps B errs by up to 0.09 deg on the narrow side of FINE, over
            a mu_c interval, and more on the wide, safe side near the friction angle).
        reach_cells: cells per piece of a contact interval in the reach integral (phase 6),
            crowded toward both ends (where the slip rate can grow without bound).
        tail_cells: sub-cells of a piece's last cell where its turn starts at a balance
            (phase 6), each e times narrower toward it; the innermost needs an infinite reach.
        tail_probe: where the rate's growth K / x near a balance is sampled, as a fraction
            of that last cell.
        crossing_rel: u_X this close to an end of its edge (times the part's radius) counts
            as on both sides of it (phase 4: the part may stay or pivot). Where the force
            line passes through a vertex (a rectangle's short edge at mu_c = 0.25) the
            simulator's contact tolerance (1e-9 a) and rounding decide either way.
    """

    collinear_rel: float = 1e-12
    endpoint_steps: int = 16
    locus_points: int = 64
    grazing_margin: float = 1e-6
    mu_samples: int = 3
    b_margin: float = 2e-3
    reach_cells: int = 32
    tail_cells: int = 40
    tail_probe: float = 1e-6
    crossing_rel: float = 1e-6

    def mu_values(self, lo: float, hi: float) -> list[float]:
        """The mu_c at which an interval is sampled: ``mu_samples`` evenly, both ends (one
        for a point)."""
        return [lo] if hi <= lo else [float(m) for m in np.linspace(lo, hi, max(2, self.mu_samples))]


DEFAULT = FeederTolerances()
FINE = FeederTolerances(endpoint_steps=200, locus_points=400, b_margin=0.0)
DESIGN = FeederTolerances(reach_cells=16)
"""A design's preset: reach profiles of every candidate at half the cells, in half the time.
Measured 2026-11-27 on the pentagon's eleven candidates at 20-70 degrees, mu_c 0.25: the
first fence's reach for a 0.5 % loss grows by 2 to 15 %, the reach for a 29 degree arc by
-1 to 9 % (a coarser upper sum is a looser bound, never a tighter one)."""


def feeder_part(vertices: ArrayLike, center_of_mass: ArrayLike = (0.0, 0.0),
                tol: FeederTolerances = DEFAULT) -> Footprint:
    """The part as the fence maps take it: its footprint (:meth:`Footprint.create`, one
    validation for every route) in the body frame, the CM at the origin
    (:meth:`Footprint.centred`; ``center_of_mass`` defaults to the origin of ``vertices``).
    The CM must lie strictly inside the convex hull: on a hull edge, that edge has no height
    above the CM and phase 4 could not decide it."""
    part = Footprint.create(vertices, center_of_mass).centred()
    hull = part.hull
    e = np.roll(hull, -1, axis=0) - hull
    inside = e[:, 0] * (-hull[:, 1]) - e[:, 1] * (-hull[:, 0])  # edge x (CM - h_j)
    if not np.all(inside > tol.collinear_rel * part.circumradius ** 2):
        raise InvalidInput("center_of_mass", "must lie strictly inside the part's convex hull")
    return part


@dataclass(frozen=True)
class Fence:
    """One fence: angle gamma (module docstring), the interval of mu_c against the part, and
    optionally its reach: how far it extends beyond the part's first contact toward its
    free end (the least over where parts meet it; the part's units; phase 6)."""

    angle: float
    mu_low: float
    mu_high: float
    reach: float | None = None

    @classmethod
    def create(cls, angle: float, mu_c: float | tuple[float, float], reach: float | None = None) -> Fence:
        g = float(angle)
        if not (math.isfinite(g) and abs(g) < 0.5 * math.pi and g != 0.0):
            raise InvalidInput("fence_angle", "must be in (-pi/2, pi/2) and not 0 (a fence square to "
                               "the belt's motion holds every part)")
        lo, hi = (mu_c, mu_c) if isinstance(mu_c, (int, float)) else mu_c
        lo, hi = float(lo), float(hi)
        if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 <= lo <= hi):
            raise InvalidInput("mu_c", "must be finite with 0 <= low <= high")
        if reach is not None and not (math.isfinite(reach) and reach >= 0.0):
            raise InvalidInput("reach", "must be a finite length >= 0 (0: the part may meet the fence at its end)")
        return cls(angle=g, mu_low=lo, mu_high=hi, reach=None if reach is None else float(reach))

    @property
    def sign(self) -> float:
        """sgn(gamma): the part slides toward -sgn(gamma) t (module docstring)."""
        return 1.0 if self.angle > 0.0 else -1.0

    @property
    def tangent(self) -> np.ndarray:
        """t = (cos gamma, sin gamma), along the fence."""
        return np.array([math.cos(self.angle), math.sin(self.angle)])

    @property
    def normal(self) -> np.ndarray:
        """n = J t, the face's normal into the part."""
        return perp(self.tangent)

    @property
    def side(self) -> str:
        """The side of the belt the fence hangs from (its free end is on the other side)."""
        return "right" if self.angle > 0.0 else "left"

    @property
    def jam_threshold(self) -> float:
        """|tan gamma|: a flush part jams for mu_c >= this (6.4)."""
        return abs(math.tan(self.angle))

    def sliding_mu(self) -> tuple[float, float] | None:
        """The part of [mu_low, mu_high] where a flush part slides (None: it always jams)."""
        if self.mu_low >= self.jam_threshold:
            return None
        return self.mu_low, min(self.mu_high, self.jam_threshold)

    def may_jam(self) -> bool:
        return self.mu_high >= self.jam_threshold


def flush_orientation(part: Footprint, j: int, gamma: float) -> float:
    """theta with edge j flush on the fence (the part above it): theta + phi_j = gamma."""
    return wrap(gamma - part.hull_edge_angle(j))


def contact_interval(part: Footprint, k: int, gamma: float) -> tuple[float, float]:
    """(start, width): the orientations in which hull vertex k meets the fence first,
    [flush_k, flush_{k-1}] (phase 1)."""
    start = flush_orientation(part, k, gamma)
    width = wrap(part.hull_edge_angle(k) - part.hull_edge_angle(k - 1))
    return start, width


def rotation(theta: float) -> np.ndarray:
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s], [s, c]])


def balance_mu(c: np.ndarray, n: np.ndarray, t: np.ndarray) -> float | None:
    """The mu at which the cone edge n + mu t from contact c passes through the CM,
    c x (n + mu t) = 0 (None when c x t = 0: it never does, or always)."""
    ct = float(c[0] * t[1] - c[1] * t[0])
    if ct == 0.0:
        return None
    return -float(c[0] * n[1] - c[1] * n[0]) / ct


def _mu_samples_for_sense(c: np.ndarray, n: np.ndarray, mu: tuple[float, float]) -> list[float]:
    """mu_c values that show every sense Mason's rule gives over the interval at contact c:
    its ends and both sides of each mu where a cone edge passes through the CM."""
    lo, hi = mu
    out = [lo, hi]
    for edge in (perp(n), -perp(n)):
        star = balance_mu(c, n, edge)
        if star is not None and lo < star < hi:
            out += [max(lo, star * (1.0 - BALANCE_SIDE_REL)), min(hi, star * (1.0 + BALANCE_SIDE_REL))]
    return out


def senses_at(part: Footprint, k: int, theta: float, fence: Fence) -> set[str]:
    """The senses ('ccw', 'cw') Mason's rule allows at vertex k, orientation theta, over the
    fence's mu_c interval (phase 2); a translation ('none') allows both."""
    c = rotation(theta) @ part.hull[k]
    n = fence.normal
    out: set[str] = set()
    for mu in _mu_samples_for_sense(c, n, (fence.mu_low, fence.mu_high)):
        s = mason_sense(c, n, PUSH, mu)
        out |= {"ccw", "cw"} if s == "none" else {s}
    return out


def vote_breakpoints(part: Footprint, k: int, fence: Fence) -> list[float]:
    """Orientations where a ray of Mason's rule at vertex k passes through the CM: the
    push direction and the cone edges at both ends of the mu_c interval (phase 2)."""
    n = fence.normal
    t = perp(n)
    rays = [PUSH]
    for mu in (fence.mu_low, fence.mu_high):
        rays += [n + mu * t, n - mu * t]
    hk = part.hull[k]
    base = math.atan2(float(hk[1]), float(hk[0]))
    out = []
    for w in rays:
        a = math.atan2(float(w[1]), float(w[0])) - base
        out += [wrap(a), wrap(a + math.pi)]
    return out


def crossing(part: Footprint, j: int, mu: float, sign: float) -> float:
    """u_X of edge j (phase 4): where the force line n + mu sgn t through the CM meets it."""
    u_c, h_c = part.cm_over_hull_edge(j)
    return u_c - mu * sign * h_c


def crossing_span(part: Footprint, e: int, mu: tuple[float, float], sign: float,
                  tol: FeederTolerances = DEFAULT) -> tuple[float, float]:
    """The least and largest u_X of edge e over [mu_low, mu_high] (phase 4), widened by
    ``tol.crossing_rel`` part radii either way."""
    u = sorted(crossing(part, e, m, sign) for m in mu)
    pad = tol.crossing_rel * part.circumradius
    return u[0] - pad, u[1] + pad


def final_edges(part: Footprint, j: int, fence: Fence, tol: FeederTolerances = DEFAULT) -> frozenset[int]:
    """Every edge a part flush on edge j can come to rest on (phase 4), over the sliding
    part of the mu_c interval; empty when it always jams."""
    mu = fence.sliding_mu()
    if mu is None:
        return frozenset()
    out: set[int] = set()
    seen: set[int] = set()
    todo = [j % part.hull_size]
    while todo:
        e = todo.pop()
        if e in seen:
            continue
        seen.add(e)
        _, length, _ = part.hull_edge(e)
        u = crossing_span(part, e, mu, fence.sign, tol)
        if u[1] >= 0.0 and u[0] <= length:
            out.add(e)
        if u[0] < 0.0:
            todo.append((e - 1) % part.hull_size)
        if u[1] > length:
            todo.append((e + 1) % part.hull_size)
    return frozenset(out)


@dataclass(frozen=True)
class EndpointTurn:
    """The turn of the part leaving the fence's end on edge j (phase 5), in radians, in
    the sense sgn(gamma): between ``least`` (extreme B) and ``most`` (extreme A)."""

    edge: int
    least: float
    most: float
    contact_lost: bool  # B ends with E leaving the edge before A
    mu_used: tuple[float, ...]
    locus_evaluations: int
    sense_flags: int  # steps where Mason's rule at E did not give the turn's sense


def canonical_crossing(part: Footprint, j: int, fence: Fence, mu: float) -> float:
    """u_X of edge j in the frame where gamma > 0 (mirrored for gamma < 0: u -> L - u),
    not clipped to the edge."""
    u_x = crossing(part, j, mu, fence.sign)
    return part.hull_edge(j)[1] - u_x if fence.sign < 0.0 else u_x


def canonical_edge(part: Footprint, j: int, fence: Fence, mu: float) -> tuple[float, float, float, float]:
    """(u_c, h_c, L, l_0) of edge j in the frame where gamma > 0 (mirrored for gamma < 0:
    u -> L - u); l_0 = u_X clipped to the edge."""
    u_c, h_c = part.cm_over_hull_edge(j)
    _, length, _ = part.hull_edge(j)
    if fence.sign < 0.0:
        u_c = length - u_c
    return u_c, h_c, length, min(max(canonical_crossing(part, j, fence, mu), 0.0), length)


def canonical_outline(part: Footprint, j: int, fence: Fence) -> np.ndarray:
    """The part's outline (CM frame) in canonical_edge's frame with no turn yet: edge j
    along t0 = (cos |gamma|, sin |gamma|), the part above it (toward n0 = J t0), a point at
    (u, h) in the edge's frame (u mirrored to L - u for gamma < 0) at (u - u_c) t0 + (h - h_c) n0,
    as the contact of endpoint_turn at l = u, in the order the outline was given (its
    dipods, solver/feeder/part_bound.py, follow that order). Mirrored outlines run the other way."""
    p, length, e = part.hull_edge(j)
    given = part.vertices[::-1] if part.input_reversed else part.vertices
    u = (given - p) @ e
    h = (given - p) @ perp(e)
    u_c, h_c, _, _ = canonical_edge(part, j, fence, fence.mu_low)
    if fence.sign < 0.0:
        u = length - u
    g = abs(fence.angle)
    t0 = np.array([math.cos(g), math.sin(g)])
    return np.outer(u - u_c, t0) + np.outer(h - h_c, perp(t0))


def slip_normal(e: np.ndarray) -> np.ndarray:
    """J g, g = (d . e / d . n) n - e (n = J e): the slip along the contact line e per CCW
    radian of turn about a COR r is (r - c) . J g (phase 5; phase 6 with the face as the
    line)."""
    n = perp(e)
    return perp(float(PUSH @ e) / float(PUSH @ n) * n - e)


def _slip_per_radian(boundary: np.ndarray, c: np.ndarray, e: np.ndarray) -> np.ndarray:
    """(r - c) . J g (slip_normal) at each extreme COR r of a disk locus's ``boundary``."""
    return (boundary - c) @ slip_normal(e)


def upward_slip_scene(a: float, c: np.ndarray, psi: float, mu: float) -> tuple[PushScene, int]:
    """The frictionless scene of the cone edge n_e + mu e at contact c on an edge at angle
    psi (E slipping toward the edge's upstream end, phase 5) and the sign of its moment arm
    (force_scene): 0 through the CM, > 0 turning the part CW (no such slip)."""
    return force_scene(PushScene.create(a, c, psi, PUSH_ANGLE), -math.atan(mu))


def max_slip_rate(a: float, c: np.ndarray, psi: float, mu: float, n_points: int) -> tuple[float, bool]:
    """Largest dl/ddelta over the disk's motions at contact c (CM frame), edge angle psi
    (phase 5), and whether Mason's rule at c gives CCW."""
    return max_slip_rates(a, [(c, psi, mu)], n_points)[0]


def max_slip_rates(a: float, queries: Sequence[tuple[np.ndarray, float, float]],
                   n_points: int, boundaries: Boundaries = disk_boundaries) -> list[tuple[float, bool]]:
    """:func:`max_slip_rate` at each (c, psi, mu), the disk loci of all of them solved at
    once by ``boundaries`` (models/locus/cor_disk.py, disk_boundaries, or the solver's
    compiled twin)."""
    out: list[tuple[float, bool]] = []
    pending: list[tuple[int, PushScene, np.ndarray, np.ndarray]] = []
    for c, psi, mu in queries:
        e = np.array([math.cos(psi), math.sin(psi)])
        ccw = mason_sense(c, perp(e), PUSH, mu) == "ccw"
        turned, m_sign = upward_slip_scene(a, c, psi, mu)
        if m_sign == 0:
            out.append((math.inf, ccw))  # that force passes through the CM: slip without turning
        elif m_sign > 0:
            out.append((0.0, ccw))  # that slip would turn the part CW: none toward the upstream end
        else:
            pending.append((len(out), turned, c, e))
            out.append((math.nan, ccw))
    for (i, _, c, e), boundary in zip(pending, boundaries([turned for _, turned, _, _ in pending], n_points)):
        out[i] = (max(float(np.max(_slip_per_radian(boundary, c, e))), 0.0), out[i][1])
    return out


def face_slip_rate(a: float, c: np.ndarray, fence: Fence, mu: float, n_points: int) -> float:
    """Largest slip of the part toward the fence's end per radian of turn (either sense)
    over the disk's motions, with the part's vertex at c (CM frame, world axes) on the
    fence's face (phase 6); inf where the slipping force passes through the CM (the part
    can slide without turning).

    Slip of the part along the face toward the end, w = -sgn(gamma) t, is the fence's slip
    along sgn(gamma) t relative to the part: per CCW radian (r - c) . J g with
    g = (d . t / d . n) n - t (phase 5's rate with the face as the contact line). It needs
    the cone edge n + mu sgn(gamma) t, whose frictionless motions all turn one sense s;
    per radian of |turn| the slip toward the end is s sgn(gamma) (r - c) . J g."""
    scene = PushScene.create(a, c, fence.angle, PUSH_ANGLE)
    turned, m_sign = force_scene(scene, -fence.sign * math.atan(mu))
    if m_sign == 0:
        return math.inf
    sense = -float(m_sign)  # a positive moment arm turns the part CW (max_slip_rate)
    boundary = disk_boundaries([turned], n_points)[0]
    return max(float(np.max(sense * fence.sign * _slip_per_radian(boundary, c, fence.tangent))), 0.0)


def _face_rate_over_mu(part: Footprint, k: int, theta: float, fence: Fence, tol: FeederTolerances) -> float:
    """face_slip_rate at vertex k and orientation theta, the largest over the fence's mu_c
    interval: inf when some mu_c in it puts the cone edge through the CM."""
    c = rotation(theta) @ part.hull[k]
    lo, hi = fence.mu_low, fence.mu_high
    if hi > lo:  # the cone edge n + mu sgn(gamma) t, t = (cos gamma, sin gamma)
        star = balance_mu(c, fence.normal, fence.sign * fence.tangent)
        if star is not None and lo <= star <= hi:
            return math.inf
    mus = tol.mu_values(lo, hi)
    return max(face_slip_rate(part.circumradius, c, fence, float(m), tol.locus_points) for m in mus)


def _reach_nodes(lo: float, hi: float, cells: int) -> np.ndarray:
    """Offsets from lo to hi crowded toward both ends (smoothstep of an even grid: the cells
    at the ends are about 3/cells^2 of the span)."""
    u = np.linspace(0.0, 1.0, cells + 1)
    return lo + (hi - lo) * u * u * (3.0 - 2.0 * u)


@dataclass(frozen=True)
class Piece:
    """Initial orientations [start, start + width] in which hull vertex ``vertex`` touches
    first and the part turns in ``sense`` ("ccw" brings edge vertex - 1 flush at the end
    of the vertex's contact interval, "cw" edge ``vertex`` at its start): phases 1-2."""

    vertex: int
    start: float
    width: float
    sense: str
    lo: float = 0.0  # the piece's cuts, as offsets into the vertex's contact interval (exact,
    hi: float = 0.0  # so the last piece's hi is that interval's width to the bit)

    @property
    def flushed_edge(self) -> int:
        return self.vertex - 1 if self.sense == "ccw" else self.vertex


def _reach_after_flush(part: Footprint, fence: Fence, j: int, pivot_slip: Callable[[int, str], float],
                       tol: FeederTolerances = DEFAULT) -> float:
    """Reach needed once edge j is flush until E meets u_X of the edge that stays (phase 6),
    the largest over the edges it may stay on (phase 4's chains): the pivots on the way
    (onto edge e - 1 about vertex e turning CCW, onto e + 1 about vertex e + 1 turning CW,
    each bounded over that vertex's whole contact interval), then at most the length of the
    edge that stays from its upstream end back to u_X."""
    mu = fence.sliding_mu()
    assert mu is not None
    need = 0.0
    for step in (-1, 1):
        e, slip = j % part.hull_size, 0.0
        for _ in range(part.hull_size):
            length = part.hull_edge(e)[1]
            u = crossing_span(part, e, mu, fence.sign, tol)
            if u[1] >= 0.0 and u[0] <= length:  # e may stay: slide until E meets u_X
                ell0 = min(canonical_edge(part, e, fence, float(x))[3] for x in mu)
                need = max(need, slip + length - ell0)
            if step < 0 and u[0] < 0.0:
                slip += pivot_slip(e, "ccw")
                e = (e - 1) % part.hull_size
            elif step > 0 and u[1] > length:
                slip += pivot_slip((e + 1) % part.hull_size, "cw")
                e = (e + 1) % part.hull_size
            else:
                break
    return need


@dataclass(frozen=True)
class ReachProfile:
    """Phase 6 for every reach at once: cells of initial orientation [lo, lo + width] and
    for each a bound on the reach it needs (part units; inf: no reach suffices, a balance
    where the part can slide without turning touches the cell). A fence of reach R leaves
    unaligned exactly the cells that need more than R (:meth:`unaligned`)."""

    lo: np.ndarray
    width: np.ndarray
    need: np.ndarray

    @classmethod
    def none(cls) -> ReachProfile:
        """A fence on which every flush part jams: nothing to align."""
        return cls(np.zeros(0), np.zeros(0), np.zeros(0))

    def unaligned(self, reach: float) -> Arcs:
        """The initial orientations a fence of this reach may leave unaligned."""
        over = self.need > reach
        return Arcs.of(zip(self.lo[over].tolist(), self.width[over].tolist()))

    def meeting(self, arcs: Arcs) -> np.ndarray:
        """Which cells meet the closed set ``arcs`` (boolean per cell)."""
        hit = np.zeros(self.lo.shape, dtype=bool)
        for s, w in arcs.arcs:
            hit |= (np.mod(self.lo - s, TWO_PI) <= w) | (np.mod(s - self.lo, TWO_PI) <= self.width)
        return hit

    def needed(self, arcs: Arcs, allowance: float = 0.0) -> tuple[float, float]:
        """The least reach that aligns every orientation of ``arcs`` but at most
        ``allowance`` radians of them (the cells needing the most, whole), and the measure
        of the cells it leaves unaligned: (inf, measure) when even that is not enough;
        (0, 0) for the empty set."""
        hit = np.nonzero(self.meeting(arcs))[0]
        if hit.size == 0:
            return 0.0, 0.0
        order = hit[np.argsort(-self.need[hit], kind="stable")]
        dropped = np.cumsum(self.width[order])
        keep = int(np.searchsorted(dropped, allowance, side="right"))  # cells that may stay unaligned
        if keep == order.size:
            return 0.0, float(dropped[-1])
        return float(self.need[order[keep]]), float(dropped[keep - 1]) if keep else 0.0


@dataclass(frozen=True)
class SampledReach:
    """Phase 6 over a mu_c interval, one :class:`ReachProfile` per mu_c sample (both ends and
    between, ``FeederTolerances.mu_values``). A part has one mu_c: near its balance only a
    sliver is unaligned, wherever in the interval mu_c lies, whereas one profile over the
    whole interval (``fence_map`` with a reach) must leave unaligned every orientation whose
    balance some mu_c of the interval puts there. A design needs each sample's reach; its
    losses are each sample's (their union, the safe side), each leaving at most its share of
    an allowance. Between the samples the balance
    moves continuously and is not bounded here (the validation draws mu_c over the
    interval)."""

    profiles: tuple[ReachProfile, ...]

    def unaligned(self, reach: float) -> Arcs:
        return Arcs.union_of(p.unaligned(reach) for p in self.profiles)

    def needed(self, arcs: Arcs, allowance: float = 0.0) -> tuple[float, float]:
        """The least reach every sample needs, each leaving at most its share of the
        allowance unaligned (their union stays within it)."""
        got = [p.needed(arcs, allowance / len(self.profiles)) for p in self.profiles]
        return max(r for r, _ in got), sum(d for _, d in got)


ReachBound = ReachProfile | SampledReach
"""What a placed search asks of a fence's reach: unaligned(reach) and needed(arcs, allowance)."""


def sampled_reach(part: Footprint, fence: Fence, tol: FeederTolerances = DEFAULT,
                  checkpoint: Callable[[str], None] | None = None) -> ReachBound:
    """The fence's reach bound for a design: one profile for a point mu_c, one per mu_c
    sample over an interval (:class:`SampledReach`)."""
    mus = tol.mu_values(fence.mu_low, fence.mu_high)
    if len(mus) == 1:
        return reach_profile(part, fence, tol=tol, checkpoint=checkpoint)
    return SampledReach(tuple(reach_profile(part, Fence.create(fence.angle, (m, m)), tol=tol, checkpoint=checkpoint)
                              for m in mus))


def reach_profile(part: Footprint, fence: Fence, pieces: list[Piece] | None = None,
                  tol: FeederTolerances = DEFAULT, checkpoint: Callable[[str], None] | None = None) -> ReachProfile:
    """The reach each initial orientation needs for an edge to come flush and slide until
    the end meets u_X (phase 6), per cell of each piece (:func:`contact_pieces`): a cell's
    bound is an upper sum graded toward where the turn starts (upper_sum), exact when R x is
    monotone on the cell; a cell touching an orientation where the part can slide without
    turning needs an infinite reach."""
    if fence.sliding_mu() is None:
        return ReachProfile.none()
    pieces = contact_pieces(part, fence) if pieces is None else pieces
    rates: dict[tuple[int, float], float] = {}

    def rate(k: int, theta: float) -> float:
        key = (k, theta)
        if key not in rates:
            rates[key] = _face_rate_over_mu(part, k, theta, fence, tol)
        return rates[key]

    def upper_sum(k: int, nodes: np.ndarray) -> np.ndarray:
        """Cumulative slip bound from nodes[0] to each node; nodes[-1] is where the turn
        starts (a piece's far end, or a pivot's first orientation), which may be a balance
        where the rate grows like K / x, x the distance to it. A cell bounds the integral by
        max(R x) ln(x_i / x_i+1), near exact where R x tends to K (a plain upper sum
        overshoots there by about K per cell: measured, 11.5 against 8.7 part units for a
        pivot); the last cell, touching nodes[-1], by its width times the larger rate (inf
        at a balance)."""
        r = np.array([rate(k, float(x)) for x in nodes])
        x = np.abs(nodes - nodes[-1])
        with np.errstate(invalid="ignore"):
            rx = np.where(np.isinf(r), np.inf, r * x)
        with np.errstate(divide="ignore", invalid="ignore"):  # nodes closer than rounding: no bound, the safe side
            inner = np.nan_to_num(np.maximum(rx[:-2], rx[1:-1]) * np.log(x[:-2] / x[1:-1]), nan=np.inf)
        last = abs(float(nodes[-1] - nodes[-2])) * max(float(r[-2]), float(r[-1]))
        with np.errstate(over="ignore"):  # a sum past the largest float is inf: unaligned, the safe side
            return np.concatenate([[0.0], np.cumsum(np.append(inner, last))])

    totals: dict[tuple[int, str], float] = {}

    def pivot_slip(k: int, sense: str) -> float:
        if (k, sense) not in totals:
            start, width = contact_interval(part, k, fence.angle)
            nodes = start + _reach_nodes(0.0, width, tol.reach_cells)
            totals[(k, sense)] = float(upper_sum(k, nodes if sense == "cw" else nodes[::-1])[-1])
        return totals[(k, sense)]

    lo: list[float] = []
    width: list[float] = []
    need_of: list[float] = []
    for piece in pieces:
        if checkpoint is not None:
            checkpoint(f"the reach needed from vertex {piece.vertex} turning {piece.sense}")
        k = piece.vertex
        j = piece.flushed_edge % part.hull_size
        after = _reach_after_flush(part, fence, j, pivot_slip, tol)
        c_start, c_width = contact_interval(part, k, fence.angle)
        # the offsets are the cuts themselves: recomputing them from start and width left a
        # rounding-sized span before the last piece, 0/0 in its upper sum, so the whole
        # piece unaligned whatever the reach
        if piece.sense == "cw":  # to flush_k at offset 0: the turn passes [0, lo] first
            before = (float(upper_sum(k, c_start + _reach_nodes(0.0, piece.lo, tol.reach_cells))[-1])
                      if piece.lo > 0.0 else 0.0)
            nodes = piece.start + _reach_nodes(0.0, piece.width, tol.reach_cells)
        else:  # to flush_{k-1} at the interval's end
            before = (float(upper_sum(k, (c_start + _reach_nodes(piece.hi, c_width, tol.reach_cells))[::-1])[-1])
                      if piece.hi < c_width else 0.0)
            nodes = (piece.start + _reach_nodes(0.0, piece.width, tol.reach_cells))[::-1]
        need = before + after + upper_sum(k, nodes)
        tail = _balance_tail(nodes, float(need[-2]), lambda th: rate(k, th), tol)
        for i in range(len(nodes) - (1 if tail is None else 2)):  # the cell's far end bounds every orientation in it
            lo.append(min(float(nodes[i]), float(nodes[i + 1])))
            width.append(abs(float(nodes[i + 1] - nodes[i])))
            need_of.append(float(need[i + 1]))
        if tail is not None:
            lo.extend(tail[0])
            width.extend(tail[1])
            need_of.extend(tail[2])
    return ReachProfile(np.array(lo), np.array(width), np.array(need_of))


def _balance_tail(nodes: np.ndarray, need_before: float, rate: Callable[[float], float],
                  tol: FeederTolerances) -> tuple[list[float], list[float], list[float]] | None:
    """The last cell of a piece whose turn starts at a balance (the rate is inf at nodes[-1]),
    split toward it: the rate there grows like K / x with x the distance to the balance, so
    from x to the cell's far end x_1 the slip is at most M ln(x_1 / x), M the largest of R x
    at x_1 and near the balance (the same bound as the inner cells of upper_sum). Sub-cells
    [x_1 e^-m, x_1 e^-(m-1)] need at most need_before + M m; the innermost, touching the
    balance, needs an infinite reach. None when there is no balance at nodes[-1] (or no
    finite M)."""
    end, far = float(nodes[-1]), float(nodes[-2])
    if not math.isinf(rate(end)) or not math.isfinite(need_before):
        return None
    x1 = abs(end - far)
    toward = math.copysign(1.0, far - end)  # from the balance into the cell
    probe = x1 * tol.tail_probe
    m_bound = max(rate(far) * x1, rate(end + toward * probe) * probe)
    if not math.isfinite(m_bound):
        return None
    lo, width, need = [], [], []
    for m in range(1, tol.tail_cells + 1):
        outer, inner = x1 * math.exp(-(m - 1)), x1 * math.exp(-m)
        lo.append(min(end + toward * inner, end + toward * outer))
        width.append(outer - inner)
        need.append(need_before + m_bound * m)
    inner = x1 * math.exp(-tol.tail_cells)
    lo.append(min(end, end + toward * inner))
    width.append(inner)
    need.append(math.inf)
    return lo, width, need


def contact_pieces(part: Footprint, fence: Fence) -> list[Piece]:
    """Phases 1-2: the pieces of initial orientation, per hull vertex meeting the fence
    first, cut where Mason's rule changes its vote; a piece where both senses are possible
    (a mu_c interval) appears once per sense."""
    pieces: list[Piece] = []
    for k in range(part.hull_size):
        start, width = contact_interval(part, k, fence.angle)
        cuts = sorted({0.0, width} | {d for b in vote_breakpoints(part, k, fence)
                                      if 0.0 < (d := wrap(b - start)) < width})
        for a, b in zip(cuts[:-1], cuts[1:]):
            senses = senses_at(part, k, start + 0.5 * (a + b), fence)
            pieces.extend(Piece(vertex=k, start=start + a, width=b - a, sense=sense, lo=a, hi=b)
                          for sense in sorted(senses))
    return pieces


OwnRate = Callable[[int, float], Callable[[float, float], float]]
"""The part's own bound on the slip per radian of phase 5: for edge j and mu_c, a function
of the contact l (part units, canonical_edge's frame) and the turn delta, at most the disk's
(the circumscribing disk's loci contain the part's, 7.5); inf where it has none."""


def endpoint_turn(part: Footprint, j: int, fence: Fence, tol: FeederTolerances = DEFAULT,
                  own_rate: OwnRate | None = None) -> EndpointTurn:
    """Extremes A and B of leaving the fence's end on edge j (phase 5), with the disk bound,
    or the smaller of it and ``own_rate``'s (the part's own loci).

    B bounds the slip: the contact's position l on the edge (from u_X toward the edge's
    upstream end L) and the turn delta obey dl/ddelta <= R(l, delta), the largest slip per
    radian over the disk's motions (max_slip_rate), so by comparison l(delta) stays below
    the path with dl/ddelta = R from (u_X, 0); B is the turn at which that path reaches L
    (capped at A). R is infinite at l = u_X (the slipping force through the CM: the part
    slides off without turning) and zero where no motion slips upward (the path stalls in
    l while the part turns), so neither l nor delta is a safe variable to step in: the
    path is integrated in its arc length s, (dl / a, ddelta)/ds = (R / a, 1) / |(R / a, 1)|
    (lengths in part radii a; Heun, ``endpoint_steps`` steps of ((L - u_X) / a + A) / steps,
    enough to reach an end)."""
    return endpoint_turns(part, [(j, fence)], tol, own_rate)[0]


@dataclass
class _SlipPath:
    """One integration of endpoint_turn's slip path (one edge, one mu_c), stepped in
    lockstep with the others (endpoint_turns)."""

    job: int
    mu: float
    u_c: float
    h_c: float
    end: float
    cap: float
    g: float
    t0: np.ndarray  # the edge's direction before any turn, (cos g, sin g)
    n0: np.ndarray  # J t0
    own: Callable[[float, float], float] | None
    x: np.ndarray
    ds: float
    steps_left: int


def endpoint_turns(part: Footprint, jobs: Sequence[tuple[int, Fence]], tol: FeederTolerances = DEFAULT,
                   own_rate: OwnRate | None = None, boundaries: Boundaries = disk_boundaries) -> list[EndpointTurn]:
    """:func:`endpoint_turn` of each (edge j, fence), every path (an edge and a mu_c) taking
    its Heun steps in lockstep with the others, so that each step's disk loci are solved
    together (max_slip_rates): the same steps as one at a time, the same answers to the last
    digit or two (the batched root-finding of (3.35) may round differently: B moved by at
    most 3e-17 rad over 68 maps, tests/models/feeder/test_fence.py)."""
    a = part.circumradius
    least, most, lost, evaluations, flags, used = [], [], [], [], [], []
    paths: list[_SlipPath] = []
    for k, (j, fence) in enumerate(jobs):
        g = abs(fence.angle)
        t0 = np.array([math.cos(g), math.sin(g)])
        mu_range = fence.sliding_mu()
        if mu_range is None:
            raise InvalidInput("mu_c", "the part jams on this fence for every mu_c given: it never reaches the end")
        mus = tol.mu_values(*mu_range)
        most.append(0.5 * math.pi - g)
        least.append(most[k])
        lost.append(False)
        evaluations.append(0)
        flags.append(0)
        used.append(tuple(float(m) for m in mus))
        cap = most[k] - tol.grazing_margin
        for mu in mus:
            u_c, h_c, length, ell0 = canonical_edge(part, j, fence, float(mu))
            own = None if own_rate is None else own_rate(j, float(mu))
            x = np.array([ell0 / a, 0.0])
            end = length / a
            ds = ((end - x[0]) + cap) / tol.endpoint_steps
            paths.append(_SlipPath(k, float(mu), u_c, h_c, end, cap, g, t0, perp(t0), own, x, ds,
                                   4 * tol.endpoint_steps))

    def headings(where: list[tuple[_SlipPath, np.ndarray]]) -> list[np.ndarray]:
        """(dl / a, ddelta)/ds of each path at its contact l = ell_a a and turn delta."""
        queries = []
        for p, (ell_a, delta) in where:
            c = rotation(delta) @ ((ell_a * a - p.u_c) * p.t0 - p.h_c * p.n0)
            queries.append((c, p.g + delta, p.mu))
        out = []
        for (p, (ell_a, delta)), (r, ccw) in zip(where, max_slip_rates(a, queries, tol.locus_points, boundaries)):
            evaluations[p.job] += 1
            if math.isinf(r):  # the slipping force through the CM: slide without turning
                out.append(np.array([1.0, 0.0]))
                continue
            flags[p.job] += 0 if ccw else 1
            if p.own is not None and r > 0.0:
                r = min(r, p.own(ell_a * a, delta))
            out.append(np.array([r / a, 1.0]) / math.hypot(r / a, 1.0))
        return out

    active = paths
    while active:
        k1 = headings([(p, p.x) for p in active])
        k2 = headings([(p, p.x + p.ds * h) for p, h in zip(active, k1)])
        still = []
        for p, h1, h2 in zip(active, k1, k2):
            x, x_new = p.x, p.x + 0.5 * p.ds * (h1 + h2)
            p.steps_left -= 1
            if x_new[0] >= p.end:  # contact lost within this step: where l = L
                f = (p.end - x[0]) / (x_new[0] - x[0])
                delta_lost = x[1] + f * (x_new[1] - x[1])
                if delta_lost < p.cap:
                    lost[p.job] = True
                    least[p.job] = min(least[p.job], max(delta_lost - tol.b_margin, 0.0))
                continue
            if x_new[1] >= p.cap:
                continue
            p.x = x_new
            if p.steps_left == 0:  # no end reached (never seen): B no later than the turn reached, the safe side
                least[p.job] = min(least[p.job], max(p.x[1] - tol.b_margin, 0.0))
                continue
            still.append(p)
        active = still
    return [EndpointTurn(edge=j, least=least[k], most=most[k], contact_lost=lost[k], mu_used=used[k],
                         locus_evaluations=evaluations[k], sense_flags=flags[k])
            for k, (j, _) in enumerate(jobs)]


@dataclass(frozen=True)
class FenceMap:
    """The configuration map of one fence (5.2) with how it was bounded."""

    map: ConfigurationMap
    final_edges: tuple[int, ...]  # the hull edge of each band
    turns: tuple[EndpointTurn, ...]
    fence: Fence
    part: Footprint
    bound: str = "disk"
    notes: tuple[str, ...] = field(default=())


def fence_map(part: Footprint, fence: Fence, tol: FeederTolerances = DEFAULT,
              checkpoint: Callable[[str], None] | None = None, own_rate: OwnRate | None = None,
              boundaries: Boundaries = disk_boundaries) -> FenceMap:
    """The configuration map of ``part`` meeting ``fence`` (phases 1-6); ``checkpoint``
    (the caller's deadline: it raises to stop) is called before the extremes of leaving the
    end (before each edge's with ``own_rate``) and the reach.
    With ``own_rate`` the extremes B are bounded by the part's own loci (``bound`` "part");
    the reach (phase 6) stays bounded by the disk. ``boundaries`` solves the slip paths' disk
    loci (models.locus.cor_disk.Boundaries)."""
    return fence_maps(part, [fence], tol, checkpoint, own_rate, boundaries)[0]


def fence_maps(part: Footprint, fences: Sequence[Fence], tol: FeederTolerances = DEFAULT,
               checkpoint: Callable[[str], None] | None = None, own_rate: OwnRate | None = None,
               boundaries: Boundaries = disk_boundaries) -> list[FenceMap]:
    """:func:`fence_map` of each fence, the extremes of every fence's edges integrated in
    lockstep (endpoint_turns; one edge at a time with ``own_rate``, whose certified rays
    take long enough for the deadline to be asked between edges)."""
    layouts = []
    for fence in fences:
        finals_of_flush = {j: final_edges(part, j, fence, tol) for j in range(part.hull_size)}
        kernels: dict[int, list[tuple[float, float]]] = {}
        pieces = contact_pieces(part, fence)
        for piece in pieces:
            for f in finals_of_flush[piece.flushed_edge % part.hull_size]:
                kernels.setdefault(f, []).append((piece.start, piece.width))
        layouts.append((fence, pieces, kernels, tuple(sorted(kernels))))
    jobs = [(j, fence) for fence, _, _, edges in layouts for j in edges]
    if own_rate is None:
        if checkpoint is not None:
            checkpoint(f"the extremes of leaving the end on {len(jobs)} edges")
        turns_made = endpoint_turns(part, jobs, tol, boundaries=boundaries)
    else:
        turns_made = []
        for j, fence in jobs:
            if checkpoint is not None:
                checkpoint(f"the extremes of leaving the end on edge {j}")
            turns_made += endpoint_turns(part, [(j, fence)], tol, own_rate, boundaries)
    out = []
    for fence, pieces, kernels, edges in layouts:
        turns = tuple(turns_made[:len(edges)])
        turns_made = turns_made[len(edges):]
        out.append(_assemble_map(part, fence, pieces, kernels, edges, turns, tol, checkpoint, own_rate))
    return out


def _assemble_map(part: Footprint, fence: Fence, pieces: list[Piece], kernels: dict[int, list[tuple[float, float]]],
                  edges: tuple[int, ...], turns: tuple[EndpointTurn, ...], tol: FeederTolerances,
                  checkpoint: Callable[[str], None] | None, own_rate: OwnRate | None) -> FenceMap:
    """One fence's map from its kernels and its extremes (phases 5-6)."""
    gamma = fence.angle
    bands = []
    for j, turn in zip(edges, turns):
        theta = flush_orientation(part, j, gamma)
        if fence.sign > 0.0:
            bands.append(Arcs.of([(theta + turn.least, turn.most - turn.least)]))
        else:
            bands.append(Arcs.of([(theta - turn.most, turn.most - turn.least)]))
    jam = Arcs.circle() if fence.may_jam() else Arcs.empty()
    notes = []
    if fence.may_jam():
        notes.append(f"mu_c up to {fence.mu_high:g} >= |tan(fence_angle)| = {fence.jam_threshold:g}: "
                     "a flush part may jam on this fence (6.4)")
    unaligned = (Arcs.empty() if fence.reach is None else
                 reach_profile(part, fence, pieces, tol, checkpoint).unaligned(fence.reach))
    if not unaligned.is_empty:
        notes.append(f"a reach of {fence.reach:g} may be too short for {math.degrees(unaligned.measure):.3g} degrees "
                     "of initial orientations: the part may meet the fence's end before an edge is flush, and the "
                     "map bounds nothing there (1.8.6, ch. 4)")
    cmap = ConfigurationMap(bands=tuple(bands), kernels=tuple(Arcs.of(kernels[j]) for j in edges), jam=jam,
                            unaligned=unaligned)
    return FenceMap(map=cmap, final_edges=edges, turns=turns, fence=fence, part=part,
                    bound="disk" if own_rate is None else "part", notes=tuple(notes))
