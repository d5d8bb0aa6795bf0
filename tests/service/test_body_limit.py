"""The body-size limit (service/runtime/intake.py, PESHKIN_MAX_BODY_BYTES): a body
announced longer is refused 413 before it is read, a streamed one as soon as it passes
the limit; a 422 never echoes a large input back; deep nesting is a 422, never a 500."""

from __future__ import annotations

import json

import pytest

from service.app import create_app
from service.settings import Settings
from tests.service.runtime.conftest import TestClient

LIMIT = 4096
PUSH = {"disk_radius": 1, "contact_point": [0.2, 0.3], "edge_angle": 1.5708}


@pytest.fixture(scope="module")
def small():
    with TestClient(create_app(Settings(solver_workers=0, max_body_bytes=LIMIT)), raise_server_exceptions=False) as c:
        yield c


def test_an_announced_long_body_is_refused_unread(small):
    body = json.dumps({**PUSH, "n_points": 64, "padding": "x" * LIMIT})
    r = small.post("/v1/cor/locus", content=body, headers={"content-type": "application/json"})
    assert r.status_code == 413 and r.json()["detail"][0]["type"] == "body_too_large"


def test_a_streamed_long_body_is_refused_when_it_passes_the_limit(small):
    def chunks():
        yield b'{"disk_radius": 1, "padding": "'
        for _ in range(10):
            yield b"x" * 1024
        yield b'"}'

    r = small.post("/v1/cor/locus", content=chunks(), headers={"content-type": "application/json"})
    assert r.status_code == 413 and str(LIMIT) in r.json()["detail"][0]["msg"]


def test_a_body_under_the_limit_is_served(small):
    assert small.post("/v1/cor/locus", json={**PUSH, "outputs": ["tip"]}).status_code == 200


def test_a_huge_invalid_array_is_not_echoed(client):
    r = client.post("/v1/cor/locus", json={**PUSH, "disk_radius": [1.0] * 200_000})
    assert r.status_code == 422 and len(r.content) < 1000
    assert r.json()["detail"][0]["input"] == "a list of 200000 items"


@pytest.mark.parametrize("depth", [900, 3000])
def test_deep_nesting_is_a_422(client, depth):
    for body in ('{"disk_radius": ' + "[" * depth + "]" * depth + ', "contact_point": [0, 0], "edge_angle": 1}',
                 "[" * depth + "]" * depth):
        r = client.post("/v1/cor/locus", content=body, headers={"content-type": "application/json"})
        assert r.status_code == 422 and len(r.content) < 2000


@pytest.mark.parametrize("path, field", [("/v1/cor/tripod-statistics", "include_cors"),
                                          ("/v1/spiral/schedule", "include_path")])
@pytest.mark.parametrize("value", [0, 1, "yes", "on", "true"])
def test_booleans_are_only_true_and_false(client, path, field, value):
    r = client.post(path, json={"disk_radius": 1, field: value})
    bad = [e for e in r.json()["detail"] if e["loc"][-1] == field]
    assert r.status_code == 422 and bad and bad[0]["type"] == "bool_type"
