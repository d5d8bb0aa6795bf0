"""POST /v1/cor/sketch: the COR sketch with pusher friction (book 4.1).

The route is thin: its JSON is models.sketch.disk_sketch.cor_sketch on the same scene with the
solver's compiled sticking sweep (solver/sketch/sweep.py, its own agreement with the
reference tested in tests/solver/sketch/test_sweep.py), number for number; the nine sketch letters of figure 4-6 come through (scenes of
tests/models/sketch/test_disk_sketch.py); a push whose line passes through the CM inside the friction
cone is answered as a translation (and forward solves agree that the part translates,
sticking); a polygon is sketched as its circumscribing disk; the SVG is valid XML with the
book's elements; invalid input is 422 naming the field; the docs example runs.
"""

from __future__ import annotations

import json
import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from models.core.footprint import Footprint
from models.core.scene import PushScene
from models.core.support import random_balanced_tripods
from models.sketch.disk_sketch import IMPLIED_MODES, disk_cor_sketch
from service.limits import SKETCH_MAX_N_POINTS, SKETCH_MIN_LENGTH
from solver.motion.forward import BatchResult, solve_forward_batch
from solver.sketch.sweep import sticking_spans
from tests.scenes import CONFIGS, SHORT, SKETCH_SCENES

URL = "/v1/cor/sketch"
EXAMPLE = {"disk_radius": 1.0, "contact_point": [-0.5, -0.3], "edge_angle": math.pi / 2, "mu_c": 0.3}
L_SHAPE = [[0, 0], [3, 0], [3, 1], [1, 1], [1, 3], [0, 3]]
DOC = Path(__file__).resolve().parents[4] / "docs" / "api.md"


def strict_json(text: str):
    def reject(token):
        raise AssertionError(f"non-finite number {token} in JSON")

    return json.loads(text, parse_constant=reject)


def post(client, body, fmt=None):
    r = client.post(URL, json=body, params=None if fmt is None else {"format": fmt})
    return r, (strict_json(r.text) if r.headers["content-type"].startswith("application/json") else None)


def detail(got) -> tuple[list, str, str]:
    (item,) = got["detail"]
    return item["loc"], item["type"], item["msg"]


def body_of(params) -> dict:
    x, y, edge, mu_c = params
    return {"disk_radius": 1.0, "contact_point": [x, y], "edge_angle": math.radians(edge), "mu_c": mu_c}


def expected(sk, scene) -> dict:
    """The model's CorSketch as the response's numbers (the conversion, written out)."""

    def arr(x):
        return None if x is None else np.asarray(x, dtype=float).tolist()

    def elem(loc, sigma):
        return {
            "label": loc.label, "force_direction": arr(loc.force), "force_angle": sigma * sk.nu,
            "boundary": arr(loc.boundary), "tip": arr(loc.tip), "moment_sign": loc.moment_sign,
            "configuration": loc.configuration, "crosses_sticking_line": loc.crosses_sticking_line,
            "tip_on_cm_side": loc.tip_on_cm_side,
        }

    st = sk.sticking
    return {
        "mu_c": sk.mu_c, "nu": sk.nu, "sense": sk.sense,
        "disk_radius": scene.disk_radius, "center_of_mass": arr(scene.center_of_mass),
        "sticking_line": {"point": arr(sk.sticking_line_point), "direction": arr(sk.sticking_line_direction)},
        "edge_normal_direction": arr(sk.edge_normal_direction),
        "plus": elem(sk.plus, 1.0), "minus": elem(sk.minus, -1.0),
        "down_slipping": [arr(p) for p in sk.down_slipping],
        "up_slipping": [arr(p) for p in sk.up_slipping],
        "sticking": None if st is None else {
            "t_low": st.t_low, "t_high": st.t_high, "low": arr(st.low), "high": arr(st.high),
            "phi_low": st.phi_low, "phi_high": st.phi_high,
        },
        "tip_line_estimate": None if sk.tip_line_t is None else {
            "point": arr(sk.tip_line_low), "t": sk.tip_line_t, "error": sk.tip_line_error,
        },
        "sketch": sk.sketch, "mirrored": sk.mirrored, "implication": sk.implication,
        "allowed_modes": list(sk.allowed_modes),
    }


# ---------------------------------------------------------------------------------------
# The answer is the model's
# ---------------------------------------------------------------------------------------


