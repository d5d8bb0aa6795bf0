"""Characteristic speeds for quasi-static motion (book 6.8; its use in 7.4).

Every planning result of the project assumes the quasi-static limit (2.1.1): friction
between the workpiece and the table dominates inertia, the v -> 0 limit of 7.4. Section
6.8 estimates the speed at which that stops being true by an energy balance: when the
pusher lets go (or stops), the kinetic energy the part carries is spent against sliding
friction, and the part coasts. The coasting is the error of the quasi-static prediction.

Notation: M mass, mu_s the part-table friction coefficient, g gravity, v the relative
speed of pusher and part, a the part's radius (a disk's radius; for a polygon the largest
distance from the centre of mass (CM) to a vertex, the circumscribing disk of 3.1.8),
rho its polar radius of gyration about the CM (models/core/inertia.py), and
rbar = (1/A) integral |x - CM| dA its mean distance from the CM. Uniform density and
uniform pressure (the book's assumption in (6.2)), so the CM is the area centroid.

Re-derivations (each checked in tests/models/push/test_quasistatic.py against a numerical
integration of the sliding rigid body, and against the book's own numbers):

6.8.1, angular error, (6.1)-(6.3). After the interaction the part spins at omega = v/a
(the contact's relative speed v becomes the rim speed). Its rotational energy (6.1) is
E_rot = 1/2 I omega^2 = 1/2 M rho^2 v^2 / a^2. Spinning about its CM under uniform
pressure, an element dA at distance r feels friction mu_s g (M/A) dA at arm r, so the
friction torque is mu_s M g rbar and the energy lost in a turn theta is
E_fric = mu_s M g rbar theta. Equating,

    v_theta^2 = 2 mu_s g rbar theta a^2 / rho^2.

For the book's uniform disk, rho^2 = a^2/2 and rbar = 2a/3: E_rot = M v^2 / 4,
E_fric = (2/3) mu_s theta a M g, which is (6.2), and v_theta^2 = (8/3) mu_s a g theta,
which is (6.3). Conversely, the part coasting from speed v turns by
theta(v) = v^2 rho^2 / (2 mu_s g rbar a^2) (= 3 v^2 / (8 mu_s a g) for the disk).
Book numbers: a = 3.5 cm, mu_s = 0.25, theta = 5 deg, g = 981 cm/s^2 give 14.1 cm/s
("v = 14 cm/sec").

6.8.2, translational error, (6.4)-(6.6). E_trans = 1/2 M v^2 (6.4) against
E_fric = M g mu_s X (6.5) over a slide of length X:

    v_X^2 = 2 g mu_s X                                                    (6.6)

and the part coasting from v slides X(v) = v^2 / (2 mu_s g), whatever its shape.
Book: X = 0.5 cm gives 15.7 cm/s ("v = 16 cm/sec").

6.8.3, the quasi-static parameter, (6.7). With theta = 1 rad and X = a (errors as large as
the motion of a whole interaction), (6.6) gives v^2 = 2 mu_s a g exactly and (6.3)
gives (8/3) mu_s a g; the book takes "roughly"

    v_qs^2 = 2 mu_s a g,                                                  (6.7)

the smaller of the two, so the conservative one. That holds for every footprint, not only
the disk: v_theta(1)^2 / v_X(a)^2 = rbar a / rho^2 >= 1, because |x - CM| <= a on the part
gives rho^2 = mean |x - CM|^2 <= a mean |x - CM| = a rbar. So v_qs = min(v_theta(1),
v_X(a)). Book: 41.4 cm/s ("v = 40 cm/sec"; (6.3) at 1 rad would give 47.9).

No OCR error was found in (6.1)-(6.7): each printed equation and number follows from the
derivation above. (In 7.4 the OCR renders the speed v as "nu".)

The ratio v / v_qs is the quasi-static parameter of a push: the coasting after release is
X(v) = (v / v_qs)^2 a and theta(v) = (v / v_qs)^2 rho^2 / (rbar a) <= (v / v_qs)^2 rad
(3/4 of that for the disk). Errors grow with the square of the speed, so a ratio of 0.3
already means coasting of at most 9 % of the part's radius and 0.09 rad (about the book's
5-degree example). :class:`QuasiStaticThresholds` names the verdict's boundaries.

These are order-of-magnitude estimates, as the book says ("only an approximate upper
bound"): they treat spin and slide separately. Sliding friction couples them: a part that
both spins and slides shares its friction between the two and coasts farther in each
(a disk released with omega = v/a slides 1.27 times X(v) and turns 1.93 times theta(v),
measured in tests/models/push/test_quasistatic.py), so near a characteristic speed the
permissible error can be exceeded.

Units: any consistent length unit L and seconds. g must be given in L/s^2;
:func:`gravity` converts the standard 9.81 m/s^2 to a named length unit.

Pure numpy.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.core.inertia import polygon_mean_distance, polygon_second_moments

GRAVITY_M_S2 = 9.81
"""Gravitational acceleration in m/s^2 used when the client names a length unit instead
of giving g (standard gravity is 9.80665; the 0.03 % difference is far below the accuracy
of these estimates)."""

METRES_PER_UNIT: dict[str, float] = {
    "m": 1.0,
    "cm": 1e-2,
    "mm": 1e-3,
    "um": 1e-6,
    "in": 0.0254,
    "ft": 0.3048,
}
"""Length units accepted by :func:`gravity`, in metres."""

BOOK_ANGULAR_ERROR = math.radians(5.0)
"""The book's example permissible angular error, 5 degrees (6.8.1)."""

