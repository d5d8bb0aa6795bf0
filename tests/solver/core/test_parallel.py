"""Parallel maps on Ray (solver/core/parallel.py; issue 27): a local Ray of 1 or 2 CPUs, and
a two-node Ray cluster started with ``ray start`` (a head and a worker, each its own node
on loopback), give the same results as the in-process run; tasks not finished by the
deadline are cancelled and reported as not done."""

from __future__ import annotations

import math
import multiprocessing
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest

from models.feeder.fence import feeder_part
from solver import (
    Budget,
    FeederCatalogueProblem,
    FeederDesignProblem,
    RayPool,
    feeder_catalogue,
    parallel_map,
    release_ray,
)
from tests.service.live import free_port

pytestmark = pytest.mark.slow

PARTS = (
    feeder_part([[0, 0], [3, 0], [3.5, 1.5], [1.5, 2.5], [-0.5, 1.2]], [1.4, 1.0]),
    feeder_part([[0, 0], [2.5, 0], [2.5, 1], [0, 1]], [1.25, 0.5]),
    feeder_part([[0, 0], [2, 0], [0.4, 1.5]], [0.8, 0.5]),
    feeder_part([[0, 0], [3, 0], [2.2, 1.2], [0.5, 1.4]], [1.4, 0.6]),
)
TEMPLATE = FeederDesignProblem(PARTS[0], math.radians(20), math.radians(70), math.radians(10), (0.25, 0.25),
                               max_depth=8, alternate=False, validation_parts=4, seed=5)
RAY = str(Path(sys.executable).with_name("ray"))


def summary(result):
    return [(d.design, d.validation.parts, d.validation.in_band) for d in result.designs]


@pytest.fixture(scope="module")
def in_process():
    return summary(feeder_catalogue(FeederCatalogueProblem(PARTS, TEMPLATE)))


@pytest.mark.parametrize("workers", [1, 2])
def test_a_local_ray_answers_what_the_process_does(in_process, workers):
    try:
        result = feeder_catalogue(FeederCatalogueProblem(PARTS, TEMPLATE, RayPool(workers=workers)))
    finally:
        release_ray()
    assert result.run.backend == "ray" and result.run.cpus == workers and result.run.nodes == 1
    assert result.complete and summary(result) == in_process


def sleep_for(seconds: float, ends_at: float | None) -> float:
    time.sleep(seconds)
    return seconds


def _started(pool: RayPool) -> None:
    """Start the pool's Ray before a timed map (starting it takes seconds, far more on a busy
    machine: a deadline that covered it made the tests depend on the machine's speed)."""
    assert parallel_map(sleep_for, [0.0, 0.0], pool, Budget.of(None)).complete


def test_tasks_past_the_deadline_are_cancelled_not_reported():
    try:
        _started(RayPool(workers=2))
        run = parallel_map(sleep_for, [0.1, 120.0, 0.2], RayPool(workers=2), Budget.of(25.0))
    finally:
        release_ray()
    assert run.results[0] == 0.1 and run.results[1] is None and run.results[2] == 0.2 and run.finished == 2


def _start(args: list[str], env: dict[str, str]) -> subprocess.Popen:
    return subprocess.Popen([RAY, "start", "--block", "--disable-usage-stats", *args], env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, start_new_session=True)


def _wait_listening(host: str, port: int, proc: subprocess.Popen, timeout_s: float = 120.0) -> None:
    """Until the head's port accepts connections (Ray's own connect would retry for minutes)."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if proc.poll() is not None:
            raise RuntimeError(f"ray start exited: {proc.stderr.read().decode(errors='replace')[-2000:]}")
        try:
            with socket.create_connection((host, port), timeout=1.0):
                return
        except OSError:
            time.sleep(0.5)
    raise RuntimeError("the Ray head did not listen in time")


def _stop(proc: subprocess.Popen) -> None:
    """Stop one node: its ``ray start --block`` ends the node's processes on SIGTERM."""
    if proc.poll() is None:
        proc.terminate()
        try:
            proc.wait(timeout=60)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, 9)
            proc.wait()


def drive_two_nodes(address: str) -> tuple[int, int, int, list]:
    """In a process of its own (Ray keeps its authentication mode for a process's life, and
    the other tests' local Rays use tokens): wait for both nodes, then run the catalogue on
    them. Returns the nodes and CPUs seen, the catalogue's nodes and its summary."""
    os.environ["RAY_AUTH_MODE"] = "disabled"
    pool = RayPool(address=address)
    try:
        deadline = time.monotonic() + 90.0
        while True:  # until both nodes have joined
            run = parallel_map(sleep_for, [0.0], pool, Budget.of(30.0))
            if run.nodes == 2 or time.monotonic() > deadline:
                break
            release_ray()
            time.sleep(1.0)
        result = feeder_catalogue(FeederCatalogueProblem(PARTS, TEMPLATE, pool))
        assert result.complete
        return run.nodes, run.cpus, result.run.nodes, summary(result)
    finally:
        release_ray()


