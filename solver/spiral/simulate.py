"""A disk herded by a point pusher moving on a spiral, simulated with the forward solver
(book 4.5: spiral localization of a disk; 4.4: a point pushing a disk aside).

The book plans a spiral of radii b_1 > b_2 > ... (one radius per revolution, 4.5.5) so
that a disk of radius a known to lie inside the first circle is pushed *into* the spiral
at every collision and never out (4.5.1-4.5.3), down to the limiting radius
b_inf = a (1 + mu_c) (4.25), with the recursion b_n = b_{n-1} - d*(b_n) (4.26). The book
analyses one collision at a time with a circular pusher path and the worst COR of the
sketch; this module checks the plan on concrete supports by integrating the whole motion.

**The pusher path** is a curve P(u), u in [0, u_end], given by one of

* :func:`spiral_path`: radii b_1..b_N about a centre; u is the angle turned, the radius is
  piecewise linear in u through b_n at u = 2 pi (n - 1) (the book's "single radius per
  revolution", 4.5.5), followed by ``final_turns`` revolutions at the constant radius b_N
  (the book's spiral becomes circular at its end, 4.5.4). Counter-clockwise by default.
* :func:`polyline_path`: straight segments through given points (e.g. a planner's pusher
  polyline); u is the arc length. Its corners are points where the push direction turns.

Both tell where the tangent is discontinuous (``breakpoints``); no integration step and
no sampling interval straddles one.

**The simulation** (:func:`simulate_spiral`) is event driven:

* *Free flight*: the disk is at rest (quasi-static sliding, 4.4), the pusher advances
  along its path until |P(u) - CM| = a. The first such u is found without missing grazing
  contacts: f(u) = |P(u) - CM| - a is sampled every ``sample`` a of travel and every
  interval is either excluded by a rigorous lower bound (Lipschitz: f >= (f_0 + f_1 -
  S w) / 2 with S the path's speed bound; once |P - CM| >= a/2 is guaranteed, the
  quadratic bound f >= min(f_0, f_1) - M w^2 / 8 with M >= |f''|) or bisected; a sign
  change is refined by Brent's method. A dip of f shallower than ``graze_depth`` a is a
  touch, not a push (the pusher passing tangent to a disk it left there); every deeper
  dip is found.
* *Contact*: the contact point is the pusher point, the pushed edge is the disk's tangent
  there, the push direction is the path's tangent (not the line of centres), and the
  forward solver (solver/motion/forward.py, 4.1: sticking or slipping with pusher friction mu_c)
  gives the twist per unit push. The pose is advanced by a midpoint (RK2) step in u of the
  rigid motion about the COR (:func:`solver.sim.kinematics.advance`), and after every (half)
  step the contact is re-imposed: the CM is put back at distance a from P(u) along the
  line of centres (as simulate_disk_encounter does, 4.4).
* *End of contact*: the pusher pushes while n . p > 0 (n the unit vector from the pusher
  to the CM, p the push direction). When it reaches 0 within a step, the step length is
  re-solved by regula falsi so that the contact ends with the disk tangent to the path,
  as in 4.4 (beta_final = pi/2). The disk is then left on the inner side of the path
  (pushed *in*; the book's beta has increased to pi/2) or on the outer side (pushed *out*:
  the book's beta decreased through 0; 4.5.1). The collision parameter is reported in the
  book's convention: (CM - P)/a = cos(beta) p + sin(beta) n_in with n_in the path's
  normal towards the centre; beta = pi/2 is grazing on the inside, beta < 0 means the CM
  is outside the path.

**Pushed out**, precisely: a contact ends with the disk tangent to the path on its outer
side, (CM - P) . n_in < 0. The paths here shrink, so the pusher cannot touch it again:
localization has failed (4.5.1). **Within the promise**: the run reached the end of the
path not in contact and not pushed out, with |CM - centre| + a <= promised radius (the
path's last radius, b_N for a spiral) + ``promise_tol`` a.

Forward-solver problems are never silent: every solve's status is counted
(``not_optimal``), and an exception ends the run with status "solver_error" and its
message. Modes are the forward solver's, named in the world frame: on a counter-clockwise
path (the mirror image of the book's drawings) its "slipping_up" is the book's down-slipping.

Findings (tests/solver/spiral/test_simulate.py, docs/benchmarks.md "Spiral simulation (4.5)"):

* The simulation agrees with r*(beta): the witness support of the lowest sticking COR
  (solver/sketch/sticking.py) on a circle 1 % inside r*(beta) is pushed out, 0.2 % outside it is
  chased or pushed in (4.5.2-4.5.3).
* "At worst, the disk is pushed neither in nor out" (4.5.5) holds on circles only: on a
  spiral the pusher keeps moving in while it chases the disk, and the worst support hit at
  1.002 r*(beta) is lost when the spiral shrinks by 0.2 a per revolution (the book's
  "slightly slower" spiral is needed: for beta = 0.8, mu_c = 0.25 the worst disk is kept
  with a radius 0.2 % above r*(beta) at a shrinkage of 0.05 a per revolution, 0.5 % at
  0.2 a, 1 % at 0.5 a).
* Schedules planned by (4.26) still never lost a disk: 4.5.1 takes the collision depth d
  to be Delta b, but a disk left tangent to the previous pass is met at
  d = Delta b (1 - a/b + Delta b / 2b) (concentric circles), which is 1 - a/b smaller (a
  factor 0.2 near b_inf = 1.25 a), and that slack covers the chase. A schedule made
  critical in this true depth does lose (rare) disks.
"""

from __future__ import annotations

import math
import time
from collections import Counter
from dataclasses import dataclass, field

import numpy as np