@pytest.mark.slow
@pytest.mark.parametrize("n_points", [64, 512])
def test_json_is_the_model(client, n_points):
    r, got = post(client, {**EXAMPLE, "n_points": n_points})
    assert r.status_code == 200, r.text
    scene = PushScene.create(1.0, EXAMPLE["contact_point"], EXAMPLE["edge_angle"], 0.0)
    want = expected(disk_cor_sketch(scene, 0.3, n_points=n_points, spans=sticking_spans), scene)
    assert {k: got[k] for k in want} == want
    assert got["kind"] == "sketch" and got["sketch_of"] == "disk" and got["n_points"] == n_points
    assert got["warnings"] == [] and got["contact_distance_to_outline"] is None
    assert got["elapsed_ms"] > 0.0
    # the example of docs/api.md: mirrored d, stick or slip down
    assert (got["sketch"], got["mirrored"], got["implication"]) == ("d", True, "stick_or_slip_down")
    assert got["message"].startswith("sketch d of figure 4-6, mirrored")


@pytest.mark.slow
def test_defaults_and_other_push_directions(client):
    """push_direction, center_of_mass reach the model; the default n_points is the model's."""
    body = {**EXAMPLE, "center_of_mass": [2.0, -1.0], "contact_point": [1.4, -1.2], "push_direction": 0.2,
            "edge_angle": 1.9}
    r, got = post(client, body)
    assert r.status_code == 200, r.text
    scene = PushScene.create(1.0, (1.4, -1.2), 1.9, 0.2, (2.0, -1.0))
    want = expected(disk_cor_sketch(scene, 0.3, spans=sticking_spans), scene)
    assert {k: got[k] for k in want} == want and got["n_points"] == 512


@pytest.mark.slow
def test_polygon_is_sketched_as_its_circumscribing_disk(client):
    r, got = post(client, {"footprint": L_SHAPE, "contact_point": [0, 0.5], "edge_angle": math.pi / 2, "mu_c": 0.4})
    assert r.status_code == 200, r.text
    fp = Footprint.create(L_SHAPE)
    scene = PushScene.create(fp.circumradius, (0, 0.5), math.pi / 2, 0.0, fp.center_of_mass)
    want = expected(disk_cor_sketch(scene, 0.4, spans=sticking_spans), scene)
    assert {k: got[k] for k in want} == want
    assert got["sketch_of"] == "circumscribing_disk" and "circumscribing disk" in got["message"]
    assert got["contact_distance_to_outline"] == 0.0
    r2, got2 = post(client, {"workpiece": L_SHAPE, "contact_point": [0, 0.5], "edge_angle": math.pi / 2, "mu_c": 0.4})
    assert r2.status_code == 200 and {k: got2[k] for k in want} == want


# ---------------------------------------------------------------------------------------
# The nine sketches of figure 4-6
# ---------------------------------------------------------------------------------------


@pytest.mark.slow
@pytest.mark.parametrize("letter, mirrored, params", SKETCH_SCENES[::2], ids=lambda v: str(v))
def test_sketch_letters(client, letter, mirrored, params):
    r, got = post(client, {**body_of(params), "n_points": 256})
    assert r.status_code == 200, r.text
    assert (got["sketch"], got["mirrored"], got["kind"]) == (letter, mirrored, "sketch")
    pair = (SHORT[got["plus"]["configuration"]], SHORT[got["minus"]["configuration"]])
    assert (pair[::-1] if mirrored else pair) == CONFIGS[letter]
    assert set(got["allowed_modes"]) == set(IMPLIED_MODES[got["implication"]])
    assert f"sketch {letter} of figure 4-6" in got["message"]


def test_a_wrapped_locus_has_no_tip_side_and_no_slipping(client):
    """Sketch g: {COR}_(alpha-nu) wrapped, nothing slips; the sticking locus comes from the
    intermediate force angles (4.1.6)."""
    r, got = post(client, body_of((-0.6, 0.52, 36, 2.37)))
    assert got["sketch"] == "g" and got["implication"] == "must_stick"
    assert got["minus"]["configuration"] == "wrapped" and got["minus"]["tip_on_cm_side"] is None
    assert got["down_slipping"] == [] and got["up_slipping"] == []
    st = got["sticking"]
    assert st["t_low"] < st["t_high"] and -got["nu"] <= st["phi_low"] <= got["nu"]


# ---------------------------------------------------------------------------------------
# Translations
# ---------------------------------------------------------------------------------------


