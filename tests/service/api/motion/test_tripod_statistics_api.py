"""POST /v1/mpp/particle (book 2.5) and POST /v1/cor/tripod-statistics (figures 3-5, 7-2):
the numbers are the domain functions' numbers; invalid inputs are 422 naming the field."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models import particle
from models.scene import PushScene
from service.limits import MAX_TRIPOD_CORS, MAX_TRIPODS
from solver.motion.particle import solve_particle
from solver.motion.statistics import sticking_line_histogram, tripod_sample

PARTICLE = "/v1/mpp/particle"
TRIPODS = "/v1/cor/tripod-statistics"
HALF_PI = math.pi / 2
PUSH = {"contact_point": [-0.5, -0.3], "edge_angle": HALF_PI}


# ---------------------------------------------------------------------------------------
# The particle of book 2.5
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("body", [
    {"v_x": 1.0, "mg": 1.0, "eta": 2.0, "n": 0.0},
    {"v_x": 3.0, "mg": 0.2, "eta": 0.5, "n": 0},
    {"v_x": 1.0, "mg": 1.0, "eta": 2.0, "n": 1.0},
    {"v_x": 0.5, "mg": 4.0, "eta": 0.3, "n": 2.5},
])
def test_particle_is_the_domain_answer(client, body):
    r = client.post(PARTICLE, json=body)
    assert r.status_code == 200, r.text
    got = r.json()
    want = solve_particle(body["v_x"], body["mg"], body["eta"], body["n"])
    for key in ("newton_v_y", "mpp_v_y", "relative_disagreement", "power_newton", "power_mpp"):
        assert got[key] == getattr(want, key), key
    assert got["mpp_v_y_numeric"] == pytest.approx(want.mpp_v_y_numeric, rel=1e-12)
    assert got["status"] == "Solve_Succeeded"
    assert got["numeric_error"] <= 1e-9 and got["kkt_residual"] <= 1e-9
    assert abs(got["newton_residual"]) <= 1e-12
    sc = particle.ParticleScene.create(body["v_x"], body["mg"], body["eta"], body["n"])
    assert got["kkt_residual"] == pytest.approx(
        abs(particle.power_derivative(got["mpp_v_y_numeric"], sc)) / sc.mg, abs=1e-15)
    assert got["power_mpp"] <= got["power_newton"]


def test_particle_agrees_only_for_coulomb_friction(client):
    coulomb = client.post(PARTICLE, json={"v_x": 1.0, "mg": 1.0, "eta": 2.0, "n": 0}).json()
    assert coulomb["agree"] is True
    assert coulomb["newton_v_y"] == pytest.approx(1 / math.sqrt(3), rel=1e-14)  # mg/eta = 1/2 = u/sqrt(1+u^2)
    assert coulomb["mpp_v_y_numeric"] == pytest.approx(coulomb["newton_v_y"], rel=1e-9)
    assert abs(coulomb["relative_disagreement"]) <= 1e-12
    viscous = client.post(PARTICLE, json={"v_x": 1.0, "mg": 1.0, "eta": 2.0, "n": 1}).json()
    assert viscous["agree"] is False
    assert viscous["newton_v_y"] == pytest.approx(0.5) and viscous["mpp_v_y"] == pytest.approx(0.25)
    assert viscous["relative_disagreement"] == pytest.approx(0.5, rel=1e-14)
    assert "n = 0" in viscous["message"]


PARTICLE_INVALID = {
    "coulomb-eta-not-above-mg": ({"v_x": 1, "mg": 2, "eta": 2, "n": 0}, ["body", "eta"]),
    "n-negative": ({"v_x": 1, "mg": 1, "eta": 2, "n": -1}, ["body", "n"]),
    "n-too-big": ({"v_x": 1, "mg": 1, "eta": 2, "n": 11}, ["body", "n"]),
    "v-zero": ({"v_x": 0, "mg": 1, "eta": 2, "n": 1}, ["body", "v_x"]),
    "mg-string": ({"v_x": 1, "mg": "1", "eta": 2, "n": 1}, ["body", "mg"]),
    "eta-too-big": ({"v_x": 1, "mg": 1, "eta": 1e7, "n": 1}, ["body", "eta"]),
    "missing-n": ({"v_x": 1, "mg": 1, "eta": 2}, ["body", "n"]),
    "extra": ({"v_x": 1, "mg": 1, "eta": 2, "n": 1, "m": 3}, ["body", "m"]),
}


@pytest.mark.parametrize("case", sorted(PARTICLE_INVALID))
def test_particle_invalid_is_422(client, case):
    body, loc = PARTICLE_INVALID[case]
    r = client.post(PARTICLE, json=body)
    assert r.status_code == 422, r.text
    assert any(d["loc"][: len(loc)] == loc for d in r.json()["detail"]), r.json()


def test_particle_nan_is_422(client):
    r = client.post(PARTICLE, content='{"v_x": NaN, "mg": 1, "eta": 2, "n": 1}',
                    headers={"content-type": "application/json"})
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["body", "v_x"]


def test_particle_float_trouble_is_422_not_500(client, monkeypatch):
    """eta = mg (1 + 1 ulp) with n = 0 once divided by zero inside the solver; whatever the
    solver does with such inputs, the client gets a 422."""
    import service.convert_mpp as conv

    def boom(*args, **kwargs):
        raise ZeroDivisionError("float division by zero")

    monkeypatch.setattr(conv, "solve_particle", boom)
    r = client.post(PARTICLE, json={"v_x": 1, "mg": 1, "eta": 2, "n": 0})
    assert r.status_code == 422
    assert r.json()["detail"][0]["type"] == "numeric_range"


def test_particle_near_the_coulomb_limit_is_not_a_server_error(client):
    mg = 0.0022244279301158313
    r = client.post(PARTICLE, json={"v_x": 0.004969697907960986, "mg": mg, "eta": 0.0022244279301158318, "n": 0})
    assert r.status_code in (200, 422), r.text


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
