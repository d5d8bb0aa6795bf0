"""Request bodies (service/common/bodies.py): read as ``json.loads`` reads them, an unknown
field refused before its value is read, a body over its route's limit refused 413, and a
large body to ``/v1/cor/solve`` decoded off the event loop, in the worker, with the same
answers and the same 422s as an inline one."""

from __future__ import annotations

import asyncio
import json
import random

import msgpack
import numpy as np
import pytest

from service.app import create_app
from service.common import bodies
from service.common.bodies import BodyInvalid, decode_object
from service.settings import Settings
from tests.service.runtime.conftest import TestClient

SOLVE = "/v1/cor/solve"
FIELDS = frozenset({"a", "b", "c"})
PUSH = {"contact_point": [-0.5, -0.3], "edge_angle": 1.5707963267948966, "disk_radius": 2}


def _random_value(rng: random.Random, depth: int = 0):
    kind = rng.randrange(7 if depth < 3 else 4)
    if kind == 0:
        return rng.uniform(-1e6, 1e6)
    if kind == 1:
        return rng.randrange(-10**18, 10**18)
    if kind == 2:
        return rng.choice([None, True, False, "", "é\u2603\"\\", "x" * rng.randrange(5)])
    if kind == 3:
        return rng.random() < 0.5
    if kind == 4:
        return [_random_value(rng, depth + 1) for _ in range(rng.randrange(4))]
    return {rng.choice("abcxyz"): _random_value(rng, depth + 1) for _ in range(rng.randrange(4))}


@pytest.mark.parametrize("seed", range(40))
def test_a_known_object_reads_as_json_loads_reads_it(seed):
    rng = random.Random(seed)
    doc = {k: _random_value(rng) for k in rng.sample(sorted(FIELDS), rng.randrange(4))}
    text = json.dumps(doc, indent=rng.choice([None, 0, 2]), ensure_ascii=rng.random() < 0.5)
    assert decode_object(text.encode(), "application/json", FIELDS, 100) == json.loads(text)
    packed = msgpack.packb(doc)
    assert decode_object(packed, "application/msgpack", FIELDS, 100) == msgpack.unpackb(packed)


@pytest.mark.parametrize("text", ['{"a": 1,}', '{"a" 1}', '{"a": 1 "b": 2}', '{"a": }', '{"a": 1} x', '{"a": 1}}',
                                  '{"a": [1, 2}', "{", '  {"a": nul}', '{a: 1}', "", "   "])
def test_a_malformed_body_is_the_error_json_loads_finds(text):
    with pytest.raises(json.JSONDecodeError) as want:
        json.loads(text)
    with pytest.raises(BodyInvalid) as got:
        decode_object(text.encode(), "application/json", FIELDS, 100)
    item = got.value.item
    assert item["type"] == "json_invalid" and item["loc"] == ["body", want.value.pos]
    assert item["ctx"]["error"] == want.value.msg


def test_repeated_keys_keep_the_last_as_json_loads_does():
    text = '{"a": 1, "b": 2, "a": [3]}'
    assert decode_object(text.encode(), "application/json", FIELDS, 100) == json.loads(text)


def test_a_document_that_is_not_an_object_is_left_to_validation():
    assert decode_object(b"[1, 2]", "application/json", FIELDS, 100) == [1, 2]
    assert decode_object(msgpack.packb([1, 2]), "application/msgpack", FIELDS, 100) == [1, 2]


def test_an_unknown_field_is_refused_before_its_value_is_read():
    """The value after the unknown key is not even JSON: had it been read, the answer would
    be a syntax error; it is the unknown field."""
    text = b'{"a": 1, "padding": [[1, 2], [3, @@@ this is never read'
    with pytest.raises(BodyInvalid) as got:
        decode_object(text, "application/json", FIELDS, 100)
    assert got.value.item["loc"] == ["body", "padding"] and got.value.item["type"] == "extra_forbidden"
    # msgpack: the unknown field's value is an extension type and longer than any array allowed
    packed = msgpack.packb({"a": 1, "padding": [msgpack.ExtType(1, b"x")] * 1000})
    with pytest.raises(BodyInvalid) as got:
        decode_object(packed, "application/msgpack", FIELDS, 100)
    assert got.value.item["loc"] == ["body", "padding"] and got.value.item["type"] == "extra_forbidden"


