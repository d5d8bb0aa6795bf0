"""POST /v1/feeder/catalogue (issue 27): each part's entry is what /v1/feeder/design answers
for that part with the same request (the catalogue only runs them together), and bad
parts or settings are a 422 at their own field."""

from __future__ import annotations

import pytest

from service.limits import FEEDER_MAX_CATALOGUE_PARTS

URL = "/v1/feeder/catalogue"
PARTS = [
    {"name": "pentagon", "vertices": [[0, 0], [3, 0], [3.5, 1.5], [1.5, 2.5], [-0.5, 1.2]], "center_of_mass": [1.4, 1.0]},
    {"name": "plate", "vertices": [[0, 0], [2.5, 0], [2.5, 1], [0, 1]], "center_of_mass": [1.25, 0.5]},
]
DESIGN = {"angles": {"min": 0.349, "max": 1.222, "step": 0.1745}, "mu_c": 0.25, "alternate": False,
          "validation_parts": 3, "seed": 2}


@pytest.mark.slow
def test_each_entry_is_the_parts_own_design(client):
    r = client.post(URL, json={"parts": PARTS, "design": DESIGN})
    assert r.status_code == 200, r.text
    body = r.json()
    assert body["status"] == "complete" and body["finished"] == 2 and body["backend"] == "in_process"
    for part, got in zip(PARTS, body["designs"]):
        alone = client.post("/v1/feeder/design", json={**DESIGN, "part": {k: part[k] for k in ("vertices",
                                                                                           "center_of_mass")}}).json()
        assert got["name"] == part["name"] and got["status"] == "ok"
        assert got["fences"] == alone["design"]["fences"]
        assert got["margin"] == alone["design"]["margin"]
        assert got["validation_in_band"] == alone["validation"]["in_band"] and got["validation_parts"] == 3


@pytest.mark.parametrize("change,loc", [
    ({"parts": [PARTS[0], {"vertices": [[0, 0], [1, 0], [2, 0]], "center_of_mass": [1, 0]}]},
     ["body", "parts", 1, "vertices"]),
    ({"parts": [PARTS[0], {**PARTS[1], "center_of_mass": [9, 9]}]}, ["body", "parts", 1]),
    ({"design": {**DESIGN, "angles": {"min": 0.5, "max": 0.4, "step": 0.1}}}, ["body", "design", "angles", "max"]),
    ({"design": {**DESIGN, "mu_c_range": [0.1, 0.2]}}, ["body", "design"]),
    ({"parts": [PARTS[0]] * (FEEDER_MAX_CATALOGUE_PARTS + 1)}, ["body", "parts"]),
    ({"parts": []}, ["body", "parts"]),
])
def test_bad_parts_and_settings_are_422_at_their_field(client, change, loc):
    r = client.post(URL, json={"parts": PARTS, "design": DESIGN, **change})
    assert r.status_code == 422, r.text
    assert r.json()["detail"][0]["loc"][:len(loc)] == loc, r.text


@pytest.mark.wall_clock  # about the time limit itself: its real deadline (tests/service/conftest.py)
def test_no_time_for_any_part_is_a_504(client):
    r = client.post(URL, json={"parts": PARTS, "design": DESIGN, "time_limit_s": 1e-6})
    assert r.status_code == 504, r.text
