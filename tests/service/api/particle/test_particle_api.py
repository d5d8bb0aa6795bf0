"""POST /v1/mpp/particle (book 2.5): the numbers are the domain functions' numbers;
invalid inputs are 422 naming the field."""

from __future__ import annotations

import math

import pytest

from models.particle import balance as particle
from solver.particle.solve import solve_particle

PARTICLE = "/v1/mpp/particle"


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
    import service.api.particle.routes as routes

    def boom(*args, **kwargs):
        raise ZeroDivisionError("float division by zero")

    monkeypatch.setattr(routes, "mpp_particle", boom)
    r = client.post(PARTICLE, json={"v_x": 1, "mg": 1, "eta": 2, "n": 0})
    assert r.status_code == 422
    assert r.json()["detail"][0]["type"] == "numeric_range"


def test_particle_near_the_coulomb_limit_is_not_a_server_error(client):
    mg = 0.0022244279301158313
    r = client.post(PARTICLE, json={"v_x": 0.004969697907960986, "mg": mg, "eta": 0.0022244279301158318, "n": 0})
    assert r.status_code in (200, 422), r.text
