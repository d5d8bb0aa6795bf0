"""POST /v1/feeder/map and /v1/feeder/simulate (book 5.1, 5.2, 5.4, 6.4-6.6) against the
solver called directly, and their input errors (422 naming the field)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.feeder.fence import Fence, feeder_part, fence_map
from models.feeder.layout import lay_out
from models.feeder.maps import sequence
from solver import FenceSegment, simulate_belt_batch

PENTAGON = {"vertices": [[0, 0], [3, 0], [3.5, 1.5], [1.5, 2.5], [-0.5, 1.2]], "center_of_mass": [1.4, 1.0]}
SQUARE = {"vertices": [[0, 0], [1, 0], [1, 1], [0, 1]], "center_of_mass": [0.5, 0.5]}
SUPPORT = {"points": [[0.7, 0.6], [0.4, 0.65], [0.4, 0.25]], "weights": [1, 1, 1]}


def test_map_of_two_fences_equals_the_models_product_5_4(client):
    body = {"part": PENTAGON, "fences": [{"angle": 0.7, "mu_c": 0.25}, {"angle": -0.9, "mu_c_range": [0.1, 0.3]}],
            "resolution": 72}
    r = client.post("/v1/feeder/map", json=body)
    assert r.status_code == 200, r.text
    out = r.json()
    assert out["complete"] and out["status"] == "ok" and out["bound"] == "disk"
    part = feeder_part(PENTAGON["vertices"], PENTAGON["center_of_mass"])
    maps = [fence_map(part, Fence.create(0.7, 0.25)), fence_map(part, Fence.create(-0.9, (0.1, 0.3)))]
    for got, ref in zip(out["fences"], maps):
        assert [b["edge"] for b in got["bands"]] == list(ref.final_edges)
        for band, b_ref, k_ref in zip(got["bands"], ref.map.bands, ref.map.kernels):
            assert np.allclose(band["band"], b_ref.arcs) and np.allclose(band["kernel"], k_ref.arcs)
            assert 0.0 <= band["turn_least"] <= band["turn_most"] == pytest.approx(0.5 * math.pi - abs(got["angle"]))
    product = sequence([m.map for m in maps])
    assert [sorted(c) for c in product.code_sets] == [b["code_set"] for b in out["product"]["bands"]]
    rows = out["matrix"]["rows"]
    assert len(rows) == 72 and all(len(row) == 72 for row in rows)
    assert np.array_equal(np.array([[c == "1" for c in row] for row in rows]), product.matrix(72))


def test_a_fence_below_the_friction_angle_jams_everything_6_4(client):
    r = client.post("/v1/feeder/map", json={"part": SQUARE, "fences": [{"angle": 0.3, "mu_c": 0.5}]})
    assert r.status_code == 200, r.text
    f = r.json()["fences"][0]
    assert f["jams_possible"] and f["bands"] == [] and f["jam"] == [[0.0, 2 * math.pi]]


def test_simulation_through_two_fences_lands_in_the_maps(client):
    body = {"part": SQUARE, "support": SUPPORT, "fences": [{"angle": 0.7, "mu_c": 0.25}, {"angle": -0.8, "mu_c": 0.25}],
            "theta_initial": 0.3, "trajectory_points": 5}
    r = client.post("/v1/feeder/simulate", json=body)
    assert r.status_code == 200, r.text
    out = r.json()
    assert out["complete"] and out["status"] == "left" and len(out["runs"]) == 2
    assert all(run["in_map"] for run in out["runs"])
    assert out["runs"][1]["theta_initial"] == out["runs"][0]["theta_final"]
    assert out["theta_final"] == out["runs"][1]["theta_final"]
    assert all(len(run["trajectory"]) == 5 and run["forward_solves"] > 0 for run in out["runs"])
    kinds = [e["kind"] for e in out["runs"][0]["events"]]
    assert kinds[0] == "contact" and "flush" in kinds and kinds[-1] == "left"


def placed_square(width_radii=12.0):
    """Two alternating fences for the square laid out on a belt (world frame), as request
    fences, with the lane's start above the first."""
    a = math.sqrt(0.5)
    lay = lay_out([0.7, -0.8], a, width_radii * a, 0.1 * a, 2.0 * a)
    fences = [{"angle": f.angle, "mu_c": 0.25, "end": f.end.tolist(), "length": f.length} for f in lay.fences]
    return fences, [lay.entry_x, 1.1 * a], lay


