"""A part on a conveyor belt meeting one fence, simulated quasi-statically (issue 12; book
5.1, 6.5): the independent check of the configuration maps of models/feeder/fence.py.

Frames as in models/feeder/fence.py: the belt carries the part in -y; in the belt's frame
the fence is the pusher, moving in +y. The run is kept in the fence's frame (the fence
fixed, the belt and everything on it drifting in -y): a motion found in the belt's frame by
the forward minimum-power solver (3.7, 4.1) is shifted by -d. The fence is the segment from
its free end E along w = sgn(gamma) t for its length; its face normal is
n = (-sin gamma, cos gamma). The part slides toward E. A fence alone has E at the origin;
the fences of a belt (:func:`simulate_belt_batch`) are segments placed in that frame (the
world, belt in -y), met one after the other, each run starting where the last one ended.

Contacts and what moves the part at each (the run switches between them by events):

* none: the part drifts with the belt in -y until a vertex meets the face or E meets an
  edge (placed exactly, by ray casting), or never again: the part has left.
* a vertex on the face: the forward solve with the fence's edge angle at that vertex.
* an edge flush on the face (two vertices, or E and a vertex): the part cannot turn, so it
  translates; the belt's drag then passes through the CM whatever the support, and the
  contact force lies on the friction-cone edge against the slip, n + mu_c w. If that force
  line through the CM crosses the supported part of the edge the part slides along the
  fence; otherwise it pivots on the end the line passes (a vertex contact, or E on the
  edge). When |tan gamma| <= mu_c the part cannot slide (6.4): it is carried with the
  fence and the force balances the drag, along d through the CM; where that line meets
  the supported edge the part jams.
* E on an edge: the forward solve with E as a point pusher on that edge.

Point contacts step with the motion at the step's start held for the step (one forward
solve per step), the contact re-imposed; translations and the last turn onto A are exact.
The final orientation's error is first order in the step (docs/benchmarks.md: up to 0.5
degrees at the default step 0.02 a, 0.1 at 0.005 a; a midpoint rule, tried, was no better
per solve: the motion jumps where the contact switches between sticking and slipping). A
step after which the fence passes through the part deeper than ``contact_tol`` (another
vertex through the face, E into the part) is halved. E pushes only the edges that face it.
"""

from __future__ import annotations

import math
import time
from collections.abc import Generator
from dataclasses import dataclass, field
from enum import Enum

import numpy as np
from numpy.typing import ArrayLike

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.core.mpp import perp
from models.core.scene import PushScene
from models.feeder.fence import Fence
from solver.core.budget import UNLIMITED, Budget
from solver.core.errors import TimeLimitReached
from solver.core.tolerances import SOLVER_DEFAULT, SolverTolerances
from solver.kernels import codes as fk
from solver.motion.forward import solve_forward_scenes
from solver.sim.contacts import onto_line
from solver.sim.kinematics import Twist, advance, body_to_world
from solver.sim.stepper import MotionOracle, SolveCounts

D = np.array([0.0, 1.0])
PUSH_ANGLE = 0.5 * math.pi
GRAZING = 1e-9
"""|sin| of the angle between an edge under E and the belt's motion at which E stops pushing
(the scene's own grazing test, models.core.tolerances.Tolerances.grazing_sin)."""
DEFAULT_FENCE_LENGTH_RADII = 40.0
"""A fence's length when a run is given none, in part radii."""
START_ALONG = 0.7
"""Where a part given no start meets a fence: this fraction of its length from E."""
E_ON_EDGE = 2.0
"""E this many contact tolerances from an edge next to a vertex on the face makes that edge
flush, and from a vertex puts that vertex at E (a step accepted at the tolerance can leave
E just beyond either)."""


class Contact(Enum):
    """What touches what while the part is on the fence (the module docstring's contacts);
    the value is the kind of the run's event when it starts."""

    VERTEX = "vertex"  # hull vertex i on the fence's face: a forward solve
    END = "end"  # the fence's end E on hull edge i: a forward solve
    FLUSH = "flush"  # hull edge i flush on the face, sliding: an exact translation
    ALONG = "along"  # the edge under E lies along the belt: E no longer pushes, the part leaves
    JAM = "jam"  # flush and carried with the fence (|tan gamma| <= mu_c, 6.4)


CONTACT_TEXT = {
    Contact.VERTEX: "vertex {} on the fence's face, turning",
    Contact.FLUSH: "edge {} flush on the face, sliding",
    Contact.END: "the fence's end on edge {}, turning off it",
}


@dataclass(frozen=True)
class Mode:
    """A contact and the hull vertex or edge it is at (-1 for ALONG and JAM)."""

    contact: Contact
    index: int = -1

    @property
    def text(self) -> str:
        return CONTACT_TEXT[self.contact].format(self.index) if self.contact in CONTACT_TEXT else self.contact.value

    def __str__(self) -> str:
        return f"{self.contact.value}:{self.index}" if self.index >= 0 else self.contact.value


@dataclass(frozen=True)
class FeederSimSettings:
    """Named settings of a fence run (lengths relative to the part's radius a).

    Attributes:
        step: push per step (first order: the twist at the step's start is held for the
            step, about the COR where it was found; docs/benchmarks.md gives the error).
        contact_tol: a vertex this close to the face (or E to an edge) is in contact.
        min_step: the shortest step event location halves down to.
        max_steps: steps (of any kind) before the run gives up (status "step_limit").
        stall_steps: consecutive steps cut to ``min_step`` after which the run stops as
            "stalled" (a contact it cannot advance: a vertex exactly at E, rarely).
        clearance: the part's start: this much belt travel before it touches the face.
    """

    step: float = 0.02
    contact_tol: float = 1e-9
    min_step: float = 1e-12
    max_steps: int = 20000
    stall_steps: int = 20
    clearance: float = 0.05


DEFAULT_SIM = FeederSimSettings()


@dataclass(frozen=True)
class FenceEvent:
    push: float
    kind: str
    detail: str


