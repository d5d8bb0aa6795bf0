"""The deadline of one request: it starts when the request arrives (the ASGI middleware
:class:`service.runtime.intake.Intake` notes the moment), covers the time it waits for a worker, the solve,
the conversion and the rendering, and ends ``limit_s`` later. A solver gets what remains
minus a reserve for the work after it (converting, rendering, sending the answer back)."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

from starlette.types import Scope

from solver import Budget

ARRIVAL_KEY = "peshkin.arrived"
"""The scope state key under which the intake keeps the arrival (time.monotonic)."""


@dataclass(frozen=True)
class ReservePolicy:
    """What a solver leaves of the remaining time for the work after it: ``fraction`` of
    the request's limit, at least ``min_s`` and at most ``max_s`` seconds."""

    fraction: float = 0.1
    min_s: float = 0.05
    max_s: float = 2.0

    def reserve(self, limit_s: float) -> float:
        return min(max(self.fraction * limit_s, self.min_s), self.max_s)


DEFAULT_RESERVE = ReservePolicy()


@dataclass(frozen=True)
class Deadline:
    """``arrived`` and ``at`` on ``time.monotonic`` (one clock for every process of the
    machine); ``limit_s`` the request's time limit (its own or the server's cap); ``slots``
    the solver slots its work was given (a catalogue sizes its parallel tasks by them)."""

    arrived: float
    at: float
    limit_s: float
    reserve_s: float
    slots: int = 1

    @classmethod
    def starting(cls, arrived: float, limit_s: float, policy: ReservePolicy = DEFAULT_RESERVE) -> Deadline:
        limit = max(float(limit_s), 0.0) if math.isfinite(limit_s) else 0.0
        return cls(arrived, arrived + limit, limit, policy.reserve(limit))

    def remaining(self) -> float:
        """Seconds left (0 once passed)."""
        return max(self.at - time.monotonic(), 0.0)

    def solver_s(self) -> float:
        """Seconds a solver started now may take: what remains minus the reserve."""
        return max(self.remaining() - self.reserve_s, 0.0)

    def elapsed(self) -> float:
        return time.monotonic() - self.arrived

    def budget(self) -> Budget:
        """The solver's budget: it started when the request arrived and ends the reserve
        before the deadline; its ``limit_s`` is the request's (for the messages)."""
        return Budget(self.arrived, self.at - self.reserve_s, self.limit_s, time.monotonic)


def arrival(scope: Scope) -> float:
    """When the request of ``scope`` arrived (now, when no stamp was put on it)."""
    value = scope.get("state", {}).get(ARRIVAL_KEY)
    return float(value) if value is not None else time.monotonic()
