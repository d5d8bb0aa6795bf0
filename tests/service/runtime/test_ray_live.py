"""The server's one Ray, live (issue 35, point 8): catalogues from two web processes, as
requests and as a job, run on one Ray started by the first that needs it (not a Ray per
solver worker sized to the machine); its output stays out of the service's JSON log, the
job's end is logged, and the Ray ends with the server."""

from __future__ import annotations

import json
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import httpx
import pytest

from tests.service.live import live_server_process
from tests.service.runtime.test_deferred_live import descendants, submit, wait_for

pytestmark = pytest.mark.slow

PARTS = [
    {"name": "pentagon", "vertices": [[0, 0], [3, 0], [3.5, 1.5], [1.5, 2.5], [-0.5, 1.2]], "center_of_mass": [1.4, 1.0]},
    {"name": "plate", "vertices": [[0, 0], [2.5, 0], [2.5, 1], [0, 1]], "center_of_mass": [1.25, 0.5]},
]
CATALOGUE = {"parts": PARTS, "design": {"angles": {"min": 0.349, "max": 1.222, "step": 0.1745}, "mu_c": 0.25,
                                        "alternate": False, "validation_parts": 3, "seed": 2}, "time_limit_s": 30}


def _ray_heads(pid: int) -> int:
    """The Ray heads of the server whose supervisor is ``pid`` (a head runs in a session of
    its own, not below the server, and watches the supervisor: ``--watch <pid>``)."""
    count = 0
    for cmd in Path("/proc").glob("[0-9]*/cmdline"):
        try:
            args = cmd.read_bytes().decode(errors="replace").split("\0")
        except OSError:
            continue
        count += "solver.core.ray_head" in args and "--watch" in args and args[args.index("--watch") + 1] == str(pid)
    return count


def test_catalogues_share_the_servers_one_ray_and_its_output_stays_out_of_the_log(tmp_path):
    with live_server_process(web_workers="2", solver_workers="2", ray_workers="2",
                             jobs_path=str(tmp_path / "jobs.sqlite3"), log_level="info") as (url, proc):
        with ThreadPoolExecutor(3) as pool:
            answers = list(pool.map(lambda _: httpx.post(f"{url}/v1/feeder/catalogue", json=CATALOGUE, timeout=120),
                                    range(3)))
        job = submit(url, "feeder_catalogue", CATALOGUE)
        done = wait_for(url, job, ("succeeded", "failed"), timeout_s=120.0)
        heads = _ray_heads(proc.pid)
        below = descendants(proc.pid)
        proc.terminate()
        _, err = proc.communicate(timeout=60)
    served = [r for r in answers if r.status_code == 200]
    assert served and all(r.status_code in (200, 503) for r in answers), [r.text[:200] for r in answers]
    assert all(r.json()["backend"] == "ray" and r.json()["designs"][0]["status"] == "ok" for r in served)
    assert done["state"] == "succeeded", done
    assert heads == 1, f"{heads} Ray heads for one server"
    assert below, "the server had processes"
    log = err.decode(errors="replace").splitlines()
    not_json = [line for line in log if line.strip() and not line.lstrip().startswith("{")]
    assert not not_json, not_json[:5]
    assert any(f"job {job} succeeded" in json.loads(line).get("message", "") for line in log)
    deadline = time.monotonic() + 20.0
    while _ray_heads(proc.pid) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert _ray_heads(proc.pid) == 0, "the server's Ray outlived it"
