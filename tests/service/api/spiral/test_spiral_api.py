"""POST /v1/spiral/critical-radius and POST /v1/spiral/schedule (book 4.5).

The routes are thin: the critical radii are solver.spiral.schedule's number for number, the
schedule is plan_spiral's on the same (cached, scaled) table; (4.25) comes out of the
numerical limit; schedules are safe against their table (every step <= d*, 4.26), certified
optimal, never slower than the recursion by more than the grid, and scale with a; the
tip-line comparison is counted; the simulation check keeps every disk; bad input is 422
naming the field; the SVG pictures parse."""

from __future__ import annotations

import json
import math
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from models.spiral.critical import limiting_radius
from models.spiral.path import tip_line_spiral
from service.api.spiral.convert import simulation_summary
from service.runtime.deadline import Deadline
from solver.spiral.critical_radius import critical_radius_table
from tests.budgets import NoLimitBudgets, deadline_budgets

CRIT = "/v1/spiral/critical-radius"
SCHED = "/v1/spiral/schedule"


def strict_json(text: str):
    def reject(token):
        raise AssertionError(f"non-finite number {token} in JSON")

    return json.loads(text, parse_constant=reject)


def post(client, url, body, fmt=None):
    r = client.post(url, json=body, params=None if fmt is None else {"format": fmt})
    return r, (strict_json(r.text) if r.headers["content-type"].startswith("application/json") else None)


def detail(got):
    (item,) = got["detail"]
    return item["loc"], item["type"], item["msg"]


@pytest.mark.slow
def test_critical_radius_at_given_betas_is_the_solvers(client):
    """4.5.3: r*(beta) by the sweep at three collision parameters, the tip line 2a/sin(beta)
    beside it, d = a(1 - sin beta) (4.24), and the limit beta -> pi/2 against (4.25)."""
    body = {"disk_radius": 2.0, "mu_c": 0.25, "betas": [0.3, 0.8, 1.3], "radii": [2.4, 4.0, 10.0]}
    r, got = post(client, CRIT, body)
    assert r.status_code == 200, r.text
    tab = critical_radius_table(2.0, 0.25, "sweep", betas=[0.3, 0.8, 1.3], sweep_points=512, find_kink=False)
    assert [p["r_star"] for p in got["points"]] == tab.radii.tolist()
    for p in got["points"]:
        assert p["tip_line_radius"] == pytest.approx(4.0 / math.sin(p["beta"]), rel=1e-14)
        assert p["distance_from_grazing"] == pytest.approx(2.0 * (1.0 - math.sin(p["beta"])), rel=1e-14)
        assert p["tip_line_error"] == pytest.approx(p["tip_line_radius"] - p["r_star"], rel=1e-12)
        assert p["status"] == "approximate" and p["certified"] is False
    assert got["points"][0]["tip_line_error"] < 0.0  # the tip line is ~0.3 % low at beta = 0.3: unsafe there
    lim = got["b_inf"]
    assert lim["closed_form"] == 2.0 * 1.25 and lim["tip_line"] == 4.0
    assert lim["numeric"] == pytest.approx(2.5, abs=1e-4)  # (4.25) from beta = pi/2 - 1e-6
    # inverse: below every r* no guarantee; else bisected between the table's points to
    # 1e-4 rad, not snapped to the next given beta (which said beta*(4 = 2a) = 1.3 where it is ~1.0)
    inv = got["inverse"]
    assert inv[0]["beta_star"] is None and inv[0]["distance_star"] == 0.0
    for q, table_beta in ((inv[1], 1.3), (inv[2], 0.8)):
        assert q["beta_below"] < q["beta_star"] <= table_beta and q["beta_star"] - q["beta_below"] <= 1e-4
        assert q["distance_star"] == pytest.approx(2.0 * (1.0 - math.sin(q["beta_star"])), rel=1e-14)
        at = critical_radius_table(2.0, 0.25, "sweep", betas=[q["beta_below"], q["beta_star"]], sweep_points=512,
                                   find_kink=False).radii
        assert at[1] <= q["radius"] < at[0]  # r* crosses r inside the reported bracket
    assert inv[1]["beta_star"] < 1.1  # ~1.0 for r = 2a (4.5.3), far below the table's 1.3
    assert got["monotone"] and got["complete"] and not got["from_cache"]


