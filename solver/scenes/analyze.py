"""Answer the questions of one pushing scene, each with the cheapest model that reaches the
accuracy asked for (the levels and which model reaches which: :mod:`solver.scenes.problem`).

What one answer computed is kept for the next (:class:`solver.scenes.problem.Work`): the
same locus or sketch asked twice is computed once, a feeder design answers "which one
fence aligns it" (a design is the fewest fences, so a one-fence design is that fence, and
a longer one proves there is none), and the push to align's quasi-static verdict (6.8)
answers the speed question. The design and the push to align are answered first for that.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import numpy as np

from models.core.errors import InvalidInput
from models.feeder.fence import feeder_part
from models.push.quasistatic import ShapeMoments
from solver.core.budget import UNLIMITED, Budget
from solver.core.errors import TimeLimitReached
from solver.feeder.design import FeederDesignProblem, FeederDesignResult, feeder_design
from solver.locus.cor_locus import LocusProblem, cor_locus
from solver.push.align import AlignProblem, align
from solver.push.bounds import SKETCH_COST
from solver.scenes.problem import ORDER, Answer, ModeVerdict, Question, SceneAnalysis, SceneProblem, Tried, Work
from solver.sketch.cor_sketch import SketchProblem, cor_sketch

DESIGN_CHECK_PARTS = 100
"""Simulated parts that check a design asked for at accuracy "exact" (unless the question
gives its own number)."""

LOCUS_CLOSED_FORM = ("residual of the boundary's equations (3.30) at the returned points, which lie on the "
                     "exact boundary of the disk's locus")
LOCUS_DISK_BOUND = (LOCUS_CLOSED_FORM + "; it is the circumscribing disk's locus, which contains the polygon's (7.5): "
                    "how much larger is not measured")
LOCUS_CERTIFIED = ("length: each certified boundary point is within this of the true boundary along its ray; between "
                   "rays the boundary is not certified")
MODES_MEANING = "a verdict over every pressure distribution the model allows (4.1); no numerical error"
ALIGN_FRICTIONLESS = "0: without pusher friction the closed forms (3.41, r_min) are the circumscribing disk's bounds"
ALIGN_CLOSED_FORM = ("unknown: with pusher friction the book's closed forms (4.3) approximate the bounds (measured up "
                     "to 0.033 a from the exact ones at mu_c = 1)")
ALIGN_EXACT = "length: quadrature error of the exact bounds of the circumscribing disk, which bound the part's push"
QUASI_STATIC = "a verdict of the book's model on v / v_qs (6.8) with its permissible errors; no numerical error"
DESIGN = ("the fence maps bound every pressure distribution in the circumscribing disk (5.1, 7.5); the design's margin "
          "is how far orientations may err without changing it")


def computed(work: Work, key: tuple, index: int, compute: Callable[[], Any]) -> tuple[Any, float, int | None]:
    """The value of ``key``: reused (cost 0 and the index of the answer that computed it),
    or computed now and kept."""
    hit = work.reuse(key)
    if hit is not None:
        return hit[0], 0.0, hit[1]
    t0 = time.perf_counter()
    value = compute()
    work.keep(key, value, index)
    return value, time.perf_counter() - t0, None


def cor_locus_answer(work: Work, q: Question, i: int) -> Answer:
    """Closed form for a disk; the circumscribing disk's locus (a bound) for a polygon unless
    its exact locus is asked for, then certified along ``n_rays`` rays."""
    p = work.problem
    if p.is_disk or not q.at_least("exact"):
        result, cost, reused = computed(work, ("locus", "analytic", q.n_points), i,
                                        lambda: cor_locus(LocusProblem(p.scene, n_points=q.n_points), work.budget))
        model, level = ("closed_form", "exact") if p.is_disk else ("disk_bound", "bound")
        return Answer(q, "answered", model, level, result.analytic.boundary_residual,
                      LOCUS_CLOSED_FORM if p.is_disk else LOCUS_DISK_BOUND, cost, reused, (), result)
    result, cost, reused = computed(
        work, ("locus", "certified", q.n_points, q.n_rays), i,
        lambda: cor_locus(LocusProblem(p.scene, p.footprint, n_points=q.n_points, method="certified",
                                       n_certified=q.n_rays), work.budget))
    cert = result.certified
    if cert is None:  # a translation: no boundary to certify, the disk's answer is the polygon's
        return Answer(q, "answered", "certified", "exact", None, LOCUS_CERTIFIED, cost, reused, (), result,
                      "; ".join(result.notes))
    done = [r for r in cert.rays if bool(np.all(np.isfinite(r.point)))]
    every = result.complete and len(done) == cert.n_requested
    error = max((0.5 * (r.t_out - r.t_in) * cert.length_scale for r in done), default=None)
    note = "; ".join((*result.notes, cert.message))
    if every:
        return Answer(q, "answered", "certified", "exact", error, LOCUS_CERTIFIED, cost, reused, (), result, note)
    # some rays not certified: the circumscribing disk's locus (in the same result) is the answer
    tried = (Tried("certified", cost, f"{len(done)} of {cert.n_requested} rays certified"),)
    return Answer(q, "answered" if result.complete else "time_limited", "disk_bound", "bound",
                  result.analytic.boundary_residual, LOCUS_DISK_BOUND, 0.0, reused, tried, result, note)


def stick_or_slip_answer(work: Work, q: Question, i: int) -> Answer:
    """Without friction it slips; else the disk's sketch (4.1), exact for a disk and for a
    decisive verdict, a bound otherwise; the polygon's certified sketch when that is not
    enough."""
    p = work.problem
    mu = p.mu_c[0]
    if mu == 0.0:
        return Answer(q, "answered", "closed_form", "exact", None, "mu_c = 0: a frictionless contact cannot stick (4.1)",
                      0.0, None, (), ModeVerdict(("frictionless",)))
    disk, cost, reused = computed(work, ("sketch", "analytic", q.n_points), i,
                                  lambda: cor_sketch(SketchProblem(p.scene, mu, n_points=q.n_points), work.budget))
    verdict = ModeVerdict(disk.sketch.allowed_modes, disk)
    if p.is_disk or verdict.decisive or not q.at_least("exact"):
        exact = p.is_disk or verdict.decisive
        return Answer(q, "answered", "closed_form" if p.is_disk else "disk_bound", "exact" if exact else "bound",
                      None, MODES_MEANING, cost, reused, (), verdict)
    tried = (Tried("disk_bound", cost, f"the circumscribing disk allows {' and '.join(verdict.modes)}: not decisive "
                   "for the polygon"),)
    if work.budget.expired():
        return Answer(q, "time_limited", "disk_bound", "bound", None, MODES_MEANING, cost, reused, tried, verdict,
                      "no time was left to certify the polygon's sketch: the disk's verdict bounds it")
    result, cost_exact, reused_exact = computed(
        work, ("sketch", "certified", q.n_points, q.n_rays), i,
        lambda: cor_sketch(SketchProblem(p.scene, mu, footprint=p.footprint, method="certified", n_points=q.n_points,
                                         n_rays=q.n_rays), work.budget))
    if result.complete:
        return Answer(q, "answered", "certified", "exact", None, MODES_MEANING, cost_exact, reused_exact, tried,
                      ModeVerdict(result.sketch.allowed_modes, result))
    # a piece not certified: the disk's verdict, which bounds the polygon's, is the answer
    status = "time_limited" if result.certified is not None and result.certified.time_limited else "answered"
    return Answer(q, status, "disk_bound", "bound", None, MODES_MEANING, cost + cost_exact, reused, tried, verdict,
                  f"the polygon's certified sketch is incomplete ({result.message}): the disk's verdict bounds it")


def push_to_align_answer(work: Work, q: Question, i: int) -> Answer:
    """The book's closed forms when they reach the accuracy (always without friction),
    else the exact bounds; the fence is the scene's edge, pushing along its push."""
    p = work.problem
    mu = p.mu_c[0]
    method = "closed_form" if mu == 0.0 or not q.at_least("bound") else "both"  # both: the closed forms beside
    problem = AlignProblem(p.footprint, 0.0, p.scene.edge_angle, p.scene.push_direction, mu_c=mu, method=method,
                           quasi_static=p.quasi_static, cost=SKETCH_COST)
    t0 = time.perf_counter()
    try:
        result, cost, reused = computed(work, ("align", method), i, lambda: align(problem, work.budget))
    except TimeLimitReached as exc:
        return Answer(q, "time_limited", method, None, None, "", time.perf_counter() - t0, None, (), None, str(exc))
    except InvalidInput as exc:
        if exc.field != "time_limit_s":
            raise
        return Answer(q, "time_limited", method, None, None, "", time.perf_counter() - t0, None, (), None, exc.reason)
    if result.quasi_static is not None:
        work.keep(("quasi_static",), result.quasi_static, i)
    note = "" if not q.at_least("exact") else ("no model of the part's own push is certified: the circumscribing "
                                               "disk's bounds, which hold for the part, are answered")
    if method == "closed_form":
        return Answer(q, "answered", "closed_form", "bound" if mu == 0.0 else "estimate", 0.0 if mu == 0.0 else None,
                      ALIGN_FRICTIONLESS if mu == 0.0 else ALIGN_CLOSED_FORM, cost, reused, (), result, note)
    errors = [b.quadrature_error for b in (result.longest, result.shortest) if b.quadrature_error is not None]
    return Answer(q, "answered", "exact_bounds", "bound", max(errors) if errors else None, ALIGN_EXACT, cost, reused,
                  (), result, note)


