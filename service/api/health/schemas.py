"""Response schema of ``GET /healthz``."""

from __future__ import annotations

from typing import Literal

from service.common.fields import Strict


class HealthResponse(Strict):
    status: Literal["ok"]
    version: str