BOOK_TRANSLATIONAL_ERROR_REL = 0.5 / 3.5
"""The book's example permissible displacement relative to the part's radius:
X = 0.5 cm for the a = 3.5 cm part of 6.8.1-6.8.2."""

QUASI_STATIC_ANGLE = 1.0
"""theta of the quasi-static parameter (6.8.3): one radian, "the whole rotation"."""

Verdict = Literal["quasi_static", "transitional", "inertial"]


@dataclass(frozen=True)
class QuasiStaticThresholds:
    """Boundaries of the verdict on r = v / v_qs, the quasi-static parameter (6.7).

    Attributes:
        quasi_static_max_ratio: r at or below which the push is called quasi-static. After
            release the part coasts X = r^2 a and turns theta <= r^2 rad (module
            docstring), so 0.3 bounds them by 9 % of the part's radius and 0.09 rad
            (5.2 degrees, the book's example angular error of 6.8.1).
        inertial_min_ratio: r at or above which inertia matters as much as friction or
            more ("kinetic effects and quasi-static effects have similar magnitude" at
            r = 1, 6.8.3); the quasi-static results then do not apply and the impact limit
            (7.4, (7.1)) is the better model as r grows. In between: "transitional".
    """

    quasi_static_max_ratio: float = 0.3
    inertial_min_ratio: float = 1.0

    def __post_init__(self) -> None:
        lo, hi = self.quasi_static_max_ratio, self.inertial_min_ratio
        if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 < lo <= hi):
            raise InvalidInput("thresholds", "need 0 < quasi_static_max_ratio <= inertial_min_ratio, finite")

    def verdict(self, ratio: float) -> Verdict:
        if ratio <= self.quasi_static_max_ratio:
            return "quasi_static"
        if ratio < self.inertial_min_ratio:
            return "transitional"
        return "inertial"


DEFAULT_THRESHOLDS = QuasiStaticThresholds()


# ---------------------------------------------------------------------------------------
# Validation
# ---------------------------------------------------------------------------------------


def _number(name: str, value: float) -> float:
    if isinstance(value, bool):
        raise InvalidInput(name, "must be a number")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InvalidInput(name, "must be a number") from None
    if not math.isfinite(x):
        raise InvalidInput(name, "must be a finite number")
    return x


def _positive(name: str, value: float, what: str = "number") -> float:
    x = _number(name, value)
    if not x > 0.0:
        raise InvalidInput(name, f"must be a positive finite {what}")
    return x


def _non_negative(name: str, value: float, what: str = "number") -> float:
    x = _number(name, value)
    if x < 0.0:
        raise InvalidInput(name, f"must be a non-negative finite {what}")
    return x


def gravity(length_unit: str) -> float:
    """g = 9.81 m/s^2 in ``length_unit`` per s^2 (``m``, ``cm``, ``mm``, ``um``, ``in``, ``ft``)."""
    try:
        metres = METRES_PER_UNIT[length_unit]
    except (KeyError, TypeError):
        raise InvalidInput("length_unit", f"must be one of {', '.join(METRES_PER_UNIT)}") from None
    return GRAVITY_M_S2 / metres