@pytest.mark.slow
def test_exact_critical_radii_are_certified_upper_bounds(client):
    r, got = post(client, CRIT, {"disk_radius": 1.0, "mu_c": 0.5, "betas": [0.6, 1.2], "method": "exact"})
    assert r.status_code == 200, r.text
    _, sweep = post(client, CRIT, {"disk_radius": 1.0, "mu_c": 0.5, "betas": [0.6, 1.2]})
    for p, s in zip(got["points"], sweep["points"]):
        assert p["certified"] and p["status"] == "bracketed"
        assert p["lower_bound"] < p["midpoint"] < p["r_star"]
        assert p["r_star"] - p["lower_bound"] == pytest.approx(p["bracket_width"], rel=1e-6)
        assert s["r_star"] == pytest.approx(p["midpoint"], abs=2e-4)


def test_figure_4_19_grid_by_the_tip_line_and_the_cache(client):
    """Without betas: the grid of figure 4-19 up to max_radius; the tip line needs no solve;
    a second request for another disk size comes from the cache, scaled by a."""
    r, got = post(client, CRIT, {"disk_radius": 1.0, "mu_c": 0.3, "method": "tip_line", "max_radius": 50.0})
    assert r.status_code == 200, r.text
    betas = [p["beta"] for p in got["points"]]
    assert betas == sorted(betas) and betas[-1] == pytest.approx(0.5 * math.pi - 1e-6)
    assert max(p["r_star"] for p in got["points"]) >= 50.0
    assert all(p["r_star"] == p["tip_line_radius"] for p in got["points"])
    r2, again = post(client, CRIT, {"disk_radius": 1e-3, "mu_c": 0.3, "method": "tip_line", "max_radius": 0.05})
    assert again["from_cache"] is True
    assert [p["r_star"] for p in again["points"]] == pytest.approx([1e-3 * p["r_star"] for p in got["points"]], rel=1e-12)


@pytest.fixture(scope="module")
def sweep_plan(client):
    """One sweep plan (the table for mu_c = 0.25 up to 10 a, cached afterwards), without a
    time limit: the tests below are about the plan, which a busy machine must not cut short."""
    body = {"disk_radius": 1.0, "mu_c": 0.25, "start_radius": 8.0, "target": 1.6,
            "simulate": {"n_supports": 3, "seed": 5, "kind": "dipod"}}
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(Deadline, "budget", deadline_budgets(NoLimitBudgets))
        r, got = post(client, SCHED, body)
    assert r.status_code == 200, r.text
    return body, got


@pytest.mark.slow
def test_schedule_is_safe_optimal_and_no_slower_than_the_recursion_by_more_than_the_grid(sweep_plan):
    body, got = sweep_plan
    s, rec = got["schedule"], got["recursion"]
    assert s["solver_status"] == "OPTIMAL" and s["certificate"]["certified"]
    assert s["certificate"]["gap"] == 0 and s["certificate"]["min_reduced_cost"] >= 0
    radii = np.array(s["radii"])
    assert radii[0] == 8.0 and radii[-1] <= 1.6 and np.all(np.diff(radii) < 0.0)
    assert s["max_step_excess"] <= 0.0 and rec["max_step_excess"] <= 0.0
    assert s["greedy_revolutions"] == s["revolutions"]  # greedy is optimal on its grid (no minimum step)
    # the grid holds the recursion's radii: never worse than the recursion (4.26), the least
    assert rec["reached_target"] and s["revolutions"] == rec["revolutions"]
    assert "holding the recursion's radii" in s["optimal_among"]
    assert got["safety_margin"] == 1e-3 and got["b_inf"] == limiting_radius(1.0, 0.25)
    assert got["b_floor"] == pytest.approx(1.25 + 1e-3, abs=1e-4)
    assert got["table"]["monotone"] and got["table"]["complete"]
    path = got["path"]
    assert len(path["points"]) == s["revolutions"] * path["points_per_revolution"] + 1
    assert path["points"][0] == pytest.approx([0.0, 8.0], abs=1e-12)  # starts at the top (start_angle pi/2)
    assert path["max_chord_deviation"] < 0.05
    tip = got["tip_line"]
    assert tip["revolutions"] == len(tip_line_spiral(1.0, 8.0, 1.6)) and tip["reaches_target"] is False
    fit = got["fit"]
    assert fit is not None and fit["exponent"] > 0.0 and fit["n_points"] >= 3


