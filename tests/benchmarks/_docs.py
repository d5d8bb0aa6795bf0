"""Write one benchmark's section into docs/benchmarks.md, keeping the other sections."""

from __future__ import annotations

from pathlib import Path

DOCS = Path(__file__).resolve().parents[2] / "docs" / "benchmarks.md"


def write_section(heading: str, lines: list[str]) -> None:
    """Replace the section that starts with ``## {heading}`` (up to the next ``## ``), or
    append it at the end."""
    text = DOCS.read_text() if DOCS.exists() else "# Benchmarks\n"
    block = "\n".join([f"## {heading}", "", *lines]).rstrip() + "\n"
    start = text.find(f"## {heading}")
    if start < 0:
        DOCS.write_text(text.rstrip() + "\n\n" + block)
        return
    nxt = text.find("\n## ", start + 1)
    rest = text[nxt + 1 :] if nxt >= 0 else ""
    DOCS.write_text(text[:start] + block + ("\n" + rest if rest else ""))
