"""Schema <-> problem <-> schema of ``POST /v1/mpp/particle`` (no mechanics here)."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

from service.api.particle.schemas import ParticleRequest, ParticleResponse
from service.common.inputs import located
from service.errors import NonFiniteResult
from service.limits import AGREEMENT_REL
from solver import ParticleProblem, ParticleSolution


def particle_problem(req: ParticleRequest) -> ParticleProblem:
    return ParticleProblem(req.v_x, req.mg, req.eta, req.n)


@contextmanager
def particle_errors() -> Iterator[None]:
    """Input errors at their fields; a float overflow at the edge of the admitted ranges
    is a result out of range (422 numeric_range), not a bug."""
    try:
        with located():
            yield
    except (OverflowError, ZeroDivisionError, FloatingPointError) as exc:
        raise NonFiniteResult(f"the particle answer ({type(exc).__name__})") from exc


def particle_response(sol: ParticleSolution, elapsed_ms: float) -> ParticleResponse:
    agree = abs(sol.relative_disagreement) <= AGREEMENT_REL
    if agree:
        message = (
            "Newton's law and the minimum power principle agree"
            + (" (n = 0, Coulomb friction: book 2.5.2)" if sol.scene.n == 0.0 else "")
        )
    else:
        message = (
            f"the minimum power principle gives v_y = {sol.mpp_v_y:.6g}, Newton's law {sol.newton_v_y:.6g}: "
            f"they differ by {100.0 * sol.relative_disagreement:.4g} % because the dissipative force is "
            f"not Coulomb friction (n = {sol.scene.n:g} > 0); the principle holds only for n = 0 (book 2.5)"
        )
    return ParticleResponse(
        newton_v_y=sol.newton_v_y,
        mpp_v_y=sol.mpp_v_y,
        mpp_v_y_numeric=sol.mpp_v_y_numeric,
        relative_disagreement=sol.relative_disagreement,
        agree=agree,
        numeric_error=sol.numeric_error,
        kkt_residual=sol.kkt_residual,
        newton_residual=sol.newton_residual,
        power_newton=sol.power_newton,
        power_mpp=sol.power_mpp,
        status=sol.status,
        iterations=int(sol.iterations),
        message=message,
        solve_time_ms=sol.solve_time_s * 1e3,
        elapsed_ms=elapsed_ms,
    )