@pytest.mark.slow
def test_the_schedule_carries_its_table_and_its_certificate(sweep_plan):
    """The (beta, r*) table the schedule rests on and the potentials that prove it optimal:
    they start at 0, end at the bound, rise by at least one revolution's weight per
    revolution, and add up to the schedule's cost."""
    _, got = sweep_plan
    tab, cert = got["table"], got["schedule"]["certificate"]
    assert len(tab["betas"]) == len(tab["radii"]) == len(tab["certified"]) == tab["n_points"]
    assert np.all(np.diff(tab["betas"]) > 0.0) and all(r is None or r > 0.0 for r in tab["radii"])
    pot = np.array(cert["path_potentials"])
    assert len(pot) == got["schedule"]["revolutions"] and pot[0] == 0
    assert pot[-1] == cert["dual_bound"] == cert["primal_cost"]
    assert np.all(np.diff(pot) >= cert["revolution_weight"])


@pytest.mark.slow
def test_simulated_disks_stay_inside_the_planned_spiral(sweep_plan):
    """The issue's check, in the request: dipod supports (the extremes of the sketch) from
    random starts inside b_1 - a are herded in, none pushed out, all within b_N."""
    _, got = sweep_plan
    sim = got["simulation"]
    assert sim["n"] == 3 and sim["escaped"] == 0 and sim["all_inside"]
    assert sim["promised_radius"] == got["schedule"]["radii"][-1]
    assert sim["max_final_extent"] <= sim["promised_radius"] + 1e-6
    assert sim["contacts"] > 0 and sim["solver_failures"] == 0


@pytest.mark.slow
def test_schedule_scales_with_the_disk(client, sweep_plan):
    body, got = sweep_plan
    small = {**{k: v for k, v in body.items() if k != "simulate"}, "disk_radius": 1e-3, "start_radius": 8e-3,
             "target": 1.6e-3, "include_path": False}
    r, tiny = post(client, SCHED, small)
    assert r.status_code == 200, r.text
    assert tiny["table"]["from_cache"] is True and tiny["path"] is None
    # The recursion (4.26) scales exactly. The grid's adaptive radii sit exactly on the safety
    # boundary b + d*(b), so a few arcs flip with the rounding of the scaled numbers (4583 vs
    # 4594 arcs here): the optimum keeps its revolutions, its path may differ slightly.
    assert tiny["recursion"]["radii"] == pytest.approx([1e-3 * x for x in got["recursion"]["radii"]], rel=1e-12)
    s, t = got["schedule"], tiny["schedule"]
    assert t["revolutions"] == s["revolutions"] and t["solver_status"] == "OPTIMAL" and t["certificate"]["certified"]
    assert t["path_length"] == pytest.approx(1e-3 * s["path_length"], rel=1e-2)
    assert t["max_step_excess"] <= 0.0


@pytest.mark.slow
def test_robot_limits_and_objectives(client, sweep_plan):
    body, got = sweep_plan
    base = {k: v for k, v in body.items() if k != "simulate"} | {"include_path": False}
    _, capped = post(client, SCHED, {**base, "max_step": 0.5})
    assert max(capped["schedule"]["steps"]) <= 0.5 and capped["schedule"]["revolutions"] > got["schedule"]["revolutions"]
    _, floor = post(client, SCHED, {**base, "min_step": 0.2})
    steps = floor["schedule"]["steps"]
    assert floor["schedule"]["solver_status"] in ("OPTIMAL", "INFEASIBLE")
    if steps:
        assert min(steps[:-1]) >= 0.2 - 1e-12
    _, timed = post(client, SCHED, {**base, "objective": "time", "speed": 2.0})
    s = timed["schedule"]
    assert s["time_s"] == pytest.approx(s["path_length"] / 2.0) and s["objective_value"] == s["time_s"]
    assert s["path_length"] <= got["schedule"]["path_length"] + 1e-9
    _, cp = post(client, SCHED, {**base, "backend": "cp_sat"})
    assert cp["schedule"]["revolutions"] == got["schedule"]["revolutions"]


@pytest.mark.slow
def test_tip_line_schedule_at_mu_1_has_unsafe_revolutions(client):
    """At mu_c = 1 the tip line understates r* at mid beta (4.5.3): the request counts the
    tip-line revolutions that its own r* table shows unsafe (a witness beta each)."""
    r, got = post(client, SCHED, {"disk_radius": 1.0, "mu_c": 1.0, "start_radius": 6.0, "target": 2.2,
                                  "include_path": False})
    assert r.status_code == 200, r.text
    assert got["tip_line"]["unsafe_revolutions"] > 0 and "unsafe" in got["message"]