from models.core.errors import InvalidInput
from models.core.mpp import perp
from models.core.support import random_balanced_tripods
from solver.core.budget import UNLIMITED, Budget
from solver.core.errors import SolverError, TimeLimitReached
from solver.core.tolerances import SOLVER_DEFAULT, SolverTolerances
from solver.sim.contacts import at_distance, first_dip, gap_to_disk, regula_falsi
from solver.sim.kinematics import Twist, advance
from solver.sim.stepper import MotionOracle
from solver.sketch.sticking_locus import sticking_locus

TWO_PI = 2.0 * math.pi
HALF_PI = 0.5 * math.pi


# ---------------------------------------------------------------------------------------
# Settings
# ---------------------------------------------------------------------------------------


@dataclass(frozen=True)
class SpiralSimSettings:
    """Step sizes and tolerances of :func:`simulate_spiral` (lengths in units of a).

    Attributes:
        step: pusher travel per integration step while in contact (RK2, error O(step^2)).
        sample: pusher travel between samples of |P - CM| in free flight (only speed
            depends on it: the contact search is rigorous at any sampling).
        graze_depth: a dip of |P - CM| - a shallower than this is a touch, not a contact;
            every dip deeper than this is found.
        root_tol: pusher travel to which the start of a contact is located.
        grazing_cos: n . p (cosine of the angle between the line of centres and the push
            direction) at or below which the pusher no longer pushes: the contact ends,
            and a midpoint this close to the end is not solved (an Euler step is used).
        end_cos: |n . p| at which the regula falsi locating the end of a contact stops.
        end_iter: cap on those regula falsi trials.
        promise_tol: allowed excess of the final |CM - centre| + a over the promised radius.
        support_rel: support points may lie up to a (1 + support_rel) from the CM.
        max_steps: cap on contact steps per run.
        max_bisections: cap on interval bisections of one contact search (guards bugs).
    """

    step: float = 0.05
    sample: float = 0.25
    graze_depth: float = 1e-9
    root_tol: float = 1e-12
    grazing_cos: float = 1e-8
    end_cos: float = 1e-11
    end_iter: int = 30
    promise_tol: float = 1e-6
    support_rel: float = 1e-9
    max_steps: int = 2_000_000
    max_bisections: int = 100_000


SPIRAL_SIM_DEFAULT = SpiralSimSettings()
SPIRAL_SIM_FAST = SpiralSimSettings(step=0.1, sample=0.5)
SPIRAL_SIM_FINE = SpiralSimSettings(step=0.02)


# ---------------------------------------------------------------------------------------
# Pusher paths
# ---------------------------------------------------------------------------------------


class _Path:
    """Common interface: ``position(u)``, ``tangent(u, left)`` (dP/du), per-interval bounds
    (``speed_bound``, ``accel_bound``) valid on intervals inside one smooth piece,
    ``breakpoints`` (where dP/du jumps), ``u_end``, ``centre``, ``final_radius``,
    ``revolution_marks`` (u at each completed revolution about the centre)."""

    centre: np.ndarray
    u_end: float
    breakpoints: np.ndarray
    final_radius: float
    revolution_marks: np.ndarray
    clockwise: bool

    def position(self, u):  # pragma: no cover - interface
        raise NotImplementedError

    def tangent(self, u, left: bool = False):  # pragma: no cover - interface
        raise NotImplementedError

    def speed_bound(self, u0, u1):  # pragma: no cover - interface
        raise NotImplementedError

    def accel_bound(self, u0, u1):  # pragma: no cover - interface
        raise NotImplementedError

    def piece_end(self, u: float) -> float:
        """The first breakpoint strictly after u, or u_end."""
        bp = self.breakpoints
        j = int(np.searchsorted(bp, u, side="right"))
        return float(bp[j]) if j < bp.size else self.u_end

    def inward_normal(self, u: float, p_hat: np.ndarray) -> np.ndarray:
        """The unit normal of the path at u on the side of the centre."""
        rel = self.position(u) - self.centre
        side = 1.0 if (rel[0] * p_hat[1] - rel[1] * p_hat[0]) >= 0.0 else -1.0
        return side * perp(p_hat)


@dataclass(frozen=True, eq=False)
class SpiralPath(_Path):
    """b(u) piecewise linear through (2 pi (n-1), b_n), n = 1..N, then constant b_N for
    ``final_turns`` revolutions; P(u) = centre + b(u) (cos(phi0 + s u), sin(phi0 + s u)),
    s = -1 if clockwise else +1 (book 4.5.5)."""

    radii: np.ndarray
    centre: np.ndarray
    start_angle: float
    clockwise: bool
    final_turns: float
    knots: np.ndarray = field(repr=False)
    knot_radii: np.ndarray = field(repr=False)
    slopes: np.ndarray = field(repr=False)
    u_end: float = 0.0
    breakpoints: np.ndarray = field(default=None, repr=False)
    revolution_marks: np.ndarray = field(default=None, repr=False)
    final_radius: float = 0.0

    def _sign(self) -> float:
        return -1.0 if self.clockwise else 1.0

    def radius(self, u):
        return np.interp(u, self.knots, self.knot_radii)

    def _slope(self, u, left=False):
        j = np.searchsorted(self.knots, u, side="left" if left else "right") - 1
        return self.slopes[np.clip(j, 0, self.slopes.size - 1)]

    def position(self, u):
        u = np.asarray(u, dtype=float)
        b = self.radius(u)
        ang = self.start_angle + self._sign() * u
        return self.centre + np.stack([b * np.cos(ang), b * np.sin(ang)], axis=-1)

    def tangent(self, u, left=False):
        u = np.asarray(u, dtype=float)
        b = self.radius(u)
        db = self._slope(u, left)
        s = self._sign()
        ang = self.start_angle + s * u
        c, sn = np.cos(ang), np.sin(ang)
        return np.stack([db * c - s * b * sn, db * sn + s * b * c], axis=-1)

    def speed_bound(self, u0, u1):
        um = 0.5 * (np.asarray(u0) + np.asarray(u1))
        b = np.maximum(self.radius(u0), self.radius(u1))
        return np.hypot(b, self._slope(um))

    def accel_bound(self, u0, u1):
        # P'' = 2 s b' (-sin, cos) - b (cos, sin) inside a piece (b'' = 0).
        um = 0.5 * (np.asarray(u0) + np.asarray(u1))
        b = np.maximum(self.radius(u0), self.radius(u1))
        return b + 2.0 * np.abs(self._slope(um))


