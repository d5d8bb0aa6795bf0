"""Exact bounds on gross motions from the exact COR sketch (book 4.2-4.4).

Book 4.2: to bound a quantity x while beta runs from beta_initial to beta_final, take in
every COR sketch the COR that makes dx/dbeta largest (or smallest) and integrate. The book
approximates that COR by tips and by the tip line (closed forms in models/push/gross_motion.py);
here it is taken from the sketch itself (models/sketch/disk_sketch.py): the slipping loci (the
analytic {COR}_{alpha+-nu} cut by their consistency half-planes) and the sticking segment.

Every rate used here is linear or linear-fractional in the COR (the fence's (4.2) is
linear; the disk's (4.12) and its rotation rate are ratios with x_COR in the denominator),
so along each straight edge of a locus polygon it is monotone (while x_COR keeps its sign)
and its extremes over the sketch are at polygon vertices or at the sticking segment's
ends: the candidates this module evaluates. The polygons are the analytic boundaries
sampled at ``n_points`` points, so a bound carries their chord error (it shrinks as
n_points^-2; the benchmark reports it).

The integral over beta uses Gauss-Legendre nodes (no end points: the disk's beta = pi/2 is
a grazing push) at ``n_nodes`` and at half as many; their difference is reported as the
quadrature error estimate. The disk encounter integrates in u = ln tan(beta/2), where its
rates, which grow like 1/sin(beta) near beta = 0, become bounded. Frames are those of models/push/gross_motion.py.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from functools import partial
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike

from models.core.arrays import Real
from models.core.errors import InvalidInput
from models.core.scene import PushScene
from models.locus.cor_disk import disk_cor_locus
from models.push import gross_motion as gm
from models.sketch.disk_sketch import CorSketch, Spans, disk_cor_sketch, sticking_spans


@dataclass(frozen=True)
class SketchBound:
    """An integral bound over beta: ``value``, its quadrature error estimate (difference to
    the half-node rule), the nodes with the extreme rate, COR (frame coordinates) and the
    locus it came from at each, the book's closed form beside it when it has one, and the
    time taken."""

    value: float
    quadrature_error: float
    betas: np.ndarray
    rates: np.ndarray
    cors: np.ndarray
    sources: tuple[str, ...]
    book_value: float | None
    solve_time_s: float


def sketch_candidates(sketch: CorSketch) -> tuple[np.ndarray, list[str]]:
    """Every point where a linear or linear-fractional rate can be extreme over the sketch:
    the vertices of the slipping polygons and the ends of the sticking segment."""
    pts, src = [], []
    if sketch.sticking is not None:
        pts += [sketch.sticking.low, sketch.sticking.high]
        src += ["sticking", "sticking"]
    for polys, name in ((sketch.up_slipping, "slipping_up"), (sketch.down_slipping, "slipping_down")):
        for poly in polys:
            pts.extend(poly)
            src += [name] * len(poly)
    if not pts:
        return np.empty((0, 2)), []
    return np.asarray(pts, dtype=float), src


Extreme = tuple[float, np.ndarray, str]
"""(the extreme rate, the COR attaining it (2,), its source in the sketch)."""

RateOfCors = Callable[[np.ndarray], Real]
"""A rate at CORs r (k, 2) of one sketch."""

RateAtBeta = Callable[[float, np.ndarray], Real]
"""A rate at collision parameter beta and CORs r (k, 2)."""


def extreme_over_sketch(sketch: CorSketch, rate: RateOfCors, largest: bool) -> Extreme:
    """(value, COR, source) of the largest (or smallest) ``rate`` over the sketch: a rate
    linear or linear-fractional in the COR is extreme at a vertex of the slipping polygons
    or an end of the sticking segment (4.2)."""
    return _extreme_of(sketch_candidates(sketch), rate, largest)


def _extreme_of(candidates: tuple[np.ndarray, list[str]], rate: RateOfCors, largest: bool) -> Extreme:
    pts, src = candidates
    if len(pts) == 0:
        raise InvalidInput("mu_c", "the COR sketch is empty here: no consistent motion")
    vals = np.asarray(rate(pts), dtype=float)
    k = int(np.nanargmax(vals) if largest else np.nanargmin(vals))
    return float(vals[k]), pts[k], src[k]


def _integrate(f_node: Callable[[float], Extreme], lo: float, hi: float,
               n_nodes: int) -> tuple[tuple[float, np.ndarray, np.ndarray, np.ndarray, tuple[str, ...]], float]:
    """Gauss-Legendre with n and n/2 nodes on [lo, hi]; f_node(beta) -> (rate, cor, src)."""
    if n_nodes < 4:
        raise InvalidInput("n_nodes", "must be at least 4")
    results: dict[int, tuple[float, np.ndarray, np.ndarray, np.ndarray, tuple[str, ...]]] = {}
    for n in (n_nodes, max(2, n_nodes // 2)):
        x, w = np.polynomial.legendre.leggauss(n)
        betas = 0.5 * (hi - lo) * x + 0.5 * (hi + lo)
        vals = [f_node(float(b)) for b in betas]
        rates = np.array([v[0] for v in vals])
        results[n] = (0.5 * (hi - lo) * float(w @ rates), betas, rates, np.array([v[1] for v in vals]),
                      tuple(v[2] for v in vals))
    full = results[n_nodes]
    half = results[max(2, n_nodes // 2)]
    return full, abs(full[0] - half[0])


def fence_scene(a: float, c: float, alpha: float, beta: float) -> PushScene:
    """The fence push at angle beta (fence frame of models/push/gross_motion.py): CM at the
    origin, the vertex at c (-cos beta, sin beta), the fence face at angle alpha, pushing
    along +x."""
    contact = c * np.array([-math.cos(beta), math.sin(beta)])
    return PushScene.create(a, contact, alpha, 0.0)


FENCE_BOUNDS = ("push_max", "push_min", "slip_max", "slip_min")
"""Keys of :func:`fence_bounds_exact`."""


Checkpoint = Callable[[str], None]
"""Called with a description of the step about to start (e.g. "the sketch at beta = 0.3");
it may raise to stop the computation (the solver layer passes its budget's checkpoint,
which raises once the time limit has passed). Models never read a clock themselves."""


def _no_checkpoint(where: str) -> None:
    """The default checkpoint: never stops."""


def frictionless_candidates(scene: PushScene, n_points: int) -> tuple[np.ndarray, list[str]]:
    """mu_c = 0: the candidates of a linear rate are the vertices of the frictionless locus
    {COR}_alpha (3.30, 3.35 sampled at ``n_points``); a linear function over a region is
    extreme on its boundary."""
    loc = disk_cor_locus(scene, outputs=("boundary",), n_points=n_points)
    if loc.boundary is None:
        raise InvalidInput("alpha", "the line of force passes through the CM: the part only translates")
    return loc.boundary, ["frictionless"] * len(loc.boundary)


def fence_bounds_exact(
    a: float, c: float, alpha: float, beta_initial: float, beta_final: float, mu_c: float,
    n_nodes: int = 16, n_points: int = 256, which: tuple[str, ...] = FENCE_BOUNDS,
    checkpoint: Checkpoint = _no_checkpoint, spans: Spans = sticking_spans,
) -> dict[str, SketchBound]:
    """Bounds of the fence-alignment push (4.3) from one exact sketch per quadrature node
    (the nodes are shared, so every bound reuses the same sketches):

    * "push_max" / "push_min": the longest / shortest push until the edge lies flush,
      integral of max (min) over the sketch of (4.2), dx/dbeta = alpha_hat . (c - r) / sin(alpha);
    * "slip_max" / "slip_min": how far the fence face slips past the contact vertex (along
      alpha_hat, positive or negative) meanwhile, integral of :func:`fence_slip_rate`.

    Contact at c(-cos beta, sin beta), fence along alpha, push along +x. mu_c = 0 takes the
    frictionless locus {COR}_alpha. The book's composite closed form
    (models.push.gross_motion.fence_push_bound) is reported beside "push_max". ``checkpoint``
    is called before every sketch (:data:`Checkpoint`); ``spans`` answers the sketches'
    sticking sweeps (models.sketch.disk_sketch.Spans)."""
    unknown = [k for k in which if k not in FENCE_BOUNDS]
    if unknown:
        raise InvalidInput("which", f"unknown bounds {unknown}; choose from {list(FENCE_BOUNDS)}")
    t0 = time.perf_counter()
    cache: dict[float, tuple[np.ndarray, list[str]]] = {}

    def candidates(beta: float) -> tuple[np.ndarray, list[str]]:
        if beta not in cache:
            checkpoint(f"the sketch at beta = {beta:.6g} ({len(cache)} of {n_nodes + max(2, n_nodes // 2)} done)")
            scene = fence_scene(a, c, alpha, beta)
            if mu_c == 0.0:
                cache[beta] = frictionless_candidates(scene, n_points)
            else:
                cache[beta] = sketch_candidates(disk_cor_sketch(scene, mu_c, n_points=n_points, sweep_points=n_points,
                                                                  spans=spans))
        return cache[beta]

    rates = {
        "push_max": (lambda beta, r: gm.fence_rate(beta, c, alpha, r), True),
        "push_min": (lambda beta, r: gm.fence_rate(beta, c, alpha, r), False),
        "slip_max": (lambda beta, r: fence_slip_rate(beta, c, alpha, r), True),
        "slip_min": (lambda beta, r: fence_slip_rate(beta, c, alpha, r), False),
    }
    out = {}
    for key in which:
        rate, largest = rates[key]

        def node(beta: float, rate: RateAtBeta = rate, largest: bool = largest) -> Extreme:
            return _extreme_of(candidates(beta), lambda r: rate(beta, r), largest)

        (value, betas, vals, cors, srcs), err = _integrate(node, beta_initial, beta_final, n_nodes)
        book = None
        if key == "push_max":
            try:
                book = gm.fence_push_bound(a, c, alpha, beta_initial, beta_final, mu_c).total
            except InvalidInput:
                book = None
        out[key] = SketchBound(value, err, betas, vals, cors, srcs, book, time.perf_counter() - t0)
    return out


def fence_push_bound_exact(
    a: float, c: float, alpha: float, beta_initial: float, beta_final: float, mu_c: float,
    n_nodes: int = 16, n_points: int = 256, longest: bool = True,
) -> SketchBound:
    """The longest (or, ``longest=False``, shortest) push of a fence until the part's edge
    lies flush (4.3); see :func:`fence_bounds_exact`."""
    key = "push_max" if longest else "push_min"
    return fence_bounds_exact(a, c, alpha, beta_initial, beta_final, mu_c, n_nodes, n_points, (key,))[key]


def fence_slip_rate(beta: float, c: float, alpha: float, cor: ArrayLike) -> np.ndarray:
    """Slip of the pusher along the fence face, relative to the part, per radian of turn:
    dslip/dbeta for CORs r (k, 2) in the fence frame, positive along alpha_hat (the sign of
    models.core.scene.PushScene.slip_per_push). With omega = -sin(alpha)/(alpha . (c - r)) (3.3)
    and dx/dbeta = -1/omega (4.2): slip per push alpha . (p - omega J (c - r)) times
    dx/dbeta = cos(alpha) alpha . (c - r)/sin(alpha) + alpha . J(c - r) -- linear in r."""
    r = np.atleast_2d(np.asarray(cor, dtype=float))
    cv = c * np.array([-math.cos(beta), math.sin(beta)])
    ah = np.array([math.cos(alpha), math.sin(alpha)])
    d = cv[None, :] - r
    jd = np.stack([-d[:, 1], d[:, 0]], axis=1)
    return math.cos(alpha) * (d @ ah) / math.sin(alpha) + jd @ ah


def fence_slip_bounds_exact(
    a: float, c: float, alpha: float, beta_initial: float, beta_final: float, mu_c: float,
    n_nodes: int = 16, n_points: int = 256,
) -> tuple[SketchBound, SketchBound]:
    """How far the pusher can slip along the fence face (relative to the part) while the
    part turns from beta_initial to beta_final (issue 4, 4.3): (most positive, most
    negative) along alpha_hat; see :func:`fence_bounds_exact`. With mu_c > 0 and a
    sticking-only sketch both are 0."""
    out = fence_bounds_exact(a, c, alpha, beta_initial, beta_final, mu_c, n_nodes, n_points, ("slip_max", "slip_min"))
    return out["slip_max"], out["slip_min"]


def _log_tan_half(beta: float) -> float:
    """ln tan(beta/2) without underflow for tiny beta (down to the smallest subnormal):
    ln(beta) - ln 2 + ln(tan(h)/h), tan(h)/h = 1 + h^2/3 + ... for h = beta/2."""
    h = 0.5 * beta
    if h < 1e-8:
        return math.log(beta) - math.log(2.0) + h * h / 3.0
    return math.log(math.tan(h))


def encounter_scene(a: float, beta: float) -> PushScene:
    """The disk of 4.4 at collision parameter beta (disk-encounter frame): contact
    a(-cos beta, sin beta), the disk's tangent there as the edge (alpha = pi/2 - beta),
    push along +x."""
    contact = a * np.array([-math.cos(beta), math.sin(beta)])
    return PushScene.create(a, contact, 0.5 * math.pi - beta, 0.0)


def encounter_bounds_exact(
    a: float, beta_initial: float, mu_c: float, beta_final: float = 0.5 * math.pi,
    n_nodes: int = 16, n_points: int = 256, checkpoint: Checkpoint = _no_checkpoint,
    spans: Spans = sticking_spans,
) -> dict[str, SketchBound]:
    """Greatest and least length of the encounter (4.12) and greatest and least rotation
    (dxi/dbeta = -a cos beta / x_COR, models.push.gross_motion.rotation_rate) of a disk pushed
    aside by a point (4.4), from the exact sketch at every node (one sketch per node serves
    all four). Keys: "length_max", "length_min", "rotation_max", "rotation_min"; the book's
    (4.16) and (4.18) are given beside the maxima. ``checkpoint`` and ``spans`` as in
    :func:`fence_bounds_exact`."""
    if not 0.0 < beta_initial < beta_final <= 0.5 * math.pi:
        raise InvalidInput("beta_initial", "must satisfy 0 < beta_initial < beta_final <= pi/2")
    if n_nodes < 4:
        raise InvalidInput("n_nodes", "must be at least 4")
    t0 = time.perf_counter()
    rates = {
        "length_max": (lambda b, r: gm.encounter_rate(b, r[:, 0], r[:, 1], a), True),
        "length_min": (lambda b, r: gm.encounter_rate(b, r[:, 0], r[:, 1], a), False),
        "rotation_max": (lambda b, r: gm.rotation_rate(b, r[:, 0], r[:, 1], a), True),
        "rotation_min": (lambda b, r: gm.rotation_rate(b, r[:, 0], r[:, 1], a), False),
    }
    # The rates grow like 1/sin(beta) as beta -> 0 ((4.15): 2a/sin beta), which Gauss-
    # Legendre in beta underestimates badly for a small beta_initial. In u = ln tan(beta/2),
    # dbeta = sin(beta) du and the integrand rate * sin(beta) stays bounded.
    u0, u1 = _log_tan_half(beta_initial), _log_tan_half(beta_final)
    rules = {}
    for n in (n_nodes, max(2, n_nodes // 2)):
        x, w = np.polynomial.legendre.leggauss(n)
        us = 0.5 * (u1 - u0) * x + 0.5 * (u1 + u0)
        betas = 2.0 * np.arctan(np.exp(us))
        w = w * np.sin(betas)  # dbeta = sin(beta) du
        per_key: dict[str, list[Extreme]] = {key: [] for key in rates}
        for k, beta in enumerate(betas):
            checkpoint(f"the sketch at beta = {float(beta):.6g} (rule with {n} nodes, node {k + 1})")
            sk = disk_cor_sketch(encounter_scene(a, float(beta)), mu_c, n_points=n_points, sweep_points=n_points,
                                 spans=spans)
            if sk.sense == "none" or not sk.allowed_modes:
                # A head-on push (beta -> 0): the line of force runs through the CM and the
                # disk only translates; the encounter never ends (4.16 diverges).
                raise InvalidInput(
                    "beta_initial",
                    f"is too close to a head-on push: at beta = {float(beta):.3g} the disk only translates "
                    "and the encounter length is unbounded",
                )
            for key, (rate, largest) in rates.items():
                per_key[key].append(extreme_over_sketch(sk, partial(rate, float(beta)), largest))
        rules[n] = (betas, w, per_key)
    elapsed = time.perf_counter() - t0
    out = {}
    half = 0.5 * (u1 - u0)
    for key in rates:
        # Rotation rates are bounded and equal 1 on the sticking line (rolling without
        # slip): integrate their deviation from 1 and add beta_final - beta_initial exactly.
        base = 1.0 if key.startswith("rotation") else 0.0
        vals = {}
        for n, (betas, w, per_key) in rules.items():
            dev = np.array([v[0] for v in per_key[key]]) - base
            vals[n] = half * float(w @ dev) + base * (beta_final - beta_initial)
        betas, _, per_key = rules[n_nodes]
        book = None
        if key == "length_max":
            book = gm.encounter_length_max(beta_initial, a, beta_final)
        elif key == "rotation_max":
            book = gm.rotation_max(beta_initial, beta_final)
        out[key] = SketchBound(
            vals[n_nodes], abs(vals[n_nodes] - vals[max(2, n_nodes // 2)]), betas,
            np.array([v[0] for v in per_key[key]]), np.array([v[1] for v in per_key[key]]),
            tuple(v[2] for v in per_key[key]), book, elapsed,
        )
    return out
