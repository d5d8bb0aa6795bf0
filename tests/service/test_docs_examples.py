"""Every curl example of docs/api.md is a valid request: run in-process, it answers 200.
Budgets are unlimited here (what is checked is the request, not how busy the machine is;
the 504 of a time limit has its own tests)."""

from __future__ import annotations

import importlib
import json
import re
from pathlib import Path

import pytest

from tests.budgets import NoLimitBudgets

DOC = Path(__file__).resolve().parents[2] / "docs" / "api.md"
CURL = re.compile(
    r"curl -s '?http://127\.0\.0\.1:8000(/[^ ']+)'? -H 'content-type: application/json' \\\n  -d '([^']+)'"
)
ROUTE_MODULES = [importlib.import_module(f"service.api.{p.name}.routes")
                 for p in sorted((Path(__file__).resolve().parents[2] / "service" / "api").iterdir())
                 if (p / "routes.py").is_file()]
EXAMPLES = [(m.group(1), m.group(2)) for m in CURL.finditer(DOC.read_text(encoding="utf-8"))]


def test_the_examples_are_found():
    paths = {url.split("?")[0] for url, _ in EXAMPLES}
    assert paths == {"/v1/cor/locus", "/v1/cor/solve", "/v1/cor/membership", "/v1/cor/tripod-statistics",
                     "/v1/mpp/particle", "/v1/push/quasistatic", "/v1/cor/sketch", "/v1/push/align",
                     "/v1/push/disk-encounter", "/v1/spiral/critical-radius", "/v1/spiral/schedule"}


@pytest.mark.slow
@pytest.mark.parametrize("url, body", EXAMPLES, ids=[f"{i}:{u}" for i, (u, _) in enumerate(EXAMPLES)])
def test_doc_example_answers_200(client, monkeypatch, url, body):
    for module in ROUTE_MODULES:
        if hasattr(module, "Budget"):
            monkeypatch.setattr(module, "Budget", NoLimitBudgets)
    path, _, query = url.partition("?")
    params = dict(kv.split("=") for kv in query.split("&")) if query else None
    r = client.post(path, json=json.loads(body), params=params)
    assert r.status_code == 200, r.text
