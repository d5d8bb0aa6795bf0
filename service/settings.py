"""Runtime settings from the environment (kept minimal).

=====================  ===========  ===================================
variable               default      meaning
=====================  ===========  ===================================
``PESHKIN_HOST``       127.0.0.1    interface uvicorn listens on
``PESHKIN_PORT``       8000         TCP port
``PESHKIN_LOG_LEVEL``  info         uvicorn / ``service`` logger level
=====================  ===========  ===================================

``python -m service`` starts uvicorn with these; ``uvicorn service.app:app`` (used by
scripts/serve.sh and the Dockerfile) takes host and port from its own command line.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

LOG_LEVELS = ("critical", "error", "warning", "info", "debug", "trace")


@dataclass(frozen=True)
class Settings:
    host: str = "127.0.0.1"
    port: int = 8000
    log_level: str = "info"

    @classmethod
    def from_env(cls, environ=None) -> "Settings":
        env = os.environ if environ is None else environ
        host = env.get("PESHKIN_HOST", cls.host).strip() or cls.host
        port_text = env.get("PESHKIN_PORT", str(cls.port)).strip()
        try:
            port = int(port_text)
        except ValueError:
            raise ValueError(f"PESHKIN_PORT must be an integer, got {port_text!r}") from None
        if not 0 < port < 65536:
            raise ValueError(f"PESHKIN_PORT must be in 1..65535, got {port}")
        level = env.get("PESHKIN_LOG_LEVEL", cls.log_level).strip().lower()
        if level not in LOG_LEVELS:
            raise ValueError(f"PESHKIN_LOG_LEVEL must be one of {LOG_LEVELS}, got {level!r}")
        return cls(host=host, port=port, log_level=level)
