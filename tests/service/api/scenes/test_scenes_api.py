"""POST /v1/scenes/analyze (issue 27): the route is thin (its answers are the solver's
analysis of the same scene, converted), its documented example answers every question,
and every scene or question it cannot answer is a 422 naming the field."""

from __future__ import annotations

import math

import pytest

from models.core.footprint import Footprint
from models.core.scene import PushScene
from service.api.scenes.schemas import SceneAnalyzeRequest
from service.limits import SCENE_MAX_QUESTIONS
from solver import SKETCH_COST, AlignProblem, LocusProblem, QuasiStaticQuery, align, cor_locus

URL = "/v1/scenes/analyze"
EXAMPLE = SceneAnalyzeRequest.model_config["json_schema_extra"]["examples"][0]
PENTAGON = EXAMPLE["footprint"]


def test_the_example_answers_every_question_with_its_model(client):
    r = client.post(URL, json=EXAMPLE)
    assert r.status_code == 200, r.text
    body = r.json()
    assert body["status"] == "complete" and body["part"] == "polygon"
    answers = {a["ask"]: a for a in body["answers"]}
    assert [a["ask"] for a in body["answers"]] == [q["ask"] for q in EXAMPLE["questions"]]
    assert all(a["status"] == "answered" and a["cost_ms"] >= 0 for a in body["answers"])
    assert answers["cor_locus"]["model"] == "disk_bound" and answers["cor_locus"]["locus"]["boundary"]
    assert answers["stick_or_slip"]["modes"]["verdict"] in ("sticks", "slips", "either")
    assert answers["push_to_align"]["model"] == "exact_bounds" and answers["push_to_align"]["push"]["longest"] > 0
    assert answers["quasi_static"]["reused_from"] == 2 and answers["quasi_static"]["cost_ms"] == 0
    assert answers["aligning_fence"]["reused_from"] == 5
    assert answers["feeder_design"]["fences"]["fence_angles"]


def test_the_answers_are_the_models_called_directly(client):
    """The push and the locus of the example are those of align and cor_locus on the same
    scene, converted (the route adds nothing)."""
    body = client.post(URL, json={**EXAMPLE, "questions": [{"ask": "cor_locus", "n_points": 64},
                                                           {"ask": "push_to_align"}]}).json()
    fp = Footprint.create(PENTAGON, None)
    scene = PushScene.create(fp.circumradius, EXAMPLE["contact_point"], EXAMPLE["edge_angle"],
                             EXAMPLE["push_direction"], fp.center_of_mass)
    locus = cor_locus(LocusProblem(scene, n_points=64))
    assert body["answers"][0]["locus"]["boundary"] == locus.analytic.boundary.tolist()
    qs = QuasiStaticQuery(0.05, 0.3, 9.81)
    push = align(AlignProblem(fp, 0.0, scene.edge_angle, scene.push_direction, mu_c=0.25, method="both",
                              quasi_static=qs, cost=SKETCH_COST))
    assert body["answers"][1]["push"]["longest"] == push.longest.exact
    assert body["answers"][1]["push"]["longest_closed_form"] == push.longest.closed_form


def test_a_disk_part(client):
    body = client.post(URL, json={"disk_radius": 2.0, "contact_point": [0.5, -1.9], "edge_angle": 0.0,
                                  "push_direction": math.pi / 2, "mu_c": 0.4,
                                  "questions": [{"ask": "cor_locus", "accuracy": "exact"},
                                                {"ask": "stick_or_slip", "accuracy": "exact"}]}).json()
    assert body["part"] == "disk" and body["disk_radius"] == 2.0
    assert [(a["model"], a["accuracy"]) for a in body["answers"]] == [("closed_form", "exact")] * 2


@pytest.mark.parametrize("change,loc", [
    ({"footprint": None, "disk_radius": 1.0, "questions": [{"ask": "push_to_align"}]}, ["body", "questions", 0, "ask"]),
    ({"mu_c_range": [0.1, 0.3], "questions": [{"ask": "cor_locus"}, {"ask": "stick_or_slip"}]},
     ["body", "mu_c_range"]),
    ({"mu_c": None, "mu_c_range": [0.1, 0.3], "questions": [{"ask": "stick_or_slip"}]}, ["body", "questions", 0, "ask"]),
    ({"mu_c": None, "mu_c_range": [0.3, 0.1]}, ["body", "mu_c_range"]),
    ({"quasi_static": None, "questions": [{"ask": "quasi_static"}]}, ["body", "questions", 0, "ask"]),
    ({"questions": [{"ask": "feeder_design", "angles": {"min": 0.5, "max": 0.4, "step": 0.1}}]},
     ["body", "questions", 0, "angles", "max"]),
    ({"questions": [{"ask": "feeder_design", "angles": {"min": 0.01, "max": 1.5, "step": 0.001}}]},
     ["body", "questions", 0, "angles", "step"]),
    ({"questions": [{"ask": "cor_locus"}] * (SCENE_MAX_QUESTIONS + 1)}, ["body", "questions"]),
    ({"questions": [{"ask": "where"}]}, ["body", "questions", 0, "ask"]),
    ({"questions": [{"ask": "cor_locus", "accuracy": "perfect"}]}, ["body", "questions", 0, "accuracy"]),
    ({"disk_radius": 1.0}, ["body", "footprint"]),  # both shapes
    ({"quasi_static": {"speed": 0.1, "mu_s": 0.3}}, ["body", "quasi_static", "g"]),
])
def test_what_cannot_be_answered_is_422_at_its_field(client, change, loc):
    body = {**EXAMPLE, **change}
    r = client.post(URL, json=body)
    assert r.status_code == 422, r.text
    assert r.json()["detail"][0]["loc"][:len(loc)] == loc, r.text


@pytest.mark.wall_clock  # about the time limit itself: its real deadline (tests/service/conftest.py)
def test_no_time_for_any_answer_is_a_504_with_what_there_is(client):
    r = client.post(URL, json={**EXAMPLE, "time_limit_s": 1e-6})
    assert r.status_code == 504, r.text
    partial = r.json()["partial"]
    assert {a["status"] for a in partial["answers"]} == {"not_run"}


def test_a_part_one_fence_orients(client):
    """A square is oriented by a single fence: the aligning fence is that fence, the design has
    it alone, and its margin (infinite for one fence) is answered as pi, as /v1/feeder/design
    does."""
    square = {"footprint": [[0, 0], [1, 0], [1, 1], [0, 1]], "contact_point": [0.5, 0.0], "edge_angle": 0.0,
              "push_direction": math.pi / 2, "mu_c": 0.25,
              "questions": [{"ask": "aligning_fence"}, {"ask": "feeder_design", "validation_parts": 3}]}
    r = client.post(URL, json=square)
    assert r.status_code == 200, r.text
    fence, design = r.json()["answers"]
    assert design["fences"]["fence_angles"] and len(design["fences"]["fence_angles"]) == 1
    assert design["fences"]["margin"] == pytest.approx(math.pi)
    assert fence["fences"]["fence_angles"] == design["fences"]["fence_angles"]
    # the design was checked by 3 simulated parts, the aligning fence asked for none: not reused
    assert fence["reused_from"] is None and fence["fences"]["simulated_parts"] == 0
