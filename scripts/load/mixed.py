"""The mixed load of issue 35 on loopback: for ``--seconds`` (45) at once, 2 clients sending
feeder catalogues, 4 sending certified loci (the L-shape, 64 rays, 3 s limit), 4 sending the
cheap analytic locus, and a probe of ``/healthz`` every 50 ms; each expensive client waits
out a 503's ``Retry-After`` (not counted as its latency). Starts ``python -m service`` with
its defaults (2 web processes, a slot per CPU, the server's one Ray for catalogues) and a
jobs file of its own, samples the memory (PSS) of the server's processes and its Ray's every
second, and after it stops reads its log for tracebacks and lines that are not JSON.

What it checks: every expensive request served (200, or 504 with what it finished) or
refused (503) within a second of sending; the cheap p99 under 100 ms; memory that stops
growing; a log free of tracebacks. It prints the figures and, with ``--write``, puts them
in docs/benchmarks.md (section "Mixed load (issue 35)").

    .venv/bin/python scripts/load/mixed.py [--seconds 45] [--write]
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import os
import platform
import subprocess
import sys
import tempfile
import threading
import time
from collections import defaultdict
from pathlib import Path

import httpx
import loky

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO))

from tests.benchmarks._docs import write_section
from tests.service.live import REPO as LIVE_REPO
from tests.service.live import STARTUP_TIMEOUT_S, free_port, server_command

CHEAP = {"disk_radius": 1, "contact_point": [-0.5, -0.3], "edge_angle": 1.5707963267948966}
CERTIFIED = {"footprint": [[0, 0], [3, 0], [3, 1], [1, 1], [1, 3], [0, 3]], "contact_point": [0, 0.5],
             "edge_angle": 1.5707963267948966, "method": "certified", "n_certified": 64, "time_limit_s": 3,
             "outputs": []}
CATALOGUE = {"parts": [
    {"name": "pentagon", "vertices": [[0, 0], [3, 0], [3.5, 1.5], [1.5, 2.5], [-0.5, 1.2]], "center_of_mass": [1.4, 1.0]},
    {"name": "plate", "vertices": [[0, 0], [2.5, 0], [2.5, 1], [0, 1]], "center_of_mass": [1.25, 0.5]}],
    "design": {"angles": {"min": 0.1745, "max": 1.3963, "step": 0.0873}, "mu_c": 0.25, "alternate": False,
               "validation_parts": 10}, "time_limit_s": 20}
"""The API guide's catalogue example, with a 20 s limit."""
HOSTILE_PAUSE_S = 1.0
"""A hostile client's pause between two bodies (without it, two clients push ~480 MB/s of
padding through loopback and the two cores go to copying it)."""
PROMPT_S = 1.0
"""An expensive request is answered or refused within this of sending, or its limit plus this."""


def percentile(values: list[float], q: float) -> float:
    if not values:
        return float("nan")
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))]


def tree(pid: int) -> list[int]:
    """``pid`` and every process below it (from /proc)."""
    children: dict[int, list[int]] = defaultdict(list)
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        children[int(fields[1])].append(int(stat.parent.name))
    out, todo = [], [pid]
    while todo:
        p = todo.pop()
        out.append(p)
        todo += children.get(p, [])
    return out


def ray_heads(server_pid: int) -> list[int]:
    heads = []
    for cmd in Path("/proc").glob("[0-9]*/cmdline"):
        try:
            args = cmd.read_bytes().decode(errors="replace").split("\0")
        except OSError:
            continue
        if "solver.core.ray_head" in args and "--watch" in args and args[args.index("--watch") + 1] == str(server_pid):
            heads.append(int(cmd.parent.name))
    return heads


def pss_mb(pids: list[int]) -> float:
    """The processes' proportional set size, summed (shared pages counted once in all)."""
    total = 0
    for pid in pids:
        try:
            for line in Path(f"/proc/{pid}/smaps_rollup").read_text().splitlines():
                if line.startswith("Pss:"):
                    total += int(line.split()[1])
        except OSError:
            pass
    return total / 1024.0


class Tally:
    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.rows: dict[str, list[tuple[int, float, float]]] = defaultdict(list)  # kind -> (status, took, limit)

    def add(self, kind: str, status: int, took: float, limit: float) -> None:
        with self.lock:
            self.rows[kind].append((status, took, limit))