def test_push_line_through_the_cm_inside_the_cone_is_a_translation(client):
    """Mason's rule gives no sense: the answer says so (200, kind 'translation', no letter, no
    finite loci), and forward solves on random tripods agree: every one translates, sticking."""
    body = {**EXAMPLE, "contact_point": [-0.5, 0.0]}
    r, got = post(client, body)
    assert r.status_code == 200, r.text
    assert (got["kind"], got["sense"], got["sketch"], got["implication"]) == ("translation", "none", None, None)
    assert got["allowed_modes"] == [] and got["sticking"] is None
    assert got["down_slipping"] == [] and got["up_slipping"] == []
    assert "translates" in got["message"] and "sticking" in got["message"]
    scene = PushScene.create(1.0, (-0.5, 0.0), math.pi / 2, 0.0)
    pts, wts = random_balanced_tripods(np.random.default_rng(4), 300, 1.0)
    br = solve_forward_batch(scene, pts, wts, mu_c=0.3)
    assert {BatchResult.MODES[m] for m in br.mode} == {"sticking"}
    assert not np.isfinite(br.cor).any()  # every COR at infinity
    r, _ = post(client, body, "svg")
    assert r.status_code == 200 and 'id="translation"' in r.text


def test_contact_at_the_cm_is_a_translation(client):
    r, got = post(client, {**EXAMPLE, "contact_point": [0.0, 0.0]})
    assert r.status_code == 200, r.text
    assert got["kind"] == "translation" and "contact is at the centre of mass" in got["message"]
    assert got["tip_line_estimate"] is None


@pytest.mark.slow
def test_line_of_force_through_the_cm_alone_still_rotates(client):
    """The edge normal through the CM (a frictionless translation) pushed obliquely: with
    friction the push line decides, the part turns and the sketch is g (must stick)."""
    r, got = post(client, {**EXAMPLE, "contact_point": [-0.5, 0.0], "push_direction": 0.3})
    assert r.status_code == 200, r.text
    assert (got["kind"], got["sense"], got["sketch"]) == ("sketch", "cw", "g")
    assert got["plus"]["moment_sign"] != 0 and got["sticking"] is not None


# ---------------------------------------------------------------------------------------
# SVG
# ---------------------------------------------------------------------------------------


@pytest.mark.slow
@pytest.mark.parametrize("body, ids", [
    (body_of((-0.15, 0.89, 42, 0.06)),  # f: both slipping loci, sticking locus in view
     {"disk", "center-of-mass", "contact", "push-arrow", "friction-cone", "sticking-line", "edge-normal-line",
      "locus-plus", "locus-minus", "down-slipping-0", "up-slipping-0", "sticking-locus", "tip-line",
      "tip-line-estimate", "legend"}),
    ({**body_of((0.7732, -0.00773, math.degrees(1.66288), 1.248))},  # sticking locus ~100 a away
     {"sticking-locus-off-picture", "locus-plus", "locus-minus", "friction-cone"}),
    ({"footprint": L_SHAPE, "contact_point": [0, 0.5], "edge_angle": math.pi / 2, "mu_c": 0.4},
     {"workpiece", "down-slipping-0", "sticking-locus"}),
])
def test_svg_is_xml_with_the_sketch(client, body, ids):
    r, _ = post(client, body, "svg")
    assert r.status_code == 200, r.text
    assert r.headers["content-type"] == "image/svg+xml"
    root = ET.fromstring(r.content)
    assert root.tag == "{http://www.w3.org/2000/svg}svg"
    found = {el.get("id") for el in root.iter()}
    assert ids <= found, ids - found
    title = root.find("{http://www.w3.org/2000/svg}metadata")
    assert title is not None
    got = strict_json(client.post(URL, json=body).text)
    letter = got["sketch"]
    assert f"COR sketch {letter}" in r.text  # the title, in the SVG's metadata


@pytest.mark.slow
def test_svg_at_extreme_scales(client):
    """Drawn relative to the CM and in powers of ten: tiny parts far from the origin."""
    for a, cm in ((1e-9, [1e6, -1e6]), (1e9, [0.0, 0.0]), (SKETCH_MIN_LENGTH, [0.0, 0.0])):
        body = {"disk_radius": a, "center_of_mass": cm, "contact_point": [cm[0] - 0.5 * a, cm[1] - 0.3 * a],
                "edge_angle": math.pi / 2, "mu_c": 0.3}
        r, _ = post(client, body, "svg")
        assert r.status_code == 200, (a, r.text)
        ET.fromstring(r.content)
        got = strict_json(client.post(URL, json=body).text)
        if a != 1e-9:  # (1e6 + 5e-10 is not exact in floating point: a slightly other scene)
            assert (got["sketch"], got["mirrored"]) == ("d", True), a


