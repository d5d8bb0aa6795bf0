"""Large bodies on a live server (issue 35, point 1): two ~29 MiB msgpack bodies padded with
an unknown field are refused at that field, then a valid 100,000-tripod batch is solved, and
the web process keeps answering its probe meanwhile (the old service decoded such bodies
on the event loop: 6-14 s of a frozen web process)."""

from __future__ import annotations

import time
from concurrent.futures import ThreadPoolExecutor

import httpx
import msgpack
import numpy as np
import pytest

from tests.service.live import live_server
from tests.timing import stretched

pytestmark = pytest.mark.slow

MSGPACK = {"content-type": "application/msgpack", "accept": "application/msgpack"}
PUSH = {"contact_point": [-0.5, -0.3], "edge_angle": 1.5707963267948966, "disk_radius": 2}
PROBE_STALL_S = 2.0
"""Longest a probe may wait while the large bodies are handled: far below what decoding
them on the event loop took (seconds each), far above a probe's time on a busy machine."""


def _tripods(n: int) -> dict:
    rng = np.random.default_rng(1)
    turn = rng.uniform(0, 2 * np.pi, (n, 1)) + np.array([0, 2 * np.pi / 3, 4 * np.pi / 3])
    r = rng.uniform(0.2, 1.0, (n, 1))
    return {**PUSH, "batch": {"support_size": 3, "x": (r * np.cos(turn)).ravel().tolist(),
                              "y": (r * np.sin(turn)).ravel().tolist(), "weights": [1.0] * (3 * n)}}


def test_padded_and_large_bodies_do_not_freeze_the_web_process():
    padded = msgpack.packb({**PUSH, "padding": [[i, i + 1, i + 2] for i in range(1_900_000)]})
    assert len(padded) > 28 * 2**20
    valid = msgpack.packb(_tripods(100_000))
    with live_server(web_workers="1", solver_workers="2") as url:
        stalls: list[float] = []
        done = False

        def probe() -> None:
            with httpx.Client(timeout=30.0) as c:
                while not done:
                    t0 = time.monotonic()
                    assert c.get(f"{url}/healthz").status_code == 200
                    stalls.append(time.monotonic() - t0)
                    time.sleep(0.01)

        def post(body: bytes) -> httpx.Response:
            return httpx.post(f"{url}/v1/cor/solve", content=body, headers=MSGPACK, timeout=60.0)

        with ThreadPoolExecutor(3) as pool:
            watching = pool.submit(probe)
            answers = [*pool.map(post, [padded, padded]), post(valid)]
            done = True
            watching.result()
    for r in answers[:2]:
        assert r.status_code == 422
        assert r.json()["detail"][0]["loc"] == ["body", "padding"]
    assert answers[2].status_code == 200
    assert len(msgpack.unpackb(answers[2].content)["columns"]["cor_x"]) == 100_000
    assert stalls and max(stalls) < stretched(PROBE_STALL_S), f"a probe waited {max(stalls):.2f} s"


def test_a_large_body_that_would_be_refused_is_refused_unread():
    """With every slot held, a 30 MiB body to /v1/cor/solve is answered 503 as soon as its
    headers arrive: the web process does not read 30 MiB to refuse it (the client here sends
    1 MiB and waits)."""
    import socket

    from tests.service.runtime.test_live import SLOW_LOCUS

    with live_server(web_workers="1", solver_workers="1") as url:
        host, port = url.removeprefix("http://").split(":")
        with ThreadPoolExecutor(1) as pool:
            holder = pool.submit(httpx.post, f"{url}/v1/cor/locus", json={**SLOW_LOCUS, "time_limit_s": 8},
                                 timeout=60.0)
            time.sleep(1.0)  # the only slot is held
            with socket.create_connection((host, int(port)), timeout=30.0) as s:
                s.sendall(b"POST /v1/cor/solve HTTP/1.1\r\nHost: x\r\nContent-Type: application/msgpack\r\n"
                          b"Content-Length: 31457280\r\n\r\n" + b"\x00" * (1 << 20))
                t0 = time.monotonic()
                head = s.recv(4096)
                took = time.monotonic() - t0
            holder.result()
    assert head.startswith(b"HTTP/1.1 503"), head[:200]
    assert took < stretched(2.0)
