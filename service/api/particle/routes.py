"""``POST /v1/mpp/particle``: Newton's law against the minimum power principle for the
particle of book 2.5. Request -> problem -> :func:`solver.motion.particle.particle` ->
response."""

from __future__ import annotations

from fastapi import APIRouter

from service.api.particle.convert import (
    particle_errors,
    particle_problem,
    particle_response,
)
from service.api.particle.schemas import ParticleRequest, ParticleResponse
from service.common.responses import INVALID_INPUT
from solver import Budget, particle

router = APIRouter(tags=["mpp"])


@router.post(
    "/v1/mpp/particle",
    operation_id="mpp_particle",
    summary="Newton vs minimum power for the particle of book 2.5",
    response_model=ParticleResponse,
    responses=INVALID_INPUT,
)
def mpp_particle(req: ParticleRequest) -> ParticleResponse:
    """The steady speed v_y along the external force by Newton's law (2.29) and by the
    minimum power principle (2.30)-(2.32, closed form and IPOPT): equal only for Coulomb
    friction (n = 0)."""
    budget = Budget.of(None)
    problem = particle_problem(req)
    with particle_errors():
        sol = particle(problem, budget)
    return particle_response(sol, budget.elapsed() * 1e3)
