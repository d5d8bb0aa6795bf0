"""The service under hostile and impatient clients, live on loopback (issue 11): clients
that give up free their worker within 1 s (the job is cancelled, its worker replaced),
so the next request is served at once; a 1 s time limit is answered within 1.5 s on
every endpoint that takes one; a client that sends its request too slowly is cut off
with 408."""

from __future__ import annotations

import socket
import time
from concurrent.futures import ThreadPoolExecutor

import httpx
import pytest

from tests.service.live import live_server
from tests.timing import stretched

pytestmark = pytest.mark.slow

L_SHAPE = [[0, 0], [3, 0], [3, 1], [1, 1], [1, 3], [0, 3]]
SLOW_LOCUS = {  # a certified locus of a polygon: many seconds of work
    "footprint": L_SHAPE, "contact_point": [0, 0.5], "edge_angle": 1.5707963267948966,
    "method": "certified", "n_certified": 256, "time_limit_s": 30, "outputs": [],
}
MEMBERSHIP = {"disk_radius": 1, "contact_point": [-0.5, -0.3], "edge_angle": 1.5707963267948966, "cor": [0, 3]}
GIVE_UP_S = 0.3
FREED_WITHIN_S = 1.0
ANSWERED_WITHIN_S = 1.5

TIME_LIMITED = [  # every endpoint that takes time_limit_s, asked for more than a second of work
    ("/v1/cor/locus", {**SLOW_LOCUS, "time_limit_s": 1.0}),
    ("/v1/cor/membership", {"footprint": L_SHAPE, "contact_point": [0, 0.5], "edge_angle": 1.5707963267948966,
                            "cor": [0.4, -2.0], "time_limit_s": 1.0}),
    ("/v1/cor/sketch", {"footprint": L_SHAPE, "contact_point": [0, 0.5], "edge_angle": 1.5707963267948966,
                        "mu_c": 0.6, "method": "certified", "n_rays": 64, "time_limit_s": 1.0}),
    ("/v1/push/align", {"footprint": [[-1, -1], [1, -1], [1, 1], [-1, 1]], "orientation": 0.5235987755982988,
                        "fence_angle": 1.5707963267948966, "mu_c": 0.25, "n_nodes": 64, "time_limit_s": 1.0}),
    ("/v1/push/disk-encounter", {"disk_radius": 1, "beta_initial": 0.7853981633974483, "mu_c": 0.5,
                                 "n_nodes": 64, "time_limit_s": 1.0}),
    ("/v1/spiral/critical-radius", {"disk_radius": 1, "mu_c": 0.37, "time_limit_s": 1.0}),
    ("/v1/spiral/schedule", {"disk_radius": 1, "mu_c": 0.41, "start_radius": 20, "target": 1.5, "time_limit_s": 1.0}),
]


@pytest.fixture(scope="module")
def server():
    with live_server(web_workers="1", solver_workers="1", solver_queue="64", header_timeout_s="1",
                     body_timeout_s="1") as url:
        yield url


def _gate(url: str) -> dict:
    return httpx.get(f"{url}/readyz", timeout=5.0).json()["gates"][1]


def test_clients_that_give_up_free_their_worker_within_a_second(server):
    def impatient(_):
        try:
            r = httpx.post(f"{server}/v1/cor/locus", json=SLOW_LOCUS, timeout=GIVE_UP_S)
        except httpx.TimeoutException:
            return time.monotonic()
        assert r.status_code == 503, "the slow locus answered before the client gave up"
        return None  # refused at once: predicted not to start in time behind the others

    with ThreadPoolExecutor(8) as ex:
        gave_up = [t for t in ex.map(impatient, range(8)) if t is not None]
    assert gave_up, "no client got as far as giving up"
    gave_up = max(gave_up)
    while _gate(server)["in_use"] > 0:
        assert time.monotonic() - gave_up < stretched(FREED_WITHIN_S), "abandoned jobs still hold the solver worker"
        time.sleep(0.02)
    t0 = time.monotonic()
    r = httpx.post(f"{server}/v1/cor/membership", json=MEMBERSHIP, timeout=30.0)
    assert r.status_code == 200 and time.monotonic() - t0 < stretched(FREED_WITHIN_S + 1.0)


@pytest.mark.parametrize("path, body", TIME_LIMITED, ids=[p for p, _ in TIME_LIMITED])
def test_a_one_second_limit_is_answered_within_one_and_a_half(server, path, body):
    t0 = time.monotonic()
    r = httpx.post(f"{server}{path}", json=body, timeout=30.0)
    took = time.monotonic() - t0
    assert r.status_code in (200, 422, 504), r.text[:300]
    if r.status_code == 422:  # refused at once by the cost prediction, saying so
        assert "predict" in r.text
    assert took < stretched(ANSWERED_WITHIN_S), f"{path}: {took:.2f} s, status {r.status_code}"


def test_a_client_that_sends_too_slowly_is_cut_off(server):
    host, port = server.removeprefix("http://").split(":")
    with socket.create_connection((host, int(port)), timeout=10.0) as s:
        s.sendall(b"POST /v1/cor/locus HTTP/1.1\r\nHost: x\r\n")  # and never the rest
        t0 = time.monotonic()
        answer = s.recv(4096)
        assert answer.startswith(b"HTTP/1.1 408") and time.monotonic() - t0 < 3.0
    with socket.create_connection((host, int(port)), timeout=10.0) as s:
        s.sendall(b"POST /v1/cor/locus HTTP/1.1\r\nHost: x\r\ncontent-type: application/json\r\n"
                  b"content-length: 1000\r\n\r\n{\"disk")  # the body never finishes
        assert s.recv(4096).startswith(b"HTTP/1.1 408")
    assert httpx.get(f"{server}/healthz", timeout=5.0).status_code == 200