# ---------------------------------------------------------------------------------------
# Errors
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("mu_c", [0, 0.0, -0.5])
def test_frictionless_is_refused_with_a_pointer_to_the_locus(client, mu_c):
    r, got = post(client, {**EXAMPLE, "mu_c": mu_c})
    assert r.status_code == 422
    loc, type_, msg = detail(got)
    assert loc == ["body", "mu_c"] and type_ == "greater_than"
    assert "/v1/cor/locus" in msg and "frictionless" in msg


@pytest.mark.parametrize("body, loc, type_", [
    ({k: v for k, v in EXAMPLE.items() if k != "mu_c"}, ["body", "mu_c"], "missing"),
    ({k: v for k, v in EXAMPLE.items() if k != "contact_point"}, ["body", "contact_point"], "missing"),
    ({k: v for k, v in EXAMPLE.items() if k != "edge_angle"}, ["body", "edge_angle"], "missing"),
    ({**EXAMPLE, "mu_c": 1e7}, ["body", "mu_c"], "less_than_equal"),
    ({**EXAMPLE, "mu_c": "0.3"}, ["body", "mu_c"], "float_type"),
    ({**EXAMPLE, "n_points": SKETCH_MAX_N_POINTS + 1}, ["body", "n_points"], "less_than_equal"),
    ({**EXAMPLE, "n_points": 7}, ["body", "n_points"], "greater_than_equal"),
    ({**EXAMPLE, "disk_radius": 1e-120}, ["body", "disk_radius"], "greater_than_equal"),
    ({**EXAMPLE, "extra": 1}, ["body", "extra"], "extra_forbidden"),
    ({**EXAMPLE, "push_direction": math.pi / 2}, ["body", "push_direction"], "value_error"),
    ({**EXAMPLE, "disk_radius": None}, ["body", "disk_radius"], "value_error"),
    ({**EXAMPLE, "footprint": L_SHAPE}, ["body", "footprint"], "value_error"),
    ({**EXAMPLE, "disk_radius": None, "footprint": [[0, 0], [1, 1], [1, 0], [0, 1]]}, ["body", "footprint"],
     "value_error"),
    ({**EXAMPLE, "disk_radius": None, "footprint": [[0, 0], [1, 1]]}, ["body", "footprint"], "too_short"),
    ({**EXAMPLE, "disk_radius": None, "footprint": [[0, 0], [1e-110, 0], [0, 1e-110]], "contact_point": [0, 0]},
     ["body", "footprint"], "value_error"),
    ({**EXAMPLE, "disk_radius": 1e-13}, ["body", "disk_radius"], "value_error"),
])
def test_invalid_input_is_422_at_the_field(client, body, loc, type_):
    r, got = post(client, body)
    assert r.status_code == 422, r.text
    assert detail(got)[:2] == (loc, type_)


@pytest.mark.parametrize("literal", ["NaN", "Infinity", "-Infinity", "1e400"])
def test_non_finite_numbers_are_refused(client, literal):
    text = json.dumps(EXAMPLE).replace('"mu_c": 0.3', f'"mu_c": {literal}')
    r = client.post(URL, content=text, headers={"content-type": "application/json"})
    assert r.status_code == 422
    loc, type_, _ = detail(strict_json(r.text))
    assert loc == ["body", "mu_c"] and type_ in ("finite_number", "less_than_equal", "greater_than")


def test_unknown_format_is_refused(client):
    r, got = post(client, EXAMPLE, "png")
    assert r.status_code == 422 and detail(got)[0] == ["query", "format"]


# ---------------------------------------------------------------------------------------
# Docs
# ---------------------------------------------------------------------------------------


def test_docs_describe_every_response_field_and_the_nine_sketches():
    from service.api.sketch.schemas import CorSketchResponse

    text = DOC.read_text(encoding="utf-8")
    section = text[text.index("## `POST /v1/cor/sketch`"):]
    section = section[: section.index("\n## ", 5)]
    for name in CorSketchResponse.model_fields:
        assert f"`{name}`" in section, name
    for letter, (plus, minus) in CONFIGS.items():
        assert re.search(rf"\| {letter} \|[^\n]*{plus}[^\n]*{minus}", section), letter


def test_docs_example_is_this_answer(client):
    text = DOC.read_text(encoding="utf-8")
    m = re.search(
        r"curl -s http://127\.0\.0\.1:8000/v1/cor/sketch -H 'content-type: application/json' \\\n  -d '([^']+)'", text
    )
    assert m, "no curl example of /v1/cor/sketch in docs/api.md"
    r, got = post(client, json.loads(m.group(1)))
    assert r.status_code == 200 and got["sketch"] == "d" and got["mirrored"] is True


