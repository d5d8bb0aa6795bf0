"""The minimum-power engine over HTTP (issue 3): motions for known pressure distributions,
COR membership with certificates, tripod statistics, and the particle example of book 2.5.

Each route is one call: schema -> domain objects -> solver -> schema
(:mod:`service.convert_mpp`). The routes are plain ``def``: FastAPI runs them in its
thread pool, so a long solve does not block the event loop.
"""

from __future__ import annotations

from fastapi import APIRouter

from service.convert_mpp import (
    membership_response,
    particle_response,
    solve_response,
    tripod_statistics_response,
)
from service.schemas import ErrorResponse
from service.schemas_mpp import (
    CorSolveRequest,
    CorSolveResponse,
    MembershipRequest,
    MembershipResponse,
    ParticleRequest,
    ParticleResponse,
    TripodStatisticsRequest,
    TripodStatisticsResponse,
)

router = APIRouter()

ERRORS = {422: {"model": ErrorResponse, "description": "Invalid input: the body names the field and the reason."}}


@router.post(
    "/v1/cor/solve",
    operation_id="cor_solve",
    tags=["cor"],
    summary="Motion of a pushed workpiece for a known pressure distribution",
    response_model=CorSolveResponse,
    responses=ERRORS,
)
def cor_solve(req: CorSolveRequest) -> CorSolveResponse:
    """The motion (COR, rotation and slip per unit push, contact mode, forces) that
    minimises the frictional power (book 3.2-3.3.3; with pusher friction mu_c, 4.1), for
    one support, a batch of supports, or a modelled uniform pressure (figure 7-1)."""
    return solve_response(req)


@router.post(
    "/v1/cor/membership",
    operation_id="cor_membership",
    tags=["cor"],
    summary="Can r be the COR of this push? With a certificate",
    response_model=MembershipResponse,
    responses=ERRORS,
)
def cor_membership(req: MembershipRequest) -> MembershipResponse:
    """Decides whether the point `cor` is the centre of rotation of the push for some
    pressure distribution on the disk (or the polygon `footprint`), frictionless pusher
    (book 3.3.2-3.3.13). 'inside' comes with a witness support (re-verified by the forward
    solver), 'outside' with a dual functional and a branch-and-bound lower bound over the
    whole outline; 'undecided' when the time limit or the iteration caps are reached, or
    the point is within the tolerances of the locus boundary."""
    return membership_response(req)


@router.post(
    "/v1/cor/tripod-statistics",
    operation_id="cor_tripod_statistics",
    tags=["cor"],
    summary="CORs of random tripod supports (figures 3-5, 7-2)",
    response_model=TripodStatisticsResponse,
    responses=ERRORS,
)
def cor_tripod_statistics(req: TripodStatisticsRequest) -> TripodStatisticsResponse:
    """Random balanced tripods (3.3.3) on the disk or a polygon, seeded: their CORs
    (figure 3-5) and optionally where the sticking CORs fall along the sticking line for a
    large mu_c (figure 7-2). Statistics of a model of pressure distributions, not of the
    locus (7.7)."""
    return tripod_statistics_response(req)


@router.post(
    "/v1/mpp/particle",
    operation_id="mpp_particle",
    tags=["mpp"],
    summary="Newton vs minimum power for the particle of book 2.5",
    response_model=ParticleResponse,
    responses=ERRORS,
)
def mpp_particle(req: ParticleRequest) -> ParticleResponse:
    """The steady speed v_y along the external force by Newton's law (2.29) and by the
    minimum power principle (2.30)-(2.32, closed form and IPOPT): equal only for Coulomb
    friction (n = 0)."""
    return particle_response(req)
