"""Benchmark (not a test): batches of supports end to end over HTTP (issue 27), as rows of
JSON objects, as JSON columns and as msgpack columns, against a live server
(``python -m service``, 2 web processes, on this machine).

End to end is the client's whole cost: building the body from numpy arrays, sending it,
the server's answer, and decoding it back into numpy arrays. The "error" of every
encoding is measured too: the largest difference of its rotations from the rows' answer
(0 when the encodings carry the same numbers). Writes its section of docs/benchmarks.md."""

from __future__ import annotations

import json
import os
import time

import httpx
import msgpack
import numpy as np
import pytest

from models.core.support import random_balanced_tripods
from tests.benchmarks._docs import write_section
from tests.scenes import SEED
from tests.service.live import live_server

pytestmark = pytest.mark.benchmark

PUSH = {"contact_point": [-0.5, -0.3], "edge_angle": float(np.pi / 2), "mu_c": 0.3}
ROWS_MAX = 10_000
N = 100_000
REPEATS = 3


def _rows_body(pts, w):
    return {**PUSH, "supports": [{"points": p.tolist(), "weights": q.tolist()} for p, q in zip(pts, w)]}


def _columns_body(pts, w):
    return {**PUSH, "batch": {"support_size": 3, "x": pts[..., 0].ravel().tolist(),
                              "y": pts[..., 1].ravel().tolist(), "weights": w.ravel().tolist()}}


def _post(client, url, pts, w, how):
    """One request end to end: the rotations (numpy) and the server's elapsed_ms."""
    if how == "rows":
        r = client.post(url, content=json.dumps(_rows_body(pts, w)), headers={"content-type": "application/json"})
        doc = r.json()
        return np.array([m["rotation_per_push"] for m in doc["motions"]]), doc["elapsed_ms"], len(r.content)
    body = _columns_body(pts, w)
    if how == "json":
        r = client.post(url, content=json.dumps(body), headers={"content-type": "application/json"})
        doc = r.json()
    else:
        r = client.post(url, content=msgpack.packb(body),
                        headers={"content-type": "application/msgpack", "accept": "application/msgpack"})
        doc = msgpack.unpackb(r.content)
    assert r.status_code == 200, r.text[:300]
    return np.asarray(doc["columns"]["rotation_per_push"], dtype=float), doc["elapsed_ms"], len(r.content)


def test_batches_over_http():
    pts, w = random_balanced_tripods(np.random.default_rng(SEED), N, 1.0)
    rows = []
    with live_server() as url, httpx.Client(timeout=120) as client:
        solve = f"{url}/v1/cor/solve"
        _post(client, solve, pts[:1000], w[:1000], "msgpack")  # warm the workers
        reference = None
        for how, n in (("rows", ROWS_MAX), ("json", ROWS_MAX), ("msgpack", ROWS_MAX), ("json", N), ("msgpack", N)):
            times, server = [], []
            for _ in range(REPEATS):
                t0 = time.perf_counter()
                omega, elapsed_ms, size = _post(client, solve, pts[:n], w[:n], how)
                times.append(time.perf_counter() - t0)
                server.append(elapsed_ms / 1e3)
            if reference is None:
                reference = omega
            err = float(np.max(np.abs(omega[:ROWS_MAX] - reference)))
            rows.append((how, n, min(times), max(times), min(server), size, err))
            print(rows[-1])
    lines = [
        f"Measured {time.strftime('%Y-%m-%d')} on this machine ({os.cpu_count()} cores, the client and the server "
        "on it together), by `tests/benchmarks/test_bench_batches.py`: random balanced tripods (3.3.3) with "
        f"mu_c = {PUSH['mu_c']}, `POST /v1/cor/solve` on a live server (`python -m service`), best and worst of "
        f"{REPEATS}. End to end = building the body from numpy arrays, the request, decoding the answer into a numpy "
        "array. Error = the largest difference of the rotations from the rows' answer on the first 10,000 (the same "
        "numbers: 0).",
        "",
        "| encoding | tripods | end to end (s) | per tripod (us) | server's part (s) | answer (MB) | error |",
        "|---|---|---|---|---|---|---|",
    ]
    names = {"rows": "JSON, `supports` as objects, rows", "json": "JSON, `batch` columns",
             "msgpack": "msgpack both ways, columns"}
    for how, n, best, worst, server, size, err in rows:
        lines.append(f"| {names[how]} | {n:,} | {best:.2f}-{worst:.2f} | {best / n * 1e6:.0f} | {server:.2f} | "
                     f"{size / 1e6:.1f} | {err:.0e} |")
    write_section("Batches over HTTP: rows, columns, msgpack (issue 27)", lines)
