"""The curl examples of docs/api.md, as (url, JSON body) pairs."""

from __future__ import annotations

import re
from pathlib import Path

DOC = Path(__file__).resolve().parents[2] / "docs" / "api.md"
CURL = re.compile(
    r"curl -s '?http://127\.0\.0\.1:8000(/[^ ']+)'? -H 'content-type: application/json' \\\n  -d '([^']+)'"
)
EXAMPLES = [(m.group(1), m.group(2)) for m in CURL.finditer(DOC.read_text(encoding="utf-8"))]


def split(url: str) -> tuple[str, dict[str, str] | None]:
    """(path, query parameters or None) of an example's URL."""
    path, _, query = url.partition("?")
    return path, (dict(kv.split("=") for kv in query.split("&")) if query else None)
