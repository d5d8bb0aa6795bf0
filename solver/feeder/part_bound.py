"""The part's own bound on leaving a fence's end (book 5.1 phase 5 on the part's own COR
loci, 3.3.5, 3.3.13, 7.5): the extreme B of each band from the part's loci instead of its
circumscribing disk's.

Phase 5 (models/feeder/fence.py, endpoint_turn) bounds the slip of the fence's end E along
the part's edge per radian of turn by the largest (r - c) . J g over the frictionless COR
locus of the cone-edge force n_e + mu_c e at the contact c (slip_normal). That force is fixed
in the part's body: its direction is set by the edge and mu_c, its line by the contact's
position l on the edge. So the locus depends on (edge, mu_c, l) alone, and the turn delta
only rotates the linear function. Per edge and mu_c the locus is searched once at
``contacts`` positions l_k from u_X to the edge's upstream end L:

* dipods with both feet on the outline and the CM between them (3.3.5's dipods, which bound
  the disk's locus, on the part's outline): their CORs, one batched forward solve, are
  witnesses (points of the locus). They do not bound a polygon's locus (7.5: "for
  workpieces other than disks, the boundary is not described by dipods"), and rays of the
  exact locus do reach a few per cent beyond them;
* so rays of the exact locus (solver/locus/certified_locus.py: a certified inside point
  and a certified outside point a bracket apart) climb along its boundary from the dipod
  that maximises the slip function at each of ``turns`` turns, in the direction that
  raises it, while it rises (the exact locus's maximiser lies up to a few degrees from the
  dipods'), and their outer ends join the witnesses. A ray that is not certified, or a
  conic solve that fails, hands that contact to the disk.

The slip bound at (l, delta) is the largest value of the slip function over those points
at the two contacts around l, each times (l_k - u_X) / (l - u_X): the slip per radian grows
like 1 / (l - u_X) toward u_X, where the cone edge passes through the CM (the same grading
as the reach's upper sums), and the cell [u_X, l_1] is the disk's. The caller takes the
smaller of this and the disk's bound (7.5: the disk's locus contains the part's).

What is certified and what is not: every point used is a COR of a real pressure
distribution on the part or a certified outside point of the part's exact locus on its
ray, but the largest value between the rays traced, and between contacts, is interpolated.
docs/benchmarks.md measures the result against a finer search and against simulation,
and what it costs (seconds per fence against milliseconds for the disk).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from models.core.footprint import Footprint
from models.core.mpp import perp
from models.core.scene import PushScene
from models.feeder.fence import (
    Fence,
    canonical_crossing,
    canonical_edge,
    canonical_outline,
    rotation,
    slip_normal,
    upward_slip_scene,
)
from solver.core.errors import SolverError, TimeLimitReached
from solver.locus.certified_locus import polygon_trace, trace_ray
from solver.motion.forward import solve_forward_batch


@dataclass(frozen=True)
class PartBoundSettings:
    """How finely the part's own loci are searched.

    Attributes:
        contacts: positions of the contact along each edge (u_X to the edge's upstream end,
            crowded toward u_X as u^2 of an even grid) at which the locus is searched, per
            mu_c (the first, u_X itself, is the disk's: the force through the CM).
        dipods: directions of the dipod sweep (half turn).
        turns: turns delta (evenly over [0, A), A excluded: there the slip normal is
            infinite) whose slip functions aim the rays.
        ray_step_deg: the first step of the climb along the exact locus from each aim.
        refine_levels: times that step is halved around the best ray.
        max_rays_per_aim: most rays of one climb (0: dipods only, a witness bound from
            inside the locus, not a bound).
    """

    contacts: int = 5
    dipods: int = 360
    turns: int = 2
    ray_step_deg: float = 1.0
    refine_levels: int = 0
    max_rays_per_aim: int = 8


PART_DEFAULT = PartBoundSettings()
PART_FINE = PartBoundSettings(contacts=9, dipods=1440, turns=3, ray_step_deg=0.5, refine_levels=1,
                              max_rays_per_aim=16)
PART_DIPODS = PartBoundSettings(contacts=17, max_rays_per_aim=0)
"""Dipods only: fast, but from inside the locus (witnesses), so not a bound."""


@dataclass(frozen=True)
class PartBoundCost:
    """What the part's own bound cost: loci searched, rays traced (bracketed or not),
    dipods solved, the seconds spent, and the traces a failed conic solve cut short."""

    loci: int
    rays: int
    rays_bracketed: int
    dipods: int
    seconds: float
    solver_failures: int = 0  # conic solves that failed inside a trace (the disk bounded there)


def outline_dipods(outline: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Dipods through the CM (the origin) with both feet on the outline: for each of ``n``
    directions v over a half turn, the farthest outline points along v and -v at distances
    s1, s2, weighted s2 : s1 so that their centroid is the CM (3.3.5's dipods, on the
    part's outline instead of the disk's rim). Points (k, 2, 2), weights (k, 2), k <= n
    (lines through the CM that miss the outline on one side are left out)."""
    psi = np.pi * np.arange(n) / n
    v = np.stack([np.cos(psi), np.sin(psi)], axis=1)
    a = outline
    e = np.roll(outline, -1, axis=0) - a

    def reach(dirs: np.ndarray) -> np.ndarray:
        den = dirs[:, None, 0] * e[None, :, 1] - dirs[:, None, 1] * e[None, :, 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (a[None, :, 0] * e[None, :, 1] - a[None, :, 1] * e[None, :, 0]) / den
            lam = (a[None, :, 0] * dirs[:, None, 1] - a[None, :, 1] * dirs[:, None, 0]) / den
        ok = (den != 0.0) & (lam >= 0.0) & (lam <= 1.0) & (t > 0.0)
        return np.max(np.where(ok, t, 0.0), axis=1)
    s1, s2 = reach(v), reach(-v)
    keep = (s1 > 0.0) & (s2 > 0.0)  # a CM outside a non-convex outline misses it along some lines
    v, s1, s2 = v[keep], s1[keep], s2[keep]
    points = np.stack([s1[:, None] * v, -s2[:, None] * v], axis=1)
    weights = np.stack([s2, s1], axis=1) / (s1 + s2)[:, None]
    return points, weights


class PartLoci:
    """The part's own slip bound for one fence, searched lazily per (edge, mu_c) as
    endpoint_turn asks (``rate_for`` is a models.feeder.fence.OwnRate). ``checkpoint``
    (the caller's deadline) is called before each locus is searched. Not shared between
    threads: each map builds its own."""

    def __init__(self, part: Footprint, fence: Fence, settings: PartBoundSettings = PART_DEFAULT,
                 checkpoint: Callable[[str], None] | None = None):
        self.part, self.fence, self.settings, self.checkpoint = part, fence, settings, checkpoint
        self._loci = self._rays = self._bracketed = self._dipods = self._failed = 0
        self._seconds = 0.0

    @property
    def cost(self) -> PartBoundCost:
        return PartBoundCost(self._loci, self._rays, self._bracketed, self._dipods, self._seconds, self._failed)

    def _locus_points(self, footprint: Footprint, dipods: tuple[np.ndarray, np.ndarray], contact: np.ndarray,
                      edge_angle: float, mu: float, normals: list[np.ndarray]) -> np.ndarray | None:
        """Points of the frictionless locus of the cone edge n_e + mu e at ``contact``
        (relative to it) whose largest value of a slip function bounds it: the dipods'
        CORs (witnesses) and the outer ends of certified rays aimed at the dipods that
        maximise each of ``normals``; None where the disk decides (the force through the
        CM, or turning the part CW: no upward slip, endpoint_turn; or a ray not certified)."""
        turned, m_sign = upward_slip_scene(self.part.circumradius, contact, edge_angle, mu)
        if m_sign >= 0:
            return None
        t0 = time.perf_counter()
        try:
            solved = solve_forward_batch(turned, *dipods)
            cors = np.asarray(solved.cor, dtype=float)
            cors = cors[np.all(np.isfinite(cors), axis=1)]
            self._dipods += len(dipods[1])
            if not len(cors):  # no dipod turns the part (never seen): the disk decides
                return None
            points = [cors - contact]
            certified = self._trace_aims(turned, footprint, cors, contact, normals, points)
            self._loci += 1
        finally:  # a deadline met inside still counts the time spent
            self._seconds += time.perf_counter() - t0
        return np.concatenate(points) if certified else None

    def _trace_aims(self, turned: PushScene, footprint: Footprint, cors: np.ndarray, contact: np.ndarray,
                    normals: list[np.ndarray], points: list[np.ndarray]) -> bool:
        """For each slip normal w, climb along the exact locus's boundary from the ray
        through the dipod that maximises w . (r - c): certified rays ``ray_step_deg`` apart
        in the direction that raises w . (outer end - c) while it rises, then halving the
        step ``refine_levels`` times around the best, at most ``max_rays_per_aim`` rays.
        Every outer bracket end traced (relative to the contact) joins ``points``; False when
        a ray was not certified (the disk decides there)."""
        settings = self.settings
        if settings.max_rays_per_aim == 0:
            return True
        try:
            trace = polygon_trace(turned, footprint)
        except TimeLimitReached:
            raise
        except SolverError:
            self._failed += 1
            return False
        traced: dict[float, np.ndarray] = {}
        warm: list[np.ndarray | None] = [None]

        def outer(phi: float) -> np.ndarray | None:
            """The certified outer end of the ray at ``phi`` (relative to the contact)."""
            key = round(phi, 12)
            if key in traced:
                return traced[key]
            if self.checkpoint is not None:  # a ray takes a few tenths of a second
                self.checkpoint("a ray of the part's own locus")
            self._rays += 1
            try:
                ray = trace_ray(trace, np.array([math.cos(phi), math.sin(phi)]), warm[0])
            except TimeLimitReached:
                raise
            except SolverError:  # a conic solve that failed certifies nothing: the disk decides
                self._failed += 1
                return None
            if ray.verdict != "bracketed" or ray.inner is None:
                return None
            self._bracketed += 1
            warm[0] = ray.inner.witness_points if ray.inner.witness_points.size else None
            traced[key] = trace.centre + ray.t_out * trace.length_scale * ray.direction - contact
            return traced[key]

        for w in normals:
            r = cors[int(np.argmax((cors - contact) @ w))] - trace.centre
            phi = math.atan2(float(r[1]), float(r[0]))
            step = math.radians(settings.ray_step_deg)
            spent = len(traced)
            p = outer(phi)
            if p is None:
                return False
            best = float(p @ w)
            for level in range(settings.refine_levels + 1):
                if level:
                    step *= 0.5
                direction = 0.0
                for sign in (1.0, -1.0):  # which way rises from the best so far
                    q = outer(phi + sign * step)
                    if q is None:
                        return False
                    if float(q @ w) > best:
                        best, direction = float(q @ w), sign
                if direction:
                    phi += direction * step
                while direction and len(traced) - spent < settings.max_rays_per_aim:
                    q = outer(phi + direction * step)
                    if q is None:
                        return False
                    if float(q @ w) <= best:
                        break
                    best, phi = float(q @ w), phi + direction * step
        points.extend(q[None] for q in traced.values())
        return True

    def rate_for(self, j: int, mu: float) -> Callable[[float, float], float]:
        part, fence, settings = self.part, self.fence, self.settings
        u_c, h_c, length, ell0 = canonical_edge(part, j, fence, mu)
        if not ell0 < length:  # E is past the edge at once: nothing to search
            return lambda ell, delta: math.inf
        g = abs(fence.angle)
        t0 = np.array([math.cos(g), math.sin(g)])
        outline = canonical_outline(part, j, fence)
        footprint = Footprint.create(outline, (0.0, 0.0))
        dipods = outline_dipods(outline, settings.dipods)

        def normal(delta: float) -> np.ndarray:
            """The slip normal at turn delta, carried back into the unturned frame."""
            return rotation(-delta) @ slip_normal(np.array([math.cos(g + delta), math.sin(g + delta)]))

        most = 0.5 * math.pi - g
        normals = [normal(d) for d in most * np.arange(settings.turns) / settings.turns]
        u = np.linspace(0.0, 1.0, max(3, settings.contacts))
        nodes = ell0 + (length - ell0) * u * u
        points: list[np.ndarray | None] = []
        for i, ell in enumerate(nodes):
            if i == 0 and ell0 > 0.0:  # u_X itself: the cone edge passes through the CM
                points.append(None)
                continue
            if self.checkpoint is not None:
                self.checkpoint(f"the part's own locus on edge {j} at l = {ell:.4g}")
            points.append(self._locus_points(footprint, dipods, (ell - u_c) * t0 - h_c * perp(t0), g, mu, normals))

        u_x = canonical_crossing(part, j, fence, mu)  # unclipped

        def rate(ell: float, delta: float) -> float:
            """The larger of the two nodes around ell of R (l - u_X), over (ell - u_X): R
            grows like 1 / (l - u_X) toward u_X (the cone edge's moment arm), and this
            is exact where R (l - u_X) is monotone on the cell (as the reach's upper sums)."""
            i = int(np.clip(np.searchsorted(nodes, ell, side="right") - 1, 0, len(nodes) - 2))
            w = normal(delta)
            x = ell - u_x
            if not x > 0.0:
                return math.inf
            best = 0.0
            for k in (i, i + 1):
                pts = points[k]
                if pts is None:
                    return math.inf
                best = max(best, float(np.max(pts @ w)) * (nodes[k] - u_x) / x)
            return best

        return rate
