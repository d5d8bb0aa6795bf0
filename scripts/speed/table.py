"""The speed table of issues 26 and 36, measured the same way before and after a change.

Each row is one documented example, run in a fresh Python process (so caches and the
store start cold, as a new worker's would) through the service's own routes over an
in-process HTTP client (``TestClient``, solver work in the web process: no pool, no
store), or through the solver entry point where the row is an in-process figure. A row
reports its time and a quality figure (completeness, certified bracket widths, KKT
residuals, the answer itself) so that a faster answer can be checked to be the same one.

    # one row, this tree
    python scripts/speed/table.py --row align
    # every row, two trees interleaved (best of 3 each), markdown on stdout
    python scripts/speed/table.py --compare /tmp/before . --repeat 3 --out /tmp/speed.json

``--compare`` runs each row in each tree in turn, alternating which tree goes first, so
both see the same machine load; the best time of the repeats is reported. The trees must
share this script's interface only: the script imports ``service``, ``solver``, ``models``
and ``tests`` from the tree it is pointed at.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve()

PENTAGON = {"vertices": [[0, 0], [3, 0], [3.5, 1.5], [1.5, 2.5], [-0.5, 1.2]], "center_of_mass": [1.4, 1.0]}
TRIANGLE = {"vertices": [[0, 0], [2, 0], [0, 3]], "center_of_mass": [2 / 3, 1]}
TRIANGLE_A = math.hypot(2 / 3, 2)  # its circumradius about the CM
SQUARE = {"vertices": [[0, 0], [1, 0], [1, 1], [0, 1]], "center_of_mass": [0.5, 0.5]}
RECTANGLE = [[-1, -0.5], [1, -0.5], [1, 0.5], [-1, 0.5]]
A63, AL63 = 1.25, math.radians(70.0)  # the book's 6.3 experiment: disk a = 1.25, fence at 70 degrees

# name: (route, body, goal in the words); in-process rows have route None.
HTTP_ROWS = {
    "map_part_bound": ("/v1/feeder/map", {"part": PENTAGON, "fences": [{"angle": 0.7, "mu_c": 0.25}],
                                           "bound": "part"}, "< 1 s"),
    "design_1deg": ("/v1/feeder/design", {"part": PENTAGON, "angles": {"min": 0.349, "max": 1.222,
                                                                        "step": math.radians(1.0)},
                                           "mu_c": 0.25, "alternate": False}, "< 0.5 s"),
    "locus_certified_16": ("/v1/cor/locus", {"footprint": RECTANGLE, "contact_point": [-1, -0.3],
                                              "edge_angle": math.pi / 2, "method": "certified",
                                              "n_certified": 16, "outputs": [], "time_limit_s": 30}, "< 0.2 s"),
    "locus_certified_64": ("/v1/cor/locus", {"footprint": RECTANGLE, "contact_point": [-1, -0.3],
                                              "edge_angle": math.pi / 2, "method": "certified",
                                              "n_certified": 64, "outputs": [], "time_limit_s": 30}, "< 0.5 s"),
    "sketch_certified": ("/v1/cor/sketch", {"footprint": [[-1.5, -0.4], [1.5, -0.4], [1.5, 0.4], [-1.5, 0.4]],
                                            "contact_point": [-1.5, 0.18766172], "edge_angle": math.pi / 2,
                                            "push_direction": -0.4635935760943159, "mu_c": 0.3,
                                            "method": "certified", "n_rays": 16}, "< 0.3 s"),
    "sticking_6_3": ("/v1/cor/sketch", {"disk_radius": A63, "contact_point": [-A63 * math.sin(AL63),
                                                                              A63 * math.cos(AL63)],
                                        "edge_angle": AL63, "mu_c": 0.5, "method": "certified"}, "< 0.2 s"),
    "align": ("/v1/push/align", {"footprint": [[-1, -1], [1, -1], [1, 1], [-1, 1]],
                                 "orientation": math.pi / 6, "fence_angle": math.pi / 2, "mu_c": 0.25}, "< 40 ms"),
    "encounter": ("/v1/push/disk-encounter", {"disk_radius": 1.0, "beta_initial": math.pi / 4, "mu_c": 0.5},
                  "< 100 ms"),
    "rstar_exact_100a": ("/v1/spiral/critical-radius", {"disk_radius": 1.0, "mu_c": 0.25, "method": "exact",
                                                        "time_limit_s": 300}, "< 5 s"),
    "schedule_cold": ("/v1/spiral/schedule", {"disk_radius": 1.0, "mu_c": 0.25, "start_radius": 20.0,
                                              "target": 3.0}, "< 0.4 s"),
    "simulate_example": ("/v1/feeder/simulate", {"part": SQUARE, "support": {"points": [[0.7, 0.6], [0.4, 0.65],
                                                                                       [0.4, 0.25]], "weights": [1, 1, 1]},
                                                  "fences": [{"angle": 0.7, "mu_c": 0.25}, {"angle": -0.8, "mu_c": 0.25}],
                                                  "theta_initial": 0.3}, "< 5 ms"),
    "simulate_placed": ("/v1/feeder/simulate", {"part": SQUARE, "support": {"points": [[0.7, 0.6], [0.4, 0.65],
                                                                                      [0.4, 0.25]], "weights": [1, 1, 1]},
                                                "fences": [{"angle": 0.7, "mu_c": 0.25, "end": [-2.0, 0.0], "length": 6.0}],
                                                "theta_initial": 0.3}, "< 5 ms"),
    "tripod_stats_100k": ("/v1/cor/tripod-statistics", {"disk_radius": 1.0, "contact_point": [-0.5, -0.3],
                                                        "edge_angle": math.pi / 2, "n_tripods": 100_000,
                                                        "seed": 7, "include_cors": False}, "< 1 µs per tripod"),
}
BELT_DESIGN = {"part": TRIANGLE, "angles": {"min": math.radians(20), "max": math.radians(70),
                                             "step": math.radians(10)},
               "mu_c": 0.25, "belt": {"width": 20 * TRIANGLE_A}, "alternate": False}
"""The right triangle's placed design (tests/service/api/feeder/test_feeder_api.py)."""
LOCAL_ROWS = {
    "belt_validation_1000": "< 1 s",
    "simulator_batch200": "≥ 5,000 runs/s",
    "tripods_590k_mu0": "< 0.2 s",
    "tripods_590k_mu05": "< 0.5 s",
}
ROWS = list(HTTP_ROWS) + list(LOCAL_ROWS)


