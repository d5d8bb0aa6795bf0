"""POST /v1/push/align and POST /v1/push/disk-encounter: gross-motion bounds (book 3.4,
4.3, 4.4).

The routes are thin: every number is that of models.push.fence_geometry, models.push.gross_motion
and models.push.gross_bounds on the same inputs (bit for bit); the book's 4.3 example comes back
from a footprint; mirror images give the same pushes; the quasi-static verdict is that of
models.push.quasistatic; every invalid input is 422 naming the field; the cost model refuses
requests that would exceed time_limit_s and the clock stops between exact bounds; the docs
examples run.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from models.core.footprint import Footprint
from models.push import fence_geometry as fg
from models.push import gross_bounds as gb
from models.push import gross_motion as gm
from models.push import quasistatic as qs
from service.api.push import convert as push_convert
from service.limits import GROSS_MAX_N_NODES, MAX_TIME_LIMIT_S, SKETCH_MAX_N_POINTS
from service.runtime.deadline import Deadline
from solver.push.bounds import ENCOUNTER_SKETCH_COST, SKETCH_COST, SketchCost
from tests.budgets import ChecksBudgets, deadline_budgets

ALIGN = "/v1/push/align"
ENCOUNTER = "/v1/push/disk-encounter"
D = math.radians
SQUARE = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
SQUARE_30 = {"footprint": SQUARE, "orientation": D(30), "fence_angle": D(90)}
FAST = {"n_nodes": 4, "n_points": 16}


def strict_json(text: str):
    def reject(token):
        raise AssertionError(f"non-finite number {token} in JSON")

    return json.loads(text, parse_constant=reject)


def post(client, url, body):
    r = client.post(url, json=body)
    return r, strict_json(r.text)


def detail(got):
    (item,) = got["detail"]
    return item["loc"], item["type"], item["msg"]


def book_footprint():
    """The 4.3 example as a footprint (tests/models/push/test_fence_geometry.py): a = 1, CM at
    the origin, contact at c = 0.5746 with beta = 45 deg, flush edge at psi = 30 deg, so
    alpha = 70 deg gives beta 45 -> 80 deg."""
    c = 0.5746
    v = c * np.array([-math.cos(D(45)), math.sin(D(45))])
    w = v + np.array([math.cos(D(-75)), math.sin(D(-75))])
    return [v.tolist(), w.tolist(), [1.0, 0.0], [0.3, 0.8]]


# --- POST /v1/push/align -----------------------------------------------------------------


@pytest.mark.slow
def test_align_answer_is_the_models(client):
    body = {**SQUARE_30, "mu_c": 0.25, **FAST}
    r, got = post(client, ALIGN, body)
    assert r.status_code == 200, r.text
    fp = Footprint.create(SQUARE)
    al = fg.fence_alignment(fp, D(30), D(90), 0.0)
    (st,) = al.stages
    geo = got["geometry"]
    assert geo["disk_radius"] == al.disk_radius and geo["alpha"] == al.alpha
    assert geo["sense"] == "cw" and geo["mirrored"] is False and geo["already_flush"] is False
    assert geo["first_contact"] == {"vertex_indices": [3], "points": [al.initial_vertices[3].tolist()]}
    assert geo["final_edge"]["vertex_indices"] == [3, 0]
    assert geo["fence_normal"] == al.fence_normal.tolist()
    assert geo["total_rotation"] == al.total_rotation and geo["final_orientation"] == al.final_orientation
    (s,) = got["stages"]
    assert s["contact_vertex_index"] == 3 and s["flush_edge_vertex_indices"] == [3, 0]
    for name in ("contact_distance", "beta_initial", "beta_final", "vertex_edge_angle", "rotation",
                 "orientation_initial", "orientation_final"):
        assert s[name] == getattr(st, name), name
    assert s["contact_fence_frame"] == st.contact_fence_frame.tolist()
    args = (al.disk_radius, st.contact_distance, al.alpha, st.beta_initial, st.beta_final, 0.25)
    book = gm.fence_push_bound(*args)
    lp = s["longest_push"]
    assert lp["closed_form"] == book.total
    assert [(p["beta_start"], p["beta_end"], p["regime"], p["push"]) for p in lp["pieces"]] == [
        (p.beta_start, p.beta_end, p.regime, p.push) for p in book.pieces]
    assert lp["transitions"] == list(book.transitions)
    longest = gb.fence_push_bound_exact(*args, n_nodes=4, n_points=16, longest=True)
    shortest = gb.fence_push_bound_exact(*args, n_nodes=4, n_points=16, longest=False)
    assert lp["exact"] == longest.value and lp["quadrature_error"] == longest.quadrature_error
    assert lp["difference"] == longest.value - book.total
    assert lp["exact_sources"] == sorted(set(longest.sources))
    sp = s["shortest_push"]
    assert sp["exact"] == shortest.value and sp["quadrature_error"] == shortest.quadrature_error
    assert sp["closed_form"] is None and sp["difference"] is None  # no closed form with friction
    assert got["longest_push"] == {"exact": longest.value, "quadrature_error": longest.quadrature_error,
                                   "closed_form": book.total, "equation": lp["equation"],
                                   "difference": longest.value - book.total}
    assert got["shortest_push"]["exact"] == shortest.value
    assert got["nu"] == math.atan(0.25) and got["quasi_static"] is None
    assert "3.1.8" in got["note"] and "circumscribing" in got["note"]
    assert got["predicted_time_s"] == SKETCH_COST.bounds_s(1, 4, 16) and got["elapsed_ms"] > 0


@pytest.mark.slow
def test_book_example_4_3(client):
    """Lines 1855-1923: alpha = 70 deg, c = 0.5746 a, beta 45 -> 80 deg, mu_c = 0.25: the
    book's composite closed form is 1.63903 a; the exact sketch's longest push ~1.6451 a
    (the tip line's dip: the closed form is not a bound)."""
    body = {"footprint": book_footprint(), "center_of_mass": [0.0, 0.0], "fence_angle": D(70), "mu_c": 0.25,
            "n_nodes": 8, "n_points": 256}
    r, got = post(client, ALIGN, body)
    assert r.status_code == 200, r.text
    (s,) = got["stages"]
    assert got["geometry"]["disk_radius"] == pytest.approx(1.0, rel=1e-15)
    assert got["geometry"]["alpha"] == pytest.approx(D(70), abs=1e-14)
    assert s["contact_distance"] == pytest.approx(0.5746, rel=1e-14)
    assert (s["beta_initial"], s["beta_final"]) == pytest.approx((D(45), D(80)), abs=1e-13)
    lp = s["longest_push"]
    assert lp["closed_form"] == pytest.approx(1.63903, abs=1e-5)
    assert [p["regime"] for p in lp["pieces"]] == ["sticking", "slipping_down"]
    assert [p["equation"] for p in lp["pieces"]] == ["(4.8)", "(4.6) corrected, tip of {COR}_(alpha+nu)"]
    assert math.degrees(lp["transitions"][0]) == pytest.approx(69.4, abs=1e-2)
    assert lp["exact"] == pytest.approx(1.6451, abs=3e-4)
    assert lp["quadrature_error"] < 5e-4
    assert 0.0 < lp["difference"] < 0.01
    assert s["flush_edge_stable"] is True
    assert got["shortest_push"]["exact"] < got["longest_push"]["exact"]
    # issue 4: the fence slips along the part by -0.286 a .. +0.278 a (exact sketch; the
    # book gives no figure), along the fence face turned to the world (push along +x)
    slip = s["slip"]
    assert slip["most_positive"] == pytest.approx(0.2779, abs=1e-3)
    assert slip["most_negative"] == pytest.approx(-0.2863, abs=1e-3)
    assert slip["direction"] == pytest.approx([math.cos(D(70)), math.sin(D(70))], abs=1e-14)
    assert got["slip"] == slip


def test_frictionless_fence_is_3_41_and_exact(client):
    """mu_c = 0 (3.4): the closed forms are exact (tip and r_min); no sketch is built."""
    r, got = post(client, ALIGN, SQUARE_30)
    assert r.status_code == 200, r.text
    (s,) = got["stages"]
    a, c = math.sqrt(2.0), math.sqrt(2.0)
    longest = gm.fence_push_frictionless(a, s["contact_distance"], D(90), s["beta_initial"], s["beta_final"])
    shortest = gm.fence_push_least_frictionless(a, s["contact_distance"], D(90), s["beta_initial"], s["beta_final"])
    assert s["longest_push"]["closed_form"] == longest == s["longest_push"]["exact"]
    assert s["longest_push"]["pieces"][0]["equation"] == "(3.41)" and s["longest_push"]["transitions"] == []
    assert s["shortest_push"]["closed_form"] == shortest == s["shortest_push"]["exact"]
    assert s["longest_push"]["quadrature_error"] == 0.0 and s["longest_push"]["difference"] == 0.0
    assert got["predicted_time_s"] == 0.0 and got["method"] == "both"
    assert c == pytest.approx(s["contact_distance"])


@pytest.mark.slow
def test_methods(client):
    _, both = post(client, ALIGN, {**SQUARE_30, "mu_c": 0.5, **FAST})
    _, closed = post(client, ALIGN, {**SQUARE_30, "mu_c": 0.5, "method": "closed_form", **FAST})
    _, exact = post(client, ALIGN, {**SQUARE_30, "mu_c": 0.5, "method": "exact", **FAST})
    assert closed["longest_push"]["closed_form"] == both["longest_push"]["closed_form"]
    assert closed["longest_push"]["exact"] is None and closed["shortest_push"]["exact"] is None
    assert closed["longest_push"]["difference"] is None and closed["predicted_time_s"] == 0.0
    assert exact["longest_push"]["exact"] == both["longest_push"]["exact"]
    assert exact["longest_push"]["closed_form"] is None and exact["stages"][0]["longest_push"]["pieces"] is None


def test_mirror_image_is_reflected_onto_the_book_case(client):
    _, cw = post(client, ALIGN, {**SQUARE_30, "mu_c": 0.25, "method": "closed_form"})
    _, ccw = post(client, ALIGN, {**SQUARE_30, "orientation": D(-30), "mu_c": 0.25, "method": "closed_form"})
    assert (ccw["geometry"]["sense"], ccw["geometry"]["mirrored"]) == ("ccw", True)
    assert "reflected" in ccw["message"]
    assert ccw["longest_push"]["closed_form"] == pytest.approx(cw["longest_push"]["closed_form"], rel=1e-13)
    assert ccw["stages"][0]["beta_initial"] == pytest.approx(cw["stages"][0]["beta_initial"], abs=1e-14)
    assert cw["slip"] is None  # closed forms only: the book has none for the slip


@pytest.mark.slow
def test_slip_of_a_mirror_image_is_the_reflected_slip(client):
    """The counter-clockwise case is the book's reflected across the line of motion: the
    same slip magnitudes, along the reflected fence direction; a world rotation of the
    whole scene turns the direction with it."""
    _, cw = post(client, ALIGN, {**SQUARE_30, "mu_c": 0.25, **FAST})
    _, ccw = post(client, ALIGN, {**SQUARE_30, "orientation": D(-30), "mu_c": 0.25, **FAST})
    a, b = cw["slip"], ccw["slip"]
    assert b["most_positive"] == pytest.approx(a["most_positive"], abs=1e-12)
    assert b["most_negative"] == pytest.approx(a["most_negative"], abs=1e-12)
    assert a["most_negative"] < a["most_positive"] < 0.0  # this fence only ever slips one way
    ax, ay = a["direction"]
    assert b["direction"] == pytest.approx([ax, -ay], abs=1e-14)
    turn = D(40)
    rot = {**SQUARE_30, "mu_c": 0.25, **FAST, "orientation": SQUARE_30.get("orientation", 0.0) + turn,
           "fence_angle": SQUARE_30["fence_angle"] + turn, "push_direction": turn}
    _, turned = post(client, ALIGN, rot)
    c = turned["slip"]
    assert c["most_positive"] == pytest.approx(a["most_positive"], abs=1e-9)
    assert c["direction"] == pytest.approx([math.cos(turn) * ax - math.sin(turn) * ay,
                                            math.sin(turn) * ax + math.cos(turn) * ay], abs=1e-12)


def test_frictionless_slip_is_computed_from_the_frictionless_locus(client):
    _, got = post(client, ALIGN, SQUARE_30)
    (s,) = got["stages"]
    a = math.sqrt(2.0)
    hi, lo = gb.fence_slip_bounds_exact(a, s["contact_distance"], D(90), s["beta_initial"], s["beta_final"], 0.0,
                                        n_nodes=got["n_nodes"], n_points=got["n_points"])
    assert s["slip"]["most_positive"] == hi.value and s["slip"]["most_negative"] == lo.value
    assert got["predicted_time_s"] == 0.0


def test_contact_below_the_line_of_motion(client):
    """An oblique fence: the square at 30 deg against a fence at 70 deg turns counter-
    clockwise with the contact below the line of motion after the reflection
    (beta_initial = -15 deg): answered for mu_c = 0 by (3.41), refused with friction."""
    body = {**SQUARE_30, "fence_angle": D(70)}
    r, got = post(client, ALIGN, body)
    assert r.status_code == 200, r.text
    assert got["geometry"]["below_line_of_motion"] is True
    (s,) = got["stages"]
    assert s["beta_initial"] == pytest.approx(D(-15), abs=1e-14)
    longest, shortest = fg.frictionless_push_bounds(math.sqrt(2.0), s["contact_distance"], got["geometry"]["alpha"],
                                                    s["beta_initial"], s["beta_final"])
    assert s["longest_push"]["closed_form"] == longest and s["shortest_push"]["exact"] == shortest
    r, got = post(client, ALIGN, {**body, "mu_c": 0.25})
    assert r.status_code == 422
    loc, type_, msg = detail(got)
    assert (loc, type_) == (["body", "orientation"], "value_error") and "(4.7)" in msg


@pytest.mark.slow
def test_already_flush_and_a_chain_of_stages(client):
    r, got = post(client, ALIGN, {"footprint": SQUARE, "fence_angle": D(90), "mu_c": 0.3, **FAST})
    assert r.status_code == 200, r.text
    assert got["geometry"]["already_flush"] is True and got["stages"] == []
    assert got["geometry"]["sense"] == "none" and "already flush" in got["message"]
    assert got["longest_push"]["exact"] == 0.0 and got["longest_push"]["closed_form"] == 0.0
    assert got["shortest_push"]["exact"] == 0.0 and got["shortest_push"]["closed_form"] is None  # mu_c > 0
    # Two stages: the triangle's short base is not stable (tests/models/push/test_fence_geometry.py).
    tri = [[0, 0], [1, 0], [5, 1]]
    r, got = post(client, ALIGN, {"footprint": tri, "orientation": D(5), "fence_angle": 0.0,
                                  "push_direction": D(90), "mu_c": 0.2, **FAST})
    assert r.status_code == 200, r.text
    s1, s2 = got["stages"]
    assert (s1["flush_edge_stable"], s2["flush_edge_stable"]) == (False, True)
    assert s2["contact_vertex_index"] == 1 and got["geometry"]["final_edge"]["vertex_indices"] == [1, 2]
    for which in ("longest_push", "shortest_push"):
        assert got[which]["exact"] == pytest.approx(s1[which]["exact"] + s2[which]["exact"], rel=1e-15)
    assert got["longest_push"]["closed_form"] == pytest.approx(
        s1["longest_push"]["closed_form"] + s2["longest_push"]["closed_form"], rel=1e-15)
    assert "2 stages" in got["message"]


def test_vertex_indices_refer_to_the_request(client):
    """A clockwise outline is reversed by Footprint.create; the answer's indices are the
    request's own."""
    for outline in (SQUARE, SQUARE[::-1], SQUARE[2:] + SQUARE[:2]):
        r, got = post(client, ALIGN, {**SQUARE_30, "footprint": outline, "method": "closed_form"})
        assert r.status_code == 200, r.text
        i = got["geometry"]["first_contact"]["vertex_indices"][0]
        turned = np.array(outline[i]) @ np.array([[math.cos(D(30)), math.sin(D(30))],
                                                  [-math.sin(D(30)), math.cos(D(30))]])
        assert got["geometry"]["first_contact"]["points"][0] == pytest.approx(turned.tolist(), abs=1e-14)
        assert outline[i] == [-1.0, 1.0]
        j = got["geometry"]["final_edge"]["vertex_indices"][1]
        assert outline[j] == [-1.0, -1.0]


def test_align_quasi_static_verdict(client):
    qin = {"speed": 5.0, "mu_s": 0.3, "length_unit": "cm"}
    r, got = post(client, ALIGN, {**SQUARE_30, "quasi_static": qin})
    assert r.status_code == 200, r.text
    want = qs.assess(5.0, 0.3, qs.gravity("cm"), qs.ShapeMoments.polygon(Footprint.create(SQUARE)))
    out = got["quasi_static"]
    assert out["verdict"] == want.verdict and out["within_quasi_static"] == (want.verdict == "quasi_static")
    assert out["quasi_static"]["ratio"] == want.quasi_static.ratio
    assert out["angular"]["characteristic_speed"] == want.angular.characteristic_speed
    assert out["translational"]["ratio"] == want.translational.ratio
    assert out["g_source"] == "length_unit" and out["g"] == want.g
    r, fast = post(client, ALIGN, {**SQUARE_30, "quasi_static": {"speed": 500.0, "mu_s": 0.3, "g": 981.0}})
    assert fast["quasi_static"]["verdict"] == "inertial" and fast["quasi_static"]["within_quasi_static"] is False


@pytest.mark.parametrize(
    "change, loc, type_",
    [
        ({"fence_angle": D(10), "push_direction": D(10)}, ["body", "fence_angle"], "value_error"),
        ({"orientation": D(45)}, ["body", "orientation"], "value_error"),  # translation: no turn
        ({"footprint": [[0, 0], [1, 0], [2, 0]]}, ["body", "footprint"], "value_error"),
        ({"footprint": [[0, 0], [1e-120, 0], [0, 1e-120]]}, ["body", "footprint"], "value_error"),
        ({"center_of_mass": [5.0, 5.0]}, ["body", "center_of_mass"], "value_error"),
        ({"mu_c": -0.1}, ["body", "mu_c"], "greater_than_equal"),
        ({"method": "fast"}, ["body", "method"], "literal_error"),
        ({"n_nodes": 3}, ["body", "n_nodes"], "greater_than_equal"),
        ({"n_nodes": GROSS_MAX_N_NODES + 1}, ["body", "n_nodes"], "less_than_equal"),
        ({"n_points": SKETCH_MAX_N_POINTS + 1}, ["body", "n_points"], "less_than_equal"),
        ({"time_limit_s": 0.0}, ["body", "time_limit_s"], "greater_than"),
        ({"time_limit_s": MAX_TIME_LIMIT_S + 1}, ["body", "time_limit_s"], "less_than_equal"),
        ({"mu_c": 0.3, "n_nodes": 64, "n_points": 4096}, ["body", "time_limit_s"], "value_error"),  # cost model
        ({"quasi_static": {"speed": 1.0, "mu_s": 0.3}}, ["body", "quasi_static", "g"], "value_error"),
        ({"quasi_static": {"speed": 1.0, "mu_s": 0.3, "g": 9.81, "length_unit": "m"}},
         ["body", "quasi_static", "length_unit"], "value_error"),
        ({"quasi_static": {"speed": 1.0, "g": 9.81}}, ["body", "quasi_static", "mu_s"], "missing"),
        ({"fence_angle": None}, ["body", "fence_angle"], "missing"),
        ({"edge_angle": 1.0}, ["body", "edge_angle"], "extra_forbidden"),
    ],
)
@pytest.mark.wall_clock  # about the time limit itself: its real deadline (tests/service/conftest.py)
def test_align_bad_inputs_are_422_naming_the_field(client, change, loc, type_):
    body = {k: v for k, v in {**SQUARE_30, **change}.items() if v is not None}
    r, got = post(client, ALIGN, body)
    assert r.status_code == 422, r.text
    assert detail(got)[:2] == (loc, type_)


@pytest.mark.wall_clock  # about the time limit itself: its real deadline (tests/service/conftest.py)
def test_time_budget(client, monkeypatch):
    """The cost model refuses before any work (422); if the prediction is too optimistic the
    clock stops the request between exact bounds (504, saying where it got to, with what
    was finished)."""
    r, got = post(client, ALIGN, {**SQUARE_30, "mu_c": 0.3, "n_nodes": 16, "time_limit_s": 1.0})
    assert r.status_code == 422 and "predicted" in detail(got)[2]
    monkeypatch.setattr(push_convert, "SKETCH_COST", SketchCost(fixed_s=0.0, per_point_s=0.0))
    monkeypatch.setattr(push_convert, "ENCOUNTER_SKETCH_COST", SketchCost(fixed_s=0.0, per_point_s=0.0))
    monkeypatch.setattr(Deadline, "budget", deadline_budgets(ChecksBudgets(2)))  # 0.01 s spent in two checks, on any machine
    r, got = post(client, ALIGN, {**SQUARE_30, "mu_c": 0.3, **FAST, "time_limit_s": 0.01})
    assert r.status_code == 504
    loc, type_, msg = detail(got)
    assert loc == ["body", "time_limit_s"] and type_ == "time_limit" and "ran out" in msg
    assert "exact bounds of stage 1" in msg or "the sketch at beta" in msg  # where it got to
    assert got["reached"] in msg and got["time_limit_s"] == 0.01 and got["elapsed_s"] > 0.01
    assert [s["contact_vertex_index"] for s in got["partial"]["stages"]] == []  # stage 1 was not finished
    # the deadline is checked between the sketches of one bound, too
    monkeypatch.setattr(Deadline, "budget", deadline_budgets(ChecksBudgets(0)))
    r, got = post(client, ENCOUNTER, {"disk_radius": 1.0, "beta_initial": 0.7, "mu_c": 0.5, **FAST,
                                      "time_limit_s": 1e-9})
    loc, _, msg = detail(got)
    assert r.status_code == 504 and loc == ["body", "time_limit_s"]
    assert "ran out" in msg and "the sketch at beta" in msg and "node 1" in msg
    # what was finished: the closed forms, the exact bounds left out
    done = got["partial"]
    assert done["length_greatest"]["closed_form"] == pytest.approx(gm.encounter_length_max(0.7, 1.0), rel=1e-15)
    assert done["length_greatest"]["exact"] is None and done["rotation_least"]["exact"] is None


@pytest.mark.slow
def test_align_numbers_stay_finite_at_the_limits(client):
    big = [[x * 1e9 for x in p] for p in SQUARE]
    tiny = [[x * 1e-99 for x in p] for p in SQUARE]
    for mu_c in (0.0, 1e6):
        knobs = {"mu_c": mu_c, "method": "exact", "n_nodes": 4, "n_points": 8}
        _, unit = post(client, ALIGN, {**SQUARE_30, **knobs})
        for outline, scale in ((big, 1e9), (tiny, 1e-99)):
            r, got = post(client, ALIGN, {**SQUARE_30, "footprint": outline, **knobs})
            assert r.status_code == 200, r.text  # strict_json refuses NaN / Infinity
            assert got["longest_push"]["exact"] == pytest.approx(scale * unit["longest_push"]["exact"], rel=1e-9)
            assert got["shortest_push"]["exact"] == pytest.approx(scale * unit["shortest_push"]["exact"], rel=1e-9)
    r, got = post(client, ALIGN, {**SQUARE_30, "orientation": 1e6, "fence_angle": -1e6, "push_direction": 1e6})
    assert r.status_code == 200, r.text


# --- POST /v1/push/disk-encounter ----------------------------------------------------------


@pytest.mark.slow
def test_encounter_answer_is_the_models(client):
    body = {"disk_radius": 2.0, "beta_initial": D(40), "mu_c": 0.4, **FAST}
    r, got = post(client, ENCOUNTER, body)
    assert r.status_code == 200, r.text
    bounds = gb.encounter_bounds_exact(2.0, D(40), 0.4, n_nodes=4, n_points=16)
    book_length = gm.encounter_length_max(D(40), 2.0)
    book_rotation = gm.rotation_max(D(40))
    for key, name, book in (("length_max", "length_greatest", book_length), ("length_min", "length_least", None),
                            ("rotation_max", "rotation_greatest", book_rotation),
                            ("rotation_min", "rotation_least", None)):
        out = got[name]
        assert out["exact"] == bounds[key].value and out["quadrature_error"] == bounds[key].quadrature_error, key
        assert out["closed_form"] == book
        assert out["difference"] == (None if book is None else bounds[key].value - book)
    assert got["length_greatest"]["equation"] == "(4.16)"
    assert got["rotation_greatest"]["exact"] == pytest.approx(math.pi / 2 - D(40), abs=1e-12)
    assert got["length_frictionless"] == gm.encounter_length_frictionless(D(40), 2.0)
    assert got["offset"] == pytest.approx(2.0 * (1 - math.sin(D(40))), rel=1e-15)
    assert got["beta_source"] == "beta_initial" and got["beta_final"] == math.pi / 2
    si = got["sketch_i"]
    assert si["onset_beta"] == gm.sketch_i_onset(0.4) and si["at_start"] is bool(gm.sketch_i(D(40), 0.4))
    assert si["occurs"] is True and "(4.17)" in si["note"]
    assert got["length_least"]["exact"] < got["length_greatest"]["exact"]
    assert got["rotation_least"]["exact"] < got["rotation_greatest"]["exact"]
    assert got["predicted_time_s"] == ENCOUNTER_SKETCH_COST.bounds_s(1, 4, 16)


@pytest.mark.slow
def test_encounter_book_numbers_and_the_offset(client):
    """(4.16) at beta = 45 deg is a ln((1 + cos)/(1 - cos)) = 1.7627 a; the exact greatest
    length is below it at mu_c = 0.5 (sketch i from 45 deg: the tip line overestimates);
    the offset d = a (1 - sin beta) (4.24) gives the same encounter."""
    r, got = post(client, ENCOUNTER, {"disk_radius": 1.0, "beta_initial": D(45), "mu_c": 0.5, "method": "closed_form"})
    assert r.status_code == 200, r.text
    c = math.cos(D(45))
    assert got["length_greatest"]["closed_form"] == pytest.approx(math.log((1 + c) / (1 - c)), rel=1e-14)
    assert got["length_greatest"]["exact"] is None and got["predicted_time_s"] == 0.0
    d = 1.0 - math.sin(D(45))
    r, by_offset = post(client, ENCOUNTER, {"disk_radius": 1.0, "offset": d, "mu_c": 0.5, "method": "closed_form"})
    assert by_offset["beta_source"] == "offset" and by_offset["beta_initial"] == pytest.approx(D(45), abs=1e-15)
    assert by_offset["offset"] == d
    assert by_offset["length_greatest"]["closed_form"] == pytest.approx(got["length_greatest"]["closed_form"], rel=1e-14)
    r, ex = post(client, ENCOUNTER, {"disk_radius": 1.0, "beta_initial": D(45), "mu_c": 0.5, "n_nodes": 8, "n_points": 64})
    assert ex["length_greatest"]["exact"] < ex["length_greatest"]["closed_form"]
    assert ex["length_greatest"]["difference"] < 0.0


def test_encounter_quasi_static_is_that_of_the_disk(client):
    body = {"disk_radius": 3.5, "beta_initial": 0.6, "mu_c": 0.5, "method": "closed_form",
            "quasi_static": {"speed": 10.0, "mu_s": 0.25, "length_unit": "cm"}}
    r, got = post(client, ENCOUNTER, body)
    assert r.status_code == 200, r.text
    want = qs.assess(10.0, 0.25, qs.gravity("cm"), qs.ShapeMoments.disk(3.5))
    assert got["quasi_static"]["verdict"] == want.verdict == "quasi_static"
    assert got["quasi_static"]["within_quasi_static"] is True
    assert got["quasi_static"]["angular"]["characteristic_speed"] == want.angular.characteristic_speed


@pytest.mark.slow
def test_encounter_warns_about_a_poor_quadrature(client):
    r, got = post(client, ENCOUNTER, {"disk_radius": 1.0, "beta_initial": 1e-6, "mu_c": 0.5, **FAST})
    assert r.status_code == 200, r.text
    assert "warning" in got["message"] and "n_nodes" in got["message"]


@pytest.mark.parametrize(
    "change, loc, type_",
    [
        ({"beta_initial": None}, ["body", "beta_initial"], "value_error"),  # neither
        ({"offset": 0.2}, ["body", "offset"], "value_error"),  # both
        ({"beta_initial": None, "offset": 1.0}, ["body", "offset"], "value_error"),  # d = a: head-on
        ({"beta_initial": None, "offset": 0.0}, ["body", "offset"], "greater_than_equal"),
        ({"beta_initial": 0.0}, ["body", "beta_initial"], "beta_range"),
        ({"beta_initial": math.pi / 2}, ["body", "beta_initial"], "beta_range"),
        ({"mu_c": 0.0}, ["body", "mu_c"], "greater_than"),
        ({"disk_radius": 0.0}, ["body", "disk_radius"], "greater_than_equal"),
        ({"n_nodes": 2}, ["body", "n_nodes"], "greater_than_equal"),
        ({"n_nodes": 64, "n_points": 4096}, ["body", "time_limit_s"], "value_error"),
        ({"method": None, "beta_initial": "0.5"}, ["body", "beta_initial"], "float_type"),
        ({"alpha": 1.0}, ["body", "alpha"], "extra_forbidden"),
    ],
)
@pytest.mark.wall_clock  # about the time limit itself: its real deadline (tests/service/conftest.py)
def test_encounter_bad_inputs_are_422_naming_the_field(client, change, loc, type_):
    base = {"disk_radius": 1.0, "beta_initial": 0.5, "mu_c": 0.5, "method": "closed_form"}
    body = {k: v for k, v in {**base, **change}.items() if v is not None}
    if "n_points" in change:
        body["method"] = "both"
    r, got = post(client, ENCOUNTER, body)
    assert r.status_code == 422, r.text
    assert detail(got)[:2] == (loc, type_)


def test_limits_are_in_the_openapi_schema(client):
    doc = client.get("/openapi.json").json()
    align = doc["components"]["schemas"]["PushAlignRequest"]
    assert set(align["required"]) == {"footprint", "fence_angle"}
    assert align["properties"]["n_nodes"]["maximum"] == GROSS_MAX_N_NODES
    assert align["properties"]["n_points"]["maximum"] == SKETCH_MAX_N_POINTS
    assert align["properties"]["time_limit_s"]["maximum"] == MAX_TIME_LIMIT_S
    enc = doc["components"]["schemas"]["PushDiskEncounterRequest"]
    assert enc["x-exactly-one-of"] == [["beta_initial", "offset"]] and "oneOf" not in enc
    assert enc["properties"]["mu_c"]["exclusiveMinimum"] == 0
    for url, op_id in ((ALIGN, "push_align"), (ENCOUNTER, "push_disk_encounter")):
        op = doc["paths"][url]["post"]
        assert op["operationId"] == op_id
        assert op["responses"]["422"]["content"]["application/json"]["schema"] == {
            "$ref": "#/components/schemas/ErrorResponse"}


DOC = Path(__file__).resolve().parents[4] / "docs" / "api.md"
CURL = re.compile(
    r"curl -s '?http://127\.0\.0\.1:8000(/v1/push/[^ ']+)'? -H 'content-type: application/json' \\\n  -d '([^']+)'"
)


def test_docs_examples_of_these_endpoints_run(client):
    """Both endpoints have examples in docs/api.md (tests/service/test_docs_examples.py runs
    them all); the closed-form ones run here too, with their quasi-static verdicts."""
    examples = [(url, json.loads(body)) for url, body in CURL.findall(DOC.read_text(encoding="utf-8"))
                if url in (ALIGN, ENCOUNTER)]
    assert {url for url, _ in examples} == {ALIGN, ENCOUNTER}
    quick = [(url, body) for url, body in examples if body.get("method") == "closed_form"]
    assert len(quick) == 2
    for url, body in quick:
        r, got = post(client, url, body)
        assert r.status_code == 200, (body, r.text)
        assert got["quasi_static"]["verdict"] == "quasi_static"