def test_a_part_through_placed_fences_is_picked_up_where_it_left_the_last_1_8_6(client):
    """Fences given as world-frame segments are met one after the other from the start (a
    belt, figure 1-9): the answer equals the solver's belt simulation, the trajectory is in
    the world frame, each run starts where the one before ended, and the top view is one
    panel."""
    fences, start, lay = placed_square()
    body = {"part": SQUARE, "support": SUPPORT, "fences": fences, "theta_initial": 0.3, "start": start,
            "trajectory_points": 2000}
    r = client.post("/v1/feeder/simulate", json=body)
    assert r.status_code == 200, r.text
    out = r.json()
    assert out["complete"] and out["status"] == "left" and [run["status"] for run in out["runs"]] == ["left"] * 2
    assert all(run["in_map"] for run in out["runs"])
    first, second = out["runs"]
    assert first["trajectory"][0][1:3] == pytest.approx(start)
    assert second["trajectory"][0][1:3] == pytest.approx(first["trajectory"][-1][1:3])
    part = feeder_part(SQUARE["vertices"], SQUARE["center_of_mass"])
    body_pts = np.array(SUPPORT["points"]) - np.array(SQUARE["center_of_mass"])
    segs = [FenceSegment.create(Fence.create(f.angle, 0.25), f.end, f.length) for f in lay.fences]
    (ref,) = simulate_belt_batch(part, segs, 0.25, [(body_pts, np.ones(3) / 3)], [0.3], [start])
    assert out["theta_final"] == pytest.approx(ref.theta_final, abs=1e-9)
    r = client.post("/v1/feeder/simulate?format=svg", json=body)
    assert r.status_code == 200 and r.text.count("<g id=\"axes_") == 1


@pytest.mark.parametrize(("patch", "loc"), [
    ({"fences": "no length"}, ["body", "fences", 1, "length"]),
    ({"fences": "one unplaced"}, ["body", "fences", 1, "end"]),
    ({"start": [0.0, 0.0], "fences": "unplaced"}, ["body", "start"]),
    ({"fence_length": 5.0}, ["body", "fence_length"]),
    ({"start": "on the first fence"}, ["body", "start"]),
    ({"start": [1e9, 0.0]}, ["body", "start"]),
])
def test_bad_placed_fences_are_422_at_their_field(client, patch, loc):
    fences, start, _ = placed_square()
    body = {"part": SQUARE, "support": SUPPORT, "fences": fences, "theta_initial": 0.3, "start": start}
    body.update(patch)
    if patch.get("fences") == "no length":
        body["fences"] = [fences[0], {k: v for k, v in fences[1].items() if k != "length"}]
    elif patch.get("fences") == "one unplaced":
        body["fences"] = [fences[0], {"angle": -0.8, "mu_c": 0.25}]
    elif patch.get("fences") == "unplaced":
        body["fences"] = [{"angle": 0.7, "mu_c": 0.25}]
    if patch.get("start") == "on the first fence":
        end, w = np.array(fences[0]["end"]), np.array([math.cos(0.7), math.sin(0.7)])
        body["start"] = (end + 0.5 * fences[0]["length"] * w).tolist()
    r = client.post("/v1/feeder/simulate", json=body)
    assert r.status_code == 422, r.text
    assert r.json()["detail"][0]["loc"][:len(loc)] == loc


def test_a_step_limit_is_an_incomplete_answer(client):
    body = {"part": SQUARE, "support": SUPPORT, "fences": [{"angle": 0.7, "mu_c": 0.25}], "theta_initial": 0.3,
            "max_steps": 2}
    out = client.post("/v1/feeder/simulate", json=body).json()
    assert out["status"] == "step_limit" and not out["complete"] and out["theta_final"] is None
    assert out["runs"][0]["in_map"] is None