def client_loop(base: str, kind: str, path: str, body: dict, stop: threading.Event, tally: Tally) -> None:
    limit = float(body.get("time_limit_s", 30.0))
    with httpx.Client(timeout=120.0) as c:
        while not stop.is_set():
            t0 = time.monotonic()
            try:
                r = c.post(f"{base}{path}", json=body)
                status = r.status_code
            except httpx.HTTPError:
                status = -1
            tally.add(kind, status, time.monotonic() - t0, limit)
            if status == 503:
                stop.wait(min(float(r.headers.get("retry-after", "1")), 10.0))


def padded_client(base: str, seconds: float) -> list[tuple[int, float, float]]:
    """A hostile client, in a process of its own (so that its sending does not slow the
    measuring clients' own interpreter): ~29 MiB msgpack bodies, a valid push padded with an
    unknown field of 1.9 million small lists, to /v1/cor/solve, one a second."""
    import msgpack

    body = msgpack.packb({**CHEAP, "padding": [[i, i + 1, i + 2] for i in range(1_900_000)]})
    rows = []
    ends = time.monotonic() + seconds
    with httpx.Client(timeout=120.0) as c:
        while time.monotonic() < ends:
            t0 = time.monotonic()
            r = c.post(f"{base}/v1/cor/solve", content=body, headers={"content-type": "application/msgpack"})
            rows.append((r.status_code, time.monotonic() - t0, 30.0))
            time.sleep(HOSTILE_PAUSE_S)
    return rows


def probe_loop(base: str, stop: threading.Event, tally: Tally) -> None:
    with httpx.Client(timeout=30.0) as c:
        while not stop.is_set():
            t0 = time.monotonic()
            status = c.get(f"{base}/healthz").status_code
            tally.add("healthz", status, time.monotonic() - t0, 0.0)
            stop.wait(0.05)


def start_server(log_path: Path, jobs: Path) -> tuple[str, subprocess.Popen]:
    port = free_port()
    env = {k: v for k, v in os.environ.items() if not k.startswith("PESHKIN_")}
    env.update({"PESHKIN_PORT": str(port), "PESHKIN_JOBS_PATH": str(jobs), "PESHKIN_STORE_PATH": ""})
    log = open(log_path, "wb")
    proc = subprocess.Popen(server_command(), cwd=LIVE_REPO, env=env, stdout=log, stderr=log)
    base = f"http://127.0.0.1:{port}"
    ends = time.monotonic() + STARTUP_TIMEOUT_S
    while time.monotonic() < ends:
        try:
            if httpx.get(f"{base}/readyz", timeout=1.0).status_code == 200:
                return base, proc
        except httpx.HTTPError:
            pass
        time.sleep(0.2)
    proc.kill()
    raise RuntimeError("the server did not become ready")


