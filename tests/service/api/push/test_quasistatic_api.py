"""POST /v1/push/quasistatic: characteristic speeds for quasi-static motion (book 6.8).

The route is thin: its numbers are those of models.push.quasistatic on the same inputs (bit for
bit); the book's own numbers come back; units only rescale; every invalid input is 422
naming the field; at the limits every number of the answer is finite; the docs example runs.
"""

from __future__ import annotations

import itertools
import json
import math
import re
from pathlib import Path

import pytest

from models.core.footprint import Footprint
from models.push import quasistatic as qs
from service.limits import (
    MAX_DISK_RADIUS,
    QS_MAX_ANGULAR_ERROR,
    QS_MAX_GRAVITY,
    QS_MAX_MU_S,
    QS_MAX_SPEED,
    QS_MIN_GRAVITY,
    QS_MIN_LENGTH,
    QS_MIN_MU_S,
)

URL = "/v1/push/quasistatic"
BOOK = {"speed": 10.0, "mu_s": 0.25, "length_unit": "cm", "disk_radius": 3.5}
L_SHAPE = [[0, 0], [3, 0], [3, 1], [1, 1], [1, 2.5], [0, 2.5]]


def strict_json(text: str):
    def reject(token):
        raise AssertionError(f"non-finite number {token} in JSON")

    return json.loads(text, parse_constant=reject)


def post(client, body):
    r = client.post(URL, json=body)
    return r, strict_json(r.text)


def detail(got) -> tuple[list, str]:
    (item,) = got["detail"]
    return item["loc"], item["type"]


def test_disk_answer_is_the_model_and_the_book(client):
    """6.8.1: 14 cm/s for 5 degrees; 6.8.2: 16 cm/s for X = 0.5 cm (the default a/7);
    6.8.3: 40 cm/s ("roughly": 41.4)."""
    r, got = post(client, BOOK)
    assert r.status_code == 200, r.text
    want = qs.assess(10.0, 0.25, qs.gravity("cm"), qs.ShapeMoments.disk(3.5))
    assert got["g"] == want.g and got["g_source"] == "length_unit" and got["length_unit"] == "cm"
    for name in ("angular", "translational"):
        o, w = got[name], getattr(want, name)
        assert o["characteristic_speed"] == w.characteristic_speed
        assert o["ratio"] == w.ratio
        assert o["permissible_error"] == w.permissible_error
        assert o["error_at_speed"] == w.error_at_speed
        assert o["within_tolerance"] is w.within_tolerance
        assert (o["equation"], o["section"], o["formula"]) == (w.equation, w.section, w.formula)
    assert got["quasi_static"]["characteristic_speed"] == want.quasi_static.characteristic_speed
    assert got["quasi_static"]["ratio"] == want.quasi_static.ratio
    assert round(got["angular"]["characteristic_speed"]) == 14
    assert round(got["translational"]["characteristic_speed"]) == 16
    assert round(got["quasi_static"]["characteristic_speed"], -1) == 40
    assert got["angular"]["permissible_error"] == pytest.approx(math.radians(5.0), rel=1e-15)
    assert got["translational"]["permissible_error"] == pytest.approx(0.5, rel=1e-15)
    assert (got["angular"]["equation"], got["translational"]["equation"], got["quasi_static"]["equation"]) == (
        "(6.3)", "(6.6)", "(6.7)")
    assert got["angular"]["formula"] == "v^2 = (8/3) mu_s a g theta"
    assert got["part"] == {"kind": "disk", "radius": 3.5, "radius_of_gyration": 3.5 * math.sqrt(0.5),
                           "mean_distance": 3.5 * (2.0 / 3.0), "spin_factor": qs.ShapeMoments.disk(3.5).spin_factor,
                           "center_of_mass": None}
    assert got["verdict"] == "quasi_static" and got["message"].startswith("quasi-static")
    assert got["thresholds"] == {"quasi_static_max_ratio": 0.3, "inertial_min_ratio": 1.0}
    assert "6.8" in got["reference"] and got["elapsed_ms"] >= 0.0