@dataclass
class FenceRun:
    """One part through one fence: initial and final orientation (None unless it left the
    fence), ``status`` ("left" | "missed" (never touched the fence) | "jammed" | "step_limit" |
    "stalled" (a contact the simulator cannot advance) | "time_limit"), the events, the trajectory
    (push, cm, theta) at every step and the forward solves that ran. A run of a batch that
    was not asked to record (``recorded`` False) keeps only its first and last pose and no
    events; ``steps`` and ``outline_reach`` (the largest |x| of the hull over every pose,
    world frame) are kept either way."""

    theta_initial: float
    theta_final: float | None
    status: str
    events: list[FenceEvent]
    pushes: np.ndarray
    cms: np.ndarray
    thetas: np.ndarray
    counts: SolveCounts
    solve_time_s: float
    flush_edges: list[int] = field(default_factory=list)
    steps: int | None = None
    outline_reach: float | None = None
    recorded: bool = True
    was_flushed: bool | None = None

    @property
    def complete(self) -> bool:
        return self.status in ("left", "missed", "jammed")

    @property
    def flushed(self) -> bool:
        """Whether an edge came flush on the face: the configuration map assumes it does
        (a fence too short for the part to finish turning, or one nearly along the belt,
        lets it leave still turning on a vertex)."""
        return bool(self.flush_edges) if self.was_flushed is None else self.was_flushed

    @property
    def step_count(self) -> int:
        return len(self.pushes) - 1 if self.steps is None else self.steps

    @property
    def message(self) -> str:
        return f"{self.status} after {self.step_count} steps, {self.counts.solves} forward solves"


@dataclass(frozen=True)
class FenceSegment:
    """A fence placed in the world frame (the belt moving in -y, fences fixed): the fence
    (its angle and mu_c interval), its free end E and its length from E toward its root
    along w = sgn(gamma) t. A fence in its own frame has E at the origin."""

    fence: Fence
    end: np.ndarray
    length: float

    @classmethod
    def create(cls, fence: Fence, end: ArrayLike, length: float) -> FenceSegment:
        e = np.asarray(end, dtype=float).reshape(-1)
        if e.shape != (2,) or not np.all(np.isfinite(e)):
            raise InvalidInput("end", "must be a finite point [x, y]")
        if not (math.isfinite(length) and length > 0.0):
            raise InvalidInput("length", "must be finite and > 0")
        return cls(fence, e, float(length))

    @property
    def direction(self) -> np.ndarray:
        """w: from E toward the root."""
        return self.fence.sign * self.fence.tangent

    @property
    def root(self) -> np.ndarray:
        return self.end + self.length * self.direction


class _FenceGeometry:
    """A placed fence (world frame: E at ``segment.end``) and where the part's hull (its
    footprint's, body frame) stands against it at a pose: heights above the face, positions
    along it, E's gaps to the hull's edges, the next contact, overlaps."""

    def __init__(self, part: Footprint, segment: FenceSegment):
        self.part, self.fence, self.length = part, segment.fence, segment.length
        self.w = segment.direction
        self.n = segment.fence.normal
        self.e = segment.end  # the free end E
        self.next_vertex = (np.arange(part.hull_size) + 1) % part.hull_size

    def hull(self, cm: np.ndarray, theta: float) -> np.ndarray:
        return body_to_world(cm, theta, self.part.hull)

    def heights(self, pts: np.ndarray) -> np.ndarray:
        return (pts - self.e) @ self.n

    def along(self, pts: np.ndarray) -> np.ndarray:
        return (pts - self.e) @ self.w

    def on_fence(self, s: np.ndarray) -> np.ndarray:
        return (s >= 0.0) & (s <= self.length)

    def pushed_gaps(self, pts: np.ndarray) -> np.ndarray:
        """E's distance to each edge it can push (inf for an edge facing away from it: its
        inward normal against the belt's relative motion +y, so E and that edge separate;
        an edge along the belt stays, E then no longer pushes it)."""
        q = pts[self.next_vertex] - pts
        r = self.e - pts
        u = np.clip(np.einsum("ij,ij->i", r, q) / np.einsum("ij,ij->i", q, q), 0.0, 1.0)
        gap = np.hypot(*(r - u[:, None] * q).T)
        away = perp(q) @ D < -GRAZING * np.hypot(q[:, 0], q[:, 1])
        return np.where(away, np.inf, gap)

    def next_contact(self, pts: np.ndarray, floor: float) -> float | None:
        """The drift (in -y, more than ``floor``) after which the part first touches the
        fence, or None."""
        best = math.inf
        cos_g = float(self.n @ D)
        for p in pts:  # a vertex drifting onto the face
            lam = float(self.heights(p[None])[0]) / cos_g
            if lam > floor and self.on_fence(np.array([self.along((p - lam * D)[None])[0]]))[0]:
                best = min(best, lam)
        q = np.roll(pts, -1, axis=0)
        for a, b in zip(pts, q):  # E rising (relative to the part) onto an edge
            e = b - a
            den = float(D[0] * (-e[1]) + D[1] * e[0])  # cross(D, e) with sign
            if abs(den) <= 1e-12 * math.hypot(float(e[0]), float(e[1])):
                continue  # an edge along the belt's motion: E slides along it
            r = self.e - a
            lam = float(r[0] * e[1] - r[1] * e[0]) / den  # E + lam D = a + mu e (Cramer)
            mu = float(r[0] * D[1] - r[1] * D[0]) / den
            if lam > floor and 0.0 <= mu <= 1.0:
                best = min(best, lam)
        return None if math.isinf(best) else best

    def overlaps(self, pts: np.ndarray, tol: float) -> bool:
        """Whether the fence passes through the part's hull deeper than ``tol`` (clipping
        the segment by the hull's edges, each kept ``tol`` inside)."""
        q = pts[self.next_vertex] - pts
        length = np.hypot(q[:, 0], q[:, 1])
        nx, ny = -q[:, 1] / length, q[:, 0] / length  # each edge's inward unit normal
        # inside by more than tol where base > 0; the clip moves along the fence at rate
        bases = (nx * (self.e[0] - pts[:, 0]) + ny * (self.e[1] - pts[:, 1]) - tol).tolist()
        rates = (nx * self.w[0] + ny * self.w[1]).tolist()
        lo, hi = 0.0, self.length
        for base, rate in zip(bases, rates):
            if rate == 0.0:
                if base <= 0.0:
                    return False
                continue
            cut = -base / rate
            lo, hi = (max(lo, cut), hi) if rate > 0.0 else (lo, min(hi, cut))
            if lo >= hi:
                return False
        return True