def summary(kind: str, rows: list[tuple[int, float, float]]) -> dict:
    by_status: dict[int, int] = defaultdict(int)
    for status, _, _ in rows:
        by_status[status] += 1
    refused = [t for s, t, _ in rows if s == 503]
    answered = [t for s, t, _ in rows if s not in (503,)]
    late = sum(1 for s, t, lim in rows if (s == 503 and t > PROMPT_S) or (s != 503 and t > lim + PROMPT_S))
    return {"kind": kind, "n": len(rows), "statuses": dict(sorted(by_status.items())),
            "p50_ms": 1e3 * percentile(answered, 0.5), "p99_ms": 1e3 * percentile(answered, 0.99),
            "max_s": max(answered, default=0.0), "refused_max_s": max(refused, default=0.0), "late": late}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=45.0)
    ap.add_argument("--write", action="store_true")
    ap.add_argument("--bodies", action="store_true", help="two more clients sending 29 MiB padded msgpack bodies")
    args = ap.parse_args()
    work = Path(tempfile.mkdtemp(prefix="peshkin-mixed-"))
    log_path = work / "server.log"
    base, proc = start_server(log_path, work / "jobs.sqlite3")
    stop, tally = threading.Event(), Tally()
    clients = ([("catalogue", "/v1/feeder/catalogue", CATALOGUE)] * 2 + [("certified", "/v1/cor/locus", CERTIFIED)] * 4
               + [("cheap", "/v1/cor/locus", CHEAP)] * 4)
    threads = [threading.Thread(target=client_loop, args=(base, k, p, b, stop, tally), daemon=True)
               for k, p, b in clients]
    threads.append(threading.Thread(target=probe_loop, args=(base, stop, tally), daemon=True))
    hostile = None
    if args.bodies:
        hostile = multiprocessing.get_context("spawn").Pool(2)
        padded = hostile.starmap_async(padded_client, [(base, args.seconds)] * 2)
    memory: list[float] = []
    t0 = time.monotonic()
    for t in threads:
        t.start()
    while time.monotonic() - t0 < args.seconds:
        memory.append(pss_mb(tree(proc.pid) + [p for h in ray_heads(proc.pid) for p in tree(h)]))
        time.sleep(1.0)
    stop.set()
    for t in threads:
        t.join(timeout=130)
    if hostile is not None:
        for rows_of_one in padded.get(timeout=300):
            for row in rows_of_one:
                tally.add("padded", *row)
        hostile.close()
    heads = len(ray_heads(proc.pid))
    proc.terminate()
    proc.wait(timeout=60)
    log = log_path.read_text(errors="replace").splitlines()
    tracebacks = sum("Traceback" in line for line in log)
    not_json = [line for line in log if line.strip() and not line.lstrip().startswith("{")]
    errors = [line for line in log if line.lstrip().startswith("{") and json.loads(line).get("level") == "ERROR"]
    kinds = ("cheap", "healthz", "certified", "catalogue", *(("padded",) if args.bodies else ()))
    rows = [summary(k, tally.rows[k]) for k in kinds]
    for r in rows:
        print(r, flush=True)
    third = max(len(memory) // 3, 1)
    print(f"memory MB: first third max {max(memory[:third]):.0f}, last third max {max(memory[-third:]):.0f}, "
          f"peak {max(memory):.0f}; Ray heads {heads}; log: {len(log)} lines, {tracebacks} tracebacks, "
          f"{len(not_json)} not JSON, {len(errors)} errors", flush=True)
    if args.write:
        write(args.seconds, rows, memory, heads, len(log), tracebacks, not_json, errors, args.bodies)


def write(seconds: float, rows: list[dict], memory: list[float], heads: int, lines: int, tracebacks: int,
          not_json: list[str], errors: list[str], bodies: bool) -> None:
    load = os.getloadavg()[0]
    third = max(len(memory) // 3, 1)
    table = ["| clients | requests | answers by status | p50 (ms) | p99 (ms) | slowest answer (s) | slowest refusal (s) "
             "| late (over 1 s) |", "|---|---:|---|---:|---:|---:|---:|---:|"]
    names = {"cheap": "4 cheap (analytic locus)", "healthz": "probe (/healthz, every 50 ms)",
             "certified": "4 certified loci (64 rays, 3 s)", "catalogue": "2 catalogues (2 parts, 20 s)",
             "padded": "2 hostile (29 MiB padded msgpack bodies, 1 s apart)"}
    for r in rows:
        statuses = ", ".join(f"{k}: {v}" for k, v in r["statuses"].items())
        table.append(f"| {names[r['kind']]} | {r['n']} | {statuses} | {r['p50_ms']:.1f} | {r['p99_ms']:.1f} | "
                     f"{r['max_s']:.2f} | {r['refused_max_s']:.2f} | {r['late']} |")
    out = [
        f"`scripts/load/mixed.py` ({platform.machine()}, {loky.cpu_count()} usable CPUs, load average {load:.1f} at "
        f"the end, {time.strftime('%Y-%m-%d')}): `python -m service` with its defaults (2 web processes, 2 slots, "
        f"the server's one Ray for catalogues) and {seconds:g} s of the issue's mixed load, the clients on the same "
        "machine; an expensive client waits out a 503's `Retry-After` (not counted in its latency); a row's "
        "latencies are of the answers that were not refusals; *late* counts refusals after 1 s and answers later "
        "than their limit plus 1 s.",
        "",
        *table,
        "",
        f"Memory of the server's processes and its Ray (PSS, summed, sampled each second): at most "
        f"{max(memory[:third]):.0f} MB in the first third of the run, {max(memory[-third:]):.0f} MB in the last; "
        f"{heads} Ray head for the server. The log: {lines} lines, {tracebacks} tracebacks, {len(not_json)} lines "
        f"that are not JSON, {len(errors)} at level ERROR.",
    ]
    write_section("Mixed load with large bodies (issue 35)" if bodies else "Mixed load (issue 35)", out)


if __name__ == "__main__":
    main()