def test_polygon_answer_is_the_model(client):
    body = {"speed": 0.3, "mu_s": 0.4, "g": 9.81, "footprint": L_SHAPE, "angular_error": 0.1,
            "translational_error": 0.05}
    r, got = post(client, body)
    assert r.status_code == 200, r.text
    fp = Footprint.create(L_SHAPE)
    part = qs.ShapeMoments.polygon(fp)
    want = qs.assess(0.3, 0.4, 9.81, part, angular_error=0.1, translational_error=0.05)
    assert got["g_source"] == "g" and got["length_unit"] is None
    assert got["part"]["kind"] == "polygon"
    assert got["part"]["radius"] == part.radius == fp.circumradius
    assert got["part"]["radius_of_gyration"] == part.radius_of_gyration
    assert got["part"]["mean_distance"] == part.mean_distance
    assert got["part"]["center_of_mass"] == fp.center_of_mass.tolist()
    assert got["angular"]["characteristic_speed"] == want.angular.characteristic_speed
    assert got["angular"]["equation"] == "(6.3), generalised"
    assert got["translational"]["characteristic_speed"] == want.translational.characteristic_speed
    assert got["quasi_static"]["ratio"] == want.quasi_static.ratio
    assert got["verdict"] == want.verdict
    # The reversed outline is the same part.
    r2, got2 = post(client, {**body, "footprint": L_SHAPE[::-1]})
    assert got2["part"]["mean_distance"] == pytest.approx(part.mean_distance, rel=1e-14)


def test_g_and_length_unit_agree_and_units_only_rescale(client):
    _, by_unit = post(client, BOOK)
    _, by_g = post(client, {**{k: v for k, v in BOOK.items() if k != "length_unit"}, "g": 981.0})
    assert by_g["g_source"] == "g"
    for name in ("angular", "translational", "quasi_static"):
        assert by_g[name]["ratio"] == pytest.approx(by_unit[name]["ratio"], rel=1e-14)
    _, in_m = post(client, {"speed": 0.1, "mu_s": 0.25, "length_unit": "m", "disk_radius": 0.035,
                            "translational_error": 0.005})
    for name in ("angular", "translational", "quasi_static"):
        assert by_unit[name]["characteristic_speed"] == pytest.approx(100 * in_m[name]["characteristic_speed"], rel=1e-14)
        assert by_unit[name]["ratio"] == pytest.approx(in_m[name]["ratio"], rel=1e-14)
    assert by_unit["translational"]["error_at_speed"] == pytest.approx(100 * in_m["translational"]["error_at_speed"], rel=1e-14)
    assert in_m["verdict"] == by_unit["verdict"]


@pytest.mark.parametrize("ratio, verdict", [(0.0, "quasi_static"), (0.25, "quasi_static"), (0.5, "transitional"),
                                            (1.0, "inertial"), (3.0, "inertial")])
def test_verdicts(client, ratio, verdict):
    v_qs = qs.quasi_static_speed(0.25, qs.gravity("cm"), 3.5)
    r, got = post(client, {**BOOK, "speed": ratio * v_qs})
    assert r.status_code == 200, r.text
    assert got["verdict"] == verdict
    assert got["quasi_static"]["ratio"] == pytest.approx(ratio, rel=1e-14, abs=0.0)
    assert got["message"].startswith(verdict.replace("_", "-"))
    if verdict == "inertial":
        assert "7.4" in got["message"]
    for name in ("angular", "translational"):
        o = got[name]
        assert o["error_at_speed"] == pytest.approx(o["permissible_error"] * o["ratio"] ** 2, rel=1e-13, abs=0.0)
        assert o["within_tolerance"] == (o["ratio"] <= 1.0)


@pytest.mark.parametrize(
    "change, loc, type_",
    [
        ({"disk_radius": None}, ["body", "disk_radius"], "value_error"),  # neither shape
        ({"footprint": L_SHAPE}, ["body", "footprint"], "value_error"),  # both shapes
        ({"length_unit": None}, ["body", "g"], "value_error"),  # neither g nor unit
        ({"g": 981.0}, ["body", "length_unit"], "value_error"),  # both
        ({"length_unit": "furlong"}, ["body", "length_unit"], "literal_error"),
        ({"speed": -1.0}, ["body", "speed"], "greater_than_equal"),
        ({"speed": QS_MAX_SPEED * 2}, ["body", "speed"], "less_than_equal"),
        ({"speed": "10"}, ["body", "speed"], "float_type"),
        ({"speed": True}, ["body", "speed"], "float_type"),
        ({"mu_s": 0.0}, ["body", "mu_s"], "greater_than_equal"),
        ({"mu_s": QS_MAX_MU_S * 2}, ["body", "mu_s"], "less_than_equal"),
        ({"angular_error": 0.0}, ["body", "angular_error"], "greater_than"),
        ({"angular_error": 7.0}, ["body", "angular_error"], "less_than_equal"),
        ({"translational_error": 0.0}, ["body", "translational_error"], "greater_than_equal"),
        ({"disk_radius": -3.5}, ["body", "disk_radius"], "greater_than_equal"),
        ({"velocity": 3.0}, ["body", "velocity"], "extra_forbidden"),
    ],
)
def test_bad_inputs_are_422_naming_the_field(client, change, loc, type_):
    body = {**BOOK, **change}
    body = {k: v for k, v in body.items() if v is not None}
    r, got = post(client, body)
    assert r.status_code == 422, r.text
    assert detail(got) == (loc, type_)


