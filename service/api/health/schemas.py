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


class StorageOut(Out):
    name: str = Field(description="`jobs` (the jobs file) or `result store` (kept expensive results).")
    path: str = Field(description="The file.")
    state: Literal["ok", "off", "full", "read_only", "broken", "unavailable"] = Field(
        description="ok; off (found unusable at start: the feature is off until the server restarts); full (its disk, "
        "or its own size cap); read_only; broken (not a SQLite database); unavailable (anything else).")
    reason: str = Field(description="What is wrong, in the library's words (empty when ok).")


class ReadyResponse(Out):
    status: Literal["ready", "degraded", "saturated"] = Field(
        description="'ready' (200) while both admission gates have room and every file works; 'degraded' (200: "
        "requests are served, but a file of the service fails: its feature is off or waits, see `storage`); "
        "'saturated' (503) when a gate is full."
    )
    version: str = Field(
        description="Version of the service, e.g. '0.1.0'."
    )
    solver_workers: int | None = Field(description="Solver worker processes of this web process (0: work runs in its "
                                       "threads); null unless the caller is an operator (deployments with keys).")
    gates: list[GateOut] | None = Field(
        description="The two admission gates of this web process, `requests` and `expensive`, with their use, "
        "capacity, admissions and refusals; null unless the caller is an operator (PESHKIN_OPERATOR_KEYS, on a "
        "deployment with keys)."
    )
    storage: list[StorageOut] | None = Field(
        description="The service's files (jobs, result store) and their state; null unless the caller is an "
        "operator."
    )
