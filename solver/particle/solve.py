"""The book 2.5 particle, minimum power principle solved numerically with CasADi + IPOPT.

The power (2.30) ``P(v_y) = -mg v_y + eta (v_x^2 + v_y^2)^((n+1)/2)`` is minimised over
``v_y`` (2.31) as a one-variable NLP. With ``v_y = v_x t`` and the objective divided by
``eta v_x^(n+1)`` it reads

    min_t  -K t + (1 + t^2)^((n+1)/2),     K = mg / (eta v_x^n),

which is convex for every n >= 0 and bounded below for n = 0 exactly when K < 1, i.e.
eta > mg (models.particle.balance). IPOPT works on ``tau = t / s`` with an a-priori scale s
(:func:`_scales`). The numeric minimiser is compared with the closed-form /
bracketed root of the stationarity condition (2.32) and with Newton's answer (2.29);
sign conventions are those of :mod:`models.particle.balance` (v_y measured along the external
force). IPOPT only, never CasADi's HiGHS plugin (shared-library clash, see
tests/test_highs_hazard.py).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import casadi as ca

from models.core.errors import InvalidInput
from models.particle import balance as mp
from solver.core.backends import in_backend
from solver.core.budget import UNLIMITED, Budget
from solver.core.errors import NotConverged, SolverError
from solver.core.threads import CasadiFunction, PerThreadCache
from solver.core.tolerances import SOLVER_DEFAULT, SolverTolerances


@dataclass(frozen=True)
class ParticleSolution:
    """Newton vs minimum power for one particle scene (book 2.5).

    ``newton_v_y``: (2.29). ``mpp_v_y``: root of (2.32). ``mpp_v_y_numeric``: IPOPT's
    minimiser of (2.30). ``relative_disagreement``: (newton - mpp) / newton, which is 0 for
    n = 0 and 1/2 for n = 1. ``numeric_error``: |numeric - mpp| / mpp. ``power_newton`` and
    ``power_mpp`` are (2.30) at the two answers (the minimum power principle prefers the
    wrong one whenever n > 0). ``status`` is IPOPT's return status. ``kkt_residual``:
    |dP/dv_y| / mg at the numeric minimiser (2.31); ``newton_residual``: Newton's force
    balance (2.27) at ``newton_v_y``, relative to mg.
    """

    scene: mp.ParticleScene
    newton_v_y: float
    mpp_v_y: float
    mpp_v_y_numeric: float
    relative_disagreement: float
    numeric_error: float
    power_newton: float
    power_mpp: float
    status: str
    iterations: int
    solve_time_s: float
    kkt_residual: float
    newton_residual: float

    @property
    def complete(self) -> bool:
        """Always True: a solution is returned only when IPOPT succeeded
        (:func:`minimise_power` raises NotConverged otherwise)."""
        return True

    @property
    def message(self) -> str:
        return (f"IPOPT {self.status} in {self.iterations} iterations: v_y = {self.mpp_v_y_numeric:.6g} "
                f"(closed form {self.mpp_v_y:.6g}, Newton {self.newton_v_y:.6g})")


def ipopt_options(tol: SolverTolerances) -> dict:
    return {
        "ipopt.tol": tol.casadi_tol,
        "ipopt.print_level": 0,
        "ipopt.sb": "yes",
        "print_time": 0,
    }


def _scales(scene: mp.ParticleScene) -> tuple[float, float]:
    """K = mg / (eta v_x^n) and an a-priori scale s of t = v_y / v_x.

    s is the crude estimate h^-1(K) with h(t) = t (t <= 1), t^n (t >= 1), within a factor
    2^(|n-1|/(2n)) of the answer for n > 0, and K / sqrt(1 - K) for n = 0 (within a
    factor sqrt(2) of it). The NLP in tau = t / s with the objective divided by K s has
    O(1) variable and gradient even when K spans many decades."""
    log_k = math.log(scene.mg) - math.log(scene.eta) - scene.n * math.log(scene.v_x)
    k = math.exp(log_k)
    if scene.n == 0.0:
        slack = -math.expm1(log_k)  # 1 - K without cancellation
        if not slack > 0.0:
            raise InvalidInput("eta", "is indistinguishable from mg in floating point: for n = 0 eta must exceed mg (2.5)")
        return k, k / math.sqrt(slack)
    return k, math.exp(log_k if log_k <= 0.0 else log_k / scene.n)


def _particle_nlp(options: dict) -> ca.Function:
    """(2.30) in tau, divided by K s, with the parameters (K, s, n): one nlpsol for every
    scene (called with the CasADi lock held: solver.core.threads.CasadiFunction)."""
    tau, par = ca.SX.sym("tau"), ca.SX.sym("p", 3)
    k, scale, n = par[0], par[1], par[2]
    t = scale * tau
    objective = (-k * t + (1.0 + t * t) ** (0.5 * (n + 1.0))) / (k * scale)
    return ca.nlpsol("particle_mpp", "ipopt", {"x": tau, "p": par, "f": objective}, options)


_PARTICLE_NLPS: PerThreadCache[tuple, CasadiFunction] = PerThreadCache(4)
"""Each thread's particle NLP, by its IPOPT options."""


