"""Runtime settings from the environment (service/settings.py)."""

from __future__ import annotations

import warnings

import pytest

from service.app import create_app
from service.settings import DEFAULT_JOBS_PATH, Settings

with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient


def test_settings_defaults_and_env():
    assert Settings.from_env({}) == Settings("127.0.0.1", 8000, "info", jobs_path=DEFAULT_JOBS_PATH)
    assert Settings.from_env({"PESHKIN_JOBS_PATH": ""}).jobs_path == "" == Settings().jobs_path
    s = Settings.from_env({"PESHKIN_HOST": "0.0.0.0", "PESHKIN_PORT": "9001", "PESHKIN_LOG_LEVEL": "DEBUG"})
    assert s == Settings("0.0.0.0", 9001, "debug", jobs_path=DEFAULT_JOBS_PATH)
    for bad in ({"PESHKIN_PORT": "http"}, {"PESHKIN_PORT": "70000"}, {"PESHKIN_LOG_LEVEL": "loud"}):
        with pytest.raises(ValueError):
            Settings.from_env(bad)


def test_runtime_settings_are_read_and_checked():
    s = Settings.from_env({"PESHKIN_WEB_WORKERS": "3", "PESHKIN_SOLVER_WORKERS": "0", "PESHKIN_SOLVER_QUEUE": "5",
                           "PESHKIN_MAX_TIME_LIMIT_S": "12.5", "PESHKIN_HEADER_TIMEOUT_S": "2"})
    assert (s.web_workers, s.solver_workers, s.solver_queue, s.max_time_limit_s, s.header_timeout_s) == (3, 0, 5, 12.5, 2.0)
    for bad in ({"PESHKIN_WEB_WORKERS": "0"}, {"PESHKIN_SOLVER_WORKERS": "-2"}, {"PESHKIN_MAX_TIME_LIMIT_S": "nan"},
                {"PESHKIN_HEADER_TIMEOUT_S": "0"}, {"PESHKIN_DEADLINE_GRACE_S": "soon"}, {"PESHKIN_RETRY_AFTER_S": "1.5"}):
        with pytest.raises(ValueError, match=next(iter(bad))):
            Settings.from_env(bad)


def test_solver_workers_auto_are_the_usable_cpus_for_the_whole_server():
    """One slot per CPU the process may use, shared by the web processes (so not divided
    among them: service/runtime/slots.py)."""
    auto = Settings.from_env({"PESHKIN_SOLVER_WORKERS": "auto", "PESHKIN_WEB_WORKERS": "2"})
    assert auto.solver_processes(cpus=2) == 2 and auto.solver_processes(cpus=8) == 8
    assert auto.solver_processes(cpus=0) == 1  # at least one
    assert Settings(solver_workers=3).solver_processes(cpus=64) == 3


MEMBERSHIP = {"disk_radius": 1, "contact_point": [-0.5, -0.3], "edge_angle": 1.5707963267948966, "cor": [0, 3]}


@pytest.mark.parametrize("cap", [30.0, 300.0])
def test_one_cap_of_time_limits_from_the_settings_in_the_schema_and_the_deadline(cap):
    """Issue 25: an operator who raises PESHKIN_MAX_TIME_LIMIT_S gets the limits they set
    (the schemas no longer cap at a constant 30 s): 120 s is served under a cap of 300 s and
    refused, 422 at time_limit_s naming the cap, under the default 30 s; the service's
    OpenAPI document states the cap as every time limit's maximum, the part-bound map's
    too."""
    with TestClient(create_app(Settings(solver_workers=0, max_time_limit_s=cap)), raise_server_exceptions=False) as c:
        r = c.post("/v1/cor/membership", json={**MEMBERSHIP, "time_limit_s": 120})
        if cap < 120:
            assert r.status_code == 422
            detail = r.json()["detail"][0]
            assert detail["loc"] == ["body", "time_limit_s"] and detail["type"] == "less_than_equal"
            assert f"at most {cap:g} s" in detail["msg"] and "PESHKIN_MAX_TIME_LIMIT_S" in detail["msg"]
        else:
            assert r.status_code == 200, r.text
        schemas = c.get("/openapi.json").json()["components"]["schemas"]
    maxima = set()
    for name, schema in schemas.items():
        limit = schema.get("properties", {}).get("time_limit_s")
        if limit is not None and name.endswith("Request"):
            maxima |= {b["maximum"] for b in [limit, *limit.get("anyOf", [])] if "maximum" in b}
    assert maxima == {cap}


def test_operations_settings_are_read_and_checked():
    """Issue 27's settings: log format, access log, API keys, rate limit, CORS origins."""
    key = "k" * 16
    s = Settings.from_env({"PESHKIN_LOG_FORMAT": "TEXT", "PESHKIN_ACCESS_LOG": "off",
                           "PESHKIN_API_KEYS": f" {key}, {key}-2 ", "PESHKIN_RATE_LIMIT": "120/60",
                           "PESHKIN_CORS_ORIGINS": "https://a.example.org/, http://localhost:3000"})
    assert (s.log_format, s.access_log, s.api_keys, s.rate_limit) == ("text", False, (key, key + "-2"), (120, 60.0))
    assert s.cors_origins == ("https://a.example.org", "http://localhost:3000")
    assert Settings.from_env({}).api_keys == () and Settings.from_env({}).rate_limit is None
    for bad in ({"PESHKIN_API_KEYS": "short"}, {"PESHKIN_API_KEYS": f"{key} with space"},
                {"PESHKIN_RATE_LIMIT": "fast"}, {"PESHKIN_RATE_LIMIT": "0/60"}, {"PESHKIN_RATE_LIMIT": "5/inf"},
                {"PESHKIN_CORS_ORIGINS": "example.org"}, {"PESHKIN_LOG_FORMAT": "xml"},
                {"PESHKIN_ACCESS_LOG": "maybe"}):
        with pytest.raises(ValueError, match=next(iter(bad))):
            Settings.from_env(bad)
    assert key not in repr(s) and "<2 keys>" in repr(s)
