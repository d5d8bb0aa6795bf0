#!/usr/bin/env bash
# Run the test suite.
#
#   bash scripts/test.sh                      # whole suite (benchmarks skipped)
#   bash scripts/test.sh tests/models -k disk # extra args go to pytest
#   bash scripts/test.sh --run-benchmarks     # include benchmark-marked tests
#
# Creates ./.venv with Python 3.11 if it is missing, installs the pinned
# dev dependencies (skipped when the requirement files are unchanged since
# the last install), then runs `python -m pytest -q`.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

VENV="${VENV:-.venv}"

die() { echo "test.sh: $*" >&2; exit 1; }

find_python() {
    local candidate
    for candidate in "${PYTHON:-}" python3.11 python3; do
        [[ -n "$candidate" ]] || continue
        if command -v "$candidate" >/dev/null 2>&1 &&
            "$candidate" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))' 2>/dev/null; then
            echo "$candidate"
            return 0
        fi
    done
    return 1
}

if [[ ! -x "$VENV/bin/python" ]]; then
    py="$(find_python)" || die "Python 3.11 not found (set PYTHON=/path/to/python3.11)"
    echo "test.sh: creating $VENV with $py" >&2
    "$py" -m venv "$VENV"
fi
"$VENV/bin/python" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))' ||
    die "$VENV is not a Python 3.11 venv; remove it and rerun"

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

exec "$VENV/bin/python" -m pytest -q "$@"