def spiral_path(
    radii,
    centre=(0.0, 0.0),
    clockwise: bool = False,
    start_angle: float = 0.0,
    final_turns: float = 1.0,
) -> SpiralPath:
    """The pusher's spiral from radii per revolution b_1, b_2, ..., b_N (book 4.5.5).

    The radius falls linearly in the turned angle from b_n to b_{n+1} during revolution
    n, then stays b_N for ``final_turns`` revolutions (>= 0). One radius gives a circle.
    """
    b = np.asarray(radii, dtype=float).reshape(-1)
    if b.size == 0 or not np.all(np.isfinite(b)) or np.any(b <= 0.0):
        raise InvalidInput("radii", "need one or more positive radii, one per revolution")
    if not (math.isfinite(final_turns) and final_turns >= 0.0):
        raise InvalidInput("final_turns", "must be a finite number >= 0")
    if b.size == 1 and final_turns == 0.0:
        raise InvalidInput("final_turns", "a single radius needs final_turns > 0 (a circle)")
    cen = np.asarray(centre, dtype=float).reshape(2)
    knots = TWO_PI * np.arange(b.size, dtype=float)
    kr = b.copy()
    if final_turns > 0.0:
        knots = np.append(knots, knots[-1] + TWO_PI * final_turns)
        kr = np.append(kr, b[-1])
    slopes = np.diff(kr) / np.diff(knots)
    u_end = float(knots[-1])
    marks = TWO_PI * np.arange(1, int(math.floor(u_end / TWO_PI + 1e-12)) + 1, dtype=float)
    return SpiralPath(
        radii=b, centre=cen, start_angle=float(start_angle), clockwise=bool(clockwise),
        final_turns=float(final_turns), knots=knots, knot_radii=kr, slopes=slopes,
        u_end=u_end, breakpoints=knots[1:-1].copy(), revolution_marks=marks,
        final_radius=float(b[-1]),
    )


@dataclass(frozen=True, eq=False)
class PolylinePath(_Path):
    """Straight segments through ``points``; u is the arc length."""

    points: np.ndarray
    centre: np.ndarray
    cum: np.ndarray = field(repr=False)
    dirs: np.ndarray = field(repr=False)
    u_end: float = 0.0
    breakpoints: np.ndarray = field(default=None, repr=False)
    revolution_marks: np.ndarray = field(default=None, repr=False)
    final_radius: float = 0.0
    clockwise: bool = False

    def _segment(self, u, left=False):
        j = np.searchsorted(self.cum, u, side="left" if left else "right") - 1
        return np.clip(j, 0, self.dirs.shape[0] - 1)

    def position(self, u):
        u = np.asarray(u, dtype=float)
        j = self._segment(u)
        return self.points[j] + (u - self.cum[j])[..., None] * self.dirs[j]

    def tangent(self, u, left=False):
        return self.dirs[self._segment(np.asarray(u, dtype=float), left)]

    def speed_bound(self, u0, u1):
        return np.ones_like(np.asarray(u0, dtype=float))

    def accel_bound(self, u0, u1):
        return np.zeros_like(np.asarray(u0, dtype=float))


