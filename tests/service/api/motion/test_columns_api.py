"""Batches as columns and msgpack bodies of POST /v1/cor/solve and POST
/v1/cor/tripod-statistics (the minimum-power motions of 3.2-3.3.3 and 4.1, the tripods of
figure 3-5).

Columns are the rows transposed: the same numbers bit for bit, whichever way the batch was
sent (`supports` objects or the `batch` columns) and however the answer is encoded (JSON
or msgpack). Every bad input is a 422 naming its field.
"""

from __future__ import annotations

import math

import msgpack
import numpy as np
import pytest
from starlette.requests import Request

from models.core.support import random_balanced_tripods
from service.common.binary import wants_msgpack
from service.limits import MAX_BATCH, MAX_TRIPOD_CORS
from tests.scenes import SEED

URL = "/v1/cor/solve"
STATS = "/v1/cor/tripod-statistics"
PUSH = {"contact_point": [-0.5, -0.3], "edge_angle": math.pi / 2}
MSGPACK = {"content-type": "application/msgpack", "accept": "application/msgpack"}
ROW_FIELDS = {  # a column's name -> (a row's field, component)
    "status": ("status", None), "mode": ("mode", None), "cor_x": ("cor", 0), "cor_y": ("cor", 1),
    "velocity_cm_x": ("velocity_cm", 0), "velocity_cm_y": ("velocity_cm", 1),
    "rotation_per_push": ("rotation_per_push", None), "slip_per_push": ("slip_per_push", None),
    "sense": ("sense", None), "power": ("power", None), "contact_force_x": ("contact_force", 0),
    "contact_force_y": ("contact_force", 1), "kkt_residual": ("kkt_residual", None), "gap": ("gap", None),
    "cor_on_support": ("cor_on_support", None), "iterations": ("iterations", None),
}


def tripods(n: int, seed: int = SEED):
    return random_balanced_tripods(np.random.default_rng(seed), n, 1.0)


def as_columns(points: np.ndarray, weights: np.ndarray) -> dict:
    return {"support_size": points.shape[1], "x": points[..., 0].ravel().tolist(),
            "y": points[..., 1].ravel().tolist(), "weights": weights.ravel().tolist()}


def as_objects(points: np.ndarray, weights: np.ndarray) -> list[dict]:
    return [{"points": p.tolist(), "weights": w.tolist()} for p, w in zip(points, weights)]


def assert_columns_are_rows(columns: dict, rows: list[dict]) -> None:
    assert set(columns) == set(ROW_FIELDS) | {"mason_sense"}
    for name, (field, k) in ROW_FIELDS.items():
        want = [row[field] if k is None or row[field] is None else row[field][k] for row in rows]
        assert columns[name] == want, name
    assert {columns["mason_sense"]} == {row["mason_sense"] for row in rows}


@pytest.mark.parametrize("mu_c", [0.0, 0.4, 50.0])
def test_columns_are_the_rows_bit_for_bit_3_3_3_and_4_1(client, mu_c):
    """A batch sent as columns answers, column by column, what the same supports sent as
    objects answer row by row: frictionless (3.3.3), sticking and slipping (4.1)."""
    points, weights = tripods(400)
    points[5] = [[0.0, 0.8], [0.3, -0.2], [-0.3, -0.2]]  # COR on a support point for some mu_c
    weights[5] = [1.0, 2.0, 2.0]
    rows = client.post(URL, json={**PUSH, "mu_c": mu_c, "supports": as_objects(points, weights)}).json()
    cols = client.post(URL, json={**PUSH, "mu_c": mu_c, "batch": as_columns(points, weights)}).json()
    assert rows["input"] == "supports" and rows["columns"] is None and len(rows["motions"]) == 400
    assert cols["input"] == "batch" and cols["motions"] is None
    assert_columns_are_rows(cols["columns"], rows["motions"])
    assert cols["batch"] == {**rows["batch"], "support_sizes": [3]}
    assert len({*cols["columns"]["mode"]}) >= 1 and cols["batch"]["converged"] == 400
    also = client.post(URL, json={**PUSH, "mu_c": mu_c, "supports": as_objects(points, weights),
                                  "layout": "columns"}).json()
    assert also["columns"] == cols["columns"]
    back = client.post(URL, json={**PUSH, "mu_c": mu_c, "batch": as_columns(points[:50], weights[:50]),
                                  "layout": "rows"}).json()
    assert back["motions"] == rows["motions"][:50]


