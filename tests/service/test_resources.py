"""One list of the HTTP resources (service/api/__init__.py): the folders, the app's routers
and what a solver worker imports before it forks all come from it."""

from __future__ import annotations

import importlib
from pathlib import Path

from service.api import RESOURCES, ROUTE_MODULES
from service.app import create_app
from service.settings import Settings

API = Path(__file__).resolve().parents[2] / "service" / "api"


def test_every_resource_folder_is_listed_once():
    folders = sorted(p.name for p in API.iterdir() if (p / "__init__.py").is_file())
    assert sorted(RESOURCES) == folders
    assert len(set(RESOURCES)) == len(RESOURCES)


def test_the_app_serves_the_routes_of_every_listed_resource_and_no_other():
    app = create_app(Settings.from_env())
    operations = {op["operationId"] for path in app.openapi()["paths"].values() for op in path.values()}
    listed = set()
    for module in ROUTE_MODULES:
        router = importlib.import_module(module).router
        listed |= {route.operation_id for route in router.routes}
    assert operations == listed


def test_solver_workers_preload_the_listed_routes():
    from service.runtime.jobs import Runner

    settings = Settings.from_env()
    runner = Runner.from_settings(settings, preload=ROUTE_MODULES)
    try:
        if runner.pool is not None:
            assert runner.pool.preload[: len(ROUTE_MODULES)] == ROUTE_MODULES
            assert "service.runtime.jobs" in runner.pool.preload
    finally:
        runner.close()
