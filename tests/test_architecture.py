"""Architecture checks: the one-way layering service -> solver -> models, and the
resources of service/api independent of each other.

The contracts live in pyproject.toml under [tool.importlinter]; these tests
run import-linter on the real code base (in a fresh interpreter) and also
prove, on a throw-away fixture project, that the contracts actually bite.
"""

from __future__ import annotations

import ast
import shutil
import subprocess
import sys
import textwrap
import tomllib
from pathlib import Path

import pytest

REPO_ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = REPO_ROOT / "pyproject.toml"

_LINT = textwrap.dedent(
    """
    import sys
    from importlinter.cli import lint_imports
    sys.exit(lint_imports(config_filename="pyproject.toml", no_cache=True, no_logo=True))
    """
)


def _importlinter_config() -> dict:
    with PYPROJECT.open("rb") as fh:
        return tomllib.load(fh)["tool"]["importlinter"]


def _run_lint_imports(cwd: Path) -> subprocess.CompletedProcess[str]:
    # A fresh interpreter, so nothing imported by the test session leaks into
    # the graph, and cwd is what import-linter puts on sys.path.
    return subprocess.run(
        [sys.executable, "-c", _LINT],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=300,
    )


def _stage_copy(dest: Path, root_packages: list[str]) -> None:
    """Copy pyproject + existing packages into dest; stub the missing ones."""
    shutil.copy2(PYPROJECT, dest / "pyproject.toml")
    for pkg in root_packages:
        src = REPO_ROOT / pkg
        if (src / "__init__.py").is_file():
            shutil.copytree(src, dest / pkg, ignore=shutil.ignore_patterns("__pycache__"))
        else:
            (dest / pkg).mkdir()
            (dest / pkg / "__init__.py").write_text("")


# ---------------------------------------------------------------------------
# The configuration itself
# ---------------------------------------------------------------------------


def test_config_has_contracts() -> None:
    contracts = _importlinter_config().get("contracts", [])
    assert len(contracts) > 0, "import-linter configuration has zero contracts"


def test_config_declares_expected_contracts() -> None:
    cfg = _importlinter_config()
    assert cfg["root_packages"] == ["models", "solver", "service"]
    by_id = {c["id"]: c for c in cfg["contracts"]}

    assert by_id["layers"]["type"] == "layers"
    assert by_id["layers"]["layers"] == ["service", "solver", "models"]

    models = by_id["models-pure"]
    assert models["type"] == "forbidden" and models["source_modules"] == ["models"]
    assert set(models["forbidden_modules"]) >= {
        "cvxpy", "casadi", "ortools", "scipy", "fastapi",
        "pydantic", "starlette", "matplotlib", "uvicorn",
    }

    inside_models = by_id["models-layers"]
    assert inside_models["type"] == "layers" and inside_models["containers"] == ["models"]
    assert inside_models["exhaustive"]
    folders = sorted(p.name for p in (REPO_ROOT / "models").iterdir() if (p / "__init__.py").is_file())
    assert sorted(name.strip() for layer in inside_models["layers"] for name in layer.split("|")) == folders

    solver = by_id["solver-no-web"]
    assert solver["type"] == "forbidden" and solver["source_modules"] == ["solver"]
    assert set(solver["forbidden_modules"]) >= {
        "fastapi", "pydantic", "starlette", "uvicorn", "matplotlib", "service",
    }

    inside = by_id["solver-layers"]
    assert inside["type"] == "layers" and inside["containers"] == ["solver"] and inside["exhaustive"]
    capabilities = sorted(p.name for p in (REPO_ROOT / "solver").iterdir() if (p / "__init__.py").is_file())
    named = sorted(name.strip() for layer in inside["layers"] for name in layer.split("|"))
    assert named == capabilities

    public = by_id["solver-public"]
    assert public["type"] == "protected" and public["allowed_importers"] == ["solver"]
    assert sorted(public["protected_modules"]) == [f"solver.{name}" for name in capabilities]

    below = by_id["service-runtime-below-api"]
    assert below["type"] == "forbidden" and set(below["source_modules"]) == {"service.runtime", "service.common"}
    assert set(below["forbidden_modules"]) >= {"service.api", "service.app"}

    api = by_id["api-independent"]
    assert api["type"] == "independence"
    resources = sorted(p.name for p in (REPO_ROOT / "service" / "api").iterdir() if (p / "__init__.py").is_file())
    assert resources, "service/api holds no resource packages"
    assert sorted(api["modules"]) == [f"service.api.{name}" for name in resources]


# ---------------------------------------------------------------------------
# The real code base keeps every contract
# ---------------------------------------------------------------------------


