#!/usr/bin/env bash
# Run the test suite.
#
#   bash scripts/test.sh                      # whole suite (benchmarks skipped), 2 workers: what CI runs
#   bash scripts/test.sh --fast               # everyday tier: no tests marked slow, 2 workers
#   bash scripts/test.sh -n 0 tests/models    # one process (e.g. for pdb)
#   bash scripts/test.sh tests/models -k disk # extra args go to pytest
#   bash scripts/test.sh --run-benchmarks     # include benchmark-marked tests
#
# Creates ./.venv with Python 3.11 if it is missing, installs the pinned
# dev dependencies (skipped when the requirement files are unchanged since
# the last install), then runs `python -m pytest -q -n $PYTEST_WORKERS` (pytest-xdist,
# default 2 workers; later arguments win, so `-n 0` runs in one process).
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

SCRIPT=test.sh
# shellcheck source=scripts/_venv.sh
source scripts/_venv.sh

# Install only when the requirement files changed since the last successful
# install.  The dev set includes the runtime set, so both stamps are written.
dev_stamp="$VENV/.requirements-dev.sha256"
runtime_stamp="$VENV/.requirements-runtime.sha256"
want_dev="$(cat requirements-dev.txt requirements.txt | sha256sum | cut -d' ' -f1)"
if [[ "$(cat "$dev_stamp" 2>/dev/null || true)" != "$want_dev" ]]; then
    echo "test.sh: installing dev dependencies into $VENV" >&2
    "$VENV/bin/python" -m pip install --quiet --disable-pip-version-check --upgrade pip
    "$VENV/bin/python" -m pip install --quiet --disable-pip-version-check -r requirements-dev.txt
    echo "$want_dev" >"$dev_stamp"
    cat requirements.txt | sha256sum | cut -d' ' -f1 >"$runtime_stamp"
fi

warm_kernels

workers="${PYTEST_WORKERS:-2}"
if [[ "${1:-}" == "--fast" ]]; then
    shift
    exec "$VENV/bin/python" -m pytest -q -m "not slow" -n "$workers" "$@"
fi
exec "$VENV/bin/python" -m pytest -q -n "$workers" "$@"
