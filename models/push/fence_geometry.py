"""Geometry of the gross-motion problems of book 3.4, 4.3 and 4.4 from a world-frame scene.

**Fence alignment** (3.4, figures 3-20 and 3-21; 4.3, figures 4-7 and 4-8). A fence, a
straight edge with direction ``fence_angle``, advances along ``push_direction`` and meets a
polygonal part (a :class:`models.core.footprint.Footprint` turned by ``orientation`` about its
centre of mass, CM). It first touches one vertex; the part turns about it until an
edge at that vertex lies flush with the fence. :func:`fence_alignment` finds everything
the closed forms of :mod:`models.push.gross_motion` and the exact bounds of
:mod:`models.push.gross_bounds` need, in their *fence frame* (CM at the origin, the fence
moving along +x, the fence face along alpha_hat = (cos alpha, sin alpha), alpha in
(0, pi), the contact vertex at c (-cos beta, sin beta)):

* the disk radius a (the footprint's circumradius about the CM, 3.1.8: the bounds are
  those of the circumscribing disk's COR sketch), the contact vertex, c = its distance
  from the CM, the book's alpha (the fence's angle from the push direction) and
  beta_initial (the angle between the line of motion and the line from the contact to
  the CM);
* the edge that ends flush and beta_final = pi - alpha - psi
  (:func:`models.push.gross_motion.fence_final_beta`), psi the angle at the contact vertex from
  the ray towards the CM clockwise to that edge;
* the sense of turning.

Only the convex hull matters: the part rests against a straight fence on its hull, so the
vertex touched first is a hull vertex and the edge that ends flush is a hull edge (across a
concavity it is a *bridge*, not an edge of the polygon; ``flush_is_polygon_edge`` says
which).

*Mirror cases.* The closed forms hold for the book's case: the line of force (normal to
the fence through the contact) passes on the clockwise side of the CM (moment arm
alpha_hat . c = -c cos(alpha + beta) > 0). A part that would turn counter-clockwise is
mapped onto it by the reflection across the line of motion through the CM: y -> -y in the
fence frame, which turns alpha into pi - alpha, beta into -beta, the moment arm into its
negative and counter-clockwise into clockwise, and leaves every length and every angle
turned unchanged. ``mirrored`` reports it; angles (alpha, beta, psi) are then those of
the reflected scene.

*Below the line of motion.* After the reflection the contact usually lies above the line
of motion through the CM (0 < beta < pi, figures 3-20 and 4-7), but with an oblique fence
it can lie at or below it (beta <= 0; alpha + beta in (pi/2, pi] still). The frictionless
bounds depend on the line of force only and hold there (:func:`frictionless_push_bounds`;
models.push.gross_motion's range checks refuse beta <= 0). With contact friction they do not:
at beta = 0 the sticking COR B of (4.7) runs off to infinity, and
:func:`require_friction_frame` refuses such stages.

*Refused* (InvalidInput naming the reason): a fence parallel to the push, and a first
contact whose line of force passes through the CM (the part translates and never turns,
3.3.11.1; an unstable balance: turn it a little).

*Edges already flush.* When an edge of the hull at the first contact is parallel to the
fence (to ``grazing_sin``) the fence touches a whole edge. If the line of force through
the CM (normal to the fence) crosses that edge, the part does not turn: zero push, no
stages.

*Stages.* The book takes for granted that the part stops turning once an edge is flush
(3.4, [42]). That holds for a frictionless fence only if the CM's foot on the flush edge
lies within the edge (the normal line of force through the CM meets the edge): for a
polygon with an obtuse angle next to a short edge it does not, and the part keeps turning
about the far end of the edge until the next hull edge is flush. :func:`fence_alignment`
follows that chain (each link is again the book's problem, with the new contact vertex)
and returns every link as a :class:`FenceStage`; the longest push to the final, stable
edge is the sum of the stages' bounds. An already-flush edge that is not stable starts the
chain at its end nearer the line of force. The stability test is the frictionless one
(force along the fence normal); with contact friction the force may tilt inside the
friction cone, which the book does not treat for an edge contact.

**Disk encounter** (4.4, figure 4-10): :func:`encounter_beta_from_offset` turns the
offset d of the pusher's line from grazing into the collision parameter, (4.24)
a (1 - sin beta) = d.

Pure numpy; angles in radians, world frame as in docs/mechanics.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from models.core.errors import InvalidInput, ModelError
from models.core.footprint import Footprint, convex_hull_indices
from models.core.tolerances import DEFAULT, Tolerances
from models.push import gross_motion as gm

Sense = Literal["cw", "ccw", "none"]


def _rotation(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s], [s, c]])


def _cross(u: ArrayLike, v: ArrayLike) -> np.ndarray:
    u = np.asarray(u, dtype=float)
    v = np.asarray(v, dtype=float)
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def _finite(name: str, value: float) -> float:
    x = float(value)
    if not math.isfinite(x):
        raise InvalidInput(name, "must be a finite number")
    return x


def fence_frame_alpha(fence_angle: float, push_direction: float, tolerances: Tolerances = DEFAULT) -> tuple[float, np.ndarray]:
    """The book's alpha of a fence with direction ``fence_angle`` pushed along
    ``push_direction`` (both world, radians), and the fence's inward normal n (world):
    n is normal to the fence with n . p > 0, alpha_hat = z x n, alpha = the angle from p to
    alpha_hat, in (0, pi), n . p = sin alpha (as models.core.scene.PushScene). A fence parallel
    to the push (|sin alpha| <= grazing_sin) is refused."""
    fa = _finite("fence_angle", fence_angle)
    ph = _finite("push_direction", push_direction)
    p = np.array([math.cos(ph), math.sin(ph)])
    t = np.array([math.cos(fa), math.sin(fa)])
    n = np.array([-t[1], t[0]])
    s = float(n @ p)
    if abs(s) <= tolerances.grazing_sin:
        raise InvalidInput(
            "fence_angle",
            "is parallel to the push direction: the fence would slide along the part and never push it",
        )
    if s < 0.0:
        n = -n
    alpha_hat = np.array([-n[1], n[0]])
    alpha = math.atan2(p[0] * alpha_hat[1] - p[1] * alpha_hat[0], float(p @ alpha_hat))
    return alpha, n


@dataclass(frozen=True)
class FenceStage:
    """One link of the alignment: the part turns about ``contact_index`` (a vertex of the
    footprint, indices of ``Footprint.vertices``) until the hull edge to ``flush_index``
    lies on the fence. Book quantities in the (possibly reflected) fence frame:
    ``contact_distance`` c, ``beta_initial`` -> ``beta_final`` (= pi - alpha - psi;
    beta_initial <= 0 for a contact at or below the line of motion, module docstring),
    ``vertex_edge_angle`` psi; ``rotation`` = beta_final - beta_initial, the angle turned
    (>= 0); ``orientation_initial``/``orientation_final``: the part's world orientation
    (the footprint turned by it about its CM) at the ends of the stage;
    ``contact_fence_frame`` = c (-cos beta_initial, sin beta_initial);
    ``flush_edge_stable``: the frictionless line of force through the CM crosses the
    flush edge, so the part stops there (the last stage)."""

    contact_index: int
    flush_index: int
    flush_is_polygon_edge: bool
    contact_distance: float
    beta_initial: float
    beta_final: float
    vertex_edge_angle: float
    rotation: float
    orientation_initial: float
    orientation_final: float
    contact_fence_frame: np.ndarray
    flush_edge_stable: bool


@dataclass(frozen=True)
class FenceAlignment:
    """The fence-alignment problem of 3.4/4.3 for a footprint (module docstring).

    ``initial_vertices`` are the footprint's vertices turned by the orientation (world, at
    first contact). ``alpha`` is the book's alpha in the fence frame after the reflection (if
    ``mirrored``), ``alpha_unmirrored`` before it; ``sense`` the part's sense of turning in
    the world ("none" when an edge is already flush and stable); ``first_contact_index``
    the vertex the fence touches first and ``first_contact_point`` its world position at
    first contact (for an edge already flush: the end at which the part turns, or, when
    it does not turn, the end nearer the line of force through the CM);
    ``initial_flush_edge`` the footprint indices of an edge already flush at first contact
    (else None); ``stages`` the links of the chain (first = the book's problem; empty
    when nothing turns); ``final_edge`` the edge flush at the end, on which the part
    rests stably against a frictionless fence."""

    disk_radius: float
    center_of_mass: np.ndarray
    initial_vertices: np.ndarray
    alpha: float
    alpha_unmirrored: float
    fence_normal: np.ndarray
    sense: Sense
    mirrored: bool
    first_contact_index: int
    first_contact_point: np.ndarray
    initial_flush_edge: tuple[int, int] | None
    stages: tuple[FenceStage, ...]
    final_edge: tuple[int, int]
    total_rotation: float
    final_orientation: float

    @property
    def already_flush(self) -> bool:
        return self.initial_flush_edge is not None and not self.stages


def _is_polygon_edge(vertices: np.ndarray, i: int, j: int, rel: float) -> bool:
    """True when the hull edge i-j is an edge of the polygon, possibly through collinear
    polygon vertices (every vertex strictly between i and j along one way round lies on the
    segment, to ``rel`` times its length)."""
    n = len(vertices)
    seg = vertices[j] - vertices[i]
    length = float(np.hypot(*seg))
    for step in (1, -1):
        k = (i + step) % n
        ok = True
        while k != j:
            d = vertices[k] - vertices[i]
            t = float(d @ seg) / (length * length)
            if abs(float(_cross(seg, d))) > rel * length * length or not -rel <= t <= 1.0 + rel:
                ok = False
                break
            k = (k + step) % n
        if ok:
            return True
    return False


def _stage_chain(q: np.ndarray, hull: list[int], contact: int, alpha: float, verts: np.ndarray, theta: float,
                 mirrored: bool, arm_tol: float) -> list[FenceStage]:
    """The links of the alignment in the (reflected) fence frame ``q`` from the first
    contact vertex: each turns about its contact until the next hull edge is flush, and the
    chain ends at the first edge the frictionless line of force through the CM crosses
    (module docstring, "Stages")."""
    ah = np.array([math.cos(alpha), math.sin(alpha)])
    stages: list[FenceStage] = []
    orient = theta
    sign = 1.0 if mirrored else -1.0  # world orientation change per unit turn (cw in the frame)
    for _ in range(len(hull)):
        qv = q[contact]
        c = float(np.hypot(*qv))
        beta = math.atan2(qv[1], -qv[0])
        pos = hull.index(contact)
        w = hull[(pos + 1) % len(hull)]  # the clockwise-first edge of a counter-clockwise hull
        e = q[w] - qv
        psi = math.atan2(float(_cross(e, -qv)), float(e @ -qv))
        beta_f = gm.fence_final_beta(alpha, psi)
        turn = max(beta_f - beta, 0.0)
        q_new = q @ _rotation(-turn).T
        stable = float(ah @ q_new[w]) <= arm_tol
        stages.append(FenceStage(
            contact_index=contact, flush_index=w,
            flush_is_polygon_edge=_is_polygon_edge(verts, contact, w, 1e-9),
            contact_distance=c, beta_initial=beta, beta_final=beta_f, vertex_edge_angle=psi,
            rotation=turn, orientation_initial=orient, orientation_final=orient + sign * turn,
            contact_fence_frame=gm.fence_contact(beta, c), flush_edge_stable=stable,
        ))
        orient += sign * turn
        q = q_new
        if stable:
            return stages
        contact = w
    raise ModelError("fence_alignment: no stable edge within one turn of the hull")  # pragma: no cover


def fence_alignment(
    footprint: Footprint,
    orientation: float,
    fence_angle: float,
    push_direction: float,
    tolerances: Tolerances = DEFAULT,
) -> FenceAlignment:
    """The fence-alignment problem of 3.4/4.3 in the book's fence frame (module docstring).

    ``orientation``: the footprint is turned by this angle (radians, counter-clockwise)
    about its CM; ``fence_angle``: the direction of the fence face (theta and theta + pi
    are the same fence); ``push_direction``: the fence's direction of travel (world). The
    fence comes from behind (from -p) and touches the hull vertex farthest back along its
    normal first.
    """
    theta = _finite("orientation", orientation)
    alpha0, n_world = fence_frame_alpha(fence_angle, push_direction, tolerances)
    phi = _finite("push_direction", push_direction)
    cm = np.asarray(footprint.center_of_mass, dtype=float)
    a = float(footprint.circumradius)
    verts = np.asarray(footprint.vertices, dtype=float)
    world = cm + (verts - cm) @ _rotation(theta).T  # the turned footprint, world frame
    q = (verts - cm) @ _rotation(theta - phi).T  # fence frame: CM at 0, push along +x
    alpha = alpha0
    grazing = tolerances.grazing_sin
    arm_tol = tolerances.translation_rel * a

    def frame_normals(al: float) -> tuple[np.ndarray, np.ndarray]:
        return np.array([math.sin(al), -math.cos(al)]), np.array([math.cos(al), math.sin(al)])

    hull = convex_hull_indices(q / a)
    n_f, ah = frame_normals(alpha)
    depth = q[hull] @ n_f
    pos = int(np.argmin(depth))
    k = hull[pos]
    nxt, prv = hull[(pos + 1) % len(hull)], hull[pos - 1]

    def unit(v: np.ndarray) -> np.ndarray:
        return v / float(np.hypot(*v))

    flush_edge = None
    for other in (nxt, prv):
        if float(unit(q[other] - q[k]) @ n_f) <= grazing:
            flush_edge = (k, other)
            break

    mirrored = False
    if flush_edge is not None:
        m_ends = np.array([float(ah @ q[i]) for i in flush_edge])
        if m_ends.min() <= arm_tol and m_ends.max() >= -arm_tol:
            # The line of force through the CM crosses the edge: no turn at all.
            first = flush_edge[int(np.argmin(np.abs(m_ends)))]
            return FenceAlignment(
                disk_radius=a, center_of_mass=cm.copy(), initial_vertices=world, alpha=alpha, alpha_unmirrored=alpha0,
                fence_normal=n_world, sense="none", mirrored=False, first_contact_index=first,
                first_contact_point=world[first].copy(), initial_flush_edge=flush_edge, stages=(),
                final_edge=flush_edge, total_rotation=0.0, final_orientation=theta,
            )
        mirrored = bool(m_ends.max() < 0.0)
        arms = -m_ends if mirrored else m_ends
        contact = flush_edge[int(np.argmin(arms))]  # the end the part turns about
    else:
        m_k = float(ah @ q[k])
        if abs(m_k) <= arm_tol:  # also c = 0: a vertex at the CM
            raise InvalidInput(
                "orientation",
                "the fence's line of force at the first contact passes through the centre of mass: "
                "the part translates without turning (3.3.11.1) and no edge comes flush (an unstable "
                "balance; turn the part a little)",
            )
        mirrored = m_k < 0.0
        contact = k

    if mirrored:  # reflect across the line of motion through the CM: y -> -y
        q = q * np.array([1.0, -1.0])
        alpha = math.pi - alpha
        # the mirror image of the same hull, reversed to stay counter-clockwise (not a new
        # hull: with nearly collinear vertices a recomputed one may drop the contact vertex)
        hull = [hull[0], *hull[:0:-1]]
        n_f, ah = frame_normals(alpha)

    stages = _stage_chain(q, hull, contact, alpha, verts, theta, mirrored, arm_tol)
    rot_total = 0.0
    for st in stages:
        rot_total += st.rotation
    orient = stages[-1].orientation_final
    last = stages[-1]
    return FenceAlignment(
        disk_radius=a, center_of_mass=cm.copy(), initial_vertices=world, alpha=alpha, alpha_unmirrored=alpha0,
        fence_normal=n_world, sense="ccw" if mirrored else "cw", mirrored=mirrored,
        first_contact_index=stages[0].contact_index, first_contact_point=world[stages[0].contact_index].copy(),
        initial_flush_edge=flush_edge, stages=tuple(stages),
        final_edge=(last.contact_index, last.flush_index), total_rotation=rot_total, final_orientation=orient,
    )


def frictionless_push_bounds(a: float, c: float, alpha: float, beta_initial: float, beta_final: float) -> tuple[float, float]:
    """Longest and shortest push of a frictionless fence over one stage: (3.41) (every COR
    at the tip of {COR}_alpha, the slowest) and the r_min push (every COR at r_min (3.31),
    the fastest), both exact for mu_c = 0 (models.push.gross_motion). The same differences of
    the antiderivatives as ``fence_push_frictionless`` and ``fence_push_least_frictionless``,
    but for any contact with a clockwise moment arm (alpha + beta_initial > pi/2), also at
    or below the line of motion (beta <= 0, which those refuse: the frictionless locus
    depends on the line of force only). Returns (longest, shortest)."""
    a, c, alpha = _finite("disk_radius", a), _finite("contact_distance", c), _finite("alpha", alpha)
    bi, bf = _finite("beta_initial", beta_initial), _finite("beta_final", beta_final)
    if not a > 0.0:
        raise InvalidInput("disk_radius", "must be positive")
    if not 0.0 < c <= a * (1.0 + 1e-12):
        raise InvalidInput("contact_distance", "must be positive and at most the disk radius (3.4)")
    if not 0.0 < alpha < math.pi:
        raise InvalidInput("alpha", "must lie strictly between 0 and pi")
    if bf < bi:
        raise InvalidInput("beta_final", "must not be smaller than beta_initial (the part turns clockwise)")
    if not alpha + bi > gm.HALF_PI:
        raise InvalidInput("beta_initial", "alpha + beta must exceed pi/2 (a clockwise moment arm, 3.3.1)")
    if not bf < math.pi - alpha:
        raise InvalidInput("beta_final", "must be below pi - alpha: there the CM would reach the fence line")
    longest = gm.fence_push_frictionless_indefinite
    shortest = gm.fence_push_least_frictionless_indefinite
    return (float(longest(bf, a, c, alpha) - longest(bi, a, c, alpha)),
            float(shortest(bf, a, c, alpha) - shortest(bi, a, c, alpha)))


def require_friction_frame(alignment: FenceAlignment, mu_c: float) -> None:
    """With contact friction the bounds (the closed forms of 4.3 and the exact sketch) need
    every stage's contact above the line of motion through the CM, 0 < beta_initial:
    at beta = 0 the sticking locus reaches to infinity (B of (4.7) runs off), the exact
    bound's integrand is singular, and when the push lies inside the friction cone
    (|pi/2 - alpha| <= atan mu_c) the part can translate with the fence without turning.
    Raises InvalidInput("orientation", ...) otherwise; mu_c = 0 always passes."""
    if not mu_c > 0.0:
        return
    for i, st in enumerate(alignment.stages):
        if not st.beta_initial > 0.0:
            raise InvalidInput(
                "orientation",
                f"with contact friction (mu_c > 0) the contact of stage {i + 1} must lie above the line of "
                f"motion through the centre of mass (0 < beta, book figure 4-7); here beta_initial = "
                f"{st.beta_initial:.6g} rad (the fence is oblique and the part turns towards it): at "
                "beta = 0 the sticking COR B of (4.7) runs off to infinity and a part whose push lies in "
                "the friction cone can translate with the fence. Only mu_c = 0 is answered for this "
                "orientation",
            )


def encounter_beta_from_offset(disk_radius: float, offset: float) -> float:
    """The collision parameter of a pusher whose line passes ``offset`` d inside the
    grazing line of a disk of radius a (4.4, (4.24)): a (1 - sin beta) = d, so
    beta = pi/2 - 2 asin(sqrt(d / 2a)) (the same equation, free of the cancellation in
    1 - d/a for a small offset). 0 < d < a gives 0 < beta < pi/2; d = 0 grazes
    (no encounter), d = a is a head-on push through the CM (an endless one)."""
    a = _finite("disk_radius", disk_radius)
    d = _finite("offset", offset)
    if not a > 0.0:
        raise InvalidInput("disk_radius", "must be positive")
    if not 0.0 < d < a:
        raise InvalidInput(
            "offset",
            "must lie strictly between 0 (the pusher grazes the disk) and disk_radius (a head-on push "
            "through the centre, which never ends)",
        )
    beta = 0.5 * math.pi - 2.0 * math.asin(math.sqrt(0.5 * d / a))
    if not 0.0 < beta < 0.5 * math.pi:
        raise InvalidInput("offset", "is too close to 0 or to disk_radius: beta rounds to 0 or pi/2")
    return beta
