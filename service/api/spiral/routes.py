"""Spiral localization of a disk over HTTP (book 4.5): the critical radius r*(beta) of
figure 4-19 and the fastest guaranteed spiral (4.26) planned on OR-Tools.

Each route: request -> problem (:mod:`service.api.spiral.convert`) -> one solver call
(:func:`solver.spiral.critical_radius.critical_radii`, :func:`solver.spiral.plan.plan_spiral`)
-> response or picture (:mod:`service.api.spiral.render`), in a solver worker
(:mod:`service.runtime.jobs`; a first table for a new mu_c takes seconds).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from fastapi import APIRouter, Query, Request
from fastapi.responses import Response

from service.api.spiral.convert import (
    critical_radius_problem,
    critical_radius_response,
    schedule_problem,
    schedule_response,
    table_partial,
)
from service.api.spiral.render import (
    CriticalCurve,
    render_critical_radius_svg,
    render_schedule_svg,
)
from service.api.spiral.schemas import (
    SpiralCriticalRadiusRequest,
    SpiralCriticalRadiusResponse,
    SpiralScheduleRequest,
    SpiralScheduleResponse,
)
from service.common.bodies import BodyRoute
from service.common.fields import ResponseFormat
from service.common.inputs import located
from service.common.responses import IN_WORKER, SVG_MEDIA_TYPE, json_or_svg
from service.errors import nothing_computed, time_limited
from service.runtime.deadline import Deadline
from service.runtime.deferred import Deferrable, json_answer
from service.runtime.jobs import runner
from service.store import result_store
from solver import critical_radii, plan_spiral

router = APIRouter(tags=["spiral"], route_class=BodyRoute)

FORMAT = Query("json", alias="format", description="`json` (default) or `svg` for a picture.")
TABLE_TIME_LIMIT_HINT = "the rows finished are kept: a retry starts from them"


@router.post(
    "/v1/spiral/critical-radius",
    operation_id="spiral_critical_radius",
    summary="Critical radius r*(beta) of spiral localization, its inverse and b_inf (book 4.5.3-4.5.4)",
    response_model=SpiralCriticalRadiusResponse,
    responses={**json_or_svg("JSON (default) or, with `format=svg`, an SVG picture."), **IN_WORKER},
)
async def spiral_critical_radius(
    req: SpiralCriticalRadiusRequest, request: Request, response_format: ResponseFormat = FORMAT,
) -> Response:
    """The tightest pusher circle r*(beta) that still pushes a disk met at collision
    parameter beta into the circle (4.5.2-4.5.3: the distance from the pusher's line to the
    lower end of the sticking locus), by the certified sticking locus, the book's sweep or
    its tip line; the inverse beta*(r) and the critical distance from grazing d*(r) (4.24);
    the limiting radius b_inf against (4.25). SVG: figure 4-19 (a / r* against beta / pi)."""
    return await runner(request).expensive_job(
        request, critical_radius_job, req, response_format == "svg", time_limit_s=req.time_limit_s)


def critical_radius_job(
    req: SpiralCriticalRadiusRequest, svg: bool, deadline: Deadline,
) -> SpiralCriticalRadiusResponse | Response:
    budget = deadline.budget()
    problem = replace(critical_radius_problem(req), store=result_store())
    with located():
        res = critical_radii(problem, budget)
    if res.table.time_limited and not np.any(np.isfinite(res.table.radii)):
        raise nothing_computed("the first collision parameter of the r* table", budget.limit_s, budget.elapsed())
    body = critical_radius_response(req, res, budget.elapsed() * 1e3)
    if svg:
        tab = res.table
        ok = np.isfinite(tab.radii)  # points not decided are left out of the picture
        betas = tab.betas[ok]
        curve = CriticalCurve(
            label=f"mu_c = {req.mu_c:g} ({req.method})", mu_c=req.mu_c, betas=betas, radii=tab.radii[ok],
            a=req.disk_radius, tip_line=None if req.method == "tip_line" else 2.0 * req.disk_radius / np.sin(betas),
            b_inf=body.b_inf.closed_form, certified=tab.certified[ok],
        )
        svg = render_critical_radius_svg([curve], f"Critical radius of spiral localization (4.5.3), a = {req.disk_radius:g}")
        return Response(content=svg, media_type=SVG_MEDIA_TYPE)
    return body


@router.post(
    "/v1/spiral/schedule",
    operation_id="spiral_schedule",
    summary="The fastest guaranteed spiral to localise a disk, certified on OR-Tools (book 4.5.5)",
    response_model=SpiralScheduleResponse,
    responses={**json_or_svg("JSON (default) or, with `format=svg`, an SVG picture."), **IN_WORKER},
)
async def spiral_schedule(
    req: SpiralScheduleRequest, request: Request, response_format: ResponseFormat = FORMAT,
) -> Response:
    """The radii b_1 ... b_N of a pusher spiralling in from `start_radius` to `target`,
    every revolution safe by (4.26) (the disk is pushed into the spiral, never out), with
    the fewest revolutions or the shortest path under optional robot limits, solved as a
    shortest path on OR-Tools and certified optimal; the book's recursion and its tip-line
    version beside it; the path as a polyline; the approach to b_inf (figure 4-21); and,
    on request, disks with random pressure distributions pushed along it. SVG: the path and
    figure 4-21."""
    return await runner(request).expensive_job(
        request, schedule_job, req, response_format == "svg", time_limit_s=req.time_limit_s)


def schedule_job(req: SpiralScheduleRequest, svg: bool, deadline: Deadline) -> SpiralScheduleResponse | Response:
    budget = deadline.budget()
    problem = replace(schedule_problem(req), store=result_store())
    with time_limited(table_partial, TABLE_TIME_LIMIT_HINT), located():
        plan = plan_spiral(problem, budget)
    body = schedule_response(req, plan, budget.elapsed() * 1e3)
    if svg:
        fit = plan.fit
        points = None if body.path is None else body.path.points
        svg = render_schedule_svg(
            radii=plan.radii, a=req.disk_radius, b_inf=body.b_inf, b_floor=body.b_floor,
            path_points=None if points is None else np.asarray(points), centre=np.asarray(req.center, dtype=float),
            target=req.target, fit=None if fit is None else (fit.exponent, fit.coefficient, fit.n_min, fit.n_max),
            title=f"Spiral localization (4.5.5), mu_c = {req.mu_c:g}, a = {req.disk_radius:g}",
            tip_line_radii=plan.tip_line.radii,
        )
        return Response(content=svg, media_type=SVG_MEDIA_TYPE)
    return body


DEFERRABLE = {
    "spiral_critical_radius": Deferrable("POST /v1/spiral/critical-radius", SpiralCriticalRadiusRequest,
                                         critical_radius_job, json_answer),
    "spiral_schedule": Deferrable("POST /v1/spiral/schedule", SpiralScheduleRequest, schedule_job, json_answer),
}
"""The operations ``POST /v1/jobs`` runs later (service.runtime.deferred)."""
