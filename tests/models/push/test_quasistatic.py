"""Characteristic speeds for quasi-static motion (book 6.8), each checked by an independent
computation: a numerical integration of the sliding rigid body (mass elements, Coulomb
friction on each under uniform pressure, midpoint time steps until rest), grid and Monte
Carlo quadrature of the part's mean distance and radius of gyration, closed forms, and the
book's own numbers (6.8.1-6.8.3)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.errors import InvalidInput
from models.core.footprint import Footprint
from models.core.inertia import polygon_radius_of_gyration
from models.push import quasistatic as qs
from tests.scenes import SEED, point_in_polygon, polygon_grid

CM_G = 981.0  # the book's g in cm/s^2
L_SHAPE = np.array([[0, 0], [3, 0], [3, 1], [1, 1], [1, 2.5], [0, 2.5]], dtype=float)
U_SHAPE = np.array([[0, 0], [3, 0], [3, 2], [2.6, 2], [2.6, 0.4], [0.4, 0.4], [0.4, 2], [0, 2]], dtype=float)
RECTANGLE = np.array([[-1.0, -0.5], [1.0, -0.5], [1.0, 0.5], [-1.0, 0.5]])


# --- the independent computation: a sliding rigid body coasting to rest ------------------


def disk_elements(a: float, rings: int = 60, sectors: int = 120):
    """Midpoint polar cells of a uniform disk: positions and masses (summing to 1)."""
    dr = a / rings
    r = (np.arange(rings) + 0.5) * dr
    phi = (np.arange(sectors) + 0.5) * 2.0 * math.pi / sectors
    rr, pp = np.meshgrid(r, phi)
    mass = (rr * dr).ravel()
    pts = np.column_stack([(rr * np.cos(pp)).ravel(), (rr * np.sin(pp)).ravel()])
    return pts, mass / mass.sum()


def polygon_elements(vertices: np.ndarray, cells: int = 240):
    """Midpoint cells of a square grid inside the polygon, relative to their centroid."""
    pts = polygon_grid(vertices, cells)
    return pts - pts.mean(axis=0), np.full(len(pts), 1.0 / len(pts))


def coast(pts, mass, v0, omega0, mu, g, steps=2000, free=True):
    """Integrate M dv/dt = sum f_i, I domega/dt = sum r_i x f_i with f_i = -mu g m_i u_i/|u_i|
    (u_i the element's velocity) from (v0, omega0) until rest, by midpoint steps. A velocity
    that would reverse within a step stops there (Coulomb friction cannot reverse a motion);
    velocities below 1e-12 of the initial ones (rounding residues, which Coulomb friction
    would otherwise amplify to full strength) are zero. With ``free`` False the CM is held
    (pure spin about it, the model of 6.8.1). Returns the path of the CM, the angle turned
    and the times at which the slide and the spin ended."""
    inertia = float(mass @ np.sum(pts**2, axis=1))
    root_i = math.sqrt(inertia)
    v = np.array(v0, dtype=float)
    w = float(omega0)
    speed0 = float(np.linalg.norm(v)) + abs(w) * root_i
    tiny = 1e-12 * speed0
    dt = speed0 / (mu * g) / steps
    phi = path = turned = t = 0.0
    ended = {"slide": 0.0, "spin": 0.0}

    def accel(v, w, phi):
        c, s = math.cos(phi), math.sin(phi)
        r = pts @ np.array([[c, s], [-s, c]])
        u = v[None, :] + w * np.column_stack([-r[:, 1], r[:, 0]])
        n = np.linalg.norm(u, axis=1)
        f = -mu * g * mass[:, None] * u / np.where(n > 0.0, n, np.inf)[:, None]
        force = f.sum(axis=0) if free else np.zeros(2)
        return force, float(np.sum(r[:, 0] * f[:, 1] - r[:, 1] * f[:, 0])) / inertia

    for _ in range(20 * steps):
        if float(np.linalg.norm(v)) <= tiny and abs(w) * root_i <= tiny:
            return path, turned, ended["slide"], ended["spin"]
        a1, al1 = accel(v, w, phi)
        vm, wm = v + 0.5 * dt * a1, w + 0.5 * dt * al1
        if float(vm @ v) <= 0.0 < float(v @ v) or wm * w < 0.0:
            a2, al2 = a1, al1  # the motion stops within the half step: no midpoint beyond it
        else:
            a2, al2 = accel(vm, wm, phi + 0.5 * dt * w)
        vn, wn = v + dt * a2, w + dt * al2
        stop_v = float(v @ v) / float(v @ (v - vn)) if float(vn @ v) <= 0.0 < float(v @ v) else math.inf
        stop_w = w / (w - wn) if wn * w <= 0.0 and w != 0.0 else math.inf
        frac = min(stop_v, stop_w, 1.0)
        h = frac * dt  # the acceleration a2, al2 held over the (partial) step
        vp, wp = v + h * a2, w + h * al2
        path += 0.5 * (float(np.linalg.norm(v)) + float(np.linalg.norm(vp))) * h
        turned += 0.5 * (w + wp) * h
        phi += 0.5 * (w + wp) * h
        t += h
        if np.any(v):
            ended["slide"] = t
        if w != 0.0:
            ended["spin"] = t
        v = np.zeros(2) if stop_v <= frac or float(np.linalg.norm(vp)) <= tiny else vp
        w = 0.0 if stop_w <= frac or abs(wp) * root_i <= tiny else wp
    raise AssertionError("did not come to rest")


# --- the book's numbers ------------------------------------------------------------------


def test_book_numbers_of_6_8():
    """6.8.1: a = 3.5 cm, mu_s = .25, theta = 5 deg -> "v = 14 cm/sec"; 6.8.2: X = .5 cm ->
    "v = 16 cm/sec"; 6.8.3: "v = 40 cm/sec" (roughly; it is 41.4)."""
    g = qs.gravity("cm")
    assert g == pytest.approx(CM_G, rel=1e-15)
    disk = qs.ShapeMoments.disk(3.5)
    v_theta = qs.angular_error_speed(0.25, g, disk, math.radians(5.0))
    v_x = qs.translational_error_speed(0.25, g, 0.5)
    v_qs = qs.quasi_static_speed(0.25, g, 3.5)
    assert round(v_theta) == 14 and v_theta == pytest.approx(14.1334, abs=1e-4)
    assert round(v_x) == 16 and v_x == pytest.approx(15.6605, abs=1e-4)
    assert round(v_qs, -1) == 40 and v_qs == pytest.approx(41.4337, abs=1e-4)
    # The same through assess(), whose default permissible errors are the book's examples.
    res = qs.assess(0.0, 0.25, g, disk)
    assert res.angular.characteristic_speed == v_theta and res.angular.permissible_error == math.radians(5.0)
    assert res.translational.permissible_error == pytest.approx(0.5, rel=1e-15)
    assert res.translational.characteristic_speed == pytest.approx(v_x, rel=1e-15)
    assert res.quasi_static.characteristic_speed == v_qs
    assert (res.angular.equation, res.translational.equation, res.quasi_static.equation) == ("(6.3)", "(6.6)", "(6.7)")


def test_disk_closed_forms_are_the_printed_equations():
    """(6.3) v^2 = 8/3 mu a g theta, (6.6) v^2 = 2 g mu X, (6.7) v^2 = 2 mu a g."""
    disk = qs.ShapeMoments.disk(2.0)
    assert disk.radius_of_gyration == pytest.approx(2.0 / math.sqrt(2.0), rel=1e-15)
    assert disk.mean_distance == pytest.approx(4.0 / 3.0, rel=1e-15)
    assert disk.spin_factor == pytest.approx(8.0 / 3.0, rel=1e-15)
    for mu, g, theta, x in [(0.25, 9.81, 0.1, 0.3), (1.3, 32.2, 2.0, 7.0), (1e-3, 1e4, 1e-4, 1e-6)]:
        assert qs.angular_error_speed(mu, g, disk, theta) ** 2 == pytest.approx(8 / 3 * mu * 2.0 * g * theta, rel=1e-14)
        assert qs.translational_error_speed(mu, g, x) ** 2 == pytest.approx(2 * g * mu * x, rel=1e-14)
        assert qs.quasi_static_speed(mu, g, 2.0) ** 2 == pytest.approx(2 * mu * 2.0 * g, rel=1e-14)
        v = 0.7
        assert qs.angular_error_at(v, mu, g, disk) == pytest.approx(3 * v * v / (8 * mu * g * 2.0), rel=1e-14)
        assert qs.translational_error_at(v, mu, g) == pytest.approx(v * v / (2 * mu * g), rel=1e-14)


# --- against the integrated dynamics -------------------------------------------------------


def test_a_sliding_disk_stops_after_the_distance_of_6_6():
    pts, m = disk_elements(3.5)
    mu, g = 0.25, CM_G
    x = 0.5
    v = qs.translational_error_speed(mu, g, x)  # 6.8.2: from this speed it slides X
    path, turned, t, _ = coast(pts, m, (v * 0.6, v * 0.8), 0.0, mu, g, steps=200)
    assert path == pytest.approx(x, rel=1e-12)
    assert abs(turned) < 1e-12
    assert t == pytest.approx(v / (mu * g), rel=1e-12)
    assert qs.translational_error_at(v, mu, g) == pytest.approx(path, rel=1e-9)


def test_a_spinning_disk_turns_by_the_angle_of_6_3():
    """omega = v/a after the interaction, friction torque of uniform pressure: the disk turns
    theta(v) = 3 v^2 / (8 mu a g); at v of (6.3) for 5 degrees it turns 5 degrees. The
    midpoint polar grid gives the torque to ~1e-4 relative."""
    a, mu, g = 3.5, 0.25, CM_G
    pts, m = disk_elements(a)
    disk = qs.ShapeMoments.disk(a)
    v = qs.angular_error_speed(mu, g, disk, math.radians(5.0))
    path, turned, _, _ = coast(pts, m, (0.0, 0.0), v / a, mu, g, steps=200)
    assert path < 1e-12 * a  # a symmetric spin does not move the CM
    assert turned == pytest.approx(math.radians(5.0), rel=2e-4)
    assert qs.angular_error_at(v, mu, g, disk) == pytest.approx(turned, rel=2e-4)


@pytest.mark.slow
@pytest.mark.parametrize("shape", ["rectangle", "l_shape", "u_shape"])
def test_a_spinning_polygon_turns_by_the_generalised_6_3(shape):
    """theta(v) = v^2 rho^2 / (2 mu g rbar a^2) against the integrated spin of the grid body.
    The rectangle is free (central symmetry: its spin exerts no net force); the L and the U
    are spun about their CM (the book's model, 6.8.1), their own spin would move the CM."""
    vertices = {"rectangle": RECTANGLE, "l_shape": L_SHAPE, "u_shape": U_SHAPE}[shape]
    fp = Footprint.create(vertices)
    part = qs.ShapeMoments.polygon(fp)
    pts, m = polygon_elements(fp.vertices - fp.center_of_mass)
    mu, g, v = 0.4, 9.81, 1.3
    path, turned, _, _ = coast(pts, m, (0.0, 0.0), v / part.radius, mu, g, steps=200, free=shape == "rectangle")
    assert path < 1e-12
    assert turned == pytest.approx(qs.angular_error_at(v, mu, g, part), rel=2e-3)


def test_slide_and_spin_together_coast_farther_than_either_estimate():
    """A finding: 6.8 treats the spin and the slide separately. Together, friction is shared
    between them (its force and torque are each smaller than alone), so the disk coasts
    farther and turns more than (6.6) and (6.3) say. Provably at least as far (|force| <=
    mu M g, |torque| <= mu M g rbar); for omega = v/a, measured 1.27 times the slide and
    1.93 times the turn, and slide and spin end together (as Farkas, Bartels, Unger and
    Wolf, PRL 90, 248302 (2003), found for the disk)."""
    a, mu, g, v = 1.0, 0.5, 9.81, 1.0
    pts, m = disk_elements(a, rings=30, sectors=64)
    disk = qs.ShapeMoments.disk(a)
    path, turned, t_slide, t_spin = coast(pts, m, (v, 0.0), v / a, mu, g, steps=400)
    assert t_slide == pytest.approx(t_spin, rel=1e-2)
    slide_ratio = path / qs.translational_error_at(v, mu, g)
    turn_ratio = turned / qs.angular_error_at(v, mu, g, disk)
    assert slide_ratio > 1.0 and turn_ratio > 1.0
    assert slide_ratio == pytest.approx(1.27, abs=0.02)
    assert turn_ratio == pytest.approx(1.93, abs=0.03)


# --- the part's geometry by quadrature -----------------------------------------------------


def test_part_geometry_of_polygons_against_monte_carlo():
    rng = np.random.default_rng(SEED)
    for vertices in (L_SHAPE, U_SHAPE, RECTANGLE):
        fp = Footprint.create(vertices)
        part = qs.ShapeMoments.polygon(fp)
        assert part.kind == "polygon" and part.radius == fp.circumradius
        assert part.radius_of_gyration == pytest.approx(polygon_radius_of_gyration(fp), rel=1e-13)
        lo, hi = fp.vertices.min(axis=0), fp.vertices.max(axis=0)
        pts = rng.uniform(lo, hi, size=(400_000, 2))
        d = np.linalg.norm(pts[point_in_polygon(pts, fp.vertices)] - fp.center_of_mass, axis=1)
        se = d.std(ddof=1) / math.sqrt(d.size)
        assert abs(part.mean_distance - d.mean()) < 5.0 * se
        # rho^2 <= a rbar (|x - CM| <= a): the angular speed at 1 rad is never below (6.7)
        assert part.radius_of_gyration**2 <= part.radius * part.mean_distance
        assert part.spin_factor >= 2.0


def test_quasi_static_parameter_is_the_smaller_of_6_3_and_6_6():
    """(6.7) is (6.6) at X = a exactly; (6.3) at 1 rad is larger, by 4/3 in v^2 for the disk
    and by rbar a / rho^2 >= 1 for any footprint (the module docstring's inequality)."""
    mu, g = 0.3, 9.81
    disk = qs.ShapeMoments.disk(1.7)
    v_qs = qs.quasi_static_speed(mu, g, 1.7)
    assert v_qs == pytest.approx(qs.translational_error_speed(mu, g, 1.7), rel=1e-15)
    assert qs.angular_error_speed(mu, g, disk, 1.0) ** 2 == pytest.approx(4.0 / 3.0 * v_qs**2, rel=1e-14)
    rng = np.random.default_rng(SEED)
    for _ in range(50):
        n = int(rng.integers(3, 12))
        th = 2.0 * math.pi * (np.arange(n) + rng.uniform(0.0, 0.4, n)) / n
        r = rng.uniform(0.2, 1.0, n)
        part = qs.ShapeMoments.polygon(Footprint.create(np.column_stack([r * np.cos(th), r * np.sin(th)])))
        assert qs.angular_error_speed(mu, g, part, qs.QUASI_STATIC_ANGLE) >= qs.quasi_static_speed(mu, g, part.radius)


def test_polygon_is_invariant_under_rigid_motions_and_orientation():
    base = qs.ShapeMoments.polygon(Footprint.create(L_SHAPE))
    c, s = math.cos(0.7), math.sin(0.7)
    moved = L_SHAPE @ np.array([[c, s], [-s, c]]) + np.array([1e3, -2e3])
    for vertices in (moved, L_SHAPE[::-1]):
        other = qs.ShapeMoments.polygon(Footprint.create(vertices))
        assert other.radius == pytest.approx(base.radius, rel=1e-12)
        assert other.radius_of_gyration == pytest.approx(base.radius_of_gyration, rel=1e-12)
        assert other.mean_distance == pytest.approx(base.mean_distance, rel=1e-12)


# --- dimensions, scale, units --------------------------------------------------------------


@pytest.mark.parametrize("k", [1e-60, 1e-3, 7.0, 1e60])
def test_lengths_times_k_speeds_times_sqrt_k(k):
    """Speeds scale as sqrt(length) (g fixed): lengths x k and the push speed x sqrt(k) leave
    every ratio and the verdict unchanged; errors scale as theta x 1, X x k."""
    mu, g, v = 0.3, 9.81, 0.8
    for part, scaled in (
        (qs.ShapeMoments.disk(0.05), qs.ShapeMoments.disk(0.05 * k)),
        (qs.ShapeMoments.polygon(Footprint.create(L_SHAPE)), qs.ShapeMoments.polygon(Footprint.create(L_SHAPE * k))),
    ):
        base = qs.assess(v, mu, g, part, translational_error=0.01)
        big = qs.assess(v * math.sqrt(k), mu, g, scaled, translational_error=0.01 * k)
        for name in ("angular", "translational", "quasi_static"):
            b, s = getattr(base, name), getattr(big, name)
            assert s.characteristic_speed == pytest.approx(b.characteristic_speed * math.sqrt(k), rel=1e-12)
            assert s.ratio == pytest.approx(b.ratio, rel=1e-12)
        assert big.angular.error_at_speed == pytest.approx(base.angular.error_at_speed, rel=1e-12)
        assert big.translational.error_at_speed == pytest.approx(base.translational.error_at_speed * k, rel=1e-12)
        assert big.verdict == base.verdict


def test_units_metres_against_centimetres():
    """The same push in m and in cm: speeds x 100, the same ratios and verdict."""
    in_m = qs.assess(0.1, 0.25, qs.gravity("m"), qs.ShapeMoments.disk(0.035), translational_error=0.005)
    in_cm = qs.assess(10.0, 0.25, qs.gravity("cm"), qs.ShapeMoments.disk(3.5), translational_error=0.5)
    for name in ("angular", "translational", "quasi_static"):
        assert getattr(in_cm, name).characteristic_speed == pytest.approx(100 * getattr(in_m, name).characteristic_speed, rel=1e-14)
        assert getattr(in_cm, name).ratio == pytest.approx(getattr(in_m, name).ratio, rel=1e-14)
    assert in_cm.verdict == in_m.verdict
    assert qs.gravity("in") == pytest.approx(386.22, rel=1e-4)  # 9.81 m/s^2 in inches
    assert qs.gravity("mm") == pytest.approx(9810.0, rel=1e-14)


# --- ratios and verdict --------------------------------------------------------------------


def test_error_at_speed_over_permissible_is_the_ratio_squared():
    part = qs.ShapeMoments.polygon(Footprint.create(U_SHAPE))
    for v in (0.0, 0.01, 0.3, 5.0):
        res = qs.assess(v, 0.6, 9.81, part, angular_error=0.2, translational_error=0.1)
        for cs in (res.angular, res.translational):
            assert cs.error_at_speed == pytest.approx(cs.permissible_error * cs.ratio**2, rel=1e-14, abs=0.0)
            assert cs.within_tolerance == (cs.error_at_speed <= cs.permissible_error * (1 + 1e-15))
        assert res.quasi_static.ratio == pytest.approx(v / math.sqrt(2 * 0.6 * part.radius * 9.81), rel=1e-14)


def test_verdict_thresholds_and_their_meaning():
    t = qs.DEFAULT_THRESHOLDS
    assert (t.quasi_static_max_ratio, t.inertial_min_ratio) == (0.3, 1.0)
    mu, g, a = 0.25, 9.81, 0.035
    disk = qs.ShapeMoments.disk(a)
    v_qs = qs.quasi_static_speed(mu, g, a)
    for ratio, verdict in ((0.0, "quasi_static"), (0.299, "quasi_static"), (0.31, "transitional"),
                           (0.999, "transitional"), (1.0, "inertial"), (7.0, "inertial")):
        assert qs.assess(ratio * v_qs, mu, g, disk).verdict == verdict, ratio
    # At the threshold the part coasts 9 % of a and turns (3/4) 0.09 rad (disk), <= 0.09 for any part.
    at = qs.assess(0.3 * v_qs, mu, g, disk, translational_error=a)
    assert at.translational.error_at_speed == pytest.approx(0.09 * a, rel=1e-12)
    assert at.angular.error_at_speed == pytest.approx(0.75 * 0.09, rel=1e-12)
    poly = qs.ShapeMoments.polygon(Footprint.create(L_SHAPE))
    v = 0.3 * qs.quasi_static_speed(mu, g, poly.radius)
    assert qs.angular_error_at(v, mu, g, poly) <= 0.09
    strict = qs.QuasiStaticThresholds(quasi_static_max_ratio=0.1, inertial_min_ratio=0.5)
    assert qs.assess(0.2 * v_qs, mu, g, disk, thresholds=strict).verdict == "transitional"


# --- bad inputs ----------------------------------------------------------------------------


@pytest.mark.parametrize(
    "kwargs, field",
    [
        (dict(speed=-1.0), "speed"),
        (dict(speed=math.nan), "speed"),
        (dict(speed="fast"), "speed"),
        (dict(mu_s=0.0), "mu_s"),
        (dict(mu_s=-0.2), "mu_s"),
        (dict(mu_s=math.inf), "mu_s"),
        (dict(g=0.0), "g"),
        (dict(g=-9.81), "g"),
        (dict(g=None), "g"),
        (dict(angular_error=0.0), "angular_error"),
        (dict(angular_error=math.nan), "angular_error"),
        (dict(translational_error=-0.1), "translational_error"),
        (dict(translational_error=True), "translational_error"),
    ],
)
def test_bad_inputs_name_their_field(kwargs, field):
    args = dict(speed=0.1, mu_s=0.3, g=9.81, part=qs.ShapeMoments.disk(1.0))
    args.update(kwargs)
    with pytest.raises(InvalidInput) as exc:
        qs.assess(**args)
    assert exc.value.field == field


def test_bad_geometry_units_and_thresholds():
    for bad in (0.0, -1.0, math.inf, math.nan):
        with pytest.raises(InvalidInput) as exc:
            qs.ShapeMoments.disk(bad)
        assert exc.value.field == "disk_radius"
    with pytest.raises(InvalidInput) as exc:
        qs.gravity("furlong")
    assert exc.value.field == "length_unit"
    for lo, hi in ((0.0, 1.0), (0.5, 0.4), (math.nan, 1.0)):
        with pytest.raises(InvalidInput):
            qs.QuasiStaticThresholds(lo, hi)
