"""The curl examples of docs/api.md, as (url, JSON body) pairs."""

from __future__ import annotations

import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
DOC = REPO / "docs" / "api.md"
CURL = re.compile(
    r"curl -s '?(?:http://127\.0\.0\.1|localhost):8000(/[^ ']+)'?"  # the URL
    r"((?:\s+-H (?:'[^']*'|\"[^\"]*\")|\s*\\\n\s*)*)"  # headers, lines continued
    r"\s+-d '([^']+)'"  # the body, on one line or several
)
EXAMPLES = [(m.group(1), m.group(3)) for m in CURL.finditer(DOC.read_text(encoding="utf-8"))
            if "$KEY" not in m.group(2)]
"""Every POST example of the API guide (those with a key of the reader's own are in the
keyed tests)."""
README_EXAMPLES = [(m.group(1), m.group(3)) for m in CURL.finditer((REPO / "README.md").read_text(encoding="utf-8"))]


def split(url: str) -> tuple[str, dict[str, str] | None]:
    """(path, query parameters or None) of an example's URL."""
    path, _, query = url.partition("?")
    return path, (dict(kv.split("=") for kv in query.split("&")) if query else None)
