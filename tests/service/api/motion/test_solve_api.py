"""POST /v1/cor/solve: the motion for a known pressure distribution (book 3.2-3.3.3, 4.1).

The route is thin: its numbers are those of a direct call of solver.motion.forward /
solver.motion.statistics / models.core.inertia on the same domain objects; batches agree with single
solves; every invalid input is 422 naming the field.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from models.core.footprint import Footprint
from models.core.inertia import impact_cor, polygon_radius_of_gyration, support_radius_of_gyration
from models.core.mpp import mason_sense
from models.core.scene import PushScene
from models.core.support import Support, random_balanced_tripods
from service.limits import MAX_BATCH, MAX_BATCH_SLOW, MAX_MU_C, MAX_SUPPORT_POINTS_SLOW
from solver.core.errors import SolverError
from solver.motion.forward import solve_forward
from solver.motion.statistics import uniform_pressure_cor

URL = "/v1/cor/solve"
HALF_PI = math.pi / 2
PUSH = {"contact_point": [-0.5, -0.3], "edge_angle": HALF_PI}
TRIPOD = {"points": [[0.6, 0.0], [-0.3, 0.5], [-0.3, -0.5]], "weights": [1, 1, 1]}
DIPOD_ON_POINT = {"points": [[0.0, 0.8], [0.0, -0.2]], "weights": [1, 4]}  # COR on point 0


def strict_json(text: str):
    def reject(token):
        raise AssertionError(f"non-finite number {token} in JSON")

    return json.loads(text, parse_constant=reject)


def post(client, body):
    r = client.post(URL, json=body)
    return r, (strict_json(r.text) if r.headers.get("content-type", "").startswith("application/json") else None)


def scene_of(body, disk_radius):
    return PushScene.create(disk_radius, body["contact_point"], body["edge_angle"],
                            body.get("push_direction", 0.0), body.get("center_of_mass", (0.0, 0.0)))


def assert_motion_equals(got: dict, want, scene: PushScene, mu_c: float, exact: bool = True):
    """The JSON motion is the ForwardResult (bit for bit when ``exact``)."""
    tol = dict(rtol=0, atol=0) if exact else dict(rtol=1e-9, atol=1e-9)
    assert got["status"] == want.status == "optimal"
    assert got["mode"] == want.mode
    assert got["sense"] == want.sense
    if want.cor is None:
        assert got["cor"] is None and got["kind"] == "translation"
    else:
        assert got["kind"] == "rotation"
        np.testing.assert_allclose(got["cor"], want.cor, **tol)
    np.testing.assert_allclose(got["velocity_cm"], want.velocity_cm, **tol)
    np.testing.assert_allclose(got["contact_force"], want.contact_force, **tol)
    for key, value in (("rotation_per_push", want.omega), ("slip_per_push", want.slip), ("power", want.power)):
        np.testing.assert_allclose(got[key], value, **tol, err_msg=key)
    if exact:
        assert got["kkt_residual"] == want.kkt_residual
        assert got["gap"] == want.gap
        assert got["iterations"] == want.iterations
    ms = mason_sense(scene.contact_rel, scene.normal, scene.push_hat, mu_c)
    assert got["mason_sense"] == ms
    assert got["mason_agrees"] == (ms == want.sense)


# ---------------------------------------------------------------------------------------
# One support
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("method", ["newton", "cvxpy", "casadi"])
@pytest.mark.parametrize("mu_c", [0.0, 0.4])
def test_single_support_is_the_solver_answer(client, method, mu_c):
    body = {**PUSH, "support": TRIPOD, "mu_c": mu_c, "method": method}
    r, got = post(client, body)
    assert r.status_code == 200, r.text
    assert got["input"] == "support" and got["method"] == method and got["mu_c"] == mu_c
    assert got["motions"] is None and got["batch"] is None and got["pressure"] is None
    a = max(0.6, math.hypot(0.5, 0.3))  # default: farthest support point or contact
    assert got["disk_radius"] == pytest.approx(a, rel=1e-15)
    scene = scene_of(body, a)
    support = Support.create(TRIPOD["points"], TRIPOD["weights"], (0.0, 0.0))
    want = solve_forward(scene, support, mu_c=mu_c, method=method)
    # casadi and the polished cvxpy answers may differ in the last bits between runs.
    assert_motion_equals(got["motion"], want, scene, mu_c, exact=method == "newton")
    assert got["motion"]["method"] == method
    assert got["motion"]["kkt_residual"] <= 1e-9
    assert abs(got["motion"]["gap"]) <= 1e-9
    assert got["solve_time_ms"] > 0.0 and got["elapsed_ms"] >= got["solve_time_ms"]


def test_motion_per_push_matches_the_scene_formulas(client):
    """rotation_per_push and slip_per_push are (3.3) and (3.2) at the returned COR."""
    for contact in ([-0.5, -0.3], [-0.5, 0.4], [-0.2, -0.55]):
        body = {"contact_point": contact, "edge_angle": HALF_PI, "push_direction": 0.2, "support": TRIPOD}
        r, got = post(client, body)
        assert r.status_code == 200, r.text
        scene = scene_of(body, got["disk_radius"])
        m = got["motion"]
        assert m["rotation_per_push"] == pytest.approx(scene.rotation_per_push(m["cor"]), rel=1e-9)
        assert m["slip_per_push"] == pytest.approx(scene.slip_per_push(m["cor"]), rel=1e-9, abs=1e-12)


def test_impact_cor_uses_the_supports_radius_of_gyration(client):
    r, got = post(client, {**PUSH, "support": TRIPOD})
    scene = scene_of(PUSH, got["disk_radius"])
    rho = support_radius_of_gyration(TRIPOD["points"], TRIPOD["weights"])
    assert got["impact"]["source"] == "support"
    assert got["impact"]["radius_of_gyration"] == pytest.approx(rho, rel=1e-15)
    np.testing.assert_allclose(got["impact"]["cor"], impact_cor(scene, rho), rtol=1e-15, atol=1e-15)
    assert got["impact"]["distance"] == pytest.approx(rho**2 / abs(scene.moment_arm), rel=1e-15)


def test_explicit_disk_radius_and_center_of_mass(client):
    shift = np.array([10.0, -5.0])
    body = {"contact_point": (np.array(PUSH["contact_point"]) + shift).tolist(), "edge_angle": HALF_PI,
            "center_of_mass": shift.tolist(), "disk_radius": 2.0,
            "support": {"points": (np.array(TRIPOD["points"]) + shift).tolist(), "weights": TRIPOD["weights"]}}
    r, got = post(client, body)
    assert r.status_code == 200, r.text
    assert got["disk_radius"] == 2.0 and got["center_of_mass"] == shift.tolist()
    r0, got0 = post(client, {**PUSH, "support": TRIPOD})
    np.testing.assert_allclose(np.array(got["motion"]["cor"]) - shift, got0["motion"]["cor"], atol=1e-9)


def test_cor_on_support_is_an_index_into_the_request(client):
    r, got = post(client, {**PUSH, "support": DIPOD_ON_POINT})
    assert got["motion"]["cor_on_support"] == 0
    np.testing.assert_allclose(got["motion"]["cor"], [0.0, 0.8], atol=1e-12)
    # A zero-weight point first and a duplicate: the index still names the request's point.
    sup = {"points": [[0.3, 0.3], [0.0, -0.2], [0.0, 0.8], [0.0, -0.2]], "weights": [0, 2, 1, 2]}
    r, got = post(client, {**PUSH, "support": sup})
    assert r.status_code == 200, r.text
    assert got["motion"]["cor_on_support"] == 2


def test_translation_has_a_null_cor(client):
    body = {"contact_point": [-0.5, 0.0], "edge_angle": HALF_PI, "support": {"points": [[0.5, 0], [-0.5, 0]], "weights": [1, 1]}}
    r, got = post(client, body)
    assert r.status_code == 200, r.text
    m = got["motion"]
    assert m["kind"] == "translation" and m["cor"] is None and m["sense"] == "none"
    assert m["mason_sense"] == "none" and m["mason_agrees"] is True
    assert abs(m["rotation_per_push"]) < 1e-12
    np.testing.assert_allclose(m["velocity_cm"], [1.0, 0.0], atol=1e-12)
    assert got["impact"]["cor"] is None and got["impact"]["distance"] is None


MASON_CASES = [
    # (contact, push_direction, mu_c)
    ([-0.5, -0.3], 0.0, 0.0),
    ([-0.5, 0.3], 0.0, 0.0),
    ([-0.5, -0.3], 0.0, 0.5),  # force cone straddles the CM: the push line decides
    ([-0.5, -0.05], 0.0, 0.5),
    ([-0.5, -0.3], 0.6, 2.0),
    ([-0.5, 0.45], -0.4, 0.1),
]


@pytest.mark.parametrize("case", range(len(MASON_CASES)))
def test_sense_agrees_with_masons_rules(client, case):
    contact, push, mu_c = MASON_CASES[case]
    rng = np.random.default_rng(case)
    pts, wts = random_balanced_tripods(rng, 20, 1.0)
    supports = [{"points": p.tolist(), "weights": w.tolist()} for p, w in zip(pts, wts)]
    body = {"contact_point": contact, "edge_angle": HALF_PI, "push_direction": push, "mu_c": mu_c,
            "disk_radius": 1.0, "supports": supports}
    r, got = post(client, body)
    assert r.status_code == 200, r.text
    scene = scene_of(body, 1.0)
    want = mason_sense(scene.contact_rel, scene.normal, scene.push_hat, mu_c)
    for m in got["motions"]:
        assert m["mason_sense"] == want
        assert m["sense"] == want and m["mason_agrees"] is True


# ---------------------------------------------------------------------------------------
# Batches
# ---------------------------------------------------------------------------------------


def _mixed_batch(rng):
    pts, wts = random_balanced_tripods(rng, 12, 1.0)
    sups = [{"points": p.tolist(), "weights": w.tolist()} for p, w in zip(pts, wts)]
    sups.insert(3, DIPOD_ON_POINT)
    sups.insert(7, {"points": [[0.5, 0.5], [-0.5, 0.5], [-0.5, -0.5], [0.5, -0.5]], "weights": [1, 2, 1, 2]})
    sups.insert(9, {"points": [[0.3, 0.3], [0.0, -0.2], [0.0, 0.8], [0.0, -0.2]], "weights": [0, 2, 1, 2]})
    return sups


@pytest.mark.parametrize("mu_c", [0.0, 0.5, 50.0])
def test_batch_agrees_with_single_solves(client, mu_c):
    sups = _mixed_batch(np.random.default_rng(11))
    body = {**PUSH, "disk_radius": 1.0, "mu_c": mu_c, "supports": sups}
    r, got = post(client, body)
    assert r.status_code == 200, r.text
    assert got["input"] == "supports" and got["motion"] is None and got["impact"] is None
    assert got["batch"]["n"] == len(sups) == len(got["motions"])
    assert got["batch"]["converged"] == len(sups)
    assert got["batch"]["support_sizes"] == [2, 3, 4]
    for i, sup in enumerate(sups):
        r1, one = post(client, {**PUSH, "disk_radius": 1.0, "mu_c": mu_c, "support": sup})
        s, b = one["motion"], got["motions"][i]
        for key in ("status", "mode", "kind", "sense", "mason_sense", "mason_agrees", "cor_on_support"):
            assert b[key] == s[key], (i, key)
        np.testing.assert_allclose(b["cor"], s["cor"], rtol=1e-9, atol=1e-9)
        for key in ("rotation_per_push", "slip_per_push", "power"):
            assert b[key] == pytest.approx(s[key], rel=1e-9, abs=1e-9), (i, key)
        np.testing.assert_allclose(b["contact_force"], s["contact_force"], rtol=1e-8, atol=1e-8)
        assert abs(b["gap"]) <= 1e-9 * b["power"] and b["iterations"] == s["iterations"]
    if mu_c == 0.0:
        assert got["motions"][3]["cor_on_support"] == 0
        assert got["motions"][9]["cor_on_support"] == 2


@pytest.mark.parametrize("method", ["cvxpy", "casadi"])
def test_slow_method_batch_agrees_with_newton(client, method):
    sups = _mixed_batch(np.random.default_rng(5))[:6]
    base = {**PUSH, "disk_radius": 1.0, "mu_c": 0.3, "supports": sups}
    r, got = post(client, {**base, "method": method})
    assert r.status_code == 200, r.text
    r0, ref = post(client, base)
    for m, m0 in zip(got["motions"], ref["motions"]):
        assert m["method"] == method and m["status"] == "optimal"
        assert m["gap"] is not None and m["iterations"] is not None
        np.testing.assert_allclose(m["cor"], m0["cor"], rtol=1e-7, atol=1e-7)


def test_batch_with_a_translation(client):
    body = {"contact_point": [-0.5, 0.0], "edge_angle": HALF_PI, "disk_radius": 1.0,
            "supports": [{"points": [[0.5, 0], [-0.5, 0]], "weights": [1, 1]}, TRIPOD]}
    r, got = post(client, body)
    assert r.status_code == 200, r.text
    assert got["motions"][0]["cor"] is None and got["motions"][0]["kind"] == "translation"
    assert got["batch"]["translations"] >= 1


# ---------------------------------------------------------------------------------------
# Modelled pressure (figure 7-1)
# ---------------------------------------------------------------------------------------


def test_uniform_pressure_on_the_disk(client):
    body = {**PUSH, "disk_radius": 1.0, "pressure": {"kind": "uniform", "resolution": 16}}
    r, got = post(client, body)
    assert r.status_code == 200, r.text
    scene = scene_of(body, 1.0)
    want = uniform_pressure_cor(scene, None, resolution=16)
    assert_motion_equals(got["motion"], want, scene, 0.0)
    assert got["pressure"] == {"kind": "uniform", "region": "disk", "resolution": 16, "n_cells": 6 * 16 * 16}
    assert got["impact"]["source"] == "uniform_disk"
    assert got["impact"]["radius_of_gyration"] == pytest.approx(math.sqrt(0.5))


def test_uniform_pressure_on_a_polygon(client):
    square = [[-1, -0.5], [1, -0.5], [1, 0.5], [-1, 0.5]]
    body = {"contact_point": [-1.0, -0.2], "edge_angle": HALF_PI, "mu_c": 0.2,
            "pressure": {"kind": "uniform", "footprint": square, "resolution": 8}}
    r, got = post(client, body)
    assert r.status_code == 200, r.text
    fp = Footprint.create(square)
    assert got["disk_radius"] == pytest.approx(fp.circumradius) and got["center_of_mass"] == [0.0, 0.0]
    scene = scene_of(body, fp.circumradius)
    want = uniform_pressure_cor(scene, fp, resolution=8, mu_c=0.2)
    assert_motion_equals(got["motion"], want, scene, 0.2)
    assert got["pressure"]["region"] == "polygon" and got["pressure"]["n_cells"] == 2 * 64
    assert got["impact"]["radius_of_gyration"] == pytest.approx(polygon_radius_of_gyration(fp), rel=1e-14)


# ---------------------------------------------------------------------------------------
# 422: every invalid input names its field
# ---------------------------------------------------------------------------------------

SUP = {**PUSH, "support": TRIPOD}

INVALID = {
    "negative-weight": ({**PUSH, "support": {"points": TRIPOD["points"], "weights": [1, -1, 1]}},
                        ["body", "support", "weights", 1]),
    "centroid-not-at-cm": ({**PUSH, "support": {"points": TRIPOD["points"], "weights": [1, 1, 2]}},
                           ["body", "support", "weights"]),
    "all-weights-zero": ({**PUSH, "support": {"points": TRIPOD["points"], "weights": [0, 0, 0]}},
                         ["body", "support", "weights"]),
    "mismatched-lengths": ({**PUSH, "support": {"points": TRIPOD["points"], "weights": [1, 1]}},
                           ["body", "support", "weights"]),
    "nan-point": ('{"contact_point": [-0.5, -0.3], "edge_angle": 1.5, "support": '
                  '{"points": [[NaN, 0], [1, 0]], "weights": [1, 1]}}', ["body", "support", "points", 0, 0]),
    "nan-weight": ('{"contact_point": [-0.5, -0.3], "edge_angle": 1.5, "support": '
                   '{"points": [[-1, 0], [1, 0]], "weights": [1, NaN]}}', ["body", "support", "weights", 1]),
    "string-weight": ({**PUSH, "support": {"points": TRIPOD["points"], "weights": [1, "1", 1]}},
                      ["body", "support", "weights", 1]),
    "string-point": ({**PUSH, "support": {"points": [[0.6, 0], ["a", 0.5], [-0.3, -0.5]], "weights": [1, 1, 1]}},
                     ["body", "support", "points", 1, 0]),
    "weight-too-big": ({**PUSH, "support": {"points": TRIPOD["points"], "weights": [1e300, 1e300, 1e300]}},
                       ["body", "support", "weights", 0]),
    "empty-support": ({**PUSH, "support": {"points": [], "weights": []}}, ["body", "support", "points"]),
    "mu-negative": ({**SUP, "mu_c": -0.1}, ["body", "mu_c"]),
    "mu-too-big": ({**SUP, "mu_c": MAX_MU_C * 2}, ["body", "mu_c"]),
    "mu-string": ({**SUP, "mu_c": "0.1"}, ["body", "mu_c"]),
    "unknown-method": ({**SUP, "method": "simplex"}, ["body", "method"]),
    "radius-zero": ({**SUP, "disk_radius": 0}, ["body", "disk_radius"]),
    "radius-negative": ({**SUP, "disk_radius": -1}, ["body", "disk_radius"]),
    "radius-below-support": ({**SUP, "disk_radius": 0.5}, ["body", "disk_radius"]),
    "nothing-given": (dict(PUSH), ["body", "support"]),
    "two-given": ({**SUP, "supports": [TRIPOD]}, ["body", "supports"]),
    "empty-batch": ({**PUSH, "supports": []}, ["body", "supports"]),
    "batch-item-bad": ({**PUSH, "supports": [TRIPOD, {"points": TRIPOD["points"], "weights": [1, 1, 2]}]},
                       ["body", "supports", 1, "weights"]),
    "batch-too-large-slow": ({**PUSH, "method": "cvxpy", "supports": [TRIPOD] * (MAX_BATCH_SLOW + 1)},
                             ["body", "supports"]),
    "support-too-large-slow": (
        {**PUSH, "method": "casadi", "support": {
            "points": [[math.cos(t), math.sin(t)] for t in np.linspace(0, 2 * math.pi, MAX_SUPPORT_POINTS_SLOW + 1,
                                                                          endpoint=False)],
            "weights": [1] * (MAX_SUPPORT_POINTS_SLOW + 1)}},
        ["body", "support", "points"]),
    "pressure-disk-without-radius": ({**PUSH, "pressure": {"kind": "uniform"}}, ["body", "disk_radius"]),
    "pressure-unknown-kind": ({**PUSH, "disk_radius": 1, "pressure": {"kind": "gaussian"}},
                              ["body", "pressure", "kind"]),
    "pressure-too-fine-for-cvxpy": ({**PUSH, "disk_radius": 1, "method": "cvxpy",
                                     "pressure": {"kind": "uniform", "resolution": 8}},
                                    ["body", "pressure", "resolution"]),
    "pressure-resolution-zero": ({**PUSH, "disk_radius": 1, "pressure": {"kind": "uniform", "resolution": 0}},
                                 ["body", "pressure", "resolution"]),
    "pressure-self-crossing": ({**PUSH, "pressure": {"kind": "uniform",
                                                     "footprint": [[0, 0], [2, 0], [2, 1], [1, -1], [0, 1]]}},
                               ["body", "pressure", "footprint"]),
    "pressure-cm-not-centroid": ({**PUSH, "center_of_mass": [0.2, 0.0], "pressure": {
        "kind": "uniform", "footprint": [[-1, -1], [1, -1], [1, 1], [-1, 1]]}}, ["body", "center_of_mass"]),
    "push-parallel": ({**SUP, "push_direction": HALF_PI}, ["body", "push_direction"]),
    "extra-field": ({**SUP, "friction": 0.3}, ["body", "friction"]),
}


@pytest.mark.parametrize("case", sorted(INVALID))
def test_invalid_input_is_422_naming_the_field(client, case):
    body, loc = INVALID[case]
    if isinstance(body, str):
        r = client.post(URL, content=body, headers={"content-type": "application/json"})
    else:
        r = client.post(URL, json=body)
    assert r.status_code == 422, r.text
    detail = strict_json(r.text)["detail"]
    locs = [d["loc"] for d in detail]
    assert any(d_loc[: len(loc)] == loc for d_loc in locs), locs
    for d in detail:
        assert d["msg"] and d["type"] and "Traceback" not in d["msg"]


@pytest.mark.slow
def test_newton_batch_size_limit(client):
    r = client.post(URL, json={**PUSH, "supports": [{"points": [[0, 0]], "weights": [1]}] * (MAX_BATCH + 1)})
    assert r.status_code == 422
    assert r.json()["detail"][0]["loc"] == ["body", "supports"]
    assert r.json()["detail"][0]["type"] == "too_long"


def test_batch_size_limits(client, monkeypatch):
    import service.api.motion.convert as conv

    monkeypatch.setattr(conv, "MAX_BATCH_POINTS", 8)
    r = client.post(URL, json={**PUSH, "supports": [TRIPOD, TRIPOD, TRIPOD]})
    assert r.status_code == 422
    assert r.json()["detail"][0]["loc"] == ["body", "supports"]
    assert "points in all" in r.json()["detail"][0]["msg"]


def test_solver_errors_are_422_not_500(client, monkeypatch):
    import solver.motion.solve as solve

    def fail(*args, **kwargs):
        raise SolverError("minimum-power problem ended with status infeasible")

    monkeypatch.setattr(solve, "solve_forward", fail)
    r = client.post(URL, json={**SUP, "method": "cvxpy"})
    assert r.status_code == 422
    d = r.json()["detail"][0]
    assert d["loc"] == ["body"] and d["type"] == "solver_error" and "infeasible" in d["msg"]


def test_subnormal_disk_is_422_not_500(client):
    """Found by the contract test: uniform pressure on a disk of radius 5e-324 divided by
    zero inside the discretisation."""
    r = client.post(URL, json={"contact_point": [0.0, 0.0], "edge_angle": 1.0, "disk_radius": 5e-324,
                               "pressure": {"kind": "uniform"}})
    assert r.status_code == 422, r.text
    assert r.json()["detail"][0]["type"] in ("numeric_range", "value_error")


def test_degenerate_inputs_are_not_server_errors(client):
    for body in (
        {"contact_point": [0, 0], "edge_angle": HALF_PI, "support": {"points": [[0, 0]], "weights": [1]}},
        {"contact_point": [0, 0], "edge_angle": HALF_PI, "disk_radius": 1,
         "support": {"points": [[0, 0]], "weights": [1]}},
        {"contact_point": [-0.5, -0.3], "edge_angle": HALF_PI, "support": {"points": [[0, 0]], "weights": [1e-300]}},
        {"contact_point": [-0.5, -0.3], "edge_angle": HALF_PI, "mu_c": MAX_MU_C, "support": TRIPOD},
    ):
        r = client.post(URL, json=body)
        assert r.status_code in (200, 422), r.text
        strict_json(r.text)


@pytest.mark.parametrize("edge_angle", [3 * math.pi / 4, -math.pi / 4])
def test_mason_agrees_with_the_solver_on_a_translation(client, edge_angle):
    """A frictionless push whose normal passes through the CM (contact (-0.3, -0.3), edge
    at 135 degrees) translates: the solver says so and Mason's rule now does too (it said
    'ccw' from the push direction, ignoring the translation)."""
    r = client.post(URL, json={"contact_point": [-0.3, -0.3], "edge_angle": edge_angle, "mu_c": 0.0, "support": TRIPOD})
    m = r.json()["motion"]
    assert m["kind"] == "translation" and m["sense"] == m["mason_sense"] == "none" and m["mason_agrees"]