@pytest.mark.slow
def test_no_letter_when_the_loci_match_none_of_the_nine(client):
    """(P, W) with a wide cone whose edge points back against the push: nothing can stick,
    so the loci are not sketch g's; the answer says so and keeps the model's modes."""
    body = {**body_of((0.51, 0.36, 15, 3.0)), "push_direction": 0.11, "n_points": 64}
    r, got = post(client, body)
    assert r.status_code == 200, r.text
    assert (got["kind"], got["sketch"], got["implication"]) == ("sketch", None, None)
    assert got["sticking"] is None and got["allowed_modes"] == ["slipping_down"]
    assert "matches none of the nine" in got["message"]
    r, _ = post(client, body, "svg")
    assert r.status_code == 200 and "matches none of the nine" in r.text


# ---------------------------------------------------------------------------------------
# method "certified" (solver/sketch/certified_sketch.py)
# ---------------------------------------------------------------------------------------

RECT = [[-1.5, -0.4], [1.5, -0.4], [1.5, 0.4], [-1.5, 0.4]]
MUST_STICK = {"footprint": RECT, "contact_point": [-1.5, 0.18766172], "edge_angle": math.pi / 2,
              "push_direction": -0.4635935760943159, "mu_c": 0.3, "n_rays": 8}


@pytest.mark.slow
def test_certified_sketch_of_a_polygon_is_the_polygons_own(client):
    """The rectangle must stick (sketch g) where its circumscribing disk allows slipping up
    (mirrored i); the answer is the solver's, with its certification report."""
    from solver.sketch.certified_sketch import certified_sketch

    r, disk = post(client, {**MUST_STICK, "n_points": 256})
    assert r.status_code == 200 and disk["sketch_of"] == "circumscribing_disk" and disk["sketch"] == "i"
    assert disk["method"] == "analytic" and disk["certification"] is None
    r, got = post(client, {**MUST_STICK, "method": "certified"})
    assert r.status_code == 200, r.text
    assert got["sketch_of"] == "polygon" and got["method"] == "certified"
    assert got["sketch"] == "g" and got["allowed_modes"] == ["sticking"] and "polygon itself" in got["message"]
    cert = got["certification"]
    assert cert["complete"] and not cert["time_limited"] and cert["message"] == "every piece certified"
    assert cert["sticking_status"] == "found" and cert["n_rays"] == 8
    assert cert["sticking_lower"]["certified"] and cert["sticking_upper"]["certified"]
    lo = cert["sticking_lower"]
    assert lo["infeasible_position"] < lo["position"] < lo["feasible_position"]
    assert got["sticking"]["t_low"] == lo["position"] and got["sticking"]["phi_low"] is None
    # the disk's sticking segment contains the polygon's (7.5)
    assert disk["sticking"]["t_low"] <= got["sticking"]["t_low"] < got["sticking"]["t_high"] <= disk["sticking"]["t_high"]
    fp = Footprint.create(RECT)
    scene = PushScene.create(fp.circumradius, np.array(MUST_STICK["contact_point"]), math.pi / 2,
                             MUST_STICK["push_direction"], fp.center_of_mass)
    cs = certified_sketch(scene, 0.3, fp, n_rays=8)
    assert got["sticking"]["t_high"] == pytest.approx(cs.sketch.sticking.t_high, abs=1e-12)
    assert (cert["plus_certified_rays"], cert["minus_certified_rays"]) == (
        None if cs.plus_trace is None else cs.plus_trace.n_certified,
        None if cs.minus_trace is None else cs.minus_trace.n_certified)
    r = client.post(URL, json={**MUST_STICK, "method": "certified"}, params={"format": "svg"})
    assert r.status_code == 200 and r.headers["content-type"].startswith("image/svg+xml")
    ET.fromstring(r.text)


@pytest.mark.slow
def test_certified_sketch_of_a_disk_has_exact_sticking_ends(client):
    r, got = post(client, {**EXAMPLE, "method": "certified"})
    _, sweep = post(client, EXAMPLE)
    assert r.status_code == 200 and got["sketch_of"] == "disk"
    assert got["certification"]["n_rays"] is None and got["certification"]["plus_certified_rays"] is None
    assert got["plus"] == sweep["plus"] and got["sketch"] == sweep["sketch"]
    assert got["sticking"]["t_low"] == pytest.approx(sweep["sticking"]["t_low"], abs=1e-4)
    assert got["sticking"]["t_high"] == pytest.approx(sweep["sticking"]["t_high"], abs=1e-4)


