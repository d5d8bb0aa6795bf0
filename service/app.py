"""The FastAPI application: ``uvicorn service.app:app``."""

from __future__ import annotations

import logging

from fastapi import FastAPI

from service import __version__, errors
from service.routes import cor, health, mpp
from service.routes import push
from service.routes import sketch
from service.routes import spiral
from service.settings import Settings

DESCRIPTION = """\
Planning service for pushed sliding workpieces, after M. A. Peshkin, *Robotic Manipulation
Strategies* (1990), chapter 3. World frame: x right, y up, angles in radians CCW; lengths
in any consistent unit. Errors are HTTP 422 `{"detail": [{"loc": [...], "msg": ..., "type": ...}]}`.
"""


def create_app() -> FastAPI:
    logging.getLogger("service").setLevel(Settings.from_env().log_level.upper().replace("TRACE", "DEBUG"))
    app = FastAPI(
        title="Peshkin pushing planner",
        version=__version__,
        description=DESCRIPTION,
    )
    errors.install(app)
    app.include_router(health.router)
    app.include_router(cor.router)
    app.include_router(mpp.router)
    app.include_router(push.router)
    app.include_router(sketch.router)
    app.include_router(spiral.router)
    return app


app = create_app()
