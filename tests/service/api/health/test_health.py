"""GET /healthz: the liveness probe."""

from __future__ import annotations

from service import __version__


def test_healthz(client):
    r = client.get("/healthz")
    assert r.status_code == 200
    assert r.json() == {"status": "ok", "version": __version__}