@pytest.mark.wall_clock  # about the time limit itself: its real deadline (tests/service/conftest.py)
def test_certified_sketch_out_of_time_says_so(client):
    r, got = post(client, {**MUST_STICK, "method": "certified", "time_limit_s": 1e-6})
    assert r.status_code == 200, r.text
    cert = got["certification"]
    assert cert["time_limited"] and not cert["complete"] and cert["message"] != "every piece certified"


@pytest.mark.parametrize("change, field", [({"n_rays": 3}, "n_rays"), ({"n_rays": 257}, "n_rays"),
                                           ({"time_limit_s": 0}, "time_limit_s"), ({"method": "exact"}, "method")])
def test_certified_sketch_bad_knobs_are_422(client, change, field):
    r, got = post(client, {**MUST_STICK, "method": "certified", **change})
    assert r.status_code == 422 and detail(got)[0] == ["body", field]


@pytest.mark.slow
def test_a_certified_sketch_cut_by_its_time_limit_answers_the_disks_bound(client, monkeypatch):
    """With a work limit the certified sketch stops early; the answer is then the
    circumscribing disk's sketch, which bounds the polygon's (7.5), and the message says so
    first (issue 35: a cut one answered "PROVISIONAL ... matches none of the nine
    sketches", a verdict drawn from the pieces finished). The whole sketch has no such note."""
    from service.runtime.deadline import Deadline
    from tests.budgets import ChecksBudgets, NoLimitBudgets, deadline_budgets

    body = {"footprint": [[-1.5, -0.4], [1.5, -0.4], [1.5, 0.4], [-1.5, 0.4]], "contact_point": [-0.6, -0.4],
            "edge_angle": 0.3, "push_direction": math.pi / 2, "mu_c": 0.5, "method": "certified", "n_rays": 8,
            "time_limit_s": 10.0}
    monkeypatch.setattr(Deadline, "budget", deadline_budgets(ChecksBudgets(3)))
    cut = client.post(URL, json=body).json()
    assert cut["message"].startswith("the polygon's certified sketch is incomplete (the time limit cut it short")
    assert "circumscribing disk's sketch, which bounds it (7.5), is answered" in cut["message"]
    assert "matches none" not in cut["message"] and cut["sketch_of"] == "circumscribing_disk"
    assert cut["certification"]["complete"] is False
    analytic = client.post(URL, json={**body, "method": "analytic"}).json()
    assert cut["sketch"] == analytic["sketch"] and cut["allowed_modes"] == analytic["allowed_modes"]
    monkeypatch.setattr(Deadline, "budget", deadline_budgets(NoLimitBudgets))  # a busy machine cannot cut it
    whole = client.post(URL, json=body).json()
    assert whole["certification"]["complete"] is True and "incomplete" not in whole["message"]
    assert whole["sketch_of"] == "polygon"


def test_the_book_6_3_experiment_is_certified_whole_by_the_service():
    """Issue 26: the certified sketch of the book's 6.3 experiment (a disk of radius 1.25
    pushed by a fence at 70 degrees, contact on the rim, mu_c 0.5) answered its sticking
    locus's lower end "undecided": the restricted master stalled at a residual of 1.16e-6
    just inside the end (a cold Clarabel solve; the outcome had hung on the seeds' warm
    columns). A stalled master below POLISH_LAST_TRY is polished once more: both ends are
    certified, with the 6.3 figures (solver/sketch tests: -5.528 a and -2.481 a)."""
    from fastapi.testclient import TestClient

    from service.app import create_app
    from service.settings import Settings

    a, al = 1.25, math.radians(70)
    body = {"disk_radius": a, "contact_point": [-a * math.sin(al), a * math.cos(al)], "edge_angle": al,
            "mu_c": 0.5, "method": "certified"}
    with TestClient(create_app(Settings(solver_workers=0)), raise_server_exceptions=False) as c:
        cert = c.post("/v1/cor/sketch", json=body).json()["certification"]
    assert cert["complete"] and cert["sticking_status"] == "found"
    for end in ("sticking_lower", "sticking_upper"):
        assert cert[end]["status"] == "bracketed" and cert[end]["certified"], cert[end]
    assert abs(cert["sticking_lower"]["position"] - (-7.3374477)) < 1e-6