def _walk(js, key):
    """Every value stored under ``key`` anywhere in a JSON document."""
    if isinstance(js, dict):
        for k, v in js.items():
            if k == key:
                yield v
            yield from _walk(v, key)
    elif isinstance(js, list):
        for v in js:
            yield from _walk(v, key)


def quality(name: str, js: dict) -> dict:
    """The figures that say whether the answer is the same and as good."""
    flags = [v for v in _walk(js, "complete") if isinstance(v, bool)]
    q: dict = {"complete": all(flags) if flags else None}
    widths = [w for w in _walk(js, "bracket_width") if isinstance(w, (int, float))]
    widths += [w for w in _walk(js, "width") if isinstance(w, (int, float))]
    if widths:
        q["max_bracket"] = max(widths)
    if name == "map_part_bound":
        q["turn_least"] = [round(b["turn_least"], 9) for b in js["fences"][0]["bands"]]
    elif name == "design_1deg":
        d = js.get("design") or {}
        q["fences"] = len(d.get("fences", []))
        q["margin"] = d.get("margin")
    elif name == "sticking_6_3":
        c = js["certification"]
        q["lower"] = c["sticking_lower"]["position"]
        q["certified"] = bool(c["sticking_lower"]["certified"] and c["sticking_upper"]["certified"])
    elif name == "align":
        q["longest"] = js["longest_push"]["exact"]
        q["quadrature_error"] = js["longest_push"]["quadrature_error"]
    elif name == "encounter":
        q["values"] = sorted(float(v) for v in _walk(js, "exact") if isinstance(v, (int, float)))[:6]
        q["quadrature_error"] = max([float(v) for v in _walk(js, "quadrature_error")
                                     if isinstance(v, (int, float))] or [float("nan")])
    elif name == "rstar_exact_100a":
        q["points"] = js["table"]["n_points"] if "table" in js else len(js.get("points", []))
    elif name == "schedule_cold":
        q["revolutions"] = js["schedule"]["revolutions"]
    elif name == "tripod_stats_100k":
        q["max_kkt"] = js["max_kkt_residual"]
        q["converged"] = js["converged"]
    elif name in ("simulate_example", "simulate_placed"):
        q["final"] = [round(r["theta_final"], 6) if r.get("theta_final") is not None else r["status"]
                      for r in js["runs"]]
    return q