def _sqrt_product(*factors: float) -> float:
    """sqrt of a product of positive factors, factor by factor (no under/overflow of the
    product for inputs between 1e-300 and 1e300)."""
    out = 1.0
    for f in factors:
        out *= math.sqrt(f)
    return out


# ---------------------------------------------------------------------------------------
# Part geometry
# ---------------------------------------------------------------------------------------


@dataclass(frozen=True)
class ShapeMoments:
    """What the characteristic speeds need of the part's shape, derived from a disk's radius
    or from a :class:`Footprint` (not a second polygon type): lengths in the client's unit.

    Attributes:
        kind: "disk" or "polygon".
        radius: a, the disk's radius or the polygon's circumradius about the CM (3.1.8).
        radius_of_gyration: rho, polar, about the CM, uniform density (models/core/inertia.py).
        mean_distance: rbar = mean |x - CM| over the part: the friction torque of a spin
            about the CM under uniform pressure is mu_s M g rbar.
    """

    kind: Literal["disk", "polygon"]
    radius: float
    radius_of_gyration: float
    mean_distance: float

    @classmethod
    def disk(cls, radius: float) -> "ShapeMoments":
        """The book's uniform disk: rho = a / sqrt 2, rbar = 2a/3."""
        a = _positive("disk_radius", radius, "length")
        return cls(kind="disk", radius=a, radius_of_gyration=a * math.sqrt(0.5), mean_distance=a * (2.0 / 3.0))

    @classmethod
    def polygon(cls, footprint: Footprint) -> "ShapeMoments":
        """A uniform lamina with the footprint's shape, about the footprint's CM."""
        a = float(footprint.circumradius)
        cm = footprint.center_of_mass
        unit_vertices = (footprint.vertices - cm) / a  # work in units of a: any size
        area, polar = polygon_second_moments(unit_vertices, (0.0, 0.0))
        rho = a * math.sqrt(polar / area)
        rbar = a * polygon_mean_distance(unit_vertices, (0.0, 0.0))
        return cls(kind="polygon", radius=a, radius_of_gyration=rho, mean_distance=rbar)

    @property
    def spin_factor(self) -> float:
        """2 rbar a^2 / rho^2 / a = 2 rbar a / rho^2 (dimensionless, >= 2): v_theta^2 =
        spin_factor mu_s g a theta. 8/3 for the disk, which is (6.3)."""
        return 2.0 * (self.mean_distance / self.radius) / (self.radius_of_gyration / self.radius) ** 2


# ---------------------------------------------------------------------------------------
# Characteristic speeds (6.3), (6.6), (6.7) and the errors at a given speed
# ---------------------------------------------------------------------------------------


def angular_error_speed(mu_s: float, g: float, part: ShapeMoments, theta: float) -> float:
    """v_theta = sqrt(2 mu_s g rbar theta) a / rho: the speed whose spin, left to coast
    after the interaction, turns the part by ``theta`` radians (6.8.1; (6.3) for the disk)."""
    mu = _positive("mu_s", mu_s)
    gg = _positive("g", g)
    th = _positive("angular_error", theta, "angle (radians)")
    return _sqrt_product(part.spin_factor, mu, gg, part.radius, th)


def translational_error_speed(mu_s: float, g: float, distance: float) -> float:
    """v_X = sqrt(2 g mu_s X): the speed from which the part slides ``distance`` before
    friction stops it (6.8.2, (6.6))."""
    mu = _positive("mu_s", mu_s)
    gg = _positive("g", g)
    x = _positive("translational_error", distance, "length")
    return _sqrt_product(2.0, mu, gg, x)


def quasi_static_speed(mu_s: float, g: float, radius: float) -> float:
    """v_qs = sqrt(2 mu_s a g), the quasi-static parameter's speed (6.8.3, (6.7)):
    the smaller of (6.3) at 1 rad and (6.6) at X = a (module docstring)."""
    mu = _positive("mu_s", mu_s)
    gg = _positive("g", g)
    a = _positive("disk_radius", radius, "length")
    return _sqrt_product(2.0, mu, gg, a)