def polyline_path(points, centre=(0.0, 0.0), final_radius: float | None = None) -> PolylinePath:
    """A pusher moving along straight segments through ``points`` (M >= 2, in order of
    travel). ``centre`` is the point the disk is herded towards (reports and the inner
    side of the path); ``final_radius`` defaults to the last point's distance from it."""
    pts = np.asarray(points, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 2 or pts.shape[0] < 2 or not np.all(np.isfinite(pts)):
        raise InvalidInput("points", "need two or more finite pusher points [x, y]")
    seg = np.diff(pts, axis=0)
    length = np.linalg.norm(seg, axis=1)
    keep = np.concatenate([[True], length > 0.0])
    pts = pts[keep]
    if pts.shape[0] < 2:
        raise InvalidInput("points", "need two distinct pusher points")
    seg = np.diff(pts, axis=0)
    length = np.linalg.norm(seg, axis=1)
    cen = np.asarray(centre, dtype=float).reshape(2)
    cum = np.concatenate([[0.0], np.cumsum(length)])
    rel = pts - cen
    # Unwrapped polar angle at the vertices (each segment turns by less than pi about the
    # centre unless it passes through it), and the revolutions completed along the way.
    ang = np.unwrap(np.arctan2(rel[:, 1], rel[:, 0]))
    turned = ang - ang[0]
    total = float(turned[-1])
    marks = []
    sgn = 1.0 if total >= 0.0 else -1.0
    for k in range(1, int(math.floor(abs(total) / TWO_PI + 1e-12)) + 1):
        target = sgn * k * TWO_PI
        j = int(np.nonzero(sgn * turned >= sgn * target)[0][0]) - 1
        d = np.array([math.cos(ang[0] + target), math.sin(ang[0] + target)])
        e = seg[j]
        den = d[0] * e[1] - d[1] * e[0]
        t = 0.0 if den == 0.0 else -(d[0] * rel[j][1] - d[1] * rel[j][0]) / den
        marks.append(cum[j] + min(max(t, 0.0), 1.0) * length[j])
    fr = float(np.linalg.norm(rel[-1])) if final_radius is None else float(final_radius)
    return PolylinePath(
        points=pts, centre=cen, cum=cum, dirs=seg / length[:, None], u_end=float(cum[-1]),
        breakpoints=cum[1:-1].copy(), revolution_marks=np.array(marks, dtype=float),
        final_radius=fr, clockwise=total < 0.0,
    )


# ---------------------------------------------------------------------------------------
# Results
# ---------------------------------------------------------------------------------------


@dataclass(frozen=True)
class ContactRecord:
    """One collision: pusher parameter at its start and end, the collision parameter beta
    (book 4.4/4.5.1 convention, see the module docstring) at first contact, its smallest
    value during the contact and at the end (+-pi/2 when it ended), the book's distance
    from grazing d = a (1 - sin beta_initial) (4.24), which side of the path the disk was
    left on ("inside", "outside", or "open" if the path or the run ended in contact), and
    |CM - centre| at start and end."""

    u_start: float
    u_end: float
    beta_initial: float
    beta_min: float
    beta_final: float
    depth_initial: float
    side: str
    cm_radius_start: float
    cm_radius_end: float
    steps: int


@dataclass(frozen=True)
class SpiralRun:
    """One disk herded along a path.

    ``status``: "completed" (the path ended with the disk at rest), "in_contact_at_end",
    "escaped" (pushed out and the run stopped there), "time_limit", "step_limit",
    "solver_error". ``u_reached`` / ``path_fraction``: where the pusher got to.
    ``trajectory_u`` (T,), ``trajectory_cm`` (T, 2), ``trajectory_theta`` (T,): the pose at
    every step end and every contact start/end (the disk is at rest in between);
    ``trajectory_beta`` the collision parameter there (NaN in free flight).
    ``revolution_cm_radius``: |CM - centre| when the pusher completes each revolution.
    ``final_extent`` = |CM - centre| + a; ``inside_promise`` as in the module docstring.
    ``max_protrusion``: the largest |CM - centre| + a - |P - centre| over the samples (how
    far the disk stuck out of the pusher's current circle). ``max_force_angle``: the
    largest angle between the contact force and the contact normal (<= atan mu_c).
    ``touches``: contact-search intervals left undecided at root_tol, and meetings with
    n . p <= grazing_cos (no push), which are not contacts (normally 0).
    ``forward_solves``, ``not_optimal``, ``modes``, ``max_kkt``: forward-solver counts;
    ``error``: the message that ended a "solver_error" run."""

    status: str
    escaped: bool
    inside_promise: bool
    promised_radius: float
    final_cm: np.ndarray
    final_theta: float
    final_radius: float
    final_extent: float
    contacts: tuple[ContactRecord, ...]
    touches: int
    trajectory_u: np.ndarray
    trajectory_cm: np.ndarray
    trajectory_theta: np.ndarray
    trajectory_beta: np.ndarray
    revolution_cm_radius: np.ndarray
    max_protrusion: float
    max_force_angle: float
    u_reached: float
    path_fraction: float
    steps: int
    forward_solves: int
    not_optimal: int
    modes: dict
    max_kkt: float
    wall_time_s: float
    error: str | None = None

    @property
    def n_contacts(self) -> int:
        return len(self.contacts)

    @property
    def complete(self) -> bool:
        """The run went where it was asked: to the end of the path, or to the escape it
        stops at (not cut by the time limit, the step cap or a solver error)."""
        return self.status in ("completed", "escaped", "in_contact_at_end")

    @property
    def solve_time_s(self) -> float:
        return self.wall_time_s

    @property
    def message(self) -> str:
        text = (f"{self.status} at {100 * self.path_fraction:.3g} % of the path; {self.n_contacts} contacts, "
                f"{self.forward_solves} forward solves; final extent {self.final_extent:.6g}")
        return text + (f" ({self.error})" if self.error else "")


@dataclass(frozen=True)
class SpiralBatch:
    """Many runs on one path. ``all_inside``: every run completed, none escaped, all within
    the promise. ``worst_index``: the run with the largest final extent (escaped runs
    count as infinitely bad). ``margin`` = promised radius - largest final extent of the
    runs that were not pushed out (negative: some disk ended outside the promise).
    ``statuses`` counts run statuses ("not_run" for runs skipped by the time limit)."""

    runs: tuple[SpiralRun, ...]
    n: int
    all_inside: bool
    escaped: int
    escaped_indices: tuple[int, ...]
    outside_promise_indices: tuple[int, ...]
    promised_radius: float
    max_final_extent: float
    margin: float
    worst_index: int
    max_protrusion: float
    max_depth_initial: float
    min_beta_change: float
    contacts: int
    statuses: dict
    forward_solves: int
    not_optimal: int
    solver_failures: int
    wall_time_s: float
    supports_per_second: float
    seed: int | None = None

    @property
    def status(self) -> str:
        """"all_inside", "escaped" (a disk was pushed out), or "incomplete" (runs cut short
        or not run)."""
        if self.all_inside:
            return "all_inside"
        return "escaped" if self.escaped else "incomplete"

    @property
    def complete(self) -> bool:
        """Every run ran to its end (none "not_run", none cut by the time limit)."""
        return len(self.runs) == self.n and all(r.complete for r in self.runs)

    @property
    def solve_time_s(self) -> float:
        return self.wall_time_s

    @property
    def message(self) -> str:
        ran = len(self.runs)
        text = f"{ran} of {self.n} runs ran ({self.statuses}); {self.escaped} escaped"
        return text if ran == self.n else text + f"; {self.n - ran} not run"


# ---------------------------------------------------------------------------------------
# Contact search (free flight)
# ---------------------------------------------------------------------------------------


# ---------------------------------------------------------------------------------------
# One run
# ---------------------------------------------------------------------------------------


class _Stop(Exception):
    def __init__(self, status: str, message: str | None = None):
        super().__init__(message or status)
        self.status = status
        self.message = message


def _check_inputs(path, points, weights, a, mu_c, start_cm, s: SpiralSimSettings):
    if not (math.isfinite(a) and a > 0.0):
        raise InvalidInput("disk_radius", "must be a positive number")
    if not (math.isfinite(mu_c) and mu_c >= 0.0):
        raise InvalidInput("mu_c", "must be a finite number >= 0")
    body = np.asarray(points, dtype=float).reshape(-1, 2)
    wts = np.asarray(weights, dtype=float).reshape(-1)
    if body.shape[0] != wts.shape[0] or body.shape[0] == 0:
        raise InvalidInput("weights", "need one weight per support point")
    if np.max(np.linalg.norm(body, axis=1)) > a * (1.0 + s.support_rel):
        raise InvalidInput("points", "support points must lie in the disk (relative to the CM, |w| <= a)")
    cm = np.asarray(start_cm, dtype=float).reshape(2)
    if not np.all(np.isfinite(cm)):
        raise InvalidInput("start_cm", "must be finite")
    if float(gap_to_disk(path, cm, a, 0.0)) <= 0.0:
        raise InvalidInput("start_cm", "the pusher starts on or inside the disk")
    return body, wts, cm


class _Herding:
    """One disk herded along a path: the pusher's frame at the disk, the forward solve, the
    midpoint step and the end of a contact (the module docstring), and the trajectory."""

    def __init__(self, path: _Path, a: float, s: SpiralSimSettings, oracle: MotionOracle,
                 cm: np.ndarray, theta: float) -> None:
        self.path, self.a, self.s, self.oracle = path, a, s, oracle
        self.traj_u, self.traj_cm, self.traj_th, self.traj_b = [0.0], [cm.copy()], [theta], [math.nan]
        self.steps_total = 0
        self.current: dict | None = None  # the contact in progress, for a run stopped inside it

    def record(self, u, c, th, beta=math.nan) -> None:
        self.traj_u.append(u)
        self.traj_cm.append(c.copy())
        self.traj_th.append(th)
        self.traj_b.append(beta)

    def frame(self, u, c, left=False):
        """Pusher point, push direction, speed, unit line of centres, n . p, beta."""
        pp = self.path.position(u)
        tan = self.path.tangent(u, left)
        sp = float(np.hypot(tan[0], tan[1]))
        ph = tan / sp
        d = c - pp
        n = d / float(np.hypot(d[0], d[1]))
        n_in = self.path.inward_normal(u, ph)
        return pp, ph, sp, n, float(n @ ph), math.atan2(float(n @ n_in), float(n @ ph))

    def twist(self, u, c, th) -> Twist:
        pp, ph, sp, n, _, _ = self.frame(u, c)
        try:
            tw = self.oracle.twist(c, th, pp, math.atan2(-n[1], -n[0]) + HALF_PI, math.atan2(ph[1], ph[0]))
        except TimeLimitReached as exc:
            raise _Stop("time_limit") from exc
        except (SolverError, InvalidInput) as exc:
            raise _Stop("solver_error", f"forward solve at u = {u:.9g}: {exc}") from exc
        # The twist per unit push along p; per unit u it is scaled by the path's speed.
        return tw.scaled(sp)

    def project(self, c, u):
        return at_distance(c, self.path.position(u), self.a)

    def rk2(self, u, c, th, tw1, h):
        """One midpoint step of length h in u from (c, th) with tw1 the twist at its start;
        returns the new pose and n . p there (with the tangent of the step's own piece)."""
        c_h, th_h = advance(c, th, tw1, 0.5 * h)
        c_h = self.project(c_h, u + 0.5 * h)
        g_h = self.frame(u + 0.5 * h, c_h)[4]
        tw2 = self.twist(u + 0.5 * h, c_h, th_h) if g_h > self.s.grazing_cos else tw1
        c_n, th_n = advance(c, th, tw2, h)
        c_n = self.project(c_n, u + h)
        return c_n, th_n, self.frame(u + h, c_n, left=True)[4]

    def locate_end(self, u, c, th, tw1, g0, h, g1):
        """The step length at which n . p reaches 0 (the disk tangent to the path, contact
        lost): regula falsi on fresh RK2 steps from the step's start, until
        |n . p| <= end_cos or end_iter trials; (length, CM, theta) of the last trial."""
        if g1 >= 0.0:  # 0 <= n . p <= grazing_cos at the full step: the contact ends there
            c_n, th_n, _ = self.rk2(u, c, th, tw1, h)
            return h, c_n, th_n

        def trial(hh):
            c_t, th_t, g_t = self.rk2(u, c, th, tw1, hh)
            return g_t, (c_t, th_t)

        hh, (c_t, th_t) = regula_falsi(trial, 0.0, g0, h, g1, self.s.end_cos, self.s.end_iter)
        return hh, c_t, th_t

    def push(self, hit: float, u: float, cm: np.ndarray, theta: float, g: float, beta: float, r_start: float):
        """One contact from its start at ``hit`` until n . p reaches 0 or the path ends:
        (u, cm, theta, its record, whether the path ended in contact)."""
        s = self.s
        self.record(u, cm, theta, beta)
        beta0, beta_min, n_steps = beta, beta, 0
        self.current = {"u_start": hit, "beta0": beta0, "r_start": r_start}
        ended = at_end = False
        while not ended:
            if u >= self.path.u_end:
                at_end = True
                break
            if self.steps_total >= s.max_steps:
                raise _Stop("step_limit")
            sp = self.frame(u, cm)[2]
            h = min(s.step * self.a / sp, self.path.piece_end(u) - u)
            tw1 = self.twist(u, cm, theta)
            c_n, th_n, g_n = self.rk2(u, cm, theta, tw1, h)
            if g_n <= s.grazing_cos:
                h, c_n, th_n = self.locate_end(u, cm, theta, tw1, g, h, g_n)
                ended = True
            cm, theta, u = c_n, th_n, u + h
            n_steps += 1
            self.steps_total += 1
            _, _, _, _, g, beta = self.frame(u, cm, left=True)
            self.record(u, cm, theta, beta)
            beta_min = min(beta_min, beta)
            self.current.update(beta_min=beta_min, steps=n_steps)
            if not ended:
                # At a corner of the path the push direction turns: check it again.
                _, _, _, _, g, beta = self.frame(u, cm)
                ended = g <= s.grazing_cos
        side = ("inside" if beta > 0.0 else "outside") if ended else "open"
        record = ContactRecord(
            u_start=hit, u_end=u, beta_initial=beta0, beta_min=beta_min,
            beta_final=beta if side == "open" else math.copysign(HALF_PI, beta),
            depth_initial=self.a * (1.0 - math.sin(beta0)), side=side,
            cm_radius_start=r_start, cm_radius_end=float(np.linalg.norm(cm - self.path.centre)), steps=n_steps,
        )
        self.current = None
        return u, cm, theta, record, at_end

    def cut_contact(self) -> ContactRecord | None:
        """The record of the contact a stopped run was in, up to where it stopped."""
        if self.current is None:
            return None
        b0 = self.current["beta0"]
        return ContactRecord(
            u_start=self.current["u_start"], u_end=self.traj_u[-1], beta_initial=b0,
            beta_min=self.current.get("beta_min", b0), beta_final=float(self.traj_b[-1]),
            depth_initial=self.a * (1.0 - math.sin(b0)), side="open", cm_radius_start=self.current["r_start"],
            cm_radius_end=float(np.linalg.norm(self.traj_cm[-1] - self.path.centre)), steps=self.current.get("steps", 0),
        )

    def run(self, status: str, escaped: bool, error: str | None, contacts: list[ContactRecord], touches: int,
            promise: float, t0: float) -> SpiralRun:
        """The run's answer from its trajectory: where it ended, against the promise."""
        path, a, counts = self.path, self.a, self.oracle.counts
        tu, tc = np.array(self.traj_u), np.array(self.traj_cm)
        tt, tb = np.array(self.traj_th), np.array(self.traj_b)
        marks = path.revolution_marks[path.revolution_marks <= tu[-1]]
        rad = np.linalg.norm(tc - path.centre, axis=1)
        rev = np.interp(marks, tu, rad) if marks.size else np.zeros(0)
        pr = np.linalg.norm(path.position(tu) - path.centre, axis=1)
        final_radius = float(rad[-1])
        extent = final_radius + a
        inside = (status == "completed") and not escaped and extent <= promise + self.s.promise_tol * a
        return SpiralRun(
            status=status, escaped=escaped, inside_promise=bool(inside), promised_radius=promise,
            final_cm=tc[-1].copy(), final_theta=float(tt[-1]), final_radius=final_radius,
            final_extent=extent, contacts=tuple(contacts), touches=touches,
            trajectory_u=tu, trajectory_cm=tc, trajectory_theta=tt, trajectory_beta=tb, revolution_cm_radius=rev,
            max_protrusion=float(np.max(rad + a - pr)), max_force_angle=counts.max_force_angle,
            u_reached=float(tu[-1]), path_fraction=float(tu[-1] / path.u_end) if path.u_end > 0 else 1.0,
            steps=self.steps_total, forward_solves=counts.solves, not_optimal=counts.not_optimal,
            modes=dict(counts.modes), max_kkt=counts.max_kkt, wall_time_s=time.perf_counter() - t0,
            error=error,
        )


def simulate_spiral(
    path: _Path,
    points,
    weights,
    a: float,
    mu_c: float,
    start_cm,
    start_theta: float = 0.0,
    settings: SpiralSimSettings = SPIRAL_SIM_DEFAULT,
    promised_radius: float | None = None,
    stop_on_escape: bool = True,
    method: str = "newton",
    tol: SolverTolerances = SOLVER_DEFAULT,
    budget: Budget = UNLIMITED,
) -> SpiralRun:
    """Herd one disk along ``path`` (see the module docstring; book 4.4, 4.5).

    ``points`` (k, 2), ``weights`` (k,): the support in the disk's body frame, relative to
    the CM (|w| <= a); the body frame is turned by ``start_theta`` (CCW) at the start, the
    CM at ``start_cm`` (world). mu_c is the pusher-disk friction (4.1). ``promised_radius``
    defaults to the path's final radius.
    """
    s = settings
    body, wts, cm = _check_inputs(path, points, weights, a, mu_c, start_cm, s)
    theta = float(start_theta)
    promise = path.final_radius if promised_radius is None else float(promised_radius)
    t0 = time.perf_counter()
    herd = _Herding(path, a, s, MotionOracle(body, wts, a, mu_c, method, tol, budget), cm, theta)
    contacts: list[ContactRecord] = []
    touches = 0
    u = 0.0
    status = "completed"
    escaped = False
    error = None
    try:
        while True:
            # ---- free flight
            hit, tz = first_dip(path, cm, a, u, s.sample, s.graze_depth, s.root_tol, s.max_bisections)
            touches += tz
            if hit is None or hit >= path.u_end:
                u = path.u_end if hit is None else hit
                herd.record(u, cm, theta)
                break
            u = hit
            # ---- contact
            r_start = float(np.linalg.norm(cm - path.centre))
            cm = herd.project(cm, u)
            _, _, speed, _, g, beta = herd.frame(u, cm)
            if g <= s.grazing_cos:
                # The pusher meets the disk moving along its tangent (a corner of the path
                # turning in right at the end of a contact): a touch; move on.
                touches += 1
                u = min(path.u_end, u + s.root_tol * a / max(speed, 1e-300))
                continue
            u, cm, theta, contact, at_end = herd.push(hit, u, cm, theta, g, beta, r_start)
            contacts.append(contact)
            if contact.side == "outside":
                escaped = True
                if stop_on_escape:
                    status = "escaped"
                    break
            if at_end:
                status = "in_contact_at_end"
                break
    except _Stop as stop:
        status = stop.status
        error = stop.message
    except SolverError as exc:  # the contact search's guard
        status = "solver_error"
        error = str(exc)
    cut = herd.cut_contact()
    if cut is not None and status not in ("completed", "escaped", "in_contact_at_end"):
        contacts.append(cut)
    return herd.run(status, escaped, error, contacts, touches, promise, t0)


def collision_pose(path: _Path, u: float, beta: float, a: float):
    """Where to put a disk so that the pusher at P(u) touches it at collision parameter
    ``beta`` (book 4.4-4.5 convention: (CM - P)/a = cos(beta) p + sin(beta) n_in), and the
    2x2 map from the book's encounter frame (models.push.gross_bounds.encounter_scene: push along
    +x, the disk below the pusher's line, i.e. the centre side is -y) to the world.

    Returns (cm, m): world support points are ``points_book @ m.T``. m is a rotation when
    the path turns clockwise at u (the book's drawing), a reflection when it turns
    counter-clockwise (the mirror image), so a support given in the book's frame meets the
    same (or the mirrored) collision."""
    tan = path.tangent(u)
    p_hat = tan / float(np.hypot(tan[0], tan[1]))
    n_in = path.inward_normal(u, p_hat)
    cm = path.position(u) + a * (math.cos(beta) * p_hat + math.sin(beta) * n_in)
    return cm, np.column_stack([p_hat, -n_in])


def criterion_margins(run: SpiralRun, path: _Path, r_star) -> np.ndarray:
    """Per contact of ``run``, the smallest |P(u) - centre| - r*(beta(u)) over its samples.

    Book 4.5.2-4.5.3: while the pusher's radius is at least r*(beta), every COR of the
    sketch lies on the inner side of the critical line and the disk is pushed in, whatever
    its support; a negative margin means that guarantee lapsed during the contact (the
    disk may still have been pushed in: its own COR need not be the worst one). ``r_star``
    is a vectorised callable of beta (e.g. an interpolation of solver/spiral/critical_radius.py's table);
    the radius is the distance from the path's centre, the book's b (a spiral's osculating
    circle differs from it by O((db/du / b)^2))."""
    out = []
    tu, tb = run.trajectory_u, run.trajectory_beta
    for c in run.contacts:
        sel = (tu >= c.u_start) & (tu <= c.u_end) & np.isfinite(tb)
        if not np.any(sel):
            out.append(math.nan)
            continue
        r = np.linalg.norm(path.position(tu[sel]) - path.centre, axis=1)
        out.append(float(np.min(r - np.asarray(r_star(tb[sel]), dtype=float))))
    return np.array(out)


# ---------------------------------------------------------------------------------------
# Random supports and starts, batches
# ---------------------------------------------------------------------------------------


def random_start_positions(rng: np.random.Generator, n: int, radius: float, centre=(0.0, 0.0),
                           inner_radius: float = 0.0) -> np.ndarray:
    """``n`` CM positions uniform (in area) in the disk of ``radius`` about ``centre``, or
    in the annulus inner_radius <= |CM - centre| <= radius; shape (n, 2)."""
    if not (math.isfinite(radius) and 0.0 <= inner_radius <= radius):
        raise InvalidInput("radius", "need finite radii 0 <= inner_radius <= radius")
    r = np.sqrt(rng.uniform(inner_radius**2, radius**2, size=n))
    th = rng.uniform(0.0, TWO_PI, size=n)
    return np.asarray(centre, dtype=float) + np.column_stack([r * np.cos(th), r * np.sin(th)])


SUPPORT_KINDS = ("tripod", "rim", "dipod", "cloud")
"""Kinds of random pressure distribution drawn by :func:`random_supports`."""


def random_supports(rng: np.random.Generator, n: int, a: float, kind: str = "tripod", k: int = 8):
    """``n`` random pressure distributions in the disk of radius a, relative to the CM.

    * "tripod": balanced tripods uniform in the disk, as in the book's figure 3-5 (3.3.3,
      models.core.support.random_balanced_tripods);
    * "rim": balanced tripods with their three points on the rim (uniform angles, draws
      needing a negative weight discarded): they reach far out in the COR loci;
    * "dipod": two half weights at the ends of a random diameter, the supports of the
      outer boundary of the COR locus (3.3.8, figure 3-12): the extremes of the sketch;
    * "cloud": k points uniform in the disk with Dirichlet(1) weights, shifted so that
      their centroid is the CM and, if a point then lies outside the disk, scaled into it.

    Returns points (n, m, 2) and weights (n, m) (m = 3, 3, 2, k)."""
    if kind == "tripod":
        return random_balanced_tripods(rng, n, a)
    if kind == "rim":
        pts, wts = [], []
        while len(pts) < n:
            th = rng.uniform(0.0, TWO_PI, size=(4 * n, 3))
            w = a * np.stack([np.cos(th), np.sin(th)], axis=-1)
            m = np.stack([np.ones((4 * n, 3)), w[..., 0], w[..., 1]], axis=1)
            ok = np.abs(np.linalg.det(m)) > 1e-9 * a * a
            p = np.linalg.solve(m[ok], np.tile([1.0, 0.0, 0.0], (int(ok.sum()), 1))[..., None])[..., 0]
            good = np.all(p >= 0.0, axis=1)
            pts.extend(w[ok][good])
            wts.extend(p[good])
        return np.array(pts[:n]), np.array(wts[:n])
    if kind == "dipod":
        th = rng.uniform(0.0, math.pi, size=n)
        e = a * np.column_stack([np.cos(th), np.sin(th)])
        return np.stack([e, -e], axis=1), np.full((n, 2), 0.5)
    if kind != "cloud":
        raise InvalidInput("kind", f"must be one of {', '.join(SUPPORT_KINDS)}")
    if k < 1:
        raise InvalidInput("k", "must be at least 1")
    r = a * np.sqrt(rng.uniform(size=(n, k)))
    th = rng.uniform(0.0, TWO_PI, size=(n, k))
    w = np.stack([r * np.cos(th), r * np.sin(th)], axis=-1)
    p = rng.dirichlet(np.ones(k), size=n)
    w = w - np.einsum("bk,bki->bi", p, w)[:, None, :]
    size = np.max(np.linalg.norm(w, axis=2), axis=1)
    w = w * np.minimum(1.0, a / np.maximum(size, 1e-300))[:, None, None]
    return w, p


def simulate_spiral_batch(
    path: _Path,
    points,
    weights,
    a: float,
    mu_c: float,
    starts,
    start_thetas=None,
    settings: SpiralSimSettings = SPIRAL_SIM_DEFAULT,
    promised_radius: float | None = None,
    budget: Budget = UNLIMITED,
    seed: int | None = None,
) -> SpiralBatch:
    """Run :func:`simulate_spiral` for supports ``points`` (B, k, 2) / ``weights`` (B, k)
    from CM positions ``starts`` (B, 2) and summarise. ``budget`` bounds the whole batch:
    each run stops at its deadline ("time_limit"), runs not started are "not_run"."""
    w = np.asarray(points, dtype=float)
    p = np.asarray(weights, dtype=float)
    c0 = np.asarray(starts, dtype=float).reshape(-1, 2)
    if w.ndim != 3 or p.shape != w.shape[:2] or c0.shape[0] != w.shape[0]:
        raise InvalidInput("points", "need points (B, k, 2), weights (B, k) and starts (B, 2)")
    th0 = np.zeros(w.shape[0]) if start_thetas is None else np.asarray(start_thetas, dtype=float).reshape(-1)
    promise = path.final_radius if promised_radius is None else float(promised_radius)
    t0 = time.perf_counter()
    runs: list[SpiralRun] = []
    statuses: Counter = Counter()
    for i in range(w.shape[0]):
        if budget.expired():
            statuses["not_run"] += w.shape[0] - i
            break
        run = simulate_spiral(path, w[i], p[i], a, mu_c, c0[i], float(th0[i]), settings, promise, budget=budget)
        runs.append(run)
        statuses[run.status] += 1
    elapsed = time.perf_counter() - t0
    esc = tuple(i for i, r in enumerate(runs) if r.escaped)
    outside = tuple(i for i, r in enumerate(runs) if not r.inside_promise)
    kept = [r.final_extent for r in runs if not r.escaped]
    max_ext = max(kept) if kept else math.nan
    badness = [math.inf if r.escaped else r.final_extent for r in runs]
    worst = int(np.argmax(badness)) if runs else -1
    cts = [c for r in runs for c in r.contacts]
    done = sum(1 for r in runs if r.status in ("completed", "escaped", "in_contact_at_end"))
    return SpiralBatch(
        runs=tuple(runs), n=int(w.shape[0]),
        all_inside=len(runs) == w.shape[0] and not outside,
        escaped=len(esc), escaped_indices=esc, outside_promise_indices=outside,
        promised_radius=promise, max_final_extent=max_ext, margin=promise - max_ext,
        worst_index=worst,
        max_protrusion=max((r.max_protrusion for r in runs), default=math.nan),
        max_depth_initial=max((c.depth_initial for c in cts), default=0.0),
        min_beta_change=min((c.beta_min - c.beta_initial for c in cts), default=0.0),
        contacts=len(cts), statuses=dict(statuses),
        forward_solves=sum(r.forward_solves for r in runs),
        not_optimal=sum(r.not_optimal for r in runs),
        solver_failures=statuses.get("solver_error", 0),
        wall_time_s=elapsed, supports_per_second=done / elapsed if elapsed > 0 else math.inf,
        seed=seed,
    )


def spiral_check(
    path: _Path,
    a: float,
    mu_c: float,
    n: int,
    seed: int,
    kind: str = "tripod",
    k: int = 8,
    start_radius: float | None = None,
    settings: SpiralSimSettings = SPIRAL_SIM_DEFAULT,
    promised_radius: float | None = None,
    budget: Budget = UNLIMITED,
    start_inner_radius: float = 0.0,
) -> SpiralBatch:
    """The issue's check: ``n`` random supports (``kind``, see :func:`random_supports`)
    with random orientations, CMs uniform in the disk of ``start_radius`` (default: the
    path's starting radius minus a, so every disk starts inside the first circle) about the
    path's centre (or in the annulus from ``start_inner_radius``), herded along ``path``.
    Seeded by ``seed``."""
    rng = np.random.default_rng(seed)
    w, p = random_supports(rng, n, a, kind, k)
    if start_radius is None:
        start_radius = float(np.linalg.norm(path.position(0.0) - path.centre)) - a
    start_radius = max(start_radius, 0.0)
    starts = random_start_positions(rng, n, start_radius, path.centre, min(start_inner_radius, start_radius))
    thetas = rng.uniform(0.0, TWO_PI, size=n)
    return simulate_spiral_batch(path, w, p, a, mu_c, starts, thetas, settings, promised_radius, budget, seed)


def worst_case_support(a: float, beta: float, mu_c: float, tol: SolverTolerances = SOLVER_DEFAULT):
    """The support whose COR is the lowest sticking COR at collision parameter ``beta``
    (4.5.2-4.5.3): the witness of the inside end of the certified lower bracket of the
    sticking locus (solver/sketch/sticking.py), its point mass at the COR included. Returns
    (r* from that inside end, points relative to the CM in the frame of
    models.push.gross_bounds.encounter_scene, weights)."""
    from models.push.gross_bounds import encounter_scene

    scene = encounter_scene(a, beta)
    end = sticking_locus(scene, mu_c, tol=tol, ends="lowest").lower
    if end is None or end.feasible is None:
        raise SolverError(f"no certified lower end of the sticking locus at beta = {beta:g}")
    wit = end.feasible
    pts = wit.witness_points - scene.center_of_mass
    wts = wit.witness_weights
    if wit.point_mass_at_cor > 0.0:
        pts = np.vstack([pts, wit.cor - scene.center_of_mass])
        wts = np.append(wts, wit.point_mass_at_cor)
    return -end.feasible_position, pts, wts