def test_a_reach_reports_the_orientations_it_may_not_align_1_8_6(client):
    """The map of a fence given a reach carries the model's unaligned orientations, per fence
    and through the product; without a reach none are reported."""
    body = {"part": PENTAGON, "fences": [{"angle": 0.7, "mu_c": 0.25, "reach": 3.0}, {"angle": -0.9, "mu_c": 0.15}],
            "resolution": 36}
    out = client.post("/v1/feeder/map", json=body).json()
    part = feeder_part(PENTAGON["vertices"], PENTAGON["center_of_mass"])
    ref = fence_map(part, Fence.create(0.7, 0.25, reach=3.0)).map
    first, second = out["fences"]
    assert first["reach"] == 3.0 and np.allclose(first["unaligned"], ref.unaligned.arcs) and first["unaligned"]
    assert any("reach" in note for note in first["notes"])
    assert second["reach"] is None and second["unaligned"] == []
    product = sequence([ref, fence_map(part, Fence.create(-0.9, 0.15)).map])
    assert np.allclose(out["product"]["unaligned"], product.unaligned.arcs)
    rows = np.array([[c == "1" for c in row] for row in out["matrix"]["rows"]])
    assert rows[:, product.unaligned.cells(36)].all()


def test_maps_and_runs_as_svg_pictures_figures_1_8_5_2(client):
    """format=svg draws the maps (one panel per fence and the product, figure 1-8 / 5-2) and
    the runs (a top view per fence); the same request gives the same bytes."""
    body = {"part": PENTAGON, "fences": [{"angle": -1.0472, "mu_c": 0.25, "reach": 3.0}, {"angle": 1.0472, "mu_c": 0.25}]}
    r = client.post("/v1/feeder/map?format=svg", json=body)
    assert r.status_code == 200 and r.headers["content-type"].startswith("image/svg+xml")
    assert r.text.lstrip().startswith("<?xml") and "<svg" in r.text
    assert r.text.count("<g id=\"axes_") == 3  # two fences and their product
    assert client.post("/v1/feeder/map?format=svg", json=body).content == r.content
    sim = {"part": SQUARE, "support": SUPPORT, "fences": [{"angle": 0.7, "mu_c": 0.25}, {"angle": -0.8, "mu_c": 0.25}],
           "theta_initial": 0.3, "fence_length": 6.0}
    r = client.post("/v1/feeder/simulate?format=svg", json=sim)
    assert r.status_code == 200 and r.headers["content-type"].startswith("image/svg+xml")
    assert r.text.count("<g id=\"axes_") == 2
    assert client.post("/v1/feeder/simulate?format=json", json=sim).json()["status"] == "left"
    assert client.post("/v1/feeder/map?format=png", json=body).status_code == 422


@pytest.mark.parametrize(("fence", "loc"), [
    ({"angle": 0.5, "mu_c": 0.2, "reach": 0.0}, ["body", "fences", 0, "reach"]),
    ({"angle": 0.5, "mu_c": 0.2, "reach": 1e9}, ["body", "fences", 0, "reach"]),
    ({"angle": 2.0, "mu_c": 0.2}, ["body", "fences", 0, "angle"]),
    ({"angle": 0.0, "mu_c": 0.2}, ["body", "fences", 0, "angle"]),
    ({"angle": 0.5}, ["body", "fences", 0, "mu_c"]),
    ({"angle": 0.5, "mu_c": 0.2, "mu_c_range": [0.1, 0.3]}, ["body", "fences", 0, "mu_c"]),
    ({"angle": 0.5, "mu_c_range": [0.3, 0.1]}, ["body", "fences", 0, "mu_c_range"]),
])
def test_bad_fences_are_422_at_their_field(client, fence, loc):
    r = client.post("/v1/feeder/map", json={"part": SQUARE, "fences": [fence]})
    assert r.status_code == 422, r.text
    assert r.json()["detail"][0]["loc"][:len(loc)] == loc


