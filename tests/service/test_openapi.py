"""openapi.yaml is generated from the app and must not drift from it."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from service.app import app
from service.limits import (
    MAX_ABS_ANGLE,
    MAX_ABS_COORDINATE,
    MAX_BATCH,
    MAX_COLUMN_POINTS,
    MAX_DISK_RADIUS,
    MAX_MU_C,
    MAX_N_POINTS,
    MAX_POLYGON_VERTICES,
    MAX_SUPPORT_POINTS,
    MAX_TIME_LIMIT_S,
    MAX_WEIGHT,
    MIN_N_POINTS,
    MIN_POLYGON_VERTICES,
)

REPO_ROOT = Path(__file__).resolve().parents[2]
SCRIPT = REPO_ROOT / "scripts" / "gen_openapi.py"
DOCUMENT = REPO_ROOT / "openapi.yaml"


def _load_script():
    spec = importlib.util.spec_from_file_location("gen_openapi", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.slow
def test_openapi_yaml_is_up_to_date():
    gen = _load_script()
    assert DOCUMENT.exists(), "openapi.yaml is missing: run python scripts/gen_openapi.py"
    assert DOCUMENT.read_text(encoding="utf-8") == gen.render(), (
        "openapi.yaml drifted from the app: run python scripts/gen_openapi.py"
    )
    assert yaml.safe_load(DOCUMENT.read_text(encoding="utf-8")) == app.openapi()


def test_the_document_names_no_internal_module():
    """A client's contract does not change when the code is reorganised: no description
    names a module of models, solver or service, and no component is named after one."""
    import re

    text = DOCUMENT.read_text(encoding="utf-8")
    named = sorted(set(re.findall(r"\b(?:models|solver|service)\.[a-z_]+(?:\.[a-z_]+)*", text)))
    assert named == [], f"openapi.yaml names internal modules: {named}"
    assert not [n for n in app.openapi()["components"]["schemas"] if "__" in n]


@pytest.mark.slow
def test_generation_is_deterministic():
    gen = _load_script()
    assert gen.render() == gen.render()


@pytest.mark.slow
def test_check_mode(tmp_path):
    ok = subprocess.run([sys.executable, str(SCRIPT), "--check"], capture_output=True, text=True, cwd=REPO_ROOT)
    assert ok.returncode == 0, ok.stderr
    stale = tmp_path / "openapi.yaml"
    stale.write_text(DOCUMENT.read_text(encoding="utf-8").replace("cor_locus", "renamed"), encoding="utf-8")
    bad = subprocess.run([sys.executable, str(SCRIPT), "--check", "-o", str(stale)],
                         capture_output=True, text=True, cwd=REPO_ROOT)
    assert bad.returncode == 1
    assert "out of date" in bad.stderr


def test_stable_operation_ids():
    ops = {
        (path, method): op["operationId"]
        for path, item in app.openapi()["paths"].items()
        for method, op in item.items()
    }
    assert ops == {
        ("/healthz", "get"): "healthz",
        ("/readyz", "get"): "readyz",
        ("/metrics", "get"): "metrics",
        ("/v1/cor/locus", "post"): "cor_locus",
        ("/v1/cor/solve", "post"): "cor_solve",
        ("/v1/cor/membership", "post"): "cor_membership",
        ("/v1/cor/tripod-statistics", "post"): "cor_tripod_statistics",
        ("/v1/mpp/particle", "post"): "mpp_particle",
        ("/v1/push/quasistatic", "post"): "push_quasistatic",
        ("/v1/cor/sketch", "post"): "cor_sketch",
        ("/v1/push/align", "post"): "push_align",
        ("/v1/push/disk-encounter", "post"): "push_disk_encounter",
        ("/v1/spiral/critical-radius", "post"): "spiral_critical_radius",
        ("/v1/spiral/schedule", "post"): "spiral_schedule",
        ("/v1/feeder/map", "post"): "feeder_map",
        ("/v1/feeder/simulate", "post"): "feeder_simulate",
        ("/v1/feeder/design", "post"): "feeder_design",
        ("/v1/scenes/analyze", "post"): "scenes_analyze",
        ("/v1/feeder/catalogue", "post"): "feeder_catalogue",
        ("/v1/jobs", "post"): "jobs_submit",
        ("/v1/jobs/{job_id}", "get"): "jobs_get",
        ("/v1/jobs/{job_id}", "delete"): "jobs_cancel",
        ("/v1/jobs", "get"): "jobs_list",
    }


def test_both_media_types_and_errors_are_documented():
    op = app.openapi()["paths"]["/v1/cor/locus"]["post"]
    content = op["responses"]["200"]["content"]
    assert set(content) == {"application/json", "image/svg+xml"}
    assert content["application/json"]["schema"] == {"$ref": "#/components/schemas/CorLocusResponse"}
    assert op["responses"]["422"]["content"]["application/json"]["schema"] == {
        "$ref": "#/components/schemas/ErrorResponse"
    }
    (fmt,) = op["parameters"]
    assert fmt["name"] == "format" and fmt["in"] == "query"
    assert fmt["schema"]["enum"] == ["json", "svg"] and fmt["schema"]["default"] == "json"


def test_limits_are_in_the_schema():
    req = app.openapi()["components"]["schemas"]["CorLocusRequest"]
    props = req["properties"]
    assert req["additionalProperties"] is False
    radius = props["disk_radius"]["anyOf"][0]
    assert radius["exclusiveMinimum"] == 0 and radius["maximum"] == MAX_DISK_RADIUS
    contact = props["contact_point"]
    assert contact["minItems"] == contact["maxItems"] == 2
    assert contact["items"]["maximum"] == MAX_ABS_COORDINATE
    assert contact["items"]["minimum"] == -MAX_ABS_COORDINATE
    poly = props["workpiece"]["anyOf"][0]
    assert (poly["minItems"], poly["maxItems"]) == (MIN_POLYGON_VERTICES, MAX_POLYGON_VERTICES)
    assert (props["n_points"]["minimum"], props["n_points"]["maximum"]) == (MIN_N_POINTS, MAX_N_POINTS)
    assert props["edge_angle"]["maximum"] == MAX_ABS_ANGLE
    assert set(req["required"]) == {"contact_point", "edge_angle"}
    assert req["x-exactly-one-of"] == [["disk_radius", "workpiece", "footprint"]]
    assert props["workpiece"]["deprecated"] is True
    assert props["method"]["enum"] == ["analytic", "certified"] and props["method"]["default"] == "analytic"


def test_minimum_power_limits_are_in_the_schema():
    schemas = app.openapi()["components"]["schemas"]
    solve = schemas["CorSolveRequest"]
    assert solve["additionalProperties"] is False
    assert solve["x-exactly-one-of"] == [["support", "supports", "batch", "pressure"]]
    assert solve["properties"]["mu_c"]["minimum"] == 0 and solve["properties"]["mu_c"]["maximum"] == MAX_MU_C
    assert solve["properties"]["method"]["enum"] == ["newton", "cvxpy", "casadi"]
    assert solve["properties"]["supports"]["anyOf"][0]["maxItems"] == MAX_BATCH
    support = schemas["SupportIn"]["properties"]
    assert support["points"]["minItems"] == 1 and support["points"]["maxItems"] == MAX_SUPPORT_POINTS
    assert support["weights"]["items"]["minimum"] == 0 and support["weights"]["items"]["maximum"] == MAX_WEIGHT
    columns = schemas["SupportColumnsIn"]["properties"]
    assert columns["x"]["maxItems"] == columns["weights"]["maxItems"] == MAX_COLUMN_POINTS
    assert columns["weights"]["items"]["exclusiveMinimum"] == 0
    assert schemas["MembershipRequest"]["properties"]["time_limit_s"]["maximum"] == MAX_TIME_LIMIT_S
    for op in ("/v1/cor/solve", "/v1/cor/membership", "/v1/cor/tripod-statistics", "/v1/mpp/particle"):
        responses = app.openapi()["paths"][op]["post"]["responses"]
        assert responses["422"]["content"]["application/json"]["schema"] == {"$ref": "#/components/schemas/ErrorResponse"}


def test_time_limits_are_documented_where_they_can_run_out():
    """504 (a TimeLimitResponse) on the operations whose job runs in a solver worker under
    its deadline (all but the probes and the closed form of 6.8); 503 with Retry-After on
    every operation behind an admission gate; every operation documents 422."""
    ops = {op["operationId"]: op for item in app.openapi()["paths"].values() for op in item.values()}
    with_504 = {name for name, op in ops.items() if "504" in op["responses"]}
    assert with_504 == set(ops) - {"healthz", "readyz", "metrics", "push_quasistatic", "jobs_submit", "jobs_get",
                                   "jobs_cancel", "jobs_list"}
    with_503 = {name for name, op in ops.items() if "503" in op["responses"]}
    assert with_503 == set(ops) - {"healthz", "metrics"}
    for name in with_503 - {"readyz"}:
        assert "Retry-After" in ops[name]["responses"]["503"]["headers"]
    for name in with_504:
        assert ops[name]["responses"]["504"]["content"]["application/json"]["schema"] == {
            "$ref": "#/components/schemas/TimeLimitResponse"
        }
    assert all("422" in op["responses"] for name, op in ops.items() if name not in ("healthz", "readyz", "metrics"))


def test_every_response_field_says_what_it_is():
    """Issue 27: every property of every schema an answer can contain has a description
    (what it is, its unit and frame), so that a generated client documents it."""
    doc = app.openapi()
    schemas = doc["components"]["schemas"]

    def refs(node, out):
        if isinstance(node, dict):
            if "$ref" in node:
                out.add(node["$ref"].rsplit("/", 1)[1])
            for v in node.values():
                refs(v, out)
        elif isinstance(node, list):
            for v in node:
                refs(v, out)

    todo: set[str] = set()
    for item in doc["paths"].values():
        for op in item.values():
            refs(op["responses"], todo)
    seen: set[str] = set()
    while todo:
        name = todo.pop()
        seen.add(name)
        found: set[str] = set()
        refs(schemas[name], found)
        todo |= found - seen
    bare = [f"{n}.{f}" for n in sorted(seen) for f, spec in schemas[n].get("properties", {}).items()
            if not spec.get("description")]
    assert len(seen) > 70 and bare == []


def test_the_api_keys_are_in_the_document():
    """Issue 27: how to show a key (X-API-Key or a bearer token), optional (keys are on only
    when the deployment has some), and the 401 and 429 of every operation but the probes."""
    doc = app.openapi()
    assert doc["components"]["securitySchemes"]["ApiKey"] == {
        "type": "apiKey", "in": "header", "name": "X-API-Key",
        "description": doc["components"]["securitySchemes"]["ApiKey"]["description"]}
    assert doc["components"]["securitySchemes"]["Bearer"]["scheme"] == "bearer"
    for path, item in doc["paths"].items():
        for op in item.values():
            if path in ("/healthz", "/readyz"):
                assert "401" not in op["responses"] and "security" not in op
                continue
            assert op["security"] == [{}, {"ApiKey": []}, {"Bearer": []}]
            assert {"401", "429"} <= set(op["responses"]) and "Retry-After" in op["responses"]["429"]["headers"]
