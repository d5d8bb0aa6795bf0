"""The docs pages render in a real browser without the internet: headless Chromium loads
/docs and /redoc from a live server with every host but the loopback unresolvable, and the
rendered DOM lists the operations (Swagger UI's operation blocks, ReDoc's sections).
Skipped where no Chromium is installed (Debian: apt-get install chromium)."""

from __future__ import annotations

import shutil
import subprocess

import pytest

from tests.service.live import live_server

pytestmark = pytest.mark.slow

BROWSER = next((b for b in ("chromium", "chromium-browser", "google-chrome") if shutil.which(b)), None)
RENDER_BUDGET_MS = 20000
"""Chromium's virtual time for the page's scripts to run (not wall-clock)."""


@pytest.fixture(scope="module")
def server():
    if BROWSER is None:
        pytest.skip("no Chromium here (Debian: apt-get install chromium)")
    with live_server(web_workers="1", solver_workers="1") as url:
        yield url


def _rendered(url: str) -> str:
    out = subprocess.run(
        [BROWSER, "--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
         "--host-resolver-rules=MAP * ~NOTFOUND, EXCLUDE 127.0.0.1",
         f"--virtual-time-budget={RENDER_BUDGET_MS}", "--dump-dom", url],
        capture_output=True, text=True, timeout=120,
    )
    assert out.returncode == 0, out.stderr[-2000:]
    return out.stdout


def test_swagger_ui_renders_the_operations(server):
    dom = _rendered(f"{server}/docs")
    assert "opblock" in dom  # rendered by Swagger UI's script, not in the HTML shell
    for path in ("/v1/cor/locus", "/v1/cor/membership", "/v1/spiral/schedule", "/readyz"):
        assert path in dom, path


def test_redoc_renders_the_operations(server):
    dom = _rendered(f"{server}/redoc")
    assert "redoc-wrap" in dom
    for summary in ("COR locus of a pushed sliding workpiece", "Readiness probe"):
        assert summary in dom, summary