def test_bad_parts_and_supports_are_422_at_their_field(client):
    flat = {"vertices": [[0, 0], [1, 0], [2, 0]], "center_of_mass": [1, 0]}
    r = client.post("/v1/feeder/map", json={"part": flat, "fences": [{"angle": 0.5, "mu_c": 0.1}]})
    assert r.status_code == 422 and r.json()["detail"][0]["loc"][:2] == ["body", "part"]
    off = {"points": [[0.7, 0.6]], "weights": [1]}
    r = client.post("/v1/feeder/simulate", json={"part": SQUARE, "support": off, "fences": [{"angle": 0.7, "mu_c": 0.25}],
                                                 "theta_initial": 0.3})
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["body", "support", "points"]
    assert "centre of mass" in r.json()["detail"][0]["msg"]
    r = client.post("/v1/feeder/simulate", json={"part": SQUARE, "support": {"points": [[0.5, 0.5]], "weights": [1, 2]},
                                                 "fences": [{"angle": 0.7, "mu_c": 0.25}], "theta_initial": 0.3})
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["body", "support", "weights"]


def test_a_map_with_the_parts_own_bound_is_narrower_than_the_disks_and_says_what_it_cost_5_1_7_5(client):
    """The route's plumbing (the bound itself is tested in tests/solver/feeder): the same
    kernels and extremes A as the disk's map, B no earlier and somewhere later, the cost
    reported per fence; a time limit it cannot miss (the work is a few seconds)."""
    triangle = {"vertices": [[0, 0], [2, 0], [0, 3]], "center_of_mass": [2 / 3, 1]}
    body = {"part": triangle, "fences": [{"angle": 0.7, "mu_c": 0.25}], "bound": "part",
            "part_bound": {"contacts": 3, "max_rays_per_aim": 3}, "time_limit_s": 30}
    r = client.post("/v1/feeder/map", json=body)
    assert r.status_code == 200, r.text
    out = r.json()
    assert out["bound"] == "part" and out["complete"] and "own loci" in out["message"]
    cost = out["fences"][0]["part_bound"]
    assert cost["loci"] > 0 and cost["rays"] == cost["rays_bracketed"] + cost["solver_failures"] > 0
    assert cost["dipods"] == 360 * cost["loci"]
    disk = client.post("/v1/feeder/map", json={"part": triangle, "fences": [{"angle": 0.7, "mu_c": 0.25}]}).json()
    assert disk["bound"] == "disk" and disk["fences"][0]["part_bound"] is None
    pairs = list(zip(out["fences"][0]["bands"], disk["fences"][0]["bands"]))
    for own, wide in pairs:
        assert own["kernel"] == wide["kernel"] and own["turn_most"] == wide["turn_most"]
        assert wide["turn_least"] <= own["turn_least"]
    assert any(wide["turn_least"] < own["turn_least"] for own, wide in pairs)


@pytest.mark.parametrize("patch, loc", [
    ({"bound": "sketch"}, ["body", "bound"]),
    ({"time_limit_s": 100}, ["body", "time_limit_s"]),
    ({"bound": "part", "time_limit_s": 301}, ["body", "time_limit_s"]),
    ({"part_bound": {"contacts": 5}}, ["body", "part_bound"]),
    ({"bound": "part", "part_bound": {"contacts": 2}}, ["body", "part_bound", "contacts"]),
    ({"bound": "part", "part_bound": {"max_rays_per_aim": 0}}, ["body", "part_bound", "max_rays_per_aim"]),
    ({"bound": "part", "part": {"vertices": [[0, 0], [2, 2], [2, 0], [0, 2]], "center_of_mass": [1, 1]}},
     ["body", "part", "vertices"]),
])
def test_bad_bound_requests_are_422_at_their_field(client, patch, loc):
    body = {"part": SQUARE, "fences": [{"angle": 0.7, "mu_c": 0.25}], **patch}
    r = client.post("/v1/feeder/map", json=body)
    assert r.status_code == 422, r.text
    assert r.json()["detail"][0]["loc"][:len(loc)] == loc


