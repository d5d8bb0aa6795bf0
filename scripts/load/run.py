"""Load test on loopback (issues 11, 25): the analytic COR locus (cheap, in the web
processes) under wrk at concurrency 1, 8, 32 and 128, then at 32 and 128 again with eight
expensive clients (certified loci in the solver workers, each honouring ``Retry-After``)
beside it, and a flood of 20 feeder designs at once (each must be served with what it
computed, or refused at once). Starts the server as ``python -m service`` with its
defaults on a free port, and writes the figures into docs/benchmarks.md (section "Service
under load").

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
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import httpx
import loky

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO))

from tests.benchmarks._docs import write_section
from tests.service.live import DESIGN, live_server

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
    """``n`` clients sending certified loci one after another; a 503 waits its Retry-After."""
    def loop() -> None:
        with httpx.Client(timeout=60.0) as client:
            while not stop.is_set():
                r = client.post(f"{base}/v1/cor/locus", json=EXPENSIVE)
                key = str(r.status_code)
                counts[key] = counts.get(key, 0) + 1
                if r.status_code == 503:
                    stop.wait(float(r.headers.get("retry-after", "1")))

    threads = [threading.Thread(target=loop, daemon=True) for _ in range(n)]
    for t in threads:
        t.start()
    return threads


def beside_expensive(base: str, url: str, connections: int, seconds: float) -> dict:
    stop, counts = threading.Event(), {}
    threads = expensive_load(base, stop, 8, counts)
    time.sleep(1.0)
    row = wrk(url, connections, seconds, LOCUS)
    stop.set()
    for t in threads:
        t.join()
    row["expensive"] = counts
    return row


def flood(base: str, n: int = 20) -> dict:
    """``n`` designs at once, after one that lets the service measure their cost."""
    def one(_: int) -> tuple[int, float, dict]:
        t0 = time.monotonic()
        r = httpx.post(f"{base}/v1/feeder/design", json=DESIGN, timeout=120.0)
        return r.status_code, time.monotonic() - t0, r.json()

    first = one(0)
    with ThreadPoolExecutor(n) as ex:
        answers = list(ex.map(one, range(n)))
    served = [(t, b) for code, t, b in answers if code == 200]
    refused = [t for code, t, _ in answers if code == 503]
    return {
        "single_s": first[1], "served": len(served), "refused": len(refused),
        "other": len(answers) - len(served) - len(refused),
        "hollow": sum(1 for _, b in served if not (b["complete"] and b["design"] is not None)),
        "served_max_s": max((t for t, _ in served), default=0.0), "refused_max_s": max(refused, default=0.0),
    }


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=10.0)
    args = ap.parse_args()
    if shutil.which("wrk") is None:
        sys.exit("wrk is missing (Debian: apt-get install wrk)")
    rows, beside = [], []
    with live_server() as base:
        url = f"{base}/v1/cor/locus"
        wrk(url, 8, 2.0, LOCUS)  # warm up
        for c in CONCURRENCY:
            rows.append(wrk(url, c, args.seconds, LOCUS))
            print(rows[-1], flush=True)
        for c in (32, 128):
            beside.append(beside_expensive(base, url, c, args.seconds))
            print(beside[-1], flush=True)
        flooded = flood(base)
        print(flooded, flush=True)
    table = ["| concurrency | requests/s | p50 (ms) | p99 (ms) | requests | errors |", "|---:|---:|---:|---:|---:|---:|"]
    lines = [
        f"`scripts/load/run.py` ({platform.machine()}, {loky.cpu_count()} usable CPUs, Python "
        f"{platform.python_version()}, {time.strftime('%Y-%m-%d')}): `python -m service` with its defaults (2 web "
        "processes on SO_REUSEPORT sockets, one slot of expensive work per usable CPU shared by both), wrk on the "
        f"same machine (it takes CPU too), {args.seconds:g} s per row. Cheap request: the analytic locus of the API "
        "guide's first example (JSON, 256 boundary points), computed in the web processes.",
        "",
        *table,
    ]
    for r in rows:
        lines.append(f"| {r['c']} | {r['rps']:.0f} | {r['p50']:.2f} | {r['p99']:.2f} | {r['requests']} | {r['errors']} |")
    lines += [
        "",
        "The same with eight clients sending certified loci of an L-shaped footprint (64 brackets, 5 s limit) one "
        "after another beside it, each waiting out the `Retry-After` of a 503 (their answers in the last column):",
        "",
        "| concurrency | requests/s | p50 (ms) | p99 (ms) | requests | errors | expensive answers |",
        "|---:|---:|---:|---:|---:|---:|---|",
    ]
    for r in beside:
        answers = ", ".join(f"{k}: {v}" for k, v in sorted(r["expensive"].items()))
        lines.append(f"| {r['c']} + 8 expensive | {r['rps']:.0f} | {r['p50']:.2f} | {r['p99']:.2f} | "
                     f"{r['requests']} | {r['errors']} | {answers} |")
    f = flooded
    lines += [
        "",
        f"A flood of 20 feeder designs at once (the pentagon, 12 candidate fences, validated by 4 parts; one design "
        f"alone took {f['single_s']:.2f} s just before): {f['served']} served, each with its design computed "
        f"({f['hollow']} without), the last after {f['served_max_s']:.2f} s; {f['refused']} refused 503 with "
        f"`Retry-After`, each within {f['refused_max_s']:.2f} s of sending; {f['other']} other answers.",
    ]
    write_section("Service under load (issues 11, 25)", lines)


if __name__ == "__main__":
    main()