def quasi_static_answer(work: Work, q: Question, i: int) -> Answer:
    """The book's verdict (6.8), or the one the push to align already made."""
    p = work.problem
    assert p.quasi_static is not None  # the caller checks it is given
    query = p.quasi_static

    def assess():
        moments = ShapeMoments.disk(p.scene.disk_radius) if p.is_disk else ShapeMoments.polygon(p.footprint)
        return query.assess(moments)

    result, cost, reused = computed(work, ("quasi_static",), i, assess)
    return Answer(q, "answered", "closed_form", "exact", None, QUASI_STATIC, cost, reused, (), result)


def _design_problem(p: SceneProblem, q: Question, max_depth: int, parts: int) -> FeederDesignProblem:
    part = feeder_part(p.footprint.vertices, p.footprint.center_of_mass)
    return FeederDesignProblem(part, q.angle_min, q.angle_max, q.angle_step, p.mu_c, max_depth=max_depth,
                               alternate=q.alternate, validation_parts=parts, seed=q.seed)


def _design_answer(q: Question, result: FeederDesignResult, cost: float, reused: int | None, parts: int,
                   tried: tuple[Tried, ...] = ()) -> Answer:
    done = result.status == "ok"
    model = "design_search+simulation" if parts else "design_search"
    meaning = DESIGN + (f"; {parts} simulated parts checked it" if parts else "")
    note = "" if not q.at_least("exact") else "no design is certified for the part itself: the disk-bounded one is"
    return Answer(q, "answered" if done else "time_limited", model, "bound" if done else None, None, meaning, cost,
                  reused, tried, result, note)


