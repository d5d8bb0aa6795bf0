#!/usr/bin/env bash
# Run the planning service locally.
#
#   bash scripts/serve.sh            # http://127.0.0.1:8000  (docs at /docs)
#   HOST=0.0.0.0 PORT=9000 bash scripts/serve.sh
#
# Creates ./.venv with Python 3.11 if it is missing, installs the pinned
# runtime dependencies (skipped when requirements.txt is unchanged since the
# last install), then starts uvicorn.  Extra arguments go to uvicorn.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

VENV="${VENV:-.venv}"
REQUIREMENTS=(requirements.txt)

die() { echo "serve.sh: $*" >&2; exit 1; }

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
    echo "serve.sh: creating $VENV with $py" >&2
    "$py" -m venv "$VENV"
fi
"$VENV/bin/python" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))' ||
    die "$VENV is not a Python 3.11 venv; remove it and rerun"

# Install only when the requirement files changed since the last successful
# install (pip itself is idempotent, this just keeps restarts instant).
stamp="$VENV/.requirements-runtime.sha256"
want="$(cat "${REQUIREMENTS[@]}" | sha256sum | cut -d' ' -f1)"
if [[ "$(cat "$stamp" 2>/dev/null || true)" != "$want" ]]; then
    echo "serve.sh: installing runtime dependencies into $VENV" >&2
    "$VENV/bin/python" -m pip install --quiet --disable-pip-version-check --upgrade pip
    "$VENV/bin/python" -m pip install --quiet --disable-pip-version-check -r requirements.txt
    echo "$want" >"$stamp"
fi

exec "$VENV/bin/python" -m uvicorn service.app:app \
    --host "${HOST:-127.0.0.1}" --port "${PORT:-8000}" "$@"
