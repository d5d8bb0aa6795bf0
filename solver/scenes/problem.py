"""The problem and the answers of a scene analysis (:mod:`solver.scenes.analyze`): one
pushing scene and the questions asked of it, each answered by the cheapest model that
reaches the accuracy the caller asked for (issue 27).

Accuracy is ordered: ``estimate`` (the cheapest answer, whose error may be unknown) <
``bound`` (guaranteed for every pressure distribution the part allows: conservative) <
``exact`` (the part's own answer, certified). A model reaches a level for a given scene:

* a part that *is* a disk has closed forms that are exact (3.30-3.38, 4.1);
* for a polygon, the circumscribing disk's answer is a bound (its locus contains the
  polygon's, 7.5); a *decisive* bound (one contact mode only) is exact too, since the
  polygon's modes are among the disk's;
* certified optimisation of the polygon (3.3.13, 7.5) is exact;
* the book's closed forms of the push to align are exact without pusher friction and
  approximations with it (4.3); the exact bounds there are bounds (of the circumscribing
  disk, so of the part);
* a feeder design rests on disk-bounded maps (bound); simulated parts check it.

Each answer says which model answered, the accuracy reached, its error bound and what it
cost.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.core.scene import PushScene
from solver.core.budget import Budget
from solver.push.bounds import QuasiStaticQuery

ACCURACIES = ("estimate", "bound", "exact")
"""The levels of accuracy, from the cheapest (module docstring)."""

ASKS = ("cor_locus", "stick_or_slip", "push_to_align", "quasi_static", "aligning_fence", "feeder_design")
"""The questions a scene can be asked."""

POLYGON_ASKS = frozenset({"push_to_align", "aligning_fence", "feeder_design"})
"""Questions of a polygonal part only."""

ONE_MU_ASKS = frozenset({"stick_or_slip", "push_to_align"})
"""Questions answered for one mu_c (the feeder's maps take an interval)."""

ORDER = {"feeder_design": 0, "push_to_align": 1}
"""Questions answered before the others (they can answer another for free)."""


@dataclass(frozen=True)
class Question:
    """One question and the accuracy wanted (module docstring), with its model's knobs:
    ``n_points`` boundary points of an analytic locus or sketch, ``n_rays`` rays of a
    certified one; the candidate fences' |angles| (radians), the deepest design and whether
    its fences alternate sides, of the feeder questions; ``validation_parts`` simulated parts checking a design (seeded; None:
    the analysis's default for the accuracy asked)."""

    ask: str
    accuracy: str = "bound"
    n_points: int = 256
    n_rays: int = 16
    angle_min: float = 0.17453292519943295  # 10 degrees
    angle_max: float = 1.3962634015954636  # 80 degrees
    angle_step: float = 0.08726646259971647  # 5 degrees
    max_depth: int = 6
    alternate: bool = True
    validation_parts: int | None = None  # None: DESIGN_CHECK_PARTS at "exact", else none
    seed: int = 0

    def __post_init__(self) -> None:
        if self.ask not in ASKS:
            raise InvalidInput("ask", f"must be one of {', '.join(ASKS)}")
        if self.accuracy not in ACCURACIES:
            raise InvalidInput("accuracy", f"must be one of {', '.join(ACCURACIES)}")

    def at_least(self, level: str) -> bool:
        """Whether the accuracy asked for is ``level`` or finer."""
        return ACCURACIES.index(self.accuracy) >= ACCURACIES.index(level)


@dataclass(frozen=True)
class SceneProblem:
    """The push ``scene`` of a part that is a disk (``footprint`` None: the scene's disk) or
    a polygon (its circumscribing disk is the scene's), pusher friction ``mu_c`` (low, high;
    equal for one value), optionally the push's speed and the table (``quasi_static``), and
    the questions."""

    scene: PushScene
    footprint: Footprint | None
    mu_c: tuple[float, float]
    quasi_static: QuasiStaticQuery | None
    questions: tuple[Question, ...]

    def __post_init__(self) -> None:
        lo, hi = self.mu_c
        if not 0.0 <= lo <= hi:
            raise InvalidInput("mu_c", "must be a number >= 0 or an interval [low, high] with 0 <= low <= high")
        for k, q in enumerate(self.questions):
            if q.ask in POLYGON_ASKS and self.footprint is None:
                raise InvalidInput(f"questions.{k}.ask", f"{q.ask} needs a polygon part (footprint): a disk has no "
                                   "edge to align and no orientation to feed")
            if q.ask in ONE_MU_ASKS and lo != hi:
                raise InvalidInput(f"questions.{k}.ask", f"{q.ask} takes one mu_c, not an interval: ask once per "
                                   "value (the feeder questions take the interval)")
            if q.ask == "quasi_static" and self.quasi_static is None:
                raise InvalidInput(f"questions.{k}.ask", "quasi_static needs the push's speed and the table (speed, "
                                   "mu_s, and g or length_unit)")

    @property
    def is_disk(self) -> bool:
        return self.footprint is None


@dataclass(frozen=True)
class ModeVerdict:
    """Which contact modes the pusher can be in (4.1) over the pressure distributions the
    model allows, and the sketch they come from (None for mu_c = 0: no friction, no
    sticking)."""

    modes: tuple[str, ...]
    sketch: Any = None

    @property
    def verdict(self) -> str:
        """"sticks" (sticking only), "slips" (no sticking) or "either"."""
        if self.modes == ("sticking",):
            return "sticks"
        return "either" if "sticking" in self.modes else "slips"

    @property
    def decisive(self) -> bool:
        """One mode only: the same for every distribution of any part inside the model's."""
        return len(self.modes) == 1


@dataclass(frozen=True)
class Tried:
    """A cheaper model tried first, what it cost and why its answer was not enough."""

    model: str
    cost_s: float
    why_not: str


@dataclass(frozen=True)
class Answer:
    """The answer to ``question``: ``status`` "answered", "time_limited" (the model ran out
    of time: ``result`` is what it completed, or None) or "not_run" (no time was left);
    ``model`` that answered, ``accuracy`` reached, ``error_bound`` (None: none known) and
    what it means, ``cost_s`` of this answer's own work (0 when it reused another's:
    ``reused_from``, that answer's index), the cheaper models ``tried`` first, the solver
    ``result`` the answer rests on, and ``note``."""

    question: Question
    status: str
    model: str | None
    accuracy: str | None
    error_bound: float | None
    error_meaning: str
    cost_s: float
    reused_from: int | None
    tried: tuple[Tried, ...]
    result: Any
    note: str = ""


@dataclass(frozen=True)
class SceneAnalysis:
    """The answers, in the questions' order, and the time it all took."""

    problem: SceneProblem
    answers: tuple[Answer, ...]
    solve_time_s: float

    @property
    def complete(self) -> bool:
        return all(a.status == "answered" for a in self.answers)

    @property
    def status(self) -> str:
        """"complete" (every question answered) or "incomplete"."""
        return "complete" if self.complete else "incomplete"

    @property
    def message(self) -> str:
        done = sum(a.status == "answered" for a in self.answers)
        return f"{done} of {len(self.answers)} questions answered"


@dataclass
class Work:
    """What one analysis has computed so far, for reuse: a result per key, with the index of
    the answer that computed it."""

    problem: SceneProblem
    budget: Budget
    done: dict[tuple, tuple[Any, int]] = field(default_factory=dict)

    def reuse(self, key: tuple) -> tuple[Any, int] | None:
        return self.done.get(key)

    def keep(self, key: tuple, value: Any, index: int) -> None:
        self.done.setdefault(key, (value, index))
