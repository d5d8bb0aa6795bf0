"""Schema <-> domain conversion of ``POST /v1/push/quasistatic`` (no mechanics here).

The request becomes a :class:`models.quasistatic.PartGeometry` (disk or polygon footprint)
and a g (given, or 9.81 m/s^2 in the named length unit); :func:`models.quasistatic.assess`
computes; the answer goes back as plain finite floats. Domain ``InvalidInput`` errors
name the request's own fields (speed, mu_s, g, disk_radius, angular_error,
translational_error); the polygon's are located at ``footprint``.
"""

from __future__ import annotations

import time

from models import quasistatic as qs
from service.convert import _f, _v
from service.convert_mpp import exactly_one, footprint_of
from service.schemas_push import (
    ErrorSpeedOut,
    PartOut,
    PushQuasistaticRequest,
    PushQuasistaticResponse,
    QuasiStaticParameterOut,
    ThresholdsOut,
)

REFERENCE = (
    "M. A. Peshkin, Robotic Manipulation Strategies (1990), section 6.8 (characteristic speed "
    "for quasi-static motion), equations (6.1)-(6.7); section 7.4 (non-quasi-static speeds)"
)


def _error_speed(cs: qs.CharacteristicSpeed, name: str) -> ErrorSpeedOut:
    return ErrorSpeedOut(
        characteristic_speed=_f(cs.characteristic_speed, f"{name}.characteristic_speed"),
        ratio=_f(cs.ratio, f"{name}.ratio"),
        permissible_error=_f(cs.permissible_error, f"{name}.permissible_error"),
        error_at_speed=_f(cs.error_at_speed, f"{name}.error_at_speed"),
        within_tolerance=cs.within_tolerance,
        equation=cs.equation,
        section=cs.section,
        formula=cs.formula,
    )


def _message(res: qs.QuasiStaticAssessment, unit: str | None) -> str:
    r = res.quasi_static.ratio
    t = res.thresholds
    coast = (
        f"after release the part slides about {res.translational.error_at_speed:.3g}{' ' + unit if unit else ''} "
        f"or turns about {res.angular.error_at_speed:.3g} rad"
    )
    if res.verdict == "quasi_static":
        return (
            f"quasi-static: speed / v_qs = {r:.3g} <= {t.quasi_static_max_ratio:g} (6.7); {coast}, "
            "so friction dominates inertia and the quasi-static results (chapters 3-4) apply"
        )
    if res.verdict == "transitional":
        return (
            f"transitional: speed / v_qs = {r:.3g} is between {t.quasi_static_max_ratio:g} and "
            f"{t.inertial_min_ratio:g}; {coast}: inertia is no longer negligible, treat the "
            "quasi-static predictions as approximate"
        )
    return (
        f"inertial: speed / v_qs = {r:.3g} >= {t.inertial_min_ratio:g}: inertia is as large as "
        f"friction or larger (6.8.3); {coast}. The quasi-static COR loci do not apply; as the "
        "ratio grows the impact limit (7.4, (7.1); `impact` of /v1/cor/solve) is the better model"
    )


def quasistatic_response(req: PushQuasistaticRequest) -> PushQuasistaticResponse:
    t_start = time.perf_counter()
    shape = exactly_one(req, ("disk_radius", "footprint"))
    g_source = exactly_one(req, ("g", "length_unit"))
    g = req.g if g_source == "g" else qs.gravity(req.length_unit)
    if shape == "disk_radius":
        part = qs.PartGeometry.disk(req.disk_radius)
        cm = None
    else:
        fp = footprint_of(req.footprint, None, ("footprint",))
        part = qs.PartGeometry.polygon(fp)
        cm = _v(fp.center_of_mass, "part.center_of_mass")
    res = qs.assess(
        req.speed, req.mu_s, g, part,
        angular_error=req.angular_error,
        translational_error=req.translational_error,
    )
    spin_factor = part.spin_factor
    return PushQuasistaticResponse(
        verdict=res.verdict,
        message=_message(res, req.length_unit),
        speed=_f(res.speed, "speed"),
        mu_s=_f(res.mu_s, "mu_s"),
        g=_f(res.g, "g"),
        g_source=g_source,
        length_unit=req.length_unit,
        part=PartOut(
            kind=part.kind,
            radius=_f(part.radius, "part.radius"),
            radius_of_gyration=_f(part.radius_of_gyration, "part.radius_of_gyration"),
            mean_distance=_f(part.mean_distance, "part.mean_distance"),
            spin_factor=_f(spin_factor, "part.spin_factor"),
            center_of_mass=cm,
        ),
        angular=_error_speed(res.angular, "angular"),
        translational=_error_speed(res.translational, "translational"),
        quasi_static=QuasiStaticParameterOut(
            characteristic_speed=_f(res.quasi_static.characteristic_speed, "quasi_static.characteristic_speed"),
            ratio=_f(res.quasi_static.ratio, "quasi_static.ratio"),
            equation=res.quasi_static.equation,
            section=res.quasi_static.section,
            formula=res.quasi_static.formula,
        ),
        thresholds=ThresholdsOut(
            quasi_static_max_ratio=res.thresholds.quasi_static_max_ratio,
            inertial_min_ratio=res.thresholds.inertial_min_ratio,
        ),
        reference=REFERENCE,
        elapsed_ms=(time.perf_counter() - t_start) * 1e3,
    )