def _check(part_support: np.ndarray, weights: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    pts = np.asarray(part_support, dtype=float).reshape(-1, 2)
    w = np.asarray(weights, dtype=float).reshape(-1)
    if len(pts) != len(w) or len(w) == 0:
        raise InvalidInput("support", "need as many weights as support points")
    if not (np.all(np.isfinite(pts)) and np.all(np.isfinite(w))) or np.any(w < 0.0) or w.sum() <= 0.0:
        raise InvalidInput("support", "points and weights must be finite, weights >= 0 and not all 0")
    return pts, w / w.sum()


@dataclass(frozen=True)
class TwistRequest:
    """What a run needs next: the forward solve of its part at pose (cm, theta) pushed at
    ``contact`` on an edge at ``edge_angle`` (world, belt frame), the push along +y; the
    driver answers with that solve's (velocity of the CM, omega) per unit push."""

    cm: np.ndarray
    theta: float
    contact: np.ndarray
    edge_angle: float


RunSteps = Generator[TwistRequest, tuple[np.ndarray, float], "FenceRun"]


class _Overlap(Exception):
    """A run's start with the fence through the part."""


def _check_mu(fence: Fence, mu_c: ArrayLike) -> None:
    mu = np.asarray(mu_c, dtype=float)
    if not np.all((fence.mu_low <= mu) & (mu <= fence.mu_high)):
        raise InvalidInput("mu_c", "must lie in the fence's mu_c interval")


def _validated(part: Footprint, fence: Fence, mu_c: float, support_points: ArrayLike,
               weights: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    _check_mu(fence, mu_c)
    return _check(np.asarray(support_points, dtype=float), np.asarray(weights, dtype=float))


def simulate_fence(part: Footprint, fence: Fence, mu_c: float, support_points: ArrayLike, weights: ArrayLike,
                   theta_initial: float, fence_length: float | None = None, start_along: float = START_ALONG,
                   settings: FeederSimSettings = DEFAULT_SIM, tol: SolverTolerances = SOLVER_DEFAULT,
                   budget: Budget = UNLIMITED, compiled: bool = True) -> FenceRun:
    """Run ``part`` (support points relative to the CM in the body frame, with weights; the
    centroid must be the CM) at orientation ``theta_initial`` onto ``fence`` with contact
    friction ``mu_c`` until it has left the fence's end, jammed, or ``max_steps``.
    The part starts above the fence at ``start_along`` of its length (default fence length:
    40 part radii). ``compiled``: the compiled loop (solver.kernels.fence); False: the
    reference, one forward solve at a time (:func:`simulate_fence_batch` runs many parts
    together)."""
    t0 = time.perf_counter()
    pts, w = _validated(part, fence, mu_c, support_points, weights)
    if compiled:
        (runs,) = _compiled_runs(part, [own_frame_segment(part, fence, fence_length)], np.array([[float(mu_c)]]),
                                 [(pts, w)], np.array([float(theta_initial)]), np.array([float(start_along)]), [None],
                                 settings, tol, budget, 1)
        return runs[0]
    oracle = MotionOracle(pts, w, part.circumradius, mu_c, tol=tol, budget=budget)
    steps = _fence_run(part, own_frame_segment(part, fence, fence_length), mu_c, theta_initial, start_along, None, settings,
                       oracle.counts, t0)
    answer = None
    while True:
        try:
            req = steps.send(answer) if answer is not None else next(steps)
        except StopIteration as done:
            return done.value
        try:
            tw = oracle.twist(req.cm, req.theta, req.contact, req.edge_angle, PUSH_ANGLE)
        except TimeLimitReached as exc:
            try:
                steps.throw(exc)
            except StopIteration as done:
                return done.value
            raise AssertionError("a run went on past its time limit") from exc
        answer = (tw.velocity, tw.omega)


def own_frame_segment(part: Footprint, fence: Fence, fence_length: float | None = None) -> FenceSegment:
    """A fence in its own frame: E at the origin, 40 part radii long unless told."""
    length = DEFAULT_FENCE_LENGTH_RADII * part.circumradius if fence_length is None else float(fence_length)
    return FenceSegment.create(fence, np.zeros(2), length)


def simulate_fence_batch(part: Footprint, fence: Fence, mu_c: ArrayLike, supports: list[tuple[ArrayLike, ArrayLike]],
                         thetas_initial: ArrayLike, fence_length: float | None = None,
                         start_along: ArrayLike | float = START_ALONG, settings: FeederSimSettings = DEFAULT_SIM,
                         tol: SolverTolerances = SOLVER_DEFAULT, budget: Budget = UNLIMITED, compiled: bool = True,
                         record: int | None = None) -> list[FenceRun]:
    """Many parts (one support and initial orientation each; ``mu_c`` one value or one per
    part) through one fence, stepped together: each round, every run still going asks for
    its next forward solve and they are solved in one batch per support size and mu_c
    (solver.motion.forward.solve_forward_scenes).
    Each run follows exactly the steps :func:`simulate_fence` takes (the same events, the
    same motions to rounding); its ``solve_time_s`` is the time from the batch's start
    until it finished. Past the budget every run still going ends with "time_limit".
    ``compiled`` (default): every run in one compiled loop (solver.kernels.fence), the runs
    of the first ``record`` parts (default all) with their trajectories and events; past the
    budget the parts not started end "time_limit". False: the reference, stepped together."""
    thetas = np.atleast_1d(np.asarray(thetas_initial, dtype=float))
    if len(thetas) != len(supports):
        raise InvalidInput("thetas_initial", "need one initial orientation per support")
    along = np.broadcast_to(np.asarray(start_along, dtype=float), thetas.shape)
    mus = _per_part(mu_c, len(thetas))
    _check_mu(fence, mus)
    checked = [_check(np.asarray(pts, dtype=float), np.asarray(w, dtype=float)) for pts, w in supports]
    segment = own_frame_segment(part, fence, fence_length)
    if compiled:
        runs = _compiled_runs(part, [segment], np.asarray(mus, dtype=float)[:, None], checked, thetas,
                              np.asarray(along, dtype=float), [None] * len(thetas), settings, tol, budget,
                              len(thetas) if record is None else record)
        return [r[0] for r in runs]
    return _run_batch(part, segment, [float(m) for m in mus], checked, thetas, [float(x) for x in along],
                      [None] * len(thetas), settings, tol, budget)


def _per_part(mu_c: ArrayLike, n: int) -> np.ndarray:
    try:
        return np.broadcast_to(np.asarray(mu_c, dtype=float), (n,))
    except ValueError as exc:
        raise InvalidInput("mu_c", "give one value or one per part") from exc


def _run_batch(part: Footprint, segment: FenceSegment, mus: list[float], checked: list[tuple[np.ndarray, np.ndarray]],
               thetas: np.ndarray, along: list[float], starts: list[np.ndarray | None], settings: FeederSimSettings,
               tol: SolverTolerances, budget: Budget) -> list[FenceRun]:
    """The runs of many parts on one fence (mu_c ``mus[i]`` for part i), their forward
    solves batched per round by support size and mu_c."""
    t0 = time.perf_counter()
    counts = [SolveCounts() for _ in checked]
    runs: list[FenceRun | None] = [None] * len(checked)
    gens: dict[int, RunSteps] = {}
    pending: dict[int, TwistRequest] = {}

    def advance_run(i: int, answer: tuple[np.ndarray, float] | None) -> None:
        try:
            pending[i] = gens[i].send(answer) if answer is not None else next(gens[i])
        except StopIteration as done:
            runs[i] = done.value
            del gens[i]
            pending.pop(i, None)

    for i in range(len(checked)):
        gens[i] = _fence_run(part, segment, mus[i], float(thetas[i]), along[i], starts[i], settings, counts[i], t0)
        advance_run(i, None)
    try:
        while pending:
            budget.checkpoint(f"a batch of {len(pending)} forward solves")
            for k, mu in sorted({(len(checked[i][0]), mus[i]) for i in pending}):
                ids = [i for i in pending if len(checked[i][0]) == k and mus[i] == mu]
                scenes = [PushScene.create(part.circumradius, pending[i].contact, pending[i].edge_angle, PUSH_ANGLE,
                                           pending[i].cm) for i in ids]
                world = np.array([body_to_world(pending[i].cm, pending[i].theta, checked[i][0]) for i in ids])
                res = solve_forward_scenes(scenes, world, np.array([checked[i][1] for i in ids]), mu, tol)
                for row, (i, scene) in enumerate(zip(ids, scenes)):
                    counts[i].record_values(res.MODES[int(res.mode[row])], float(res.kkt_residual[row]),
                                            bool(res.converged[row]), res.contact_force[row], scene)
                    advance_run(i, (res.velocity_cm[row].copy(), float(res.omega[row])))
    except TimeLimitReached as exc:
        for i in list(gens):
            try:
                gens[i].throw(exc)
            except StopIteration as done:
                runs[i] = done.value
    out = [r for r in runs if r is not None]
    if len(out) != len(runs):  # pragma: no cover - every generator ends in a FenceRun
        raise AssertionError("a run of the batch did not finish")
    return out


# --------------------------------------------------------------------------------------
# The compiled path (solver/kernels/fence.py): the same runs as _fence_run, every part of a
# batch through every fence in one compiled loop

COMPILED_CHUNK = 8
"""Parts one compiled call runs between two looks at the budget (a few milliseconds): past
the deadline, parts not started end "time_limit" and the others are whole."""

_EVENT_KIND = {
    fk.EV_FIRST_CONTACT: "contact", fk.EV_CONTACT_AGAIN: "contact", fk.EV_VERTEX: "vertex", fk.EV_END: "end",
    fk.EV_FLUSH: "flush", fk.EV_VERTEX_CORNER: "vertex", fk.EV_END_CORNER: "end", fk.EV_LEFT: "left",
    fk.EV_MISSED: "missed", fk.EV_ALONG: "left", fk.EV_JAM: "jam", fk.EV_STALLED: "stalled", fk.EV_OVERLAP: "overlap",
}
_KERNEL_CONTACT = {fk.VERTEX: Contact.VERTEX, fk.END: Contact.END, fk.FLUSH: Contact.FLUSH}
_KERNEL_MODES = ("frictionless", "sticking", "slipping_up", "slipping_down")


def _event_detail(code: int, index: int, value: float, fence: Fence, mu_c: float, stall_steps: int) -> str:
    """The words of a compiled run's event: those of the reference (_fence_run)."""
    if code == fk.EV_FIRST_CONTACT:
        return "first contact"
    if code == fk.EV_CONTACT_AGAIN:
        return "contact again"
    if code in (fk.EV_VERTEX, fk.EV_END, fk.EV_FLUSH):
        return Mode(_KERNEL_CONTACT[(fk.VERTEX, fk.END, fk.FLUSH)[(fk.EV_VERTEX, fk.EV_END, fk.EV_FLUSH).index(code)]],
                    index).text
    if code in (fk.EV_VERTEX_CORNER, fk.EV_END_CORNER):
        contact = Contact.VERTEX if code == fk.EV_VERTEX_CORNER else Contact.END
        return Mode(contact, index).text + " (a vertex at the fence's end)"
    if code == fk.EV_LEFT:
        return f"clear of the fence at orientation {value:.9g}"
    if code == fk.EV_MISSED:
        return f"clear of the fence at orientation {value:.9g} without touching it"
    if code == fk.EV_ALONG:
        return f"the edge under the fence's end lies along the belt at orientation {value:.9g}"
    if code == fk.EV_JAM:
        return f"flush and |tan gamma| = {fence.jam_threshold:.6g} <= mu_c = {mu_c:.6g} (6.4)"
    if code == fk.EV_STALLED:
        mode = Mode(_KERNEL_CONTACT.get(index // 1000, Contact.VERTEX), index % 1000)
        return (f"{stall_steps} steps of {value:.3g} in mode {mode}: the contact cannot advance "
                "(a vertex at the fence's end where no contact there gives a step)")
    return ("the fence passes through the part at its start (a part on two fences at once is not simulated)")


def _run_of(row: np.ndarray, path: np.ndarray, events: np.ndarray, recorded: bool, seg: FenceSegment, mu_c: float,
            settings: FeederSimSettings, elapsed: float) -> FenceRun:
    """The FenceRun of one compiled run's summary row (solver.kernels.fence.S_*)."""
    status = fk.STATUSES[int(row[fk.S_STATUS])]
    counts = SolveCounts(solves=int(row[fk.S_SOLVES]), not_optimal=int(row[fk.S_NOT_OPTIMAL]),
                         max_kkt=float(row[fk.S_MAX_KKT]), max_force_angle=float(row[fk.S_MAX_ANGLE]))
    for i, name in enumerate(_KERNEL_MODES):
        if row[fk.S_MODES + i] > 0:
            counts.modes[name] = int(row[fk.S_MODES + i])
    theta = float(row[fk.S_THETA])
    evs: list[FenceEvent] = []
    flush_edges: list[int] = []
    if recorded:
        pts = path[int(row[fk.S_PATH_FROM]):int(row[fk.S_PATH_TO])]
        pushes, cms, thetas = pts[:, 0].copy(), pts[:, 1:3].copy(), pts[:, 3].copy()
        for push, code, index, value in events[int(row[fk.S_EVENTS_FROM]):int(row[fk.S_EVENTS_TO])]:
            c, i = int(code), int(index)
            evs.append(FenceEvent(float(push), _EVENT_KIND[c], _event_detail(c, i, float(value), seg.fence, mu_c,
                                                                             settings.stall_steps)))
            if c == fk.EV_FLUSH:
                flush_edges.append(i)
    else:
        pushes = np.array([0.0, float(row[fk.S_PUSH])])
        cms = np.array([[row[fk.S_START_X], row[fk.S_START_Y]], [row[fk.S_CM_X], row[fk.S_CM_Y]]], dtype=float)
        thetas = np.array([row[fk.S_START_THETA], theta], dtype=float)
    return FenceRun(theta_initial=float(row[fk.S_START_THETA]), theta_final=theta if status in ("left", "missed") else None,
                    status=status, events=evs, pushes=pushes, cms=cms, thetas=thetas, counts=counts,
                    solve_time_s=elapsed, flush_edges=flush_edges, steps=int(row[fk.S_STEPS]),
                    outline_reach=float(row[fk.S_MAX_X]), recorded=recorded,
                    was_flushed=bool(row[fk.S_FLUSHED]))


def _cut_run(theta: float, cm: np.ndarray | None, exc: TimeLimitReached, elapsed: float) -> FenceRun:
    """A part the time limit stopped before it started."""
    at = np.full((1, 2), np.nan) if cm is None else np.asarray(cm, dtype=float).reshape(1, 2)
    return FenceRun(theta_initial=theta, theta_final=None, status="time_limit",
                    events=[FenceEvent(0.0, "time_limit", str(exc))], pushes=np.zeros(1), cms=at,
                    thetas=np.array([theta]), counts=SolveCounts(), solve_time_s=elapsed, steps=0)


def _compiled_runs(part: Footprint, segments: list[FenceSegment], mus: np.ndarray,
                   checked: list[tuple[np.ndarray, np.ndarray]], thetas: np.ndarray, along: np.ndarray,
                   starts: list[np.ndarray | None], settings: FeederSimSettings, tol: SolverTolerances, budget: Budget,
                   record: int) -> list[list[FenceRun]]:
    """Every part through ``segments`` in order on the compiled path (``mus`` (parts,
    fences)); the runs of the first ``record`` parts keep their trajectories and events. A
    part the compiled solve could not carry is run again on the reference path."""
    from solver.kernels import fence as kernel  # loaded on first use (a web process never needs it)

    t0 = time.perf_counter()
    n = len(checked)
    segs = np.array([np.r_[sg.end, sg.direction, sg.fence.normal, sg.length] for sg in segments], dtype=float)
    gammas = np.array([sg.fence.angle for sg in segments], dtype=float)
    sim = np.array([settings.step, settings.contact_tol, settings.min_step, settings.max_steps, settings.stall_steps,
                    settings.clearance], dtype=float)
    tols = np.array([tol.kkt, tol.kkt_accept, tol.max_newton_iter], dtype=float)
    given = np.array([st is not None for st in starts], dtype=bool)
    body = np.array(part.hull, dtype=float)  # a copy: the kernels take writable arrays (Ray's are read-only)
    start_arr = np.array([np.zeros(2) if st is None else st for st in starts], dtype=float).reshape(n, 2)
    runs: list[list[FenceRun]] = [[] for _ in range(n)]
    again: list[int] = []
    for k in sorted({len(pts) for pts, _ in checked}):
        ids = np.array([i for i in range(n) if len(checked[i][0]) == k], dtype=np.int64)
        sup = np.array([checked[i][0] for i in ids], dtype=float).reshape(len(ids), k, 2)
        wts = np.array([checked[i][1] for i in ids], dtype=float).reshape(len(ids), k)
        rec = int(np.count_nonzero(ids < record))
        for first in range(0, len(ids), COMPILED_CHUNK):
            last = min(first + COMPILED_CHUNK, len(ids))
            try:
                budget.checkpoint(f"simulated parts {first + 1}-{last} of {len(ids)}")
            except TimeLimitReached as exc:
                for i in ids[first:]:
                    runs[i] = [_cut_run(float(thetas[i]), starts[i], exc, time.perf_counter() - t0)]
                break
            summaries, path, events = kernel.run_belt(body, sup, wts, start_arr[ids], thetas[ids], given[ids], segs,
                                                  gammas, mus[ids], part.circumradius, sim, tols, along[ids], rec,
                                                  first, last)
            elapsed = time.perf_counter() - t0
            for row_i, i in enumerate(ids[first:last]):
                for f, seg in enumerate(segments):
                    row = summaries[row_i, f]
                    if row[fk.S_STATUS] < 0:
                        break
                    if int(row[fk.S_STATUS]) == fk.GRAZING_PUSH:
                        raise InvalidInput("push_direction", "is parallel to the edge (edge_angle): the pusher would "
                                           "slide along the edge and never push the workpiece")
                    if int(row[fk.S_STATUS]) == fk.REFERENCE:
                        again.append(int(i))
                        break
                    runs[i].append(_run_of(row, path, events, bool(row_i + first < rec), seg, float(mus[i, f]),
                                           settings, elapsed))
    for i in again:  # the reference path, from the part's start
        runs[i] = _reference_belt(part, segments, mus[i], checked[i], float(thetas[i]), float(along[i]), starts[i],
                                  settings, tol, budget)
    return runs


def _reference_belt(part: Footprint, segments: list[FenceSegment], mus: np.ndarray,
                    checked: tuple[np.ndarray, np.ndarray], theta: float, along: float, start: np.ndarray | None,
                    settings: FeederSimSettings, tol: SolverTolerances, budget: Budget) -> list[FenceRun]:
    """One part through ``segments`` on the reference path (_fence_run, batched solves)."""
    out: list[FenceRun] = []
    cm = start
    for f, seg in enumerate(segments):
        (run,) = _run_batch(part, seg, [float(mus[f])], [checked], np.array([theta]), [along], [cm], settings, tol,
                            budget)
        out.append(run)
        if run.status not in ("left", "missed"):
            break
        cm, theta = run.cms[-1].copy(), float(run.thetas[-1])
    return out


@dataclass(frozen=True)
class BeltRun:
    """One part through the fences of a belt: the run at each fence it reached, in order
    (a fence it passed untouched has status "missed"), and where it ended."""

    runs: tuple[FenceRun, ...]
    fences: int  # how many fences the belt has

    @property
    def status(self) -> str:
        """"left" when it is past the last fence (some may be missed), else the status of the
        run it stopped in."""
        last = self.runs[-1]
        if len(self.runs) == self.fences and last.status in ("left", "missed"):
            return "left"
        return last.status

    @property
    def theta_final(self) -> float | None:
        return float(self.runs[-1].thetas[-1]) if self.status == "left" else None

    @property
    def complete(self) -> bool:
        """Past every fence, or jammed at one (the runs' own outcomes all complete)."""
        return all(r.complete for r in self.runs) and (len(self.runs) == self.fences or self.runs[-1].status == "jammed")

    @property
    def solve_time_s(self) -> float:
        """The sum of its runs' times (each from its fence's batch start until it finished)."""
        return float(sum(r.solve_time_s for r in self.runs))

    @property
    def message(self) -> str:
        return f"{self.status} after {len(self.runs)} of {self.fences} fences: {self.runs[-1].message}"

    @property
    def missed(self) -> bool:
        return any(r.status == "missed" for r in self.runs)

    @property
    def flushed(self) -> bool:
        """An edge came flush on every fence it touched."""
        return all(r.flushed for r in self.runs if r.status != "missed")


def simulate_belt_batch(part: Footprint, segments: list[FenceSegment], mu_c: ArrayLike,
                        supports: list[tuple[ArrayLike, ArrayLike]], thetas_initial: ArrayLike,
                        starts: ArrayLike | None = None, settings: FeederSimSettings = DEFAULT_SIM,
                        tol: SolverTolerances = SOLVER_DEFAULT, budget: Budget = UNLIMITED, compiled: bool = True,
                        record: int | None = None) -> list[BeltRun]:
    """Many parts through the placed fences of a belt in order (world frame, the belt in
    -y): each part starts with its CM at ``starts[i]`` (default: above the first fence as
    :func:`simulate_fence` places it), drifts onto the first fence, and each later fence
    picks it up where the previous run ended (a part that passes a fence untouched goes on
    to the next with status "missed" there). ``mu_c``: one value, one per part, or one per
    part and fence (shape (parts, fences)). The runs at each fence are batched as in
    :func:`simulate_fence_batch`. A part whose next fence already
    passes through it (fences too close: two contacts at once) stops there as "overlap".
    ``compiled`` and ``record`` as in :func:`simulate_fence_batch`."""
    thetas = np.array(thetas_initial, dtype=float, ndmin=1)  # a copy: updated fence by fence
    n, k = len(thetas), len(segments)
    if len(supports) != n:
        raise InvalidInput("thetas_initial", "need one initial orientation per support")
    if k == 0:
        raise InvalidInput("fences", "need at least one fence")
    mu = np.asarray(mu_c, dtype=float)
    try:
        mu = np.broadcast_to(mu[:, None] if mu.ndim == 1 else mu, (n, k))
    except ValueError as exc:
        raise InvalidInput("mu_c", "give one value, one per part, or one per part and fence") from exc
    cms: list[np.ndarray | None] = [None] * n
    if starts is not None:
        start_arr = np.asarray(starts, dtype=float).reshape(n, 2)
        if not np.all(np.isfinite(start_arr)):
            raise InvalidInput("start", "must be finite")
        cms = [row.copy() for row in start_arr]
    for j, seg in enumerate(segments):
        _check_mu(seg.fence, mu[:, j])
    checked = [_check(np.asarray(pts, dtype=float), np.asarray(w, dtype=float)) for pts, w in supports]
    if compiled:
        done = _compiled_runs(part, segments, np.asarray(mu, dtype=float), checked, thetas, np.full(n, START_ALONG),
                              cms, settings, tol, budget, n if record is None else record)
        return [BeltRun(tuple(r), k) for r in done]
    runs: list[list[FenceRun]] = [[] for _ in range(n)]
    going = list(range(n))
    for j, seg in enumerate(segments):
        done = _run_batch(part, seg, [float(mu[i, j]) for i in going], [checked[i] for i in going], thetas[going],
                          [START_ALONG] * len(going), [cms[i] for i in going], settings, tol, budget)
        for i, run in zip(going, done):
            runs[i].append(run)
            cms[i], thetas[i] = run.cms[-1].copy(), float(run.thetas[-1])
        going = [i for i in going if runs[i][-1].status in ("left", "missed")]
    return [BeltRun(tuple(r), k) for r in runs]


class _RunLog:
    """What a run has done so far: the events, the trajectory (push, cm, theta at every step)
    and the edges that came flush."""

    def __init__(self, cm: np.ndarray, theta: float) -> None:
        self.push = 0.0
        self.events: list[FenceEvent] = []
        self.pushes, self.cms, self.thetas = [0.0], [cm.copy()], [theta]
        self.flush_edges: list[int] = []

    def record(self, kind: str, detail: str) -> None:
        self.events.append(FenceEvent(self.push, kind, detail))

    def moved(self, cm: np.ndarray, theta: float, push: float) -> None:
        self.push += push
        self.pushes.append(self.push)
        self.cms.append(cm.copy())
        self.thetas.append(theta)

    def entered(self, mode: Mode) -> None:
        """Record a contact the run is in, once when it starts."""
        if not self.events or self.events[-1].detail != mode.text:
            if mode.contact is Contact.FLUSH:
                self.flush_edges.append(mode.index)
            self.record(mode.contact.value, mode.text)

    def run(self, theta_initial: float, status: str, counts: SolveCounts, t0: float) -> FenceRun:
        theta = self.thetas[-1]
        return FenceRun(theta_initial=float(theta_initial), theta_final=theta if status in ("left", "missed") else None,
                        status=status, events=self.events, pushes=np.array(self.pushes), cms=np.array(self.cms),
                        thetas=np.array(self.thetas), counts=counts, solve_time_s=time.perf_counter() - t0,
                        flush_edges=self.flush_edges)


def _start_cm(geo: _FenceGeometry, theta: float, start_along: float, settings: FeederSimSettings) -> np.ndarray:
    """The CM of a part placed just above the fence at ``start_along`` of its length from E:
    ``clearance`` part radii of belt travel before it touches the face."""
    hull0 = body_to_world(geo.e, theta, geo.part.hull)
    # the face approaches the drifting part at n . d = cos gamma per unit of belt travel
    return geo.e + start_along * geo.length * geo.w + (
        settings.clearance * geo.part.circumradius * float(geo.n @ D) - float(np.min(geo.heights(hull0)))) * geo.n


def _twist_of(need: Twist | TwistRequest, cm: np.ndarray) -> Generator[TwistRequest, tuple[np.ndarray, float], Twist]:
    """The motion per unit push in the fence's frame: ``need`` itself, or the answer to the
    forward solve it asks for (in the belt's frame, shifted by -d)."""
    if isinstance(need, Twist):
        return need
    velocity, omega = yield need
    return Twist(velocity - D, omega, cm.copy())


def _step_at_corner(geo: _FenceGeometry, hull: np.ndarray, mode: Mode, cm: np.ndarray, theta: float,
                    f_hat: np.ndarray, s: FeederSimSettings, tol_c: float
                    ) -> Generator[TwistRequest, tuple[np.ndarray, float], tuple[Mode, np.ndarray, float, float] | None]:
    """A vertex at E: the contact's normal is any between the face's and the two edges'; the
    first of those contacts (vertex on the face, or E on either edge at it) whose step
    advances, with its step (cm, theta, push), or None."""
    corner = _vertex_at_end(geo, hull, tol_c)
    if corner is None:
        return None
    m = geo.part.hull_size
    for alt in (Mode(Contact.VERTEX, corner), Mode(Contact.END, (corner - 1) % m), Mode(Contact.END, corner)):
        if alt == mode:
            continue
        velocity, omega = yield _point_request(geo, alt, cm, theta)
        alt_twist = Twist(velocity - D, omega, cm.copy())
        c2, t2, h2 = _checked_step(geo, cm, theta, hull, alt_twist, alt, f_hat, s, tol_c)
        if h2 > s.min_step * geo.part.circumradius:
            return alt, c2, t2, h2
    return None


def _fence_run(part: Footprint, segment: FenceSegment, mu_c: float, theta_initial: float, start_along: float,
               start_cm: np.ndarray | None, settings: FeederSimSettings, counts: SolveCounts, t0: float) -> RunSteps:
    """The run of :func:`simulate_fence` as a generator: it yields a :class:`TwistRequest`
    whenever it needs a forward solve and is sent back (velocity, omega); a
    TimeLimitReached thrown in ends it with status "time_limit". Returns the FenceRun.
    The part starts with its CM at ``start_cm`` (world), or, when None, just above the
    fence at ``start_along`` of its length from E; a start where the fence passes through
    the part ends the run at once as "overlap"."""
    a = part.circumradius
    geo = _FenceGeometry(part, segment)
    s = settings
    tol_c = s.contact_tol * a
    theta = float(theta_initial)
    cm = _start_cm(geo, theta, start_along, s) if start_cm is None else np.asarray(start_cm, dtype=float).copy()
    log = _RunLog(cm, theta)
    f_hat = geo.n + mu_c * geo.w
    status = "step_limit"
    stalled = 0
    touched = False  # a start may already be in contact (a belt's hand-over), with no drift onto it
    try:
        if geo.overlaps(geo.hull(cm, theta), tol_c):
            raise _Overlap
        for _ in range(s.max_steps):
            hull = geo.hull(cm, theta)
            z = geo.heights(hull)
            sig = geo.along(hull)
            touching = [i for i in range(part.hull_size) if abs(z[i]) <= tol_c and geo.on_fence(np.array([sig[i]]))[0]]
            gaps = geo.pushed_gaps(hull)
            e_contact = bool(gaps[int(np.argmin(gaps))] <= tol_c)
            touched = touched or bool(touching) or e_contact
            if not touching and not e_contact:  # drift with the belt onto the fence, or away
                lam = geo.next_contact(hull, tol_c)
                if lam is None:
                    status = "left" if touched else "missed"
                    log.record(status, f"clear of the fence at orientation {theta:.9g}"
                               + ("" if touched else " without touching it"))
                    break
                cm = cm - lam * D
                log.moved(cm, theta, lam)
                if not log.events or log.events[-1].kind != "contact":
                    log.record("contact", "first contact" if len(log.events) == 0 else "contact again")
                continue
            mode, need = _mode(geo, cm, theta, hull, touching, gaps, f_hat, mu_c, tol_c)
            twist = yield from _twist_of(need, cm)
            if mode.contact is Contact.ALONG:
                status = "left"
                log.record("left", f"the edge under the fence's end lies along the belt at orientation {theta:.9g}")
                break
            if mode.contact is Contact.JAM:
                status = "jammed"
                log.record("jam", f"flush and |tan gamma| = {geo.fence.jam_threshold:.6g} <= mu_c = {mu_c:.6g} (6.4)")
                break
            log.entered(mode)
            cm_n, th_n, h = _checked_step(geo, cm, theta, hull, twist, mode, f_hat, s, tol_c)
            if h <= s.min_step * a:
                alt = yield from _step_at_corner(geo, hull, mode, cm, theta, f_hat, s, tol_c)
                if alt is not None:
                    mode, cm_n, th_n, h = alt
                    log.record(mode.contact.value, mode.text + " (a vertex at the fence's end)")
            stalled = stalled + 1 if h <= s.min_step * a else 0
            if stalled >= s.stall_steps:
                status = "stalled"
                log.record("stalled", f"{stalled} steps of {h:.3g} in mode {mode}: the contact cannot advance "
                           "(a vertex at the fence's end where no contact there gives a step)")
                break
            cm, theta = cm_n, th_n
            log.moved(cm, theta, h)
    except TimeLimitReached as exc:
        status = "time_limit"
        log.record("time_limit", str(exc))
    except _Overlap:
        status = "overlap"
        log.record("overlap", "the fence passes through the part at its start (a part on two fences at once is "
                   "not simulated)")
    return log.run(theta_initial, status, counts, t0)


def _checked_step(geo: _FenceGeometry, cm: np.ndarray, theta: float, hull: np.ndarray, twist: Twist, mode: Mode,
                  f_hat: np.ndarray, s: FeederSimSettings, tol_c: float) -> tuple[np.ndarray, float, float]:
    """The pose after one step of ``twist`` in ``mode`` (its contact re-imposed) and the
    push it took: ``s.step`` (a flush slide: to its next event; E on an edge: never past
    the edge lying along the belt), halved until the fence does not pass through the part
    (the segment clipped against the hull), down to ``s.min_step``."""
    a = geo.part.circumradius
    h = s.step * a
    if mode.contact is Contact.FLUSH:
        # a translation is exact: go straight to the next event (E reaching the
        # downstream vertex, then the force line), never past it
        h = max(h, _flush_distance(geo, cm, theta, twist, mode.index, f_hat))
    elif mode.contact is Contact.END:
        # E stops pushing when the edge under it lies along the belt: never turn past
        # that (the twist is held for a step, so the turn is exactly omega h)
        h = min(h, _turn_to_along(hull, mode.index, twist.omega))
    while True:
        cm_n, th_n = advance(cm, theta, twist, h)
        cm_n = _reimpose(geo, cm_n, th_n, mode)
        if not geo.overlaps(geo.hull(cm_n, th_n), tol_c) or h <= s.min_step * a:
            return cm_n, th_n, h
        h *= 0.5


def _vertex_at_end(geo: _FenceGeometry, hull: np.ndarray, tol_c: float) -> int | None:
    """The hull vertex lying at the fence's end E (within the contact tolerance), if any."""
    d = np.hypot(hull[:, 0] - geo.e[0], hull[:, 1] - geo.e[1])
    k = int(np.argmin(d))
    return k if d[k] <= E_ON_EDGE * tol_c else None


def _mode(geo: _FenceGeometry, cm: np.ndarray, theta: float, hull: np.ndarray,
          touching: list[int], gaps: np.ndarray, f_hat: np.ndarray, mu_c: float,
          tol_c: float) -> tuple[Mode, Twist | TwistRequest]:
    """(mode, motion per unit push in the fence's frame, or the forward solve a point
    contact needs) at a pose in contact; ``gaps``: E's distance to each edge."""
    m = geo.part.hull_size
    edge_e = int(np.argmin(gaps))  # used when no vertex is on the face: E is on this edge
    # an edge is flush when both its ends touch the fence's face, or one does and E lies on
    # the edge away from it (two points of the edge on the face's line; the other end, past
    # E, may dip below that line by the contact tolerance times the edge's length over its
    # distance from E, so it is not asked to lie on it)
    flush = None
    sig = geo.along(hull)
    for v in touching:
        for j, o in (((v - 1) % m, (v - 1) % m), (v, (v + 1) % m)):
            if o in touching or (gaps[j] <= E_ON_EDGE * tol_c and abs(float(sig[v])) > tol_c):
                flush = j
    if flush is not None:
        ends = sorted(((float(geo.along(hull[v][None])[0]), v) for v in (flush, (flush + 1) % m)))
        (s_a, v_a), (s_b, v_b) = ends  # s_a: the downstream vertex, toward E
        supported_lo = max(s_a, 0.0)
        # sliding, the force lies on the cone's edge; carried along (|tan gamma| <= mu_c)
        # the part moves with the fence and the force balances the drag: along d
        carried = abs(math.tan(geo.fence.angle)) <= mu_c
        f = D if carried else f_hat
        x = cm - float(geo.heights(cm[None])[0]) / float(f @ geo.n) * f
        s_x = float(geo.along(x[None])[0])
        if supported_lo - tol_c <= s_x <= s_b + tol_c:
            if carried:
                return Mode(Contact.JAM), Twist(np.zeros(2), 0.0, cm.copy())
            u = float(geo.n @ D) / float(f_hat @ geo.n) * f_hat
            return Mode(Contact.FLUSH, flush), Twist(u - D, 0.0, cm.copy())
        # the force line misses the supported part: pivot on the end it passes
        if s_x > s_b:
            touching = [v_b]
        elif s_a >= 0.0:
            touching = [v_a]
        else:
            touching, edge_e = [], flush
    if touching:
        mode = Mode(Contact.VERTEX, touching[0])
        return mode, _point_request(geo, mode, cm, theta)
    q = hull[(edge_e + 1) % m] - hull[edge_e]
    if abs(float(perp(q) @ D)) <= GRAZING * math.hypot(float(q[0]), float(q[1])):
        return Mode(Contact.ALONG), Twist(-D, 0.0, cm.copy())  # the edge lies along the belt: E no longer pushes
    mode = Mode(Contact.END, edge_e)
    return mode, _point_request(geo, mode, cm, theta)


def _point_request(geo: _FenceGeometry, mode: Mode, cm: np.ndarray, theta: float) -> TwistRequest:
    """The forward solve (in the belt's frame) of a point contact: vertex i on the face
    (VERTEX) or E on edge i (END)."""
    i = mode.index
    hull = geo.hull(cm, theta)
    if mode.contact is Contact.VERTEX:
        return TwistRequest(cm.copy(), theta, hull[i].copy(), geo.fence.angle)
    q = hull[(i + 1) % geo.part.hull_size] - hull[i]
    return TwistRequest(cm.copy(), theta, geo.e.copy(), math.atan2(float(q[1]), float(q[0])))


def _flush_distance(geo: _FenceGeometry, cm: np.ndarray, theta: float, twist: Twist, edge: int,
                    f_hat: np.ndarray) -> float:
    """The push until the sliding part's next event: E reaching the edge's downstream
    vertex, or (past it) the force line through the CM."""
    rate = -float(twist.velocity @ geo.w)  # how fast the part approaches E per unit push
    if rate <= 0.0:
        return 0.0
    hull = geo.hull(cm, theta)
    s_a = min(float(geo.along(hull[edge][None])[0]), float(geo.along(hull[(edge + 1) % geo.part.hull_size][None])[0]))
    if s_a > 0.0:
        return s_a / rate
    x = cm - float(geo.heights(cm[None])[0]) / float(f_hat @ geo.n) * f_hat
    return max(float(geo.along(x[None])[0]), 0.0) / rate


def _turn_to_along(hull: np.ndarray, edge: int, omega: float) -> float:
    """The push after which edge ``edge`` turning at ``omega`` per unit push lies along the
    belt's motion (inf if it turns away)."""
    q = hull[(edge + 1) % len(hull)] - hull[edge]
    # the turn (counter-clockwise) that brings the edge along +-D, in [0, pi)
    off = math.atan2(float(perp(q) @ D), float(q @ D)) % math.pi
    if omega > 0.0:
        return off / omega
    if omega < 0.0:
        return (math.pi - off) / -omega
    return math.inf


def _reimpose(geo: _FenceGeometry, cm: np.ndarray, theta: float, mode: Mode) -> np.ndarray:
    """The contact of ``mode`` made exact again after a step."""
    i = mode.index
    hull = geo.hull(cm, theta)
    if mode.contact is Contact.FLUSH:
        # the lower end of the edge over the fence goes onto the face: an end past E may
        # stand a rounding-sized tilt above it, and putting that one on the line would push
        # the other into the face (every later step refused: a stall)
        ends = [v for v in (i, (i + 1) % geo.part.hull_size) if geo.on_fence(geo.along(hull[v][None]))[0]] or [i]
        i = min(ends, key=lambda v: float(geo.heights(hull[v][None])[0]))
    if mode.contact in (Contact.VERTEX, Contact.FLUSH):
        return onto_line(cm, hull[i], geo.n, float(geo.n @ geo.e))
    q = hull[(i + 1) % geo.part.hull_size] - hull[i]
    n_e = perp(q) / math.hypot(float(q[0]), float(q[1]))
    return onto_line(cm, hull[i], n_e, float(n_e @ geo.e))
