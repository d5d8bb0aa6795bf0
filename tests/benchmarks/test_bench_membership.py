"""Benchmark (not a test): certified membership "can r be a COR?" and certified loci
(solver/locus/membership.py, solver/locus/certified_locus.py; book 3.3, 3.3.13, 7.5).

Writes its section of docs/benchmarks.md: the time of one
membership query near the analytic disk boundary (inside and outside, median and p95),
the certified 64-point disk boundary (time, pairs certified, bracket) and exact polygon
loci traced by certified brackets. Run with `make bench` or `pytest tests/benchmarks --run-benchmarks`."""

from __future__ import annotations

import dataclasses
import math
import platform
import statistics
import time

import numpy as np
import pytest

from models.core.footprint import Footprint
from models.locus import cor_disk as cd
from solver.core.tolerances import SOLVER_DEFAULT
from solver.locus.certified_locus import certified_disk_boundary, certified_polygon_boundary, outward_normals
from solver.locus.membership import membership
from tests.benchmarks._docs import write_section
from tests.scenes import scene_for_mu

pytestmark = pytest.mark.benchmark

MUS = (0.05, 0.3, 0.9, 1.5)
OFFSETS = (1e-3, 5e-7)  # / a, along the analytic boundary's normal (5e-7: the bracket's)
SQUARE = Footprint.create([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]])
L_SHAPE = Footprint.create([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]])


def p95(xs):
    return float(np.percentile(xs, 95))


def query_times(sc, points, verify):
    times, statuses = [], []
    for r in points:
        t0 = time.perf_counter()
        res = membership(sc, r, verify_witness=verify)
        times.append(time.perf_counter() - t0)
        statuses.append(res.status)
    return times, statuses


def test_membership_and_certified_loci():
    # warm-up: compile the restricted masters
    membership(scene_for_mu(0.3), [0.5, 0.5])
    certified_disk_boundary(scene_for_mu(0.3), n_points=8)

    lines = [
        f"`solver/locus/membership.py`, `solver/locus/certified_locus.py`; {platform.machine()}, Python "
        f"{platform.python_version()}, one core. Times in ms unless marked.",
        "",
        "One query at 64 points a distance *offset* inside / outside the analytic disk boundary",
        "(cold: no warm start). *Inside* ends with a polished witness, *outside* with a dual",
        "certified by branch and bound over the circle; *+ forward* re-verifies the witness",
        "with the Newton forward solve (16 of the points).",
        "",
        "| offset / a | mu | inside median | inside p95 | inside + forward median | outside median | outside p95 | decided |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    all_in, all_out = [], []
    for offset in OFFSETS:
        for mu in MUS:
            sc = scene_for_mu(mu)
            ring = cd.disk_cor_locus(sc, n_points=64).boundary
            nu = outward_normals(ring)
            t_in, s_in = query_times(sc, ring - offset * nu, verify=False)
            t_inf, _ = query_times(sc, ring[::4] - offset * nu[::4], verify=True)
            t_out, s_out = query_times(sc, ring + offset * nu, verify=False)
            ok = s_in.count("inside") + s_out.count("outside")
            if offset == OFFSETS[0]:
                all_in += t_in
                all_out += t_out
            lines.append(
                f"| {offset:g} | {mu:g} | {1e3 * statistics.median(t_in):.1f} | {1e3 * p95(t_in):.1f} | "
                f"{1e3 * statistics.median(t_inf):.1f} | {1e3 * statistics.median(t_out):.1f} | "
                f"{1e3 * p95(t_out):.1f} | {ok}/128 |"
            )
    lines += [
        f"| {OFFSETS[0]:g} | all | {1e3 * statistics.median(all_in):.1f} | {1e3 * p95(all_in):.1f} | | "
        f"{1e3 * statistics.median(all_out):.1f} | {1e3 * p95(all_out):.1f} | |",
        "",
        "Certified 64-point disk boundary (`certified_disk_boundary`, warm-started queries): each",
        f"analytic point bracketed by r -+ delta nu, delta = boundary_bracket a / 2 = "
        f"{0.5 * SOLVER_DEFAULT.boundary_bracket:g} a.",
        "",
        "| mu | time (s) | pairs certified | wrong | undecided | error bound / a |",
        "|---:|---:|---:|---:|---:|---:|",
    ]
    disk_times = []
    for mu in (0.05, 0.1, 0.3, 0.5, 0.72, 0.9, 1.0, 1.5, 3.0):
        res = certified_disk_boundary(scene_for_mu(mu), n_points=64)
        disk_times.append(res.solve_time_s)
        bound = "-" if res.max_error_bound is None else f"{res.max_error_bound:.1e}"
        lines.append(
            f"| {mu:g} | {res.solve_time_s:.2f} | {res.n_certified}/{len(res.pairs)} | {len(res.wrong)} | "
            f"{len(res.undecided)} | {bound} |"
        )
    lines += [
        "",
        "Speed against error of the certified disk boundary (mu = 0.3, 64 points): the bracket",
        "width boundary_bracket (the certified error bound is half of it, times a).",
        "",
        "| boundary_bracket | time (s) | pairs certified | error bound / a |",
        "|---:|---:|---:|---:|",
    ]
    for bracket in (1e-3, 1e-4, 1e-6, 1e-8):
        tol = dataclasses.replace(SOLVER_DEFAULT, boundary_bracket=bracket)
        res = certified_disk_boundary(scene_for_mu(0.3), n_points=64, tol=tol)
        bound = "-" if res.max_error_bound is None else f"{res.max_error_bound:.1e}"
        lines.append(f"| {bracket:g} | {res.solve_time_s:.2f} | {res.n_certified}/{len(res.pairs)} | {bound} |")
    lines += [
        "",
        "Exact polygon loci (`certified_polygon_boundary`): rays from the CM, each crossing",
        f"bracketed to boundary_bracket L = {SOLVER_DEFAULT.boundary_bracket:g} L and certified.",
        "",
        "| footprint | mu | rays | time (s) | certified | multi-crossing rays | probes per ray |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    poly_times = []
    for name, fp, mu, rays in (("square", SQUARE, 0.3, 64), ("square", SQUARE, 0.9, 64), ("L shape", L_SHAPE, 0.4, 32)):
        cm = fp.center_of_mass
        sc = scene_for_mu(mu, a=fp.circumradius, cm=cm)
        res = certified_polygon_boundary(sc, fp, n_rays=rays)
        poly_times.append(res.solve_time_s)
        probes = statistics.mean(r.probes for r in res.rays)
        lines.append(
            f"| {name} | {mu:g} | {rays} | {res.solve_time_s:.1f} | {res.n_certified}/{rays} | "
            f"{len(res.multi_crossing_rays)} | {probes:.1f} |"
        )
    write_section("Certified membership and certified COR loci (issue 3, book 3.3, 3.3.13, 7.5)", lines)
    # generous guards: the figures themselves are the point
    assert statistics.median(all_in) < 0.2 and statistics.median(all_out) < 0.2
    assert max(disk_times) < 20.0
    assert all(math.isfinite(t) for t in poly_times)