def test_bad_gravity_and_polygons(client):
    base = {"speed": 1.0, "mu_s": 0.3, "disk_radius": 1.0}
    for g, type_ in ((0.0, "greater_than_equal"), (QS_MAX_GRAVITY * 10, "less_than_equal"), (None, "value_error")):
        body = {**base, "g": g} if g is not None else base
        r, got = post(client, body)
        assert r.status_code == 422 and detail(got) == (["body", "g"], type_)
    bad = {"speed": 1.0, "mu_s": 0.3, "g": 9.81}
    for footprint in ([[0, 0], [1, 0], [2, 0]], [[0, 0], [1, 1], [1, 0], [0, 1]]):  # collinear, bow tie
        r, got = post(client, {**bad, "footprint": footprint})
        assert r.status_code == 422 and detail(got) == (["body", "footprint"], "value_error"), r.text
    r, got = post(client, {**bad, "footprint": [[0, 0], [1, 0]]})
    assert r.status_code == 422 and detail(got)[0] == ["body", "footprint"]
    r = client.post(URL, content=b'{"speed": NaN, "mu_s": 0.3, "g": 9.81, "disk_radius": 1}',
                    headers={"content-type": "application/json"})
    assert r.status_code == 422 and detail(strict_json(r.text))[0] == ["body", "speed"]


def test_every_number_is_finite_at_the_limits(client):
    """The limits of service/limits.py keep every speed, ratio and coasting error finite."""
    small_polygon = [[0, 0], [1e-150, 0], [0, 1e-150]]
    big_polygon = [[-1e9, -1e9], [1e9, -1e9], [1e9, 1e9], [-1e9, 1e9]]
    shapes = [{"disk_radius": QS_MIN_LENGTH}, {"disk_radius": MAX_DISK_RADIUS}, {"footprint": small_polygon},
              {"footprint": big_polygon}]
    for speed, mu_s, g, shape, theta, x in itertools.product(
        (0.0, QS_MAX_SPEED), (QS_MIN_MU_S, QS_MAX_MU_S), (QS_MIN_GRAVITY, QS_MAX_GRAVITY), shapes,
        (1e-300, QS_MAX_ANGULAR_ERROR), (QS_MIN_LENGTH, MAX_DISK_RADIUS),
    ):
        body = {"speed": speed, "mu_s": mu_s, "g": g, **shape, "angular_error": theta, "translational_error": x}
        r, got = post(client, body)  # strict_json refuses NaN / Infinity
        assert r.status_code == 200, (body, r.text)
        assert got["quasi_static"]["characteristic_speed"] > 0.0
        assert got["angular"]["characteristic_speed"] > 0.0 and got["translational"]["characteristic_speed"] > 0.0


def test_limits_are_in_the_openapi_schema(client):
    doc = client.get("/openapi.json").json()
    req = doc["components"]["schemas"]["PushQuasistaticRequest"]
    props = req["properties"]
    assert req["additionalProperties"] is False
    assert set(req["required"]) == {"speed", "mu_s"}
    assert (props["speed"]["minimum"], props["speed"]["maximum"]) == (0, QS_MAX_SPEED)
    assert (props["mu_s"]["minimum"], props["mu_s"]["maximum"]) == (QS_MIN_MU_S, QS_MAX_MU_S)
    assert props["g"]["anyOf"][0]["minimum"] == QS_MIN_GRAVITY
    assert props["length_unit"]["anyOf"][0]["enum"] == list(qs.METRES_PER_UNIT)
    assert props["angular_error"]["maximum"] == QS_MAX_ANGULAR_ERROR
    assert req["x-exactly-one-of"] == [["disk_radius", "footprint"], ["g", "length_unit"]]
    op = doc["paths"][URL]["post"]
    assert op["operationId"] == "push_quasistatic"
    assert op["responses"]["422"]["content"]["application/json"]["schema"] == {"$ref": "#/components/schemas/ErrorResponse"}


DOC = Path(__file__).resolve().parents[4] / "docs" / "api.md"
CURL = re.compile(
    r"curl -s '?http://127\.0\.0\.1:8000(/v1/push/[^ ']+)'? -H 'content-type: application/json' \\\n  -d '([^']+)'"
)


def test_docs_examples_of_this_endpoint_run(client):
    examples = [body for url, body in CURL.findall(DOC.read_text(encoding="utf-8")) if url == URL]
    assert len(examples) >= 2
    for body in examples:
        r, _ = post(client, json.loads(body))
        assert r.status_code == 200, (body, r.text)