def test_a_batch_of_one_by_one_solves_as_columns(client):
    """The conic back end solves a batch support by support; its columns are its rows."""
    points, weights = tripods(3)
    body = {**PUSH, "mu_c": 0.3, "method": "cvxpy", "supports": as_objects(points, weights)}
    rows = client.post(URL, json=body).json()
    cols = client.post(URL, json={**body, "layout": "columns"}).json()
    assert_columns_are_rows(cols["columns"], rows["motions"])


def test_msgpack_in_and_out_is_the_json_answer(client):
    """A msgpack body is read as the JSON document it encodes, and a msgpack answer decodes
    to the JSON answer (but for the time it took)."""
    points, weights = tripods(2_000)
    body = {**PUSH, "mu_c": 0.4, "batch": as_columns(points, weights)}
    by_json = client.post(URL, json=body)
    by_msgpack = client.post(URL, content=msgpack.packb(body), headers=MSGPACK)
    assert by_msgpack.status_code == 200 and by_msgpack.headers["content-type"] == "application/msgpack"
    assert "accept" in by_msgpack.headers["vary"].lower()
    got, want = msgpack.unpackb(by_msgpack.content), by_json.json()
    for answer in (got, want):
        answer.pop("elapsed_ms"), answer.pop("solve_time_ms")
    assert got == want
    only_in = client.post(URL, content=msgpack.packb(body), headers={"content-type": "application/msgpack"})
    assert only_in.headers["content-type"] == "application/json" and only_in.json()["columns"] == want["columns"]
    assert "accept" in only_in.headers["vary"].lower()  # the JSON answer depends on Accept too


def test_tripod_cors_as_columns_figure_3_5(client):
    """The CORs of random tripods (figure 3-5) as columns are the rows' points; as columns
    a sample larger than the rows' limit is answered whole, in JSON and in msgpack."""
    base = {"disk_radius": 1.0, **PUSH, "n_tripods": 500, "seed": SEED}
    rows = client.post(STATS, json=base).json()
    cols = client.post(STATS, json={**base, "layout": "columns"}).json()
    assert rows["cor_columns"] is None and cols["cors"] is None
    assert cols["cor_columns"]["x"] == [None if c is None else c[0] for c in rows["cors"]]
    assert cols["cor_columns"]["y"] == [None if c is None else c[1] for c in rows["cors"]]
    n = MAX_TRIPOD_CORS + 1
    big = {**base, "n_tripods": n, "layout": "columns"}
    assert client.post(STATS, json={**big, "layout": "rows"}).status_code == 422
    packed = client.post(STATS, content=msgpack.packb(big), headers=MSGPACK)
    assert packed.status_code == 200
    answer = msgpack.unpackb(packed.content)
    assert len(answer["cor_columns"]["x"]) == n and answer["n_tripods"] == n


def _tripod_batch(n: int = 4) -> dict:
    points, weights = tripods(n)
    return as_columns(points, weights)


@pytest.mark.parametrize("change,loc", [
    (lambda b: b["batch"].update(y=b["batch"]["y"][:-1]), ["body", "batch", "y"]),
    (lambda b: b["batch"].update(weights=b["batch"]["weights"] + [1.0]), ["body", "batch", "weights"]),
    (lambda b: b["batch"].update(support_size=5), ["body", "batch", "x"]),
    (lambda b: b["batch"]["weights"].__setitem__(7, 0.0), ["body", "batch", "weights", 7]),
    (lambda b: b["batch"]["weights"].__setitem__(7, 3.0), ["body", "batch", "weights"]),
    (lambda b: b["batch"]["x"].__setitem__(1, b["batch"]["x"][0]) or b["batch"]["y"].__setitem__(1, b["batch"]["y"][0]),
     ["body", "batch", "weights"]),
    (lambda b: b.update(method="cvxpy"), ["body", "method"]),
    (lambda b: b.update(supports=[{"points": [[0, 0]], "weights": [1]}]), ["body"]),
])
def test_bad_columns_are_422_at_their_field(client, change, loc):
    body = {**PUSH, "batch": _tripod_batch()}
    change(body)
    r = client.post(URL, json=body)
    assert r.status_code == 422, r.text
    assert [d["loc"] for d in r.json()["detail"]][0][:len(loc)] == loc, r.text


def test_a_bad_support_of_a_batch_is_named_by_its_index(client):
    body = {**PUSH, "batch": _tripod_batch(6)}
    body["batch"]["weights"][3 * 4] *= 3.0  # support 4's centroid moves off the CM
    detail = client.post(URL, json=body).json()["detail"][0]
    assert detail["loc"] == ["body", "batch", "weights"] and "support 4:" in detail["msg"]


