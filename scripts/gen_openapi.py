#!/usr/bin/env python3
"""Write the service's OpenAPI document to openapi.yaml (or check it is up to date).

    python scripts/gen_openapi.py            # (re)write openapi.yaml
    python scripts/gen_openapi.py --check    # exit 1 if openapi.yaml differs from the app
    python scripts/gen_openapi.py -o FILE    # another output path

The document is ``app.openapi()`` dumped with ``yaml.safe_dump(sort_keys=False)``: keys
in FastAPI's order, so the output is deterministic for a given code base.
"""

from __future__ import annotations

import argparse
import difflib
import sys
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[1]
if str(REPO_ROOT) not in sys.path:
    sys.path.insert(0, str(REPO_ROOT))

import yaml

DEFAULT_OUTPUT = REPO_ROOT / "openapi.yaml"


def render() -> str:
    """The OpenAPI document of ``service.app:app`` as YAML text."""
    from service.app import create_app

    return yaml.safe_dump(create_app().openapi(), sort_keys=False, allow_unicode=True, width=100)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="fail (exit 1) if the file is out of date")
    parser.add_argument("-o", "--output", type=Path, default=DEFAULT_OUTPUT, help="default: openapi.yaml")
    args = parser.parse_args(argv)
    text = render()
    if args.check:
        current = args.output.read_text(encoding="utf-8") if args.output.exists() else ""
        if current != text:
            diff = difflib.unified_diff(
                current.splitlines(keepends=True), text.splitlines(keepends=True),
                fromfile=str(args.output), tofile="app.openapi()", n=2,
            )
            sys.stderr.writelines(list(diff)[:200])
            print(f"{args.output} is out of date: run python scripts/gen_openapi.py", file=sys.stderr)
            return 1
        print(f"{args.output} is up to date")
        return 0
    args.output.write_text(text, encoding="utf-8")
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