@pytest.mark.skipif(shutil.which(RAY) is None and not Path(RAY).exists(), reason="the ray command is not installed")
def test_a_two_node_cluster_answers_what_the_process_does(in_process):
    """A head and a worker node started with ``ray start`` on 127.0.0.2 and 127.0.0.3 (Ray
    rewrites 127.0.0.1 to the host's address), authentication off on both and the driver."""
    port = free_port()
    temp = tempfile.mkdtemp(prefix="pkr-", dir="/tmp")  # short: Ray's socket paths must fit 107 bytes
    env = {**os.environ, "RAY_AUTH_MODE": "disabled", "RAY_USAGE_STATS_ENABLED": "0"}
    head = _start(["--head", f"--port={port}", "--node-ip-address=127.0.0.2", "--num-cpus=1",
                   "--include-dashboard=false", f"--temp-dir={temp}"], env)
    worker = None
    try:
        address = f"127.0.0.2:{port}"
        _wait_listening("127.0.0.2", port, head)
        worker = _start([f"--address={address}", "--node-ip-address=127.0.0.3", "--num-cpus=1"], env)
        with multiprocessing.get_context("spawn").Pool(1) as driver:
            nodes, cpus, catalogue_nodes, got = driver.apply(drive_two_nodes, (address,))
        assert (nodes, cpus, catalogue_nodes) == (2, 2, 2)
        assert got == in_process
    finally:
        for proc in (worker, head):
            if proc is not None:
                _stop(proc)
        shutil.rmtree(temp, ignore_errors=True)


def fail_on(value: float, ends_at: float | None) -> float:
    if value < 0:
        raise ValueError("a task's own error")
    time.sleep(value)
    return value


def test_a_tasks_error_reaches_the_caller_and_nothing_is_left_running():
    try:
        _started(RayPool(workers=2))
        with pytest.raises(ValueError, match="a task's own error"):
            parallel_map(fail_on, [-1.0, 30.0], RayPool(workers=2), Budget.of(60.0))
        run = parallel_map(sleep_for, [0.0], RayPool(workers=2), Budget.of(30.0))  # Ray still answers
        assert run.results == (0.0,)
    finally:
        release_ray()


def _head_pids(directory: str) -> list[int]:
    import json

    try:
        return [int(json.loads(Path(directory, "ray-head.json").read_text())["pid"])]
    except (OSError, ValueError):
        return []


def ray_of_server(directory: str) -> tuple[str, int, int, bool]:
    """In a process of its own (one of a server's solver workers): the server's Ray as this
    process sees it, after a map on it, and whether its SIGTERM handler is still the one it
    had (ray.init installs its own, which an idle worker may never run: Pool.terminate hung)."""
    import signal

    from solver.core.ray_head import server_ray

    address = server_ray(directory, 2).address
    handler = signal.getsignal(signal.SIGTERM)
    try:
        run = parallel_map(sleep_for, [0.0, 0.0, 0.0], RayPool(workers=2, parallel=1, server_dir=directory),
                           Budget.of(60.0))
        assert run.complete and run.backend == "ray"
        return address, run.cpus, os.getpid(), signal.getsignal(signal.SIGTERM) is handler
    finally:
        release_ray()


def test_the_processes_of_a_server_share_one_ray_which_ends_with_the_server():
    """Two processes (two solver workers) that need Ray at once get one Ray, the server's
    (solver/core/ray_head.py): the same address, one head; a map on it runs at most its
    `parallel` tasks at once (it reports the CPUs it had: 1); the head ends when the
    server's directory goes."""
    directory = tempfile.mkdtemp(prefix="pks-")
    try:
        with multiprocessing.get_context("spawn").Pool(2) as workers:
            seen = workers.map(ray_of_server, [directory, directory])
        assert seen[0][0] == seen[1][0] and seen[0][2] != seen[1][2]
        assert [cpus for _, cpus, _, _ in seen] == [1, 1]
        assert [kept for _, _, _, kept in seen] == [True, True]
        pids = _head_pids(directory)
        assert len(pids) == 1
    finally:
        shutil.rmtree(directory, ignore_errors=True)
    deadline = time.monotonic() + 30.0
    while pids and time.monotonic() < deadline:
        try:
            os.kill(pids[0], 0)
        except ProcessLookupError:
            break
        time.sleep(0.1)
    else:
        pytest.fail("the server's Ray head outlived its directory")


def test_a_map_short_of_time_does_not_start_ray_but_runs_in_process():
    """Issue 35, point 5: a catalogue with a limit of a few seconds always answered 504 with
    nothing, its local Ray's start (2-4 s) eating the limit. A map with less than CONNECT_S
    left in a process not yet connected runs in process and hands back what it finished."""
    from solver.core.parallel import CONNECT_S, connected

    pool = RayPool(workers=2)
    assert not connected(pool)
    run = parallel_map(sleep_for, [0.0, 0.0, 0.0], pool, Budget.of(CONNECT_S / 2))
    assert run.backend == "in_process" and run.complete and not connected(pool)
