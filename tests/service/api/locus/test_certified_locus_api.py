"""POST /v1/cor/locus with `footprint` and `method` 'certified' (book 3.3.13, 7.5).

The certified brackets are those of solver.locus.certified_locus (the service runs the same
steps under a time limit and must give exactly the solver's answer when it finishes);
`footprint` with method 'analytic' keeps the old `workpiece` behaviour (the circumscribing
disk's locus) and says so; invalid inputs are 422 naming the field.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.footprint import Footprint
from models.core.scene import PushScene
from service.common.scene import DEPRECATED_WORKPIECE
from service.limits import MAX_CERTIFIED_POINTS, MAX_TIME_LIMIT_S, MIN_CERTIFIED_POINTS
from solver.locus.certified_locus import certified_disk_boundary, certified_polygon_boundary

URL = "/v1/cor/locus"
HALF_PI = math.pi / 2
DISK = {"disk_radius": 1.0, "contact_point": [-0.5, -0.3], "edge_angle": HALF_PI}
RECT = [[-1, -0.5], [1, -0.5], [1, 0.5], [-1, 0.5]]
POLY = {"footprint": RECT, "contact_point": [-1.0, -0.3], "edge_angle": HALF_PI}


def post(client, body, params=None):
    r = client.post(URL, json=body, params=params)
    assert r.status_code == 200, r.text
    return r.json()


@pytest.mark.slow
def test_certified_disk_is_the_solver_answer(client):
    got = post(client, {**DISK, "method": "certified", "n_certified": 8})
    assert got["method"] == "certified" and got["locus_of"] == "disk"
    c = got["certified"]
    scene = PushScene.create(1.0, DISK["contact_point"], HALF_PI)
    want = certified_disk_boundary(scene, n_points=8)
    assert c["region"] == "disk" and c["complete"] is True
    assert c["n_requested"] == c["n_done"] == len(want.pairs) == 8
    assert c["n_certified"] == want.n_certified == 8
    assert c["wrong"] == list(want.wrong) == [] and c["undecided"] == list(want.undecided) == []
    assert c["bracket_width"] == pytest.approx(2.0 * want.delta, rel=1e-15)
    np.testing.assert_array_equal(c["boundary"], want.boundary)
    for b, p in zip(c["brackets"], want.pairs):
        assert b["verdict"] == p.verdict == "bracketed"
        assert (b["inner_status"], b["outer_status"]) == (p.inner.status, p.outer.status) == ("inside", "outside")
        np.testing.assert_array_equal(b["inner"], p.inner.cor)
        np.testing.assert_array_equal(b["outer"], p.outer.cor)
    # The analytic outputs are today's, and the certified points are the analytic boundary.
    analytic = post(client, {**DISK, "n_points": 8})
    assert analytic["method"] == "analytic" and analytic["certified"] is None
    np.testing.assert_array_equal(c["boundary"], analytic["boundary"])
    assert got["tip"] == analytic["tip"]


@pytest.mark.slow
def test_certified_polygon_is_the_solver_answer(client):
    got = post(client, {**POLY, "method": "certified", "n_certified": 6, "outputs": []})
    assert got["locus_of"] == "circumscribing_disk"
    c = got["certified"]
    fp = Footprint.create(RECT)
    scene = PushScene.create(fp.circumradius, POLY["contact_point"], HALF_PI)
    want = certified_polygon_boundary(scene, fp, n_rays=6)
    assert c["region"] == "polygon" and c["complete"] is True and c["n_done"] == 6
    assert c["n_certified"] == want.n_certified == 6
    np.testing.assert_array_equal(c["boundary"], want.boundary)
    np.testing.assert_array_equal(c["centre"], want.centre)
    assert c["bracket_width"] == want.width
    assert c["multi_crossing"] == list(want.multi_crossing_rays)
    for b, ray in zip(c["brackets"], want.rays):
        assert b["verdict"] == ray.verdict and b["crossings"] == ray.crossings
        np.testing.assert_array_equal(b["inner"], ray.inner.cor)
        np.testing.assert_array_equal(b["outer"], ray.outer.cor)
    # The polygon's exact locus lies inside the circumscribing disk's (7.5): every certified
    # outer end is closer to the CM than the disk locus' tip.
    disk = post(client, {**POLY, "outputs": ["tip"]})
    assert max(np.hypot(*p) for p in c["boundary"]) < disk["r_tip"]


@pytest.mark.wall_clock  # about the time limit itself: its real deadline (tests/service/conftest.py)
def test_time_limit_stops_early_and_says_so(client):
    r = client.post("/v1/cor/locus", json={**POLY, "method": "certified", "n_certified": 64, "time_limit_s": 1e-6,
                                           "outputs": []})
    assert r.status_code == 504  # not one ray certified: nothing of what was asked (issue 25)
    got = r.json()["partial"]  # the analytic locus, and the certified part saying why it is empty
    c = got["certified"]
    assert c["complete"] is False and c["n_done"] == 0 and c["time_limit_s"] == 1e-6
    assert len(c["boundary"]) == len(c["brackets"]) == c["n_done"]
    assert any("time limit" in w for w in got["warnings"])
    disk = post(client, {**DISK, "method": "certified", "n_certified": 64, "time_limit_s": 1e-6, "outputs": []})
    assert disk["certified"]["complete"] is False and 0 < disk["certified"]["n_done"] < 64


def test_footprint_analytic_keeps_the_workpiece_behaviour(client):
    old = post(client, {"workpiece": RECT, "contact_point": [-1.0, -0.3], "edge_angle": HALF_PI})
    new = post(client, POLY)
    assert new["locus_of"] == old["locus_of"] == "circumscribing_disk"
    for key in ("disk_radius", "center_of_mass", "r_tip", "tip", "boundary", "contact_distance_to_outline"):
        assert new[key] == old[key], key
    # the old name still works, and the answer says it is deprecated (issue 35)
    assert old["warnings"] == [*new["warnings"], DEPRECATED_WORKPIECE]
    assert post(client, DISK)["locus_of"] == "disk"


@pytest.mark.slow
def test_workpiece_with_method_certified_traces_the_polygon(client):
    got = post(client, {"workpiece": RECT, "contact_point": [-1.0, -0.3], "edge_angle": HALF_PI,
                        "method": "certified", "n_certified": 4, "outputs": []})
    assert got["certified"]["region"] == "polygon"


def test_translation_has_nothing_to_certify(client):
    got = post(client, {**DISK, "contact_point": [-0.5, 0.0], "method": "certified"})
    assert got["kind"] == "translation" and got["certified"] is None
    assert any("nothing to certify" in w for w in got["warnings"])


def test_svg_with_certified_is_422(client):
    r = client.post(URL, json={**DISK, "method": "certified"}, params={"format": "svg"})
    assert r.status_code == 422
    assert r.json()["detail"][0]["loc"] == ["query", "format"]


INVALID = {
    "footprint-and-workpiece": ({**POLY, "workpiece": RECT}, ["body", "footprint"]),
    "footprint-and-disk": ({**POLY, "disk_radius": 1.0}, ["body", "footprint"]),
    "footprint-self-crossing": ({**POLY, "footprint": [[0, 0], [2, 0], [2, 1], [1, -1], [0, 1]]},
                                ["body", "footprint"]),
    "footprint-two-vertices": ({**POLY, "footprint": [[0, 0], [1, 0]]}, ["body", "footprint"]),
    "unknown-method": ({**DISK, "method": "exact"}, ["body", "method"]),
    "n-certified-small": ({**DISK, "method": "certified", "n_certified": MIN_CERTIFIED_POINTS - 1},
                          ["body", "n_certified"]),
    "n-certified-big": ({**DISK, "method": "certified", "n_certified": MAX_CERTIFIED_POINTS + 1},
                        ["body", "n_certified"]),
    "time-zero": ({**DISK, "method": "certified", "time_limit_s": 0}, ["body", "time_limit_s"]),
    "time-too-long": ({**DISK, "method": "certified", "time_limit_s": MAX_TIME_LIMIT_S * 2}, ["body", "time_limit_s"]),
    "radius-zero": ({**DISK, "disk_radius": 0, "method": "certified"}, ["body", "disk_radius"]),
}


@pytest.mark.parametrize("case", sorted(INVALID))
def test_invalid_input_is_422_naming_the_field(client, case):
    body, loc = INVALID[case]
    r = client.post(URL, json=body)
    assert r.status_code == 422, r.text
    assert any(d["loc"][: len(loc)] == loc for d in r.json()["detail"]), r.json()
