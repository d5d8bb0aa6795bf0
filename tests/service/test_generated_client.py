"""The contract as a client developer meets it (issue 27): a Python client generated from
openapi.yaml by openapi-python-client, with no warning and nothing dropped, calls every
operation of a live server (``python -m service``) with the documented example of its
request (the job operations on the job the example submits), and reads each answer back
into the generated response model."""

from __future__ import annotations

import importlib
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from tests.service.live import live_server

REPO = Path(__file__).resolve().parents[2]
DOCUMENT = REPO / "openapi.yaml"
GENERATOR = Path(sys.executable).parent / "openapi-python-client"
PACKAGE = "peshkin_client"
CONFIG = f"post_hooks: []\nproject_name_override: peshkin-client\npackage_name_override: {PACKAGE}\n"

pytestmark = pytest.mark.slow


def operations(doc: dict) -> list[tuple[str, str, tuple[str, dict] | None, str]]:
    """(operation id, tag, (request schema, its documented example) or None, response
    media type)."""
    out = []
    for item in doc["paths"].values():
        for op in item.values():
            request = None
            if "requestBody" in op:
                ref = op["requestBody"]["content"]["application/json"]["schema"]["$ref"].rsplit("/", 1)[1]
                request = ref, doc["components"]["schemas"][ref]["examples"][0]
            ok = next(code for code in op["responses"] if code.startswith("2"))
            media = next(iter(op["responses"][ok]["content"]))
            out.append((op["operationId"], op["tags"][0], request, media))
    return out


@pytest.fixture(scope="module")
def client_package(tmp_path_factory):
    where = tmp_path_factory.mktemp("client")
    (where / "config.yaml").write_text(CONFIG, encoding="utf-8")
    run = subprocess.run([str(GENERATOR), "generate", "--path", str(DOCUMENT), "--config", "config.yaml",
                          "--meta", "none"], cwd=where, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "Warning" not in run.stdout and "WARNING" not in run.stdout, run.stdout  # nothing dropped
    sys.path.insert(0, str(where))
    try:
        yield importlib.import_module(PACKAGE)
    finally:
        sys.path.remove(str(where))
        for name in [m for m in sys.modules if m == PACKAGE or m.startswith(PACKAGE + ".")]:
            del sys.modules[name]


def test_every_operation_and_response_model_is_generated(client_package):
    doc = yaml.safe_load(DOCUMENT.read_text(encoding="utf-8"))
    root = Path(client_package.__file__).parent
    for op_id, tag, _, _ in operations(doc):
        assert (root / "api" / tag / f"{op_id}.py").exists(), op_id
    models = importlib.import_module(f"{PACKAGE}.models")
    for name in ("SpiralScheduleResponse", "TipLineScheduleOut", "LocusTipLineOut", "FeederDesignResponse",
                 "ErrorResponse", "TimeLimitResponse"):
        assert hasattr(models, name), name


def test_the_generated_client_calls_every_operation_of_a_live_server(client_package):
    doc = yaml.safe_load(DOCUMENT.read_text(encoding="utf-8"))
    client_module = importlib.import_module(f"{PACKAGE}.client")
    with live_server(web_workers="1", solver_workers="1", max_time_limit_s="120") as url:
        client = client_module.Client(base_url=url, timeout=120.0, raise_on_unexpected_status=True)
        called = []
        models = importlib.import_module(f"{PACKAGE}.models")
        job_id = None  # the job jobs_submit made, for the job operations after it
        for op_id, tag, request, media in operations(doc):
            op = importlib.import_module(f"{PACKAGE}.api.{tag}.{op_id}")
            if request is not None:
                schema_name, example = request
                answer = op.sync_detailed(client=client, body=getattr(models, schema_name).from_dict(example))
            elif op_id in ("jobs_get", "jobs_cancel"):
                answer = op.sync_detailed(job_id, client=client)
            else:
                answer = op.sync_detailed(client=client)
            if op_id == "jobs_submit":
                job_id = answer.parsed.id
            assert answer.status_code == (202 if op_id == "jobs_submit" else 200), (op_id, answer.content[:500])
            if media == "application/json":
                assert answer.parsed is not None and type(answer.parsed).__name__.endswith(("Response", "Out")), op_id
                assert answer.parsed.to_dict(), op_id
            else:
                assert answer.content, op_id
            called.append(op_id)
    assert len(called) == len(operations(doc)) == 23


def test_the_generated_client_shows_its_key(client_package):
    """With API keys on: the generated AuthenticatedClient (bearer token) is served, the
    plain client is answered 401, parsed as the documented ErrorResponse."""
    key = "k" * 24
    healthz = importlib.import_module(f"{PACKAGE}.api.health.healthz")
    locus = importlib.import_module(f"{PACKAGE}.api.cor.cor_locus")
    client_module = importlib.import_module(f"{PACKAGE}.client")
    models = importlib.import_module(f"{PACKAGE}.models")
    doc = yaml.safe_load(DOCUMENT.read_text(encoding="utf-8"))
    body = models.CorLocusRequest.from_dict(doc["components"]["schemas"]["CorLocusRequest"]["examples"][0])
    with live_server(web_workers="1", solver_workers="1", api_keys=key) as url:
        keyed = client_module.AuthenticatedClient(base_url=url, token=key, timeout=60.0)
        plain = client_module.Client(base_url=url, timeout=60.0)
        assert healthz.sync_detailed(client=plain).status_code == 200  # the probes stay open
        assert locus.sync_detailed(client=keyed, body=body).status_code == 200
        refused = locus.sync_detailed(client=plain, body=body)
        assert refused.status_code == 401 and type(refused.parsed).__name__ == "ErrorResponse"