def test_a_design_for_the_pentagon_is_found_proven_and_validated_5_4(client):
    body = {"part": PENTAGON, "angles": {"min": math.radians(20), "max": math.radians(70), "step": math.radians(10)},
            "mu_c": 0.25, "alternate": False, "prove_with_cp_sat": True, "validation_parts": 8, "max_depth": 10}
    r = client.post("/v1/feeder/design", json=body)
    assert r.status_code == 200, r.text
    out = r.json()
    assert out["complete"] and out["status"] == "ok" and out["candidates"] == 12
    d = out["design"]
    assert d is not None and len(d["fences"]) == out["depth_proven"] + 1
    assert out["cp_sat"]["depth_proven"] == out["depth_proven"] and out["cp_sat"]["statuses"][-1] == "OPTIMAL"
    v = out["validation"]
    assert v["parts"] == 8 and v["in_band"] + v["unflushed"] + v["unfinished"] == 8 and v["outside"] == 0
    assert len(d["final_edges"]) == 1 and d["margin"] > 0.0
    assert {"maps", "search", "cp_sat", "validation", "push_plan"} <= set(out["timings_ms"])
    base = out["push_plan_baseline"]
    assert base["pushes"] == 1 + len(base["alphas"]) and base["tolerance"] > 0.0
    body.update(validation_parts=0, prove_with_cp_sat=False)
    r = client.post("/v1/feeder/design?format=svg", json=body)
    assert r.status_code == 200 and r.headers["content-type"].startswith("image/svg+xml")
    assert r.text.count("<g id=\"axes_") == len(d["fences"]) + 1  # each fence and the product (figure 5-4)


TRIANGLE = {"vertices": [[0, 0], [2, 0], [0, 3]], "center_of_mass": [2 / 3, 1.0]}
TRIANGLE_A = math.hypot(4 / 3, 2.0)


@pytest.mark.slow  # 5 s: the heaviest of the everyday tier
def test_a_design_searched_as_placed_on_a_belt_1_8_6(client):
    """The right triangle on a belt of 20 part radii (fences at 20..70 degrees in 10 degree
    steps): fences only, guaranteed yield at least the 99.5 % asked; each placed fence has
    at least the reach its arriving orientations need, the belt is as long as the placement's
    first root to last end, and the parts simulated on it all end in the accepted band."""
    a = TRIANGLE_A
    body = {"part": TRIANGLE, "angles": {"min": math.radians(20), "max": math.radians(70), "step": math.radians(10)},
            "mu_c": 0.25, "alternate": False, "belt": {"width": 20 * a}, "validation_parts": 6, "seed": 3}
    out = client.post("/v1/feeder/design", json=body).json()
    d, lay, v = out["design"], out["layout"], out["validation"]
    assert d is not None and lay["gate"] is None and d["guaranteed_yield"] >= 0.995
    assert d["accepted_band"] == d["final_band"] and d["expected_passes"] == pytest.approx(1 / d["guaranteed_yield"])
    for f in lay["fences"]:
        assert f["reach"] >= f["reach_needed"] - 1e-9 * a and f["binding"]
        assert abs(f["end"][0]) <= 10 * a - lay["gap"] + 1e-9 * a
    assert lay["belt_length"] == pytest.approx(-lay["fences"][-1]["end"][1])
    assert v["on_belt"] and v["in_band"] == 6 and v["succeeded"] == 1.0 and v["rejected"] == 0
    r = client.post("/v1/feeder/design?format=svg", json=body)
    assert r.status_code == 200 and r.text.count("<g id=\"axes_") == len(d["fences"]) + 2  # belt, fences, product


