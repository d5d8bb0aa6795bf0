"""The map of the code in docs/architecture.md is the code: its tree is what ``ls`` shows,
its capability table names every package of every layer, the tests mirror the source
folders, and every source path the docs and the README name exists."""

from __future__ import annotations

import re
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[1]
ARCHITECTURE = REPO_ROOT / "docs" / "architecture.md"
LAYERS = ("models", "solver", "service")


def _section(text: str, heading: str) -> str:
    start = text.index(f"## {heading}")
    end = text.find("\n## ", start + 1)
    return text[start:] if end < 0 else text[start:end]


def _documented_tree() -> dict[str, set[str]]:
    """{folder: modules} from the code block under "The tree": a line is a folder (indent
    of two spaces per level) followed by its modules; '#' starts a comment."""
    block = _section(ARCHITECTURE.read_text(encoding="utf-8"), "The tree").split("```")[1]
    tree: dict[str, set[str]] = {}
    stack: list[str] = []
    for line in block.strip("\n").splitlines():
        body = line.split("#", 1)[0]
        if not body.strip():
            continue
        depth = (len(body) - len(body.lstrip(" "))) // 2
        folder, *modules = body.split()
        assert folder.endswith("/"), f"not a folder: {line!r}"
        stack[depth:] = [folder.rstrip("/")]
        tree["/".join(stack)] = set(modules)
    return tree


def _actual_tree() -> dict[str, set[str]]:
    tree = {}
    for layer in LAYERS:
        for init in sorted((REPO_ROOT / layer).rglob("__init__.py")):
            folder = init.parent
            tree[folder.relative_to(REPO_ROOT).as_posix()] = {
                p.stem for p in folder.glob("*.py") if p.name != "__init__.py"
            }
    return tree


def test_the_tree_in_the_architecture_is_what_ls_shows():
    documented, actual = _documented_tree(), _actual_tree()
    assert sorted(documented) == sorted(actual), "folders differ: update the tree in docs/architecture.md"
    for folder, modules in actual.items():
        assert documented[folder] == modules, f"{folder}/: documented {sorted(documented[folder])}, is {sorted(modules)}"


def test_the_capability_table_names_every_package_of_every_layer():
    table = _section(ARCHITECTURE.read_text(encoding="utf-8"), "The map")
    rows = [[cell.strip() for cell in line.strip().strip("|").split("|")]
            for line in table.splitlines() if line.startswith("|")]
    header, rows = rows[0], rows[2:]
    columns = {"models": header.index("`models/` (pure mechanics)"),
               "solver": header.index("`solver/` (optimisation, simulation)"),
               "service/api": header.index("`service/api/` (HTTP)")}
    for layer, column in columns.items():
        named = {name for row in rows for name in re.findall(r"`([a-z_]+)/`", row[column])}
        folders = {p.name for p in (REPO_ROOT / layer).iterdir() if (p / "__init__.py").is_file()}
        assert named == folders, f"{layer}: the table names {sorted(named)}, the folders are {sorted(folders)}"
    capabilities = [row[0] for row in rows]
    for name in (p.name for p in (REPO_ROOT / "service" / "api").iterdir() if (p / "__init__.py").is_file()):
        assert name in capabilities, f"the resource {name} has no row"


def test_the_tests_mirror_the_source_folders():
    stale = []
    for layer in ("models", "solver", "service"):
        for init in (REPO_ROOT / "tests" / layer).rglob("__init__.py"):
            rel = init.parent.relative_to(REPO_ROOT / "tests")
            if rel.parts[:2] == ("service", "runtime") or rel.parts == ("service",):
                continue
            if not (REPO_ROOT / rel).is_dir():
                stale.append(f"tests/{rel.as_posix()}")
    assert not stale, f"test folders with no source folder: {stale}"


PATH = re.compile(r"(?<![\w./-])((?:models|solver|service|tests|scripts)/[\w./-]*[\w/])")


def test_every_source_path_the_docs_name_exists():
    missing = []
    for doc in [REPO_ROOT / "README.md", *sorted((REPO_ROOT / "docs").glob("*.md"))]:
        for n, line in enumerate(doc.read_text(encoding="utf-8").splitlines(), 1):
            for path in PATH.findall(line):
                if not (REPO_ROOT / path.rstrip(".")).exists():
                    missing.append(f"{doc.name}:{n}: {path}")
    assert not missing, "the docs name paths that do not exist:\n" + "\n".join(missing)
