"""/docs (Swagger UI) and /redoc (ReDoc) are served from the package (fastapi-offline):
the pages and every script, style and icon they load come from this service, none from
another host (before, /docs loaded Swagger UI from a CDN and was blank offline)."""

from __future__ import annotations

import re

import pytest

ASSET = re.compile(r"""(?:src|href)\s*=\s*["']([^"']+)["']|url:\s*['"]([^'"]+)['"]""")


@pytest.mark.parametrize("page", ["/docs", "/redoc"])
def test_the_docs_pages_load_nothing_from_elsewhere(client, page):
    r = client.get(page)
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/html")
    refs = [a or b for a, b in ASSET.findall(r.text)]
    assert refs, "the page references its scripts"
    assert not [u for u in refs if u.startswith(("http://", "https://", "//"))], refs
    assert "cdn.jsdelivr" not in r.text and "fonts.googleapis" not in r.text
    for url in refs:
        asset = client.get(url)
        assert asset.status_code == 200 and len(asset.content) > 0, url
