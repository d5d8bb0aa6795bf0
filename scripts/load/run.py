"""Load test on loopback (issue 11): the analytic COR locus (cheap, in the web processes)
under wrk at concurrency 1, 8, 32 and 128, then at 32 again with eight expensive
requests (certified loci in the solver workers) running beside it. Starts the server as
``python -m service`` with its defaults (2 web processes) on a free port, and writes the
figures into docs/benchmarks.md (section "Service under load").

    .venv/bin/python scripts/load/run.py [--seconds 10]

Needs ``wrk`` (Debian: apt-get install wrk)."""

from __future__ import annotations

import argparse
import json
import os
import platform
import re
import shutil
import subprocess
import sys
import threading
import time
from pathlib import Path

import httpx

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO))

from tests.benchmarks._docs import write_section
from tests.service.live import live_server

LOCUS = {"disk_radius": 1, "contact_point": [-0.5, -0.3], "edge_angle": 1.5707963267948966}
EXPENSIVE = {
    "footprint": [[0, 0], [3, 0], [3, 1], [1, 1], [1, 3], [0, 3]], "contact_point": [0, 0.5],
    "edge_angle": 1.5707963267948966, "method": "certified", "n_certified": 64, "time_limit_s": 5, "outputs": [],
}
CONCURRENCY = (1, 8, 32, 128)
UNITS = {"us": 1e-3, "ms": 1.0, "s": 1e3}


def wrk(url: str, connections: int, seconds: float, body: dict) -> dict:
    out = subprocess.run(
        ["wrk", "-t", str(min(connections, 2)), "-c", str(connections), "-d", f"{seconds:g}s", "--latency",
         "-s", str(REPO / "scripts" / "load" / "post.lua"), url],
        env={**os.environ, "BODY": json.dumps(body)}, capture_output=True, text=True, check=True,
    ).stdout
    lat = {p: float(v) * UNITS[u] for p, v, u in re.findall(r"^\s+(50|99)%\s+([\d.]+)(us|ms|s)\s*$", out, re.M)}
    rps = float(re.search(r"Requests/sec:\s+([\d.]+)", out).group(1))
    total = int(re.search(r"(\d+) requests in", out).group(1))
    non2xx = re.search(r"Non-2xx or 3xx responses: (\d+)", out)
    sock = re.search(r"Socket errors: connect (\d+), read (\d+), write (\d+), timeout (\d+)", out)
    errors = (int(non2xx.group(1)) if non2xx else 0) + (sum(map(int, sock.groups())) if sock else 0)
    return {"c": connections, "rps": rps, "p50": lat["50"], "p99": lat["99"], "requests": total, "errors": errors}


def expensive_load(base: str, stop: threading.Event, n: int, counts: dict) -> list[threading.Thread]:
    def loop() -> None:
        with httpx.Client(timeout=60.0) as client:
            while not stop.is_set():
                r = client.post(f"{base}/v1/cor/locus", json=EXPENSIVE)
                key = str(r.status_code)
                counts[key] = counts.get(key, 0) + 1

    threads = [threading.Thread(target=loop, daemon=True) for _ in range(n)]
    for t in threads:
        t.start()
    return threads


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=10.0)
    args = ap.parse_args()
    if shutil.which("wrk") is None:
        sys.exit("wrk is missing (Debian: apt-get install wrk)")
    rows, beside = [], None
    with live_server() as base:
        url = f"{base}/v1/cor/locus"
        wrk(url, 8, 2.0, LOCUS)  # warm up
        for c in CONCURRENCY:
            rows.append(wrk(url, c, args.seconds, LOCUS))
            print(rows[-1], flush=True)
        stop, counts = threading.Event(), {}
        threads = expensive_load(base, stop, 8, counts)
        time.sleep(1.0)
        beside = wrk(url, 32, args.seconds, LOCUS)
        stop.set()
        for t in threads:
            t.join()
        beside["expensive"] = counts
        print(beside, flush=True)
    lines = [
        f"`scripts/load/run.py` ({platform.machine()}, {os.cpu_count()} CPUs, Python {platform.python_version()}): "
        f"`python -m service` with its defaults (2 web processes, solver workers = CPUs / 2), wrk on the same "
        f"machine (it takes CPU too), {args.seconds:g} s per row. Cheap request: the analytic locus of the API "
        "guide's first example (JSON, 256 boundary points), computed in the web processes.",
        "",
        "| concurrency | requests/s | p50 (ms) | p99 (ms) | requests | errors |",
        "|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        lines.append(f"| {r['c']} | {r['rps']:.0f} | {r['p50']:.2f} | {r['p99']:.2f} | {r['requests']} | {r['errors']} |")
    lines += [
        "",
        "The same at concurrency 32 with eight clients sending certified loci of an L-shaped footprint "
        "(64 brackets, 5 s limit) without pause beside it (answers of those: "
        + ", ".join(f"{k}: {v}" for k, v in sorted(beside["expensive"].items())) + "):",
        "",
        "| concurrency | requests/s | p50 (ms) | p99 (ms) | requests | errors |",
        "|---:|---:|---:|---:|---:|---:|",
        f"| 32 + 8 expensive | {beside['rps']:.0f} | {beside['p50']:.2f} | {beside['p99']:.2f} | "
        f"{beside['requests']} | {beside['errors']} |",
    ]
    write_section("Service under load (issue 11)", lines)


if __name__ == "__main__":
    main()