@pytest.mark.slow
@pytest.mark.parametrize("url, change, loc", [
    (CRIT, {"betas": [1.5707963267948966]}, ["body", "betas", 0]),
    (CRIT, {"betas": [1e-4]}, ["body", "betas", 0]),
    (CRIT, {"mu_c": 0.0}, ["body", "mu_c"]),
    (CRIT, {"betas": [0.5], "max_radius": 10.0}, ["body", "max_radius"]),
    (CRIT, {"max_radius": 2e4}, ["body", "max_radius"]),
    (SCHED, {"target": 1.2}, ["body", "target"]),
    (SCHED, {"target": 9.0}, ["body", "target"]),
    (SCHED, {"start_radius": 2e4}, ["body", "start_radius"]),
    (SCHED, {"objective": "time"}, ["body", "speed"]),
    (SCHED, {"simulate": {"n_supports": 0}}, ["body", "simulate", "n_supports"]),
    (SCHED, {"min_step": 0.5, "max_step": 0.2}, ["body", "min_step"]),
    (SCHED, {"max_step": 1e-6}, ["body", "max_step"]),
    (SCHED, {"resolution": 256, "target": 2.0000001}, ["body", "resolution"]),
])
def test_bad_inputs_are_422_naming_the_field(client, url, change, loc):
    base = ({"disk_radius": 1.0, "mu_c": 0.25} if url == CRIT else
            {"disk_radius": 1.0, "mu_c": 0.25, "start_radius": 8.0, "target": 1.6, "method": "tip_line"})
    if url == CRIT and "max_radius" in change and "betas" not in change:
        base["method"] = "tip_line"
    r, got = post(client, url, {**base, **change})
    assert r.status_code == 422, r.text
    assert detail(got)[0] == loc


@pytest.mark.slow
def test_pictures_are_svg(client, sweep_plan):
    body, _ = sweep_plan
    r = client.post(CRIT, json={"disk_radius": 1.0, "mu_c": 0.25, "betas": [0.3, 0.8, 1.3]}, params={"format": "svg"})
    assert r.status_code == 200 and r.headers["content-type"].startswith("image/svg+xml")
    assert "a / r*" in r.text
    ET.fromstring(r.text)
    sched = {k: v for k, v in body.items() if k != "simulate"}
    r = client.post(SCHED, json=sched, params={"format": "svg"})
    assert r.status_code == 200 and r.headers["content-type"].startswith("image/svg+xml")
    ET.fromstring(r.text)


@pytest.mark.wall_clock  # about the time limit itself: its real deadline (tests/service/conftest.py)
@pytest.mark.slow
def test_a_table_that_runs_out_of_time_is_504_with_how_far_it_got(client):
    """A first table for a new mu_c cannot be built in a microsecond: the time limit is
    reached before the first collision parameter (504), and the answer says so."""
    r, got = post(client, SCHED, {"disk_radius": 1.0, "mu_c": 0.377, "start_radius": 8.0, "target": 2.0,
                                  "time_limit_s": 1e-6})
    assert r.status_code == 504, r.text
    loc, type_, msg = detail(got)
    assert loc == ["body", "time_limit_s"] and type_ == "time_limit" and "ran out" in msg
    assert "first collision parameter" in got["reached"] and "the rows finished are kept: a retry starts from them" in msg
    table = got["partial"]["table"]
    assert table["n_points"] == 0 and table["time_limited"] is True and table["covers_radius"] is None


def test_the_simulation_summary_counts_only_the_runs_that_ran():
    """A count that summarises work says what was not run (the documented example once said
    "simulation: 4 of 4 kept" when the time limit had left every run out)."""
    assert simulation_summary(4, 0, {"not_run": 4}, False) == "simulation: none of the 4 runs ran (time limit)"
    assert simulation_summary(4, 1, {"completed": 2, "escaped": 1, "not_run": 1}, False) == (
        "simulation: 2 of the 3 runs that ran kept, 1 of 4 not run (time limit)")
    assert simulation_summary(3, 0, {"completed": 3}, True) == (
        "simulation: 3 of the 3 runs that ran kept, all inside the final radius")