def test_a_gate_design_rejects_what_the_fences_cannot_orient_7_1(client):
    """The pentagon with one candidate angle on a belt: no single-fence design of fences
    alone, so a gate: every simulated part it accepts lies in the accepted band, the others
    are rejected, none fails; the gate stands past the last fence."""
    body = {"part": {"vertices": [[0, 0], [3, 0], [3.5, 1.5], [1.5, 2.5], [-0.5, 1.2]], "center_of_mass": [1.4, 1.0]},
            "angles": {"min": 1.2217, "max": 1.2217, "step": 0.1}, "mu_c": 0.25, "alternate": False, "max_depth": 1,
            "belt": {"width": 20 * math.hypot(2.1, 1.5)}, "gate": {}, "validation_parts": 8, "seed": 2}
    out = client.post("/v1/feeder/design", json=body).json()
    d, lay, v = out["design"], out["layout"], out["validation"]
    assert d is not None and lay["gate"] is not None and 0.25 <= d["guaranteed_yield"] < 0.995
    assert lay["gate"]["y"] < lay["fences"][-1]["end"][1] and lay["gate"]["margin"] > 0.0
    assert v["outside"] == 0 and v["in_band"] + v["rejected"] == 8 and v["succeeded"] == 1.0
    assert out["fences_only_exhausted"] is not None
    svg = client.post("/v1/feeder/design?format=svg", json=body)
    assert svg.status_code == 200 and "reject gate" in svg.text  # the top view draws it (figure 1-9)


def test_a_goal_the_user_states_is_designed_for(client):
    """Accepting the triangle's hypotenuse against either guide: the design's accepted band
    lies within the goal (within the tolerance of the two orientations)."""
    a = TRIANGLE_A
    body = {"part": TRIANGLE, "angles": {"min": math.radians(20), "max": math.radians(70), "step": math.radians(10)},
            "mu_c": 0.25, "alternate": False, "belt": {"width": 20 * a}, "max_depth": 2,
            "goal": {"edge": 1, "side": "either", "tolerance": 1.0}, "gate": {"min_yield": 0.05}}
    out = client.post("/v1/feeder/design", json=body).json()
    d = out["design"]
    assert d is not None
    # the hypotenuse (2, 0) -> (0, 3) has its outward normal along +x at theta = pi/2 - phi
    phi = math.atan2(3.0, -2.0)
    centres = [(0.5 * math.pi - phi) % (2 * math.pi), (1.5 * math.pi - phi) % (2 * math.pi)]
    for start, width in d["accepted_band"]:
        for t in (start, start + width):
            assert min(abs((t - c + math.pi) % (2 * math.pi) - math.pi) for c in centres) <= 1.0 + 1e-9


@pytest.mark.parametrize(("patch", "loc"), [
    ({"goal": {"accepted": []}}, ["body", "goal", "accepted"]),
    ({"goal": {"accepted": [[7.0, 8.0]]}}, ["body", "goal", "accepted", 0, 0]),
    ({"goal": {"accepted": [[1.0, 0.5]]}}, ["body", "goal", "accepted", 0, 1]),
    ({"goal": {"edge": 3}}, ["body", "goal", "edge"]),
    ({"goal": {"edge": 0, "accepted": [[0.0, 1.0]]}}, ["body", "goal"]),
    ({"goal": {"edge": 0, "tolerance": 2.0}}, ["body", "goal", "tolerance"]),
    ({"gate": {"margin": 100.0}}, ["body", "gate", "margin"]),
    ({"gate": {"features": []}}, ["body", "gate", "features"]),
    ({"gate": {"min_yield": 0.0}}, ["body", "gate", "min_yield"]),
    ({"min_yield": 1.5}, ["body", "min_yield"]),
    ({"belt": None, "gate": {}}, ["body", "gate"]),
    ({"belt": {"width": 30.0, "entry_spread": 20.0}}, ["body", "belt", "entry_spread"]),
])
def test_bad_goals_and_gates_are_refused_at_the_field(client, patch, loc):
    body = {"part": TRIANGLE, "angles": {"min": 0.5, "max": 0.9, "step": 0.2}, "mu_c": 0.25,
            "belt": {"width": 20 * TRIANGLE_A}, **patch}
    r = client.post("/v1/feeder/design", json=body)
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == loc, r.text


