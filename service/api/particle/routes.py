"""``POST /v1/mpp/particle``: Newton's law against the minimum power principle for the
particle of book 2.5. Request -> problem -> :func:`solver.particle.solve.mpp_particle` ->
response."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import Response

from service.api.particle.convert import (
    particle_errors,
    particle_problem,
    particle_response,
)
from service.api.particle.schemas import ParticleRequest, ParticleResponse
from service.common.bodies import BodyRoute
from service.common.responses import IN_WORKER
from service.runtime.deadline import Deadline
from service.runtime.jobs import runner
from solver import mpp_particle

router = APIRouter(tags=["mpp"], route_class=BodyRoute)


@router.post(
    "/v1/mpp/particle",
    operation_id="mpp_particle",
    summary="Newton vs minimum power for the particle of book 2.5",
    response_model=ParticleResponse,
    responses=IN_WORKER,
)
async def mpp_particle_route(req: ParticleRequest, request: Request) -> Response:
    """The steady speed v_y along the external force by Newton's law (2.29) and by the
    minimum power principle (2.30)-(2.32, closed form and IPOPT): equal only for Coulomb
    friction (n = 0)."""
    return await runner(request).expensive_job(request, particle_job, req)


def particle_job(req: ParticleRequest, deadline: Deadline) -> ParticleResponse:
    budget = deadline.budget()
    problem = particle_problem(req)
    with particle_errors():
        sol = mpp_particle(problem, budget)
    return particle_response(sol, budget.elapsed() * 1e3)
