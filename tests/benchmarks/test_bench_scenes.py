"""Benchmark (not a test): scenes answered with the cheapest model that reaches the accuracy
asked for (solver.scenes, issue 27) against always using the certified model.

A set of scenes (disks and polygons, pushes at several edge angles, mu_c 0.3) is asked
"where can the COR be" and "will it stick or slip", three ways: automatic at accuracy
"bound", automatic at "exact", and always certified (the certified locus and sketch, of the
polygon or of the disk). Time is the analysis's; the locus's error is how far the answer's
boundary lies outside the certified locus (the largest distance from a certified boundary
point to the answered boundary, / a: 0 when the answer is the certified one), and the
verdict is compared with the certified one: the same, coarser (conservative) or wrong. Writes its section of
docs/benchmarks.md."""

from __future__ import annotations

import math
import os
import time

import numpy as np
import pytest

from models.core.footprint import Footprint
from models.core.scene import PushScene
from solver import LocusProblem, Question, SceneProblem, SketchProblem, analyze_scene, cor_locus, cor_sketch
from tests.benchmarks._docs import write_section
from tests.scenes import distance_to_polyline

pytestmark = pytest.mark.benchmark

MU = 0.3
N_RAYS = 16
PARTS = {
    "pentagon": [[0, 0], [3, 0], [3.5, 1.5], [1.5, 2.5], [-0.5, 1.2]],
    "rectangle 2:1": [[-1, -0.5], [1, -0.5], [1, 0.5], [-1, 0.5]],
    "triangle": [[0, 0], [2, 0], [0.4, 1.5]],
    "L": [[0, 0], [2, 0], [2, 0.6], [0.6, 0.6], [0.6, 2], [0, 2]],
    "disk": None,
}
EDGE_ANGLES = (0.0, 0.3, -0.4)


def scenes():
    """Each part pushed up (+y) by a fence tilted by each edge angle, touching its lowest vertex."""
    for name, outline in PARTS.items():
        for edge in EDGE_ANGLES:
            if outline is None:
                yield name, edge, None, PushScene.create(1.0, [0.3 * math.cos(edge), -1.0], edge, math.pi / 2)
                continue
            fp = Footprint.create(outline, None)
            low = fp.vertices[int(np.argmin(fp.vertices[:, 1] - math.tan(edge) * fp.vertices[:, 0]))]
            yield name, edge, fp, PushScene.create(fp.circumradius, low, edge, math.pi / 2, fp.center_of_mass)


def certified(scene: PushScene, fp: Footprint | None):
    t0 = time.perf_counter()
    locus = cor_locus(LocusProblem(scene, fp, method="certified", n_certified=N_RAYS))
    sketch = cor_sketch(SketchProblem(scene, MU, footprint=fp, method="certified", n_rays=N_RAYS))
    return locus, sketch, time.perf_counter() - t0


def certified_points(locus) -> np.ndarray:
    pts = locus.certified.boundary
    return pts[np.all(np.isfinite(pts), axis=1)]


def test_scenes_cheapest_model_against_always_certified():
    rows = []
    for name, edge, fp, scene in scenes():
        ref_locus, ref_sketch, ref_s = certified(scene, fp)
        ref_points = certified_points(ref_locus)
        ref_modes = set(ref_sketch.sketch.allowed_modes)
        row = {"part": name, "edge": edge, "certified_s": ref_s}
        for accuracy in ("bound", "exact"):
            problem = SceneProblem(scene, fp, (MU, MU), None, (Question("cor_locus", accuracy, n_rays=N_RAYS),
                                                               Question("stick_or_slip", accuracy, n_rays=N_RAYS)))
            t0 = time.perf_counter()
            locus, modes = analyze_scene(problem).answers
            elapsed = time.perf_counter() - t0
            answered = (certified_points(locus.result) if locus.model == "certified"
                        else locus.result.analytic.boundary)
            outside = float(np.max(distance_to_polyline(ref_points, answered))) / scene.disk_radius
            if locus.model == "certified":
                outside = 0.0  # the same certified points
            got = set(modes.result.modes)
            verdict = "same" if got == ref_modes else ("coarser" if ref_modes <= got else "WRONG")
            row[accuracy] = (elapsed, locus.model, outside, modes.model, verdict)
        rows.append(row)
        print(row)
    lines = [
        f"Measured {time.strftime('%Y-%m-%d')} on this machine ({os.cpu_count()} cores; one process) by "
        "`tests/benchmarks/test_bench_scenes.py`: each scene asked \"where can the COR be\" and \"will it stick or "
        f"slip\" (mu_c = {MU}), answered automatically at accuracy `bound` and `exact`, against always certified "
        f"(the certified locus and sketch, {N_RAYS} rays). Locus error: the largest distance of a certified boundary "
        "point from the answered boundary, / a (0: the certified answer itself; a disk's closed form is within its "
        "sampling of the certified points). Modes: against the certified sketch's, 'same', 'coarser' (more modes: "
        "a conservative answer, which the polygon's modes are among) or 'WRONG' (a mode of the polygon missing).",
        "",
        "| part | edge angle | always certified (s) | auto `bound` (s) | models | locus error / a | modes "
        "| auto `exact` (s) | models | locus error / a | modes |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        cells = [r["part"], f"{r['edge']:+.1f}", f"{r['certified_s']:.2f}"]
        for accuracy in ("bound", "exact"):
            s, lm, err, mm, verdict = r[accuracy]
            cells += [f"{s:.3f}", f"{lm}, {mm}", f"{err:.2g}", verdict]
        lines.append("| " + " | ".join(cells) + " |")
    total = sum(r["certified_s"] for r in rows)
    auto = {acc: sum(r[acc][0] for r in rows) for acc in ("bound", "exact")}
    lines += ["", f"In all: always certified {total:.1f} s; automatic `bound` {auto['bound']:.2f} s "
              f"({total / auto['bound']:.0f}x faster), automatic `exact` {auto['exact']:.1f} s "
              f"({total / auto['exact']:.1f}x faster)."]
    write_section("Scenes: the cheapest model against always certified (issue 27)", lines)