@pytest.mark.parametrize(("patch", "loc"), [
    ({"angles": {"min": 0.9, "max": 0.5, "step": 0.1}}, ["body", "angles", "max"]),
    ({"angles": {"min": 0.1, "max": 1.5, "step": 0.001}}, ["body", "angles", "step"]),
    ({"angles": {"min": 0.1, "max": 1.6, "step": 0.1}}, ["body", "angles", "max"]),
    ({"mu_c": None}, ["body", "mu_c"]),
    ({"mu_c_range": [0.1, 0.2]}, ["body", "mu_c"]),
    ({"max_depth": 0}, ["body", "max_depth"]),
    ({"validation_parts": 10_001}, ["body", "validation_parts"]),
    ({"angles": {"min": 0.4, "max": 1.0, "step": 1e-310}}, ["body", "angles", "step"]),
    ({"belt": {"width": 1e12}}, ["body", "belt", "width"]),
    ({"belt": {"width": 1.0}}, ["body", "belt", "width"]),
    ({"belt": {"width": 10.0, "entry_x": 6.0}}, ["body", "belt", "entry_x"]),
    # an outline whose hull is fine but which is no simple polygon: refused before any map
    ({"validation_parts": 2, "part": {"vertices": [[0, 0], [1, 0], [1, 0], [1, 1], [0, 1]],
                                      "center_of_mass": [0.5, 0.5]}}, ["body", "part", "vertices"]),
])
def test_bad_design_requests_are_422_at_their_field(client, patch, loc):
    body = {"part": SQUARE, "angles": {"min": 0.4, "max": 1.0, "step": 0.2}, "mu_c": 0.2}
    body.update(patch)
    if body.get("mu_c") is None:
        body.pop("mu_c")
    r = client.post("/v1/feeder/design", json=body)
    assert r.status_code == 422, r.text
    assert r.json()["detail"][0]["loc"][:len(loc)] == loc


def test_the_push_plan_baseline_of_a_64_gon_is_cut_and_reported_not_a_504(client, monkeypatch):
    """Issue 25: the regular 64-gon with its centre of mass at (0.01, 0), whose baseline push
    plan needs over a minute: the design still answers 200 within its limit, the baseline
    marked cut (it checks its tenth of the time at every class of turns). The limit is a
    work limit (3000 clock readings; the design needs about 16 of its own), so a busy
    machine cannot make the design itself run out."""
    from service.runtime.deadline import Deadline
    from tests.budgets import ChecksBudgets, deadline_budgets

    monkeypatch.setattr(Deadline, "budget", deadline_budgets(ChecksBudgets(3000)))
    gon = {"vertices": [[math.cos(2 * math.pi * i / 64), math.sin(2 * math.pi * i / 64)] for i in range(64)],
           "center_of_mass": [0.01, 0.0]}
    body = {"part": gon, "angles": {"min": math.radians(20), "max": math.radians(70), "step": math.radians(10)},
            "mu_c": 0.25, "max_depth": 8, "time_limit_s": 10}
    r = client.post("/v1/feeder/design", json=body)
    assert r.status_code == 200, r.text[:300]
    out = r.json()
    assert out["push_plan_baseline"]["complete"] is False and out["push_plan_baseline"]["pushes"] is None
    assert out["candidates"] == 12 and out["push_plan_baseline"]["solve_time_ms"] < 10_000


@pytest.mark.slow  # 5 s: the heaviest of the everyday tier
def test_on_a_belt_the_defaults_find_what_exists_and_a_refusal_says_which_setting(client):
    """Issue 35, point 12: the right triangle on a belt with the defaults (no `alternate`, no
    `gate`) has its placed design (sides free on a belt); asked to alternate, there is none,
    and the answer says that the same search with the sides free finds one."""
    base = {"part": TRIANGLE, "angles": {"min": math.radians(20), "max": math.radians(70), "step": math.radians(10)},
            "mu_c": 0.25, "belt": {"width": 20 * TRIANGLE_A}, "time_limit_s": 30}
    found = client.post("/v1/feeder/design", json=base).json()
    assert found["design"] is not None and found["relaxed"] == [], found["message"]
    alternating = client.post("/v1/feeder/design", json={**base, "alternate": True, "gate": None}).json()
    assert alternating["design"] is None
    lifted = {r["setting"]: r for r in alternating["relaxed"]}
    assert lifted["alternate"]["searched"] and lifted["alternate"]["fences"] == len(found["design"]["fences"])
    assert "with alternate false (sides free) the same search finds a placed design" in alternating["message"]
    assert "gate" in lifted  # the gate was off too: what it would add is said
