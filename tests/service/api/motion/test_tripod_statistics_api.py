"""POST /v1/cor/tripod-statistics (figures 3-5, 7-2): the numbers are the domain
functions' numbers; invalid inputs are 422 naming the field."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.scene import PushScene
from service.limits import MAX_TRIPOD_CORS, MAX_TRIPODS
from solver.motion.statistics import sticking_line_histogram, tripod_sample

TRIPODS = "/v1/cor/tripod-statistics"
HALF_PI = math.pi / 2
PUSH = {"contact_point": [-0.5, -0.3], "edge_angle": HALF_PI}


# ---------------------------------------------------------------------------------------
# Tripod statistics
# ---------------------------------------------------------------------------------------


def test_tripod_sample_is_the_domain_answer_and_reproducible(client):
    body = {**PUSH, "disk_radius": 1.0, "n_tripods": 300, "seed": 42, "mu_c": 0.3}
    got = client.post(TRIPODS, json=body).json()
    again = client.post(TRIPODS, json=body).json()
    assert got["cors"] == again["cors"]
    scene = PushScene.create(1.0, PUSH["contact_point"], HALF_PI)
    want = tripod_sample(scene, 300, 42, mu_c=0.3)
    cors = np.array([c if c is not None else [np.nan, np.nan] for c in got["cors"]])
    np.testing.assert_array_equal(cors, want.batch.cor)
    assert got["converged"] == int(want.batch.converged.sum()) == 300
    assert got["status"] == "optimal"
    assert got["max_kkt_residual"] == float(want.batch.kkt_residual.max()) <= 1e-9
    assert sum(got["mode_counts"].values()) == 300
    assert got["histogram"] is None
    other = client.post(TRIPODS, json={**body, "seed": 43}).json()
    assert other["cors"] != got["cors"]


def test_sticking_histogram(client):
    body = {**PUSH, "disk_radius": 1.0, "n_tripods": 500, "seed": 3, "histogram": True, "bins": 20,
            "include_cors": False}
    got = client.post(TRIPODS, json=body).json()
    assert got["cors"] is None
    scene = PushScene.create(1.0, PUSH["contact_point"], HALF_PI)
    want = sticking_line_histogram(scene, 500, 3, bins=20)
    h = got["histogram"]
    assert h["counts"] == want.counts.tolist()
    np.testing.assert_array_equal(h["edges"], want.edges)
    assert h["sticking_fraction"] == want.sticking_fraction
    assert h["outside_range"] == want.outside_range
    spanned = client.post(TRIPODS, json={**body, "span": [-2.0, 2.0]}).json()["histogram"]
    assert spanned["edges"][0] == -2.0 and spanned["edges"][-1] == 2.0


def test_tripods_in_a_polygon(client):
    square = [[-1, -1], [1, -1], [1, 1], [-1, 1]]
    r = client.post(TRIPODS, json={"contact_point": [-1, -0.3], "edge_angle": HALF_PI, "footprint": square,
                                   "n_tripods": 50, "seed": 1})
    assert r.status_code == 200, r.text
    assert r.json()["disk_radius"] == pytest.approx(math.sqrt(2))


TRIPOD_INVALID = {
    "no-seed": ({**PUSH, "disk_radius": 1, "n_tripods": 10}, ["body", "seed"]),
    "zero-tripods": ({**PUSH, "disk_radius": 1, "n_tripods": 0, "seed": 1}, ["body", "n_tripods"]),
    "too-many": ({**PUSH, "disk_radius": 1, "n_tripods": MAX_TRIPODS + 1, "seed": 1}, ["body", "n_tripods"]),
    "too-many-cors": ({**PUSH, "disk_radius": 1, "n_tripods": MAX_TRIPOD_CORS + 1, "seed": 1},
                      ["body", "include_cors"]),
    "neither-disk-nor-footprint": ({**PUSH, "n_tripods": 10, "seed": 1}, ["body", "disk_radius"]),
    "span-decreasing": ({**PUSH, "disk_radius": 1, "n_tripods": 10, "seed": 1, "histogram": True,
                         "span": [1, -1]}, ["body", "span"]),
    "mu-negative": ({**PUSH, "disk_radius": 1, "n_tripods": 10, "seed": 1, "mu_c": -1}, ["body", "mu_c"]),
    "radius-zero": ({**PUSH, "disk_radius": 0, "n_tripods": 10, "seed": 1}, ["body", "disk_radius"]),
}


@pytest.mark.parametrize("case", sorted(TRIPOD_INVALID))
def test_tripod_invalid_is_422(client, case):
    body, loc = TRIPOD_INVALID[case]
    r = client.post(TRIPODS, json=body)
    assert r.status_code == 422, r.text
    assert any(d["loc"][: len(loc)] == loc for d in r.json()["detail"]), r.json()


def test_thin_footprint_is_refused_before_sampling(client):
    """Rejection sampling from the bounding box would take minutes for a sliver."""
    sliver = [[0, 0], [1, 1], [0.999, 1]]
    r = client.post(TRIPODS, json={"contact_point": [0.5, 0.5], "edge_angle": 1.0, "footprint": sliver,
                                   "n_tripods": 10, "seed": 1})
    assert r.status_code == 422, r.text
    assert r.json()["detail"][0]["loc"] == ["body", "footprint"]


@pytest.mark.parametrize("body, loc", [
    ({"contact_point": [1e8, 3e8], "edge_angle": 0.0, "push_direction": 1.0, "disk_radius": 5e-324,
      "center_of_mass": [1e8, 3e8]}, ["body", "disk_radius"]),
    ({"contact_point": [0, 0.5], "edge_angle": HALF_PI, "footprint": [[0, 0], [1, 0], [1, 1], [0, 1]],
      "center_of_mass": [0.01, 0.01]}, ["body", "center_of_mass"]),
])
def test_unsamplable_regions_are_refused(client, body, loc):
    """Inputs on which the rejection sampler of balanced tripods would never finish."""
    r = client.post(TRIPODS, json={**body, "n_tripods": 10, "seed": 1})
    assert r.status_code == 422, r.text
    assert r.json()["detail"][0]["loc"] == loc


def test_explicit_area_centroid_is_accepted(client):
    r = client.post(TRIPODS, json={"contact_point": [0, 0.5], "edge_angle": HALF_PI, "n_tripods": 10, "seed": 1,
                                   "footprint": [[0, 0], [1, 0], [1, 1], [0, 1]], "center_of_mass": [0.5, 0.5]})
    assert r.status_code == 200, r.text
