"""POST /v1/cor/membership: "can r be a COR?" with a certificate (book 3.3.2-3.3.13).

The route returns solver.locus.membership's answer unchanged; the certificates make sense on
their own (a witness is a support with its centroid at the CM whose forward COR is r, a
dual has a positive margin); the analytic locus' tip separates inside from outside.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.footprint import Footprint
from models.core.scene import PushScene
from service.limits import MAX_TIME_LIMIT_S
from solver.core.budget import Budget
from solver.core.errors import SolverError
from solver.locus.membership import membership

URL = "/v1/cor/membership"
HALF_PI = math.pi / 2
DISK = {"disk_radius": 1.0, "contact_point": [-0.5, -0.3], "edge_angle": HALF_PI}
RECT = [[-1, -0.5], [1, -0.5], [1, 0.5], [-1, 0.5]]
POLY = {"footprint": RECT, "contact_point": [-1.0, -0.3], "edge_angle": HALF_PI}


def post(client, body):
    r = client.post(URL, json=body)
    assert r.status_code == 200, r.text
    return r.json()


def direct(body):
    fp = None
    if "footprint" in body:
        fp = Footprint.create(body["footprint"], body.get("center_of_mass"))
        scene = PushScene.create(fp.circumradius, body["contact_point"], body["edge_angle"],
                                 body.get("push_direction", 0.0), fp.center_of_mass)
    else:
        scene = PushScene.create(body["disk_radius"], body["contact_point"], body["edge_angle"],
                                 body.get("push_direction", 0.0), body.get("center_of_mass", (0.0, 0.0)))
    return scene, membership(scene, body["cor"], fp, budget=Budget.of(body.get("time_limit_s", 10.0)))


@pytest.mark.parametrize("body", [
    {**DISK, "cor": [0.0, 3.0]},  # inside, beyond the disk
    {**DISK, "cor": [0.0, -0.05]},  # inside the disk: a point mass at r
    {**DISK, "cor": [0.0, 4.0]},  # beyond the tip
    {**DISK, "cor": [0.5, 0.5]},
    {**POLY, "cor": [0.0, 2.0]},
    {**POLY, "cor": [0.0, -1.0]},
], ids=["disk-in", "disk-in-mass", "disk-out", "disk-out-2", "poly-in", "poly-out"])
def test_membership_is_the_solver_answer(client, body):
    got = post(client, body)
    scene, want = direct(body)
    assert got["status"] == want.status and got["certificate_kind"] == want.certificate_kind
    assert got["status"] in ("inside", "outside")
    np.testing.assert_allclose(got["cor"], want.cor, rtol=1e-15, atol=1e-15)
    assert got["cor_query"] == body["cor"]
    assert got["in_footprint"] == want.in_footprint
    assert got["length_scale"] == want.length_scale
    assert got["iterations"] == want.iterations and got["n_columns"] == want.n_columns
    assert got["message"] == want.message
    if want.status == "inside":
        w = got["witness"]
        assert got["dual"] is None
        np.testing.assert_allclose(w["points"], want.witness_points, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(w["weights"], want.witness_weights, rtol=1e-9, atol=1e-12)
        assert w["point_mass_at_cor"] == pytest.approx(want.point_mass_at_cor, abs=1e-12)
        assert w["residual"] <= 1e-8 and w["forward_cor_error"] <= 1e-6
    else:
        d = got["dual"]
        assert got["witness"] is None
        np.testing.assert_allclose(d["vector"], want.dual, rtol=1e-9, atol=1e-12)
        assert d["margin"] == pytest.approx(want.dual_margin, rel=1e-9) and d["margin"] > 0.0
        assert d["lower_bound_method"] == "branch_and_bound"


def test_witness_is_a_support_whose_forward_cor_is_r(client):
    """Cross-check through the other endpoint: the witness, fed to /v1/cor/solve, turns the
    part about the candidate, and its centroid is the CM."""
    for body in ({**DISK, "cor": [0.2, 2.0]}, {**DISK, "cor": [0.0, -0.05]}):
        got = post(client, body)
        w = got["witness"]
        pts = np.array(w["points"])
        wts = np.array(w["weights"])
        if w["point_mass_at_cor"] > 0.0:
            pts = np.vstack([pts, got["cor"]])
            wts = np.append(wts, w["point_mass_at_cor"])
        assert wts.sum() == pytest.approx(1.0, abs=1e-12)
        np.testing.assert_allclose(wts @ pts, [0.0, 0.0], atol=1e-9)
        r = client.post("/v1/cor/solve", json={"contact_point": DISK["contact_point"], "edge_angle": HALF_PI,
                                               "disk_radius": 1.0,
                                               "support": {"points": pts.tolist(), "weights": wts.tolist()}})
        assert r.status_code == 200, r.text
        np.testing.assert_allclose(r.json()["motion"]["cor"], body["cor"], atol=1e-6)


def test_the_analytic_tip_separates_inside_from_outside(client):
    """(3.37): the tip at a^2 / |alpha . c| on the axis; just inside is a COR, just beyond is not."""
    locus = client.post("/v1/cor/locus", json={**DISK, "outputs": ["tip"]}).json()
    tip = np.array(locus["tip"]["point"])
    assert post(client, {**DISK, "cor": (0.99 * tip).tolist()})["status"] == "inside"
    out = post(client, {**DISK, "cor": (1.01 * tip).tolist()})
    assert out["status"] == "outside" and out["certificate_kind"] == "dual"


@pytest.mark.wall_clock  # about the time limit itself: its real deadline (tests/service/conftest.py)
def test_time_limit_gives_undecided(client):
    got = post(client, {**DISK, "cor": [0.0, 3.0], "time_limit_s": 1e-9})
    assert got["status"] == "undecided" and got["certificate_kind"] == "none"
    assert got["witness"] is None and got["residual"] is None
    assert "time limit" in got["message"]


INVALID = {
    "radius-zero": ({**DISK, "disk_radius": 0, "cor": [0, 1]}, ["body", "disk_radius"]),
    "radius-negative": ({**DISK, "disk_radius": -2, "cor": [0, 1]}, ["body", "disk_radius"]),
    "both": ({**DISK, "footprint": RECT, "cor": [0, 1]}, ["body", "footprint"]),
    "neither": ({"contact_point": [-0.5, -0.3], "edge_angle": HALF_PI, "cor": [0, 1]}, ["body", "disk_radius"]),
    "cor-missing": (dict(DISK), ["body", "cor"]),
    "cor-string": ({**DISK, "cor": ["0", 1]}, ["body", "cor", 0]),
    "cor-short": ({**DISK, "cor": [0]}, ["body", "cor"]),
    "time-zero": ({**DISK, "cor": [0, 1], "time_limit_s": 0}, ["body", "time_limit_s"]),
    "time-too-long": ({**DISK, "cor": [0, 1], "time_limit_s": MAX_TIME_LIMIT_S + 1}, ["body", "time_limit_s"]),
    "cm-outside-footprint": ({**POLY, "center_of_mass": [5, 5], "cor": [0, 1]}, ["body", "center_of_mass"]),
    "footprint-self-crossing": ({**POLY, "footprint": [[0, 0], [2, 0], [2, 1], [1, -1], [0, 1]], "cor": [0, 1]},
                                ["body", "footprint"]),
    "push-parallel": ({**DISK, "push_direction": HALF_PI, "cor": [0, 1]}, ["body", "push_direction"]),
    "extra": ({**DISK, "cor": [0, 1], "mu_c": 0.2}, ["body", "mu_c"]),
}


@pytest.mark.parametrize("case", sorted(INVALID))
def test_invalid_input_is_422_naming_the_field(client, case):
    body, loc = INVALID[case]
    r = client.post(URL, json=body)
    assert r.status_code == 422, r.text
    assert any(d["loc"][: len(loc)] == loc for d in r.json()["detail"]), r.json()


def test_nan_cor_is_422(client):
    r = client.post(URL, content='{"disk_radius": 1, "contact_point": [-0.5, -0.3], "edge_angle": 1.5, '
                                 '"cor": [NaN, 1]}', headers={"content-type": "application/json"})
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["body", "cor", 0]


def test_solver_error_is_422(client, monkeypatch):
    import service.api.locus.routes as routes

    def fail(*args, **kwargs):
        raise SolverError("Clarabel failed on the membership master: numerical trouble")

    monkeypatch.setattr(routes, "decide_membership", fail)
    r = client.post(URL, json={**DISK, "cor": [0, 1]})
    assert r.status_code == 422 and r.json()["detail"][0]["type"] == "solver_error"