def preload_kernels() -> None:
    """Load the compiled kernels before the clock starts, as the service's solver workers
    do before their first request (their forkserver preloads ``solver.KERNEL_MODULES``):
    a row then times the request, not numba's import (about 0.4 s once per process)."""
    import importlib

    import solver

    for name in getattr(solver, "KERNEL_MODULES", ()):
        importlib.import_module(name)


def run_http(name: str) -> dict:
    import warnings

    warnings.filterwarnings("ignore")
    from fastapi.testclient import TestClient

    from service.app import create_app
    from service.settings import Settings

    route, body, _ = HTTP_ROWS[name]
    # the r* table's row runs past the default cap of a request's time limit
    app = create_app(Settings(solver_workers=0, store_path="", max_time_limit_s=600.0))
    preload_kernels()
    with TestClient(app) as c:
        c.get("/healthz")
        t0 = time.perf_counter()
        r = c.post(route, json=body)
        seconds = time.perf_counter() - t0
    js = r.json()
    if r.status_code != 200:
        return {"error": [f"HTTP {r.status_code}: {json.dumps(js)[:300]}"]}
    out = {"seconds": seconds, "quality": quality(name, js)}
    if name == "tripod_stats_100k":
        out["per_item_us"] = 1e6 * seconds / body["n_tripods"]
    return out


def run_local(name: str) -> dict:
    import numpy as np

    if name == "belt_validation_1000":  # 1,000 parts through the placed design (the route caps them at 500 before)
        import dataclasses

        from service.api.feeder.convert import design_problem
        from service.api.feeder.schemas import FeederDesignRequest
        from solver import Budget, feeder_design

        problem = dataclasses.replace(design_problem(FeederDesignRequest.model_validate(BELT_DESIGN)),
                                      validation_parts=1000, seed=7)
        res = feeder_design(problem, Budget.unlimited())
        v = res.validation
        return {"seconds": res.timings["validation"],
                "quality": {"fences": len(res.design.fences) if res.design else 0, "in_band": v.in_band,
                            "outside": v.outside, "rejected": v.rejected, "failed": v.failed, "cut": v.cut}}
    if name == "simulator_batch200":
        from models.feeder.fence import Fence
        from solver.feeder.simulate import simulate_fence_batch
        from tests.feeder_cases import part, random_encounter

        rng = np.random.default_rng(20261124)
        the_part, fence = part("pentagon"), Fence.create(0.7, 0.25)
        encs = [random_encounter(rng, "pentagon") for _ in range(200)]
        t0 = time.perf_counter()
        runs = simulate_fence_batch(the_part, fence, 0.25, [(e.body, e.weights) for e in encs],
                                    [e.theta for e in encs])
        seconds = time.perf_counter() - t0
        finals = [r.theta_final for r in runs.runs] if hasattr(runs, "runs") else [r.theta_final for r in runs]
        done = [f for f in finals if f is not None]
        return {"seconds": seconds, "per_second": 200 / seconds,
                "quality": {"left": len(done), "mean_final": float(np.mean(done)) if done else None}}
    from models.core.support import random_balanced_tripods
    from solver.motion.forward import solve_forward_batch
    from tests.scenes import scene_for_mu

    rng = np.random.default_rng(20261121)
    pts, wts = random_balanced_tripods(rng, 590_000, 1.0)
    sc = scene_for_mu(0.3)
    mu_c = 0.0 if name == "tripods_590k_mu0" else 0.5
    solve_forward_batch(sc, pts[:2000], wts[:2000], mu_c=mu_c)  # imports, first calls
    t0 = time.perf_counter()
    b = solve_forward_batch(sc, pts, wts, mu_c=mu_c)
    seconds = time.perf_counter() - t0
    return {"seconds": seconds, "quality": {"converged": int(b.converged.sum()),
                                            "max_kkt": float(b.kkt_residual.max()), "fallbacks": b.fallbacks}}