def angular_error_at(speed: float, mu_s: float, g: float, part: ShapeMoments) -> float:
    """theta(v) = v^2 / (spin_factor mu_s g a): the coasting turn from speed v (radians)."""
    v = _non_negative("speed", speed, "speed")
    ratio = v / angular_error_speed(mu_s, g, part, 1.0)
    return ratio * ratio


def translational_error_at(speed: float, mu_s: float, g: float) -> float:
    """X(v) = v^2 / (2 mu_s g): the coasting slide from speed v (length)."""
    v = _non_negative("speed", speed, "speed")
    root = v / _sqrt_product(2.0, _positive("mu_s", mu_s), _positive("g", g))
    return root * root


@dataclass(frozen=True)
class CharacteristicSpeed:
    """One characteristic speed and how the given speed compares with it.

    ``permissible_error`` is theta (rad), X (length) or, for the quasi-static parameter,
    None; ``error_at_speed`` is the coasting error at the given speed in the same unit
    (None for the parameter); ``ratio`` = speed / characteristic_speed, and
    error_at_speed / permissible_error = ratio^2."""

    characteristic_speed: float
    ratio: float
    permissible_error: float | None
    error_at_speed: float | None
    equation: str
    section: str
    formula: str

    @property
    def within_tolerance(self) -> bool:
        return self.ratio <= 1.0


@dataclass(frozen=True)
class QuasiStaticAssessment:
    speed: float
    mu_s: float
    g: float
    part: ShapeMoments
    angular: CharacteristicSpeed
    translational: CharacteristicSpeed
    quasi_static: CharacteristicSpeed
    verdict: Verdict
    thresholds: QuasiStaticThresholds


def assess(
    speed: float,
    mu_s: float,
    g: float,
    part: ShapeMoments,
    angular_error: float = BOOK_ANGULAR_ERROR,
    translational_error: float | None = None,
    thresholds: QuasiStaticThresholds = DEFAULT_THRESHOLDS,
) -> QuasiStaticAssessment:
    """All three characteristic speeds of 6.8 for a push at ``speed`` (length/s) and the
    verdict on the quasi-static parameter speed / v_qs. ``translational_error`` defaults
    to the book's example ratio X = a/7 (0.5 cm for a = 3.5 cm)."""
    v = _non_negative("speed", speed, "speed")
    mu = _positive("mu_s", mu_s)
    gg = _positive("g", g)
    theta = _positive("angular_error", angular_error, "angle (radians)")
    x = part.radius * BOOK_TRANSLATIONAL_ERROR_REL if translational_error is None else _positive(
        "translational_error", translational_error, "length"
    )

    v_theta = angular_error_speed(mu, gg, part, theta)
    v_x = translational_error_speed(mu, gg, x)
    v_qs = quasi_static_speed(mu, gg, part.radius)
    r_theta, r_x, r_qs = v / v_theta, v / v_x, v / v_qs
    disk = part.kind == "disk"
    angular = CharacteristicSpeed(
        characteristic_speed=v_theta,
        ratio=r_theta,
        permissible_error=theta,
        error_at_speed=angular_error_at(v, mu, gg, part),
        equation="(6.3)" if disk else "(6.3), generalised",
        section="6.8.1",
        formula=(
            "v^2 = (8/3) mu_s a g theta" if disk
            else "v^2 = 2 mu_s g rbar theta a^2 / rho^2 (the disk's rbar = 2a/3, rho^2 = a^2/2 give (6.3))"
        ),
    )
    translational = CharacteristicSpeed(
        characteristic_speed=v_x,
        ratio=r_x,
        permissible_error=x,
        error_at_speed=translational_error_at(v, mu, gg),
        equation="(6.6)",
        section="6.8.2",
        formula="v^2 = 2 g mu_s X",
    )
    quasi = CharacteristicSpeed(
        characteristic_speed=v_qs,
        ratio=r_qs,
        permissible_error=None,
        error_at_speed=None,
        equation="(6.7)",
        section="6.8.3",
        formula="v^2 = 2 mu_s a g",
    )
    return QuasiStaticAssessment(
        speed=v,
        mu_s=mu,
        g=gg,
        part=part,
        angular=angular,
        translational=translational,
        quasi_static=quasi,
        verdict=thresholds.verdict(r_qs),
        thresholds=thresholds,
    )