def test_layout_is_checked_against_the_input(client):
    one = {**PUSH, "support": {"points": [[0.6, 0.0], [-0.3, 0.5], [-0.3, -0.5]], "weights": [1, 1, 1]}}
    r = client.post(URL, json={**one, "layout": "columns"})
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["body", "layout"]
    points, weights = tripods(MAX_BATCH + 1)
    r = client.post(URL, json={**PUSH, "batch": as_columns(points, weights), "layout": "rows"})
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["body", "layout"]
    assert f"at most {MAX_BATCH}" in r.json()["detail"][0]["msg"]


@pytest.mark.parametrize("content", [b"\xc1", b"\x81\x01\x02", msgpack.packb({"contact_point": msgpack.ExtType(1, b"x")}),
                                     msgpack.packb([1, 2]) + b"\x00"])
def test_a_body_that_is_not_msgpack_of_json_values_is_422(client, content):
    r = client.post(URL, content=content, headers=MSGPACK)
    assert r.status_code == 422 and r.headers["content-type"] == "application/json"
    assert r.json()["detail"][0]["type"] == "msgpack_invalid" and r.json()["request_id"]


def test_msgpack_non_finite_numbers_are_refused_like_json(client):
    body = {**PUSH, "batch": _tripod_batch()}
    body["batch"]["x"][2] = float("nan")
    r = client.post(URL, content=msgpack.packb(body), headers=MSGPACK)
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["body", "batch", "x", 2]


def test_only_the_batch_routes_read_msgpack(client):
    """An operation that did not declare msgpack refuses it as a body that is not JSON."""
    body = {"disk_radius": 1, "contact_point": [0.2, 0.3], "edge_angle": 1.5708, "outputs": ["tip"]}
    r = client.post("/v1/cor/locus", content=msgpack.packb(body), headers=MSGPACK)
    assert r.status_code == 422 and r.headers["content-type"] == "application/json"


def test_openapi_declares_msgpack_for_the_batch_routes(client):
    paths = client.get("/openapi.json").json()["paths"]
    for path, name in ((URL, "CorSolve"), (STATS, "TripodStatistics")):
        op = paths[path]["post"]
        assert op["requestBody"]["content"]["application/msgpack"]["schema"]["$ref"].endswith(f"{name}Request")
        assert op["responses"]["200"]["content"]["application/msgpack"]["schema"]["$ref"].endswith(f"{name}Response")
        assert "application/json" in op["requestBody"]["content"]
    assert "application/msgpack" not in paths["/v1/cor/locus"]["post"]["requestBody"]["content"]


@pytest.mark.parametrize("accept,binary", [
    ("application/msgpack", True), ("application/x-msgpack", True), ("application/json", False), ("", False),
    ("*/*", False), ("application/json, application/msgpack", False), ("application/msgpack, application/json", True),
    ("application/json;q=0.5, application/msgpack", True), ("application/msgpack;q=0", False),
    ("text/html, application/msgpack;q=0.9", True), ("application/msgpack;q=0.2, */*;q=0.8", False),
])
def test_accept_negotiation(accept, binary):
    scope = {"type": "http", "headers": [(b"accept", accept.encode())] if accept else []}
    assert wants_msgpack(Request(scope)) is binary


def test_a_msgpack_array_longer_than_any_field_allows_is_refused_while_decoding(client):
    from service.limits import MAX_COLUMN_POINTS

    body = {**PUSH, "batch": {"support_size": 1, "x": [None] * (MAX_COLUMN_POINTS + 1), "y": [0.0], "weights": [1.0]}}
    r = client.post(URL, content=msgpack.packb(body), headers=MSGPACK)
    assert r.status_code == 422 and r.json()["detail"][0]["type"] == "msgpack_invalid"


def test_column_coordinates_are_bounded_like_every_point(client):
    body = {**PUSH, "batch": _tripod_batch()}
    body["batch"]["x"][4] = 1e300
    r = client.post(URL, json=body)
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["body", "batch", "x", 4]


def test_a_msgpack_request_is_logged_and_counted_under_its_route(client, caplog):
    """The access log and the metrics label a request by its route template: a msgpack body,
    handed on as JSON, keeps it."""
    body = {**PUSH, "batch": _tripod_batch()}
    with caplog.at_level("INFO", logger="service.access"):
        assert client.post(URL, content=msgpack.packb(body), headers=MSGPACK).status_code == 200
    routes = [getattr(r, "route", None) for r in caplog.records if r.name == "service.access"]
    assert routes[-1] == URL