def minimise_power(scene: mp.ParticleScene, tol: SolverTolerances = SOLVER_DEFAULT) -> tuple[float, str, int, float]:
    """IPOPT's minimiser v_y of (2.30) for a validated scene: (v_y, status, iterations,
    seconds). Raises SolverError when CasADi cannot build the problem, NotConverged when
    IPOPT fails or does not succeed."""
    k, scale = _scales(scene)
    t0 = time.perf_counter()
    try:
        options = ipopt_options(tol)
        nlp = _PARTICLE_NLPS.get(tuple(sorted(options.items())), lambda: CasadiFunction(lambda: _particle_nlp(options)))
    except RuntimeError as exc:
        raise SolverError(f"CasADi could not build the particle power (2.30): {exc}") from exc
    try:
        with in_backend("casadi"):
            out = nlp(x0=1.0, p=[k, scale, scene.n])  # tau = 1: the a-priori scale, not the answer
        stats = nlp.stats()
    except RuntimeError as exc:
        raise NotConverged(f"IPOPT failed on the particle power (2.30): {exc}") from exc
    elapsed = time.perf_counter() - t0
    status = str(stats.get("return_status", "unknown"))
    if not stats.get("success", False):
        raise NotConverged(f"IPOPT ended with status {status} on the particle power (2.30)")
    return scene.v_x * scale * float(out["x"]), status, int(stats.get("iter_count", -1)), elapsed


def solve_particle(
    v_x: float,
    mg: float,
    eta: float,
    n: float,
    tol: SolverTolerances = SOLVER_DEFAULT,
) -> ParticleSolution:
    """Newton (2.29), the minimum power principle in closed form (2.32) and numerically
    (2.30)-(2.31) for the particle of figure 2-2. Invalid inputs raise InvalidInput
    (models.particle.balance.ParticleScene.create)."""
    scene = mp.ParticleScene.create(v_x, mg, eta, n)
    newton = mp.newton_v_y(scene.v_x, scene.mg, scene.eta, scene.n)
    mpp = mp.mpp_v_y(scene.v_x, scene.mg, scene.eta, scene.n)
    numeric, status, iterations, elapsed = minimise_power(scene, tol)
    return ParticleSolution(
        scene=scene,
        newton_v_y=newton,
        mpp_v_y=mpp,
        mpp_v_y_numeric=numeric,
        relative_disagreement=(newton - mpp) / newton,
        numeric_error=abs(numeric - mpp) / mpp,
        power_newton=float(mp.power(newton, scene)),
        power_mpp=float(mp.power(mpp, scene)),
        status=status,
        iterations=iterations,
        solve_time_s=elapsed,
        kkt_residual=abs(float(mp.power_derivative(numeric, scene))) / scene.mg,
        newton_residual=float(mp.force_balance_residual(newton, scene)),
    )


@dataclass(frozen=True)
class ParticleProblem:
    """The particle of figure 2-2: fence speed ``v_x``, external force ``mg``, dissipative
    force ``eta`` |v|^``n`` (book 2.5)."""

    v_x: float
    mg: float
    eta: float
    n: float
    tol: SolverTolerances = SOLVER_DEFAULT


def mpp_particle(problem: ParticleProblem, budget: Budget = UNLIMITED) -> ParticleSolution:
    """:func:`solve_particle` of ``problem`` (one small NLP; ``budget`` is accepted for
    uniformity)."""
    return solve_particle(problem.v_x, problem.mg, problem.eta, problem.n, tol=problem.tol)
