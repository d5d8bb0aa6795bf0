"""No private name is used across modules (issue 10): no ``from pkg.mod import _name`` and
no ``mod._name`` on an imported project module, in the packages and in the tests. A private
name is one module's own business; what another module needs is public."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

REPO_ROOT = Path(__file__).resolve().parents[1]
PROJECT = ("models", "solver", "service", "tests")


def _is_private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def _project(module: str | None) -> bool:
    return module is not None and module.split(".")[0] in PROJECT


def private_uses(path: Path) -> list[str]:
    """Places in ``path`` that use another project module's private name."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    found = []
    aliases: set[str] = set()  # names bound to project modules in this file
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.level == 0 and _project(node.module):
            for alias in node.names:
                if _is_private(alias.name):
                    found.append(f"{path.relative_to(REPO_ROOT)}:{node.lineno}: from {node.module} import {alias.name}")
                else:
                    aliases.add(alias.asname or alias.name)  # may be a module (from solver.sketch import sticking)
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if _project(alias.name):
                    aliases.add(alias.asname or alias.name.split(".")[0])
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and _is_private(node.attr):
            base = node.value
            while isinstance(base, ast.Attribute):
                base = base.value
            if isinstance(base, ast.Name) and base.id in aliases:
                found.append(f"{path.relative_to(REPO_ROOT)}:{node.lineno}: {ast.unparse(node)}")
    return found


def test_the_scan_finds_both_kinds_of_use(tmp_path, monkeypatch):
    bad = REPO_ROOT / "tests" / "_private_probe_for_the_scan.py"
    try:
        bad.write_text("from solver.sketch.sticking import _hidden\nfrom solver.sketch import sticking as st\nst._geo\n")
        uses = private_uses(bad)
    finally:
        bad.unlink()
    assert len(uses) == 2 and "import _hidden" in uses[0] and "st._geo" in uses[1]


@pytest.mark.slow
@pytest.mark.parametrize("package", PROJECT)
def test_no_private_name_is_used_across_modules(package):
    offenders = [use for path in sorted((REPO_ROOT / package).rglob("*.py")) for use in private_uses(path)]
    assert not offenders, "private names used across modules:\n" + "\n".join(offenders)