def test_a_msgpack_array_longer_than_the_longest_field_is_refused_while_decoding():
    with pytest.raises(BodyInvalid) as got:
        decode_object(msgpack.packb({"a": [0] * 101}), "application/msgpack", FIELDS, 100)
    assert got.value.item["type"] == "msgpack_invalid"


@pytest.fixture(scope="module")
def small_inline():
    """An app whose inline limit is 4 KiB, so a modest batch is a 'large' body."""
    settings = Settings(solver_workers=0, inline_body_bytes=4096, max_body_bytes=1 << 22)
    with TestClient(create_app(settings), raise_server_exceptions=False) as client:
        yield client


def _batch(n: int, seed: int = 0) -> dict:
    """``n`` balanced tripods (equal weights at the corners of a triangle about the CM)."""
    rng = np.random.default_rng(seed)
    turn = rng.uniform(0, 2 * np.pi, (n, 1)) + np.array([0, 2 * np.pi / 3, 4 * np.pi / 3])
    r = rng.uniform(0.2, 1.0, (n, 1))
    return {**PUSH, "mu_c": 0.3, "batch": {"support_size": 3, "x": (r * np.cos(turn)).ravel().tolist(),
                                            "y": (r * np.sin(turn)).ravel().tolist(), "weights": [1.0] * (3 * n)}}


def test_a_padded_body_is_refused_at_its_unknown_field(client):
    body = b'{"contact_point": [0, 0], "padding": [' + b"[1, 2], " * 100_000 + b"@"
    r = client.post(SOLVE, content=body, headers={"content-type": "application/json"})
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["body", "padding"]


def test_other_routes_refuse_a_body_over_the_inline_limit(small_inline):
    body = json.dumps({"disk_radius": 1, "contact_point": [0.2, 0.3], "edge_angle": 1.5, "outputs": ["tip"],
                       "n_points": 64}) + " " * 5000
    r = small_inline.post("/v1/cor/locus", content=body, headers={"content-type": "application/json"})
    assert r.status_code == 413 and "/v1/cor/locus" in r.json()["detail"][0]["msg"]
    assert "4096" in r.json()["detail"][0]["msg"]


def test_a_large_body_is_decoded_off_the_event_loop_with_the_inline_answer(small_inline, client, monkeypatch):
    body = _batch(400)
    assert len(json.dumps(body)) > 4096
    where: list[bool] = []
    decode = bodies.decode_object

    def watched(raw, *args):
        try:
            asyncio.get_running_loop()
            where.append(True)
        except RuntimeError:
            where.append(False)
        return decode(raw, *args)

    monkeypatch.setattr(bodies, "decode_object", watched)
    large = small_inline.post(SOLVE, json=body)
    assert where == [False], "the large body was decoded on the event loop"
    inline = client.post(SOLVE, json=body)
    assert where == [False, True]
    assert large.status_code == inline.status_code == 200
    assert large.json()["columns"] == inline.json()["columns"]
    packed = small_inline.post(SOLVE, content=msgpack.packb(body), headers={"content-type": "application/msgpack"})
    assert packed.status_code == 200 and packed.json()["columns"] == inline.json()["columns"]


@pytest.mark.parametrize("change", [{"mu_c": "much"}, {"padding": 1}, {"batch": {"support_size": 3}}])
def test_a_large_body_is_refused_as_an_inline_one(small_inline, client, change):
    body = {**_batch(400), **change}
    large, inline = small_inline.post(SOLVE, json=body), client.post(SOLVE, json=body)
    assert large.status_code == inline.status_code == 422
    strip = [{k: v for k, v in e.items() if k != "input"} for e in large.json()["detail"]]
    assert strip == [{k: v for k, v in e.items() if k != "input"} for e in inline.json()["detail"]]
    assert large.json()["request_id"]
