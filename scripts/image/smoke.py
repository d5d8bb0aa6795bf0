"""Smoke test of the built image (``make docker-smoke``): start a container, time its cold
start to a healthy /healthz, send every documented example (the curl examples of
docs/api.md and each operation's example in the OpenAPI document) and check each answers
200, then stop it; print the image's size and the results. Exits 1 on any failure.

    python scripts/image/smoke.py IMAGE [PORT]
"""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

import httpx

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO))
from tests.service.docs_examples import EXAMPLES, split

RUN = ["podman", "run", "-d", "--rm", "--runtime", "runc", "--ulimit", "nofile=1024:1024",
       "--ulimit", "nproc=4096:4096"]
STARTUP_S = 120.0


def image_size(image: str) -> str:
    out = subprocess.run(["podman", "image", "inspect", image, "--format", "{{.Size}}"], check=True,
                         capture_output=True, text=True).stdout.strip()
    return f"{int(out) / 1e6:.0f} MB"


def dangling() -> list[str]:
    out = subprocess.run(["podman", "images", "--filter", "dangling=true", "--format", "{{.ID}}"], check=True,
                         capture_output=True, text=True).stdout
    return out.split()


def wait_healthy(url: str, started: float) -> float:
    while time.monotonic() - started < STARTUP_S:
        try:
            if httpx.get(f"{url}/healthz", timeout=1.0).status_code == 200:
                return time.monotonic() - started
        except httpx.HTTPError:
            pass
        time.sleep(0.05)
    raise RuntimeError("the container did not become healthy")


def examples(client: httpx.Client, url: str) -> list[tuple[str, str]]:
    """(path, body) of every documented example: the guide's, then the OpenAPI document's."""
    found = [(path, body) for path, body in EXAMPLES]
    spec = client.get(f"{url}/openapi.json").json()
    for path, item in spec["paths"].items():
        for method, op in item.items():
            ref = op.get("requestBody", {}).get("content", {}).get("application/json", {}).get("schema", {})
            name = ref.get("$ref", "").rsplit("/", 1)[-1]
            for example in spec["components"]["schemas"].get(name, {}).get("examples", []):
                if method == "post" and not path.startswith("/v1/jobs"):
                    found.append((path, json.dumps(example)))
    return found


def main() -> int:
    image = sys.argv[1]
    port = int(sys.argv[2]) if len(sys.argv) > 2 else 18000
    url = f"http://127.0.0.1:{port}"
    left = dangling()
    started = time.monotonic()
    cid = subprocess.run([*RUN, "-p", f"{port}:8000", image], check=True, capture_output=True, text=True).stdout.strip()
    failures = 0
    try:
        cold = wait_healthy(url, started)
        print(f"image {image}: {image_size(image)}; cold start to a healthy /healthz {cold:.2f} s; "
              f"dangling images {len(left)}")
        with httpx.Client(timeout=120.0) as client:
            for path, body in examples(client, url):
                route, params = split(path)
                t0 = time.monotonic()
                r = client.post(f"{url}{route}", params=params, content=body,
                                headers={"content-type": "application/json"})
                ok = r.status_code == (202 if route == "/v1/jobs" else 200)
                failures += not ok
                where = ""
                if ok and route == "/v1/feeder/catalogue":
                    where = f"  (backend {r.json()['backend']}, {r.json()['cpus']} CPUs)"
                print(f"  {'ok ' if ok else 'FAIL'} {r.status_code} {time.monotonic() - t0:6.2f} s  POST {path}{where}")
    finally:
        subprocess.run(["podman", "stop", "--time", "40", cid], check=False, capture_output=True)
    if left:
        print(f"dangling images left by the build: {left}")
    return 1 if failures or left else 0


if __name__ == "__main__":
    sys.exit(main())