def test_import_contracts_kept(tmp_path: Path) -> None:
    root_packages = _importlinter_config()["root_packages"]
    missing = [p for p in root_packages if not (REPO_ROOT / p / "__init__.py").is_file()]
    if missing:
        # Early in the project a layer may not exist yet: lint a copy with
        # empty stand-ins, never touching the real tree.
        _stage_copy(tmp_path, root_packages)
        cwd = tmp_path
    else:
        cwd = REPO_ROOT
    result = _run_lint_imports(cwd)
    report = result.stdout + result.stderr
    assert result.returncode == 0, f"import-linter contracts broken:\n{report}"
    n = len(_importlinter_config()["contracts"])
    assert f"Contracts: {n} kept, 0 broken." in report, report


def _is_allowed_in_models(top: str) -> bool:
    return top in sys.stdlib_module_names or top in {"numpy", "models", "__future__"}


def test_models_imports_only_numpy_and_stdlib() -> None:
    """models/ is pure mechanics: numpy and the standard library only."""
    models_dir = REPO_ROOT / "models"
    if not models_dir.is_dir():
        pytest.skip("models/ does not exist yet")
    offenders: list[str] = []
    for path in sorted(models_dir.rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                tops = [alias.name.split(".")[0] for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                tops = [node.module.split(".")[0]]
            else:
                continue
            for top in tops:
                if not _is_allowed_in_models(top):
                    rel = path.relative_to(REPO_ROOT)
                    offenders.append(f"{rel}:{node.lineno}: imports {top}")
    assert not offenders, "models/ may import only numpy + stdlib:\n" + "\n".join(offenders)


# ---------------------------------------------------------------------------
# The contracts are not vacuous: deliberate violations are caught
# ---------------------------------------------------------------------------

_VIOLATIONS = {
    "solver-core-imports-certify": ("solver/core/bad.py", "import solver.certify\n", "Inside solver"),
    "solver-locus-imports-spiral": ("solver/locus/bad.py", "import solver.spiral\n", "Inside solver"),
    "solver-push-imports-spiral": ("solver/push/bad.py", "import solver.spiral\n", "Inside solver"),
    "models-core-imports-feeder": ("models/core/bad.py", "import models.feeder\n", "Inside models"),
    "models-locus-imports-sketch": ("models/locus/bad.py", "import models.sketch\n", "Inside models"),
    "models-push-imports-spiral": ("models/push/bad.py", "import models.spiral\n", "Inside models"),
    "service-imports-a-solver-module": ("service/bad.py", "import solver.locus\n", "Outside solver"),
    "runtime-imports-a-resource": ("service/runtime/bad.py", "import service.api.locus\n", "service runtime and common"),
    "common-imports-the-app": ("service/common/bad.py", "import service.app\n", "service runtime and common"),
    "api-resource-imports-another": ("service/api/sketch/bad.py", "import service.api.locus\n", "service/api resources"),
    "models-imports-solver": ("models/bad.py", "import solver\n", "Layers"),
    "solver-imports-service": ("solver/bad.py", "import service\n", "Layers"),
    "models-imports-scipy": ("models/bad.py", "import scipy\n", "models is pure"),
    "models-imports-cvxpy": ("models/bad.py", "import cvxpy\n", "models is pure"),
    "solver-imports-fastapi": ("solver/bad.py", "from fastapi import FastAPI\n", "solver knows"),
    "solver-imports-pydantic": ("solver/bad.py", "import pydantic\n", "solver knows"),
}


@pytest.mark.parametrize("case", sorted(_VIOLATIONS))
def test_contracts_catch_violations(tmp_path: Path, case: str) -> None:
    rel, source, contract_name = _VIOLATIONS[case]
    cfg = _importlinter_config()
    packages = list(cfg["root_packages"])
    for contract in cfg["contracts"]:  # the modules contracts name must exist
        if contract["type"] == "independence":
            packages += [m.replace(".", "/") for m in contract["modules"]]
        elif contract["type"] == "protected":
            packages += [m.replace(".", "/") for m in contract["protected_modules"]]
        elif contract["type"] == "forbidden":
            packages += [m.replace(".", "/") for m in (*contract["source_modules"], *contract["forbidden_modules"])
                         if m.split(".")[0] in cfg["root_packages"]]
        elif contract.get("containers"):
            for container in contract["containers"]:
                for layer in contract["layers"]:
                    packages += [f"{container}/{name.strip()}".replace(".", "/") for name in layer.split("|")]
    for pkg in packages:
        (tmp_path / pkg).mkdir(parents=True, exist_ok=True)
        for parent in [tmp_path / pkg, *(tmp_path / pkg).parents]:
            if parent == tmp_path:
                break
            (parent / "__init__.py").touch()
    shutil.copy2(PYPROJECT, tmp_path / "pyproject.toml")
    (tmp_path / rel).write_text(source)

    result = _run_lint_imports(tmp_path)
    report = result.stdout + result.stderr
    assert result.returncode != 0, f"violation {case!r} was not detected:\n{report}"
    broken = [line for line in report.splitlines() if line.rstrip().endswith("BROKEN")]
    assert any(line.startswith(contract_name) for line in broken), report
