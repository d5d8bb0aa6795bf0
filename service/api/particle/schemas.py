"""Request and response schemas of ``POST /v1/mpp/particle``: the particle of book 2.5,
Newton's law against the minimum power principle.

Conventions are those of :mod:`service.common.fields`: strict finite numbers, unknown
fields rejected.
"""

from __future__ import annotations

from typing import Annotated

from pydantic import ConfigDict, Field

from service.common.fields import Strict
from service.common.responses import ELAPSED_MS_DESCRIPTION, Out
from service.limits import (
    PARTICLE_MAX_EXPONENT,
    PARTICLE_MAX_MAGNITUDE,
    PARTICLE_MIN_MAGNITUDE,
)

ParticleMagnitude = Annotated[
    float,
    Field(strict=True, allow_inf_nan=False, ge=PARTICLE_MIN_MAGNITUDE, le=PARTICLE_MAX_MAGNITUDE),
]


class ParticleRequest(Strict):
    """The particle of book 2.5 (figure 2-2): driven along +x at `v_x` by a frictionless
    fence, pulled by a constant force `mg`, braked by a force eta |v|^n against its velocity."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={"examples": [{"v_x": 1.0, "mg": 1.0, "eta": 2.0, "n": 1.0}]},
    )

    v_x: ParticleMagnitude = Field(description="Fence speed along +x (length / time).")
    mg: ParticleMagnitude = Field(description="Magnitude of the constant external force (weight).")
    eta: ParticleMagnitude = Field(description="Coefficient of the dissipative force eta |v|^n; for n = 0 it must exceed mg.")
    n: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0.0, le=PARTICLE_MAX_EXPONENT)] = Field(
        description=f"Exponent of the dissipative force, 0..{PARTICLE_MAX_EXPONENT:g}: 0 Coulomb, 1 viscous."
    )


class ParticleResponse(Out):
    """Newton's law vs the minimum power principle for the particle of book 2.5.

    v_y is the steady speed along the external force (the world velocity is (v_x, -v_y)
    with the force along -y)."""

    newton_v_y: float = Field(description="v_y by Newton's law (2.27)-(2.29).")
    mpp_v_y: float = Field(description="Minimiser of the power (2.30) from its stationarity (2.31)-(2.32), closed form / bracketed root.")
    mpp_v_y_numeric: float = Field(description="The same minimiser found by CasADi/IPOPT.")
    relative_disagreement: float = Field(description="(newton - mpp) / newton: 0 for n = 0, 1/2 for n = 1.")
    agree: bool = Field(description="Whether |relative_disagreement| <= 1e-9 (only n = 0).")
    numeric_error: float = Field(description="|numeric - closed form| / closed form.")
    kkt_residual: float = Field(description="|dP/dv_y| / mg at the numeric minimiser (2.31).")
    newton_residual: float = Field(description="Newton's force balance (2.27) at newton_v_y, relative to mg.")
    power_newton: float = Field(description="Power (2.30) at Newton's answer.")
    power_mpp: float = Field(description="Power (2.30) at the minimum-power answer (never larger).")
    status: str = Field(description="IPOPT's return status.")
    iterations: int = Field(
        description="IPOPT iterations of the numeric minimiser of the power (2.30)."
    )
    message: str = Field(
        description="Human-readable summary: whether Newton's law and the minimum power principle agree, and by how "
        "much they differ when n > 0."
    )
    solve_time_ms: float = Field(
        description="Time CasADi/IPOPT took to build and minimise the power (2.30), milliseconds."
    )
    elapsed_ms: float = Field(description=ELAPSED_MS_DESCRIPTION)