def feeder_design_answer(work: Work, q: Question, i: int) -> Answer:
    """The fewest fences that orient the part (5.3-5.4), checked by simulated parts when
    exact is asked for."""
    parts = q.validation_parts if q.validation_parts is not None else (DESIGN_CHECK_PARTS if q.at_least("exact") else 0)
    key = ("design", q.angle_min, q.angle_max, q.angle_step, q.alternate, q.seed, q.max_depth, parts)
    result, cost, reused = computed(work, key, i,
                                    lambda: feeder_design(_design_problem(work.problem, q, q.max_depth, parts),
                                                          work.budget))
    return _design_answer(q, result, cost, reused, parts)


def _settles_one_fence(result: FeederDesignResult) -> bool:
    """Whether a design result says if one fence orients the part: it found one, or proved
    that no design has a single fence."""
    if result.status != "ok" or result.search is None:
        return False
    design = result.design
    return (design is not None and len(design.fences) == 1) or result.search.depth_proven >= 1


def aligning_fence_answer(work: Work, q: Question, i: int) -> Answer:
    """The one fence that orients the part, if any: from a design of the same candidates
    when one was made, else a search one fence deep."""
    candidates = (q.angle_min, q.angle_max, q.angle_step)  # one fence: alternating sides does not matter
    parts = q.validation_parts if q.validation_parts is not None else (DESIGN_CHECK_PARTS if q.at_least("exact") else 0)
    for key, (result, j) in work.done.items():
        if key[0] != "design" or key[1:4] != candidates or not _settles_one_fence(result):
            continue
        single = result.design is not None and len(result.design.fences) == 1
        if single and key[7] != parts:
            continue  # the fence is the answer, but checked by another number of simulated parts
        return _design_answer(q, result, 0.0, j, key[7] if single else 0)
    result, cost, reused = computed(work, ("design", *candidates, q.alternate, q.seed, 1, parts), i,
                                    lambda: feeder_design(_design_problem(work.problem, q, 1, parts), work.budget))
    return _design_answer(q, result, cost, reused, parts)


HANDLERS: dict[str, Callable[[Work, Question, int], Answer]] = {
    "cor_locus": cor_locus_answer,
    "stick_or_slip": stick_or_slip_answer,
    "push_to_align": push_to_align_answer,
    "quasi_static": quasi_static_answer,
    "aligning_fence": aligning_fence_answer,
    "feeder_design": feeder_design_answer,
}


EXPENSIVE_ALWAYS = frozenset({"feeder_design", "aligning_fence"})
"""Questions answered by a design search at every accuracy."""


def answer_order(problem: SceneProblem, q: Question, k: int) -> tuple[int, int, str, int]:
    """Where question ``q`` (the ``k``-th) is answered: those that answer others for free
    first (ORDER), then the ones a closed form or the disk's bound answers before those that
    certify or search, so a cheap answer is never cut by an expensive one's use of the time
    limit; within those, by the question itself, so the answers do not depend on the order
    in which the questions were asked (issue 35)."""
    cheap = q.ask not in EXPENSIVE_ALWAYS and (problem.is_disk or not q.at_least("exact"))
    return (ORDER.get(q.ask, 2), 0 if cheap else 1, repr(q), k)


def analyze_scene(problem: SceneProblem, budget: Budget = UNLIMITED) -> SceneAnalysis:
    """Answer every question of ``problem`` within ``budget``; a question reached with no
    time left is "not_run", one whose model ran out of time "time_limited"."""
    t0 = time.perf_counter()
    work = Work(problem, budget)
    answers: dict[int, Answer] = {}
    order = sorted(range(len(problem.questions)), key=lambda k: answer_order(problem, problem.questions[k], k))
    for k in order:
        q = problem.questions[k]
        if budget.expired():
            answers[k] = Answer(q, "not_run", None, None, None, "", 0.0, None, (), None,
                                "the time limit was reached before this question")
            continue
        answers[k] = HANDLERS[q.ask](work, q, k)
    return SceneAnalysis(problem, tuple(answers[k] for k in range(len(problem.questions))), time.perf_counter() - t0)
