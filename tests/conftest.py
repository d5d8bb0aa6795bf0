"""Project-wide pytest configuration.

Keep this file generic: it is shared by every test package.  Add new
sections below with a clear header comment; put fixtures that belong to
one layer in that layer's own ``tests/<layer>/conftest.py`` instead.
"""

from __future__ import annotations

import os

import pytest

# ---------------------------------------------------------------------------
# The service in tests: expensive jobs run in the test process's threads
# (PESHKIN_SOLVER_WORKERS=0), so that a test can replace a budget or a solver
# with monkeypatch. tests/service/runtime/ builds apps with solver worker
# processes and checks that every route answers the same there; servers
# started as subprocesses set their own environment.
# ---------------------------------------------------------------------------
os.environ.setdefault("PESHKIN_SOLVER_WORKERS", "0")
# No result store unless a test makes one: every test computes what it checks.
os.environ.setdefault("PESHKIN_STORE_PATH", "")
os.environ.setdefault("PESHKIN_JOBS_PATH", "")  # a jobs file of each app's own, never a server's
# Feeder catalogues one design after the other in the test process (no Ray), unless a
# test asks for Ray itself (tests/solver/core/test_parallel.py, the catalogue's live test).
os.environ.setdefault("PESHKIN_RAY_WORKERS", "0")

# ---------------------------------------------------------------------------
# Benchmarks: tests marked ``@pytest.mark.benchmark`` are skipped unless the
# run asks for them with ``--run-benchmarks`` or ``RUN_BENCHMARKS=1``.
# (The marker itself is declared in pyproject.toml; it is registered here
# too so the suite also works when pytest is pointed at another config.)
# ---------------------------------------------------------------------------

_TRUTHY = {"1", "true", "yes", "on"}


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption(
        "--run-benchmarks",
        action="store_true",
        default=False,
        help="run tests marked 'benchmark' (also enabled by RUN_BENCHMARKS=1)",
    )


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line(
        "markers",
        "benchmark: slow performance benchmark; skipped unless --run-benchmarks "
        "or RUN_BENCHMARKS=1",
    )
    config.addinivalue_line(
        "markers",
        "slow: more than about half a second; left out of the fast tier (bash scripts/test.sh --fast)",
    )


def benchmarks_enabled(config: pytest.Config) -> bool:
    """True when benchmark-marked tests should run."""
    if config.getoption("--run-benchmarks"):
        return True
    return os.environ.get("RUN_BENCHMARKS", "").strip().lower() in _TRUTHY


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    if benchmarks_enabled(config):
        return
    skip = pytest.mark.skip(reason="benchmark: use --run-benchmarks or RUN_BENCHMARKS=1")
    for item in items:
        if item.get_closest_marker("benchmark") is not None:
            item.add_marker(skip)


# ---------------------------------------------------------------------------
# Shared fixtures: add generic, cross-layer fixtures below this line.
# ---------------------------------------------------------------------------
