"""Response schemas of ``GET /healthz`` and ``GET /readyz``."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from service.common.responses import Out


class HealthResponse(Out):
    status: Literal["ok"] = Field(
        description="Always 'ok' while the process serves requests."
    )
    version: str = Field(
        description="Version of the service, e.g. '0.1.0'."
    )


class GateOut(Out):
    name: str = Field(description="`requests` (all requests in flight in the web process) or `expensive` "
                      "(requests for its solver workers: running or queued).")
    in_use: int = Field(description="Requests holding the gate now (for expensive work: running or queued).")
    capacity: int = Field(description="Requests it admits at once; one more is refused 503 with Retry-After.")
    admitted: int = Field(description="Requests admitted since this web process started.")
    refused: int = Field(description="Requests refused since this web process started.")


class ReadyResponse(Out):
    status: Literal["ready", "saturated"] = Field(
        description="'ready' (200) while both admission gates have room, 'saturated' (503) when one is full."
    )
    version: str = Field(
        description="Version of the service, e.g. '0.1.0'."
    )
    solver_workers: int = Field(description="Solver worker processes of this web process (0: work runs in its threads).")
    gates: list[GateOut] = Field(
        description="The two admission gates of this web process, `requests` and `expensive`, with their use, "
        "capacity, admissions and refusals."
    )
