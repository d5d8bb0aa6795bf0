"""No function of models/, solver/ or service/ is longer than MAX_LINES (its docstring
included): a longer one is split where a step has a name (issue 23 split twelve, from
simulate_spiral's 200 lines down)."""

from __future__ import annotations

import ast
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[1]
MAX_LINES = 100


def long_functions(limit: int = MAX_LINES) -> list[str]:
    found = []
    for layer in ("models", "solver", "service"):
        for path in sorted((REPO_ROOT / layer).rglob("*.py")):
            for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
                if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                    lines = node.end_lineno - node.lineno + 1
                    if lines > limit:
                        found.append(f"{path.relative_to(REPO_ROOT)}:{node.lineno} {node.name} ({lines} lines)")
    return found


def test_no_function_is_longer_than_the_limit():
    assert long_functions() == []


def test_the_check_sees_functions():
    assert long_functions(limit=60), "no function over 60 lines found: the walk is not reading the code"