def one(tree: Path, name: str) -> dict:
    """Run one row in a fresh process rooted at ``tree``."""
    env = dict(os.environ, PESHKIN_STORE_PATH="", PYTHONPATH=str(tree))
    proc = subprocess.run([sys.executable, str(HERE), "--row", name, "--tree", str(tree)], cwd=tree, env=env,
                          capture_output=True, text=True, check=False)
    if proc.returncode != 0:
        return {"error": proc.stderr.strip().splitlines()[-1:] or ["failed"]}
    return json.loads(proc.stdout.strip().splitlines()[-1])


def compare(trees: list[Path], rows: list[str], repeat: int) -> dict:
    results: dict = {name: {str(t): [] for t in trees} for name in rows}
    for r in range(repeat):
        for name in rows:
            order = trees if r % 2 == 0 else trees[::-1]
            for t in order:
                res = one(t, name)
                results[name][str(t)].append(res)
                print(f"# {name} {t} {res.get('seconds', res.get('error'))}", file=sys.stderr, flush=True)
    return results


def best(runs: list[dict]) -> dict | None:
    ok = [r for r in runs if "seconds" in r]
    return min(ok, key=lambda r: r["seconds"]) if ok else None


def markdown(results: dict, trees: list[Path]) -> str:
    goal = {**{k: v[2] for k, v in HTTP_ROWS.items()}, **LOCAL_ROWS}
    head = "| row | " + " | ".join(f"{t.name or t} (s)" for t in trees) + " | ratio | goal | quality |"
    lines = [head, "|" + "---|" * (len(trees) + 4)]
    for name, per in results.items():
        bs = [best(per[str(t)]) for t in trees]
        cells = []
        for b in bs:
            if b is None:
                cells.append("failed")
            elif "per_second" in b:
                cells.append(f"{b['seconds']:.2f} ({b['per_second']:.0f}/s)")
            elif "per_item_us" in b:
                cells.append(f"{b['seconds']:.2f} ({b['per_item_us']:.1f} µs each)")
            else:
                cells.append(f"{b['seconds']:.3g}")
        ratio = (f"{bs[0]['seconds'] / bs[-1]['seconds']:.2f}×" if bs[0] and bs[-1] else "–")
        q = "; ".join(json.dumps(b["quality"], separators=(",", ":")) if b else "–" for b in bs)
        lines.append(f"| {name} | " + " | ".join(cells) + f" | {ratio} | {goal[name]} | {q} |")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--row", choices=ROWS)
    ap.add_argument("--tree", type=Path, default=HERE.parents[2])
    ap.add_argument("--compare", type=Path, nargs="+", help="trees to measure side by side, the first as before")
    ap.add_argument("--rows", nargs="+", choices=ROWS, default=ROWS)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--out", type=Path, help="also write the raw results here (JSON)")
    args = ap.parse_args()
    if args.row:
        os.environ["PESHKIN_STORE_PATH"] = ""  # no store: every row computes its answer
        sys.path.insert(0, str(args.tree.resolve()))
        res = run_http(args.row) if args.row in HTTP_ROWS else run_local(args.row)
        print(json.dumps(res))
        return
    trees = [t.resolve() for t in (args.compare or [args.tree])]
    results = compare(trees, args.rows, args.repeat)
    if args.out:
        args.out.write_text(json.dumps(results, indent=1))
    print(markdown(results, trees))


if __name__ == "__main__":
    main()
