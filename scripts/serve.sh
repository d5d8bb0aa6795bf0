#!/usr/bin/env bash
# Run the planning service locally.
#
#   bash scripts/serve.sh            # http://127.0.0.1:8000  (docs at /docs)
#   HOST=0.0.0.0 PORT=9000 bash scripts/serve.sh
#   PESHKIN_WEB_WORKERS=4 PESHKIN_SOLVER_WORKERS=2 bash scripts/serve.sh
#
# Creates ./.venv with Python 3.11 if it is missing, installs the pinned
# runtime dependencies (skipped when requirements.txt is unchanged since the
# last install), then starts the server: gunicorn supervising uvicorn web
# processes, each with its solver worker processes (service/server.py; every
# PESHKIN_* setting is listed in service/settings.py).
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

SCRIPT=serve.sh
# shellcheck source=scripts/_venv.sh
source scripts/_venv.sh

# Install only when the requirement files changed since the last successful
# install (pip itself is idempotent, this just keeps restarts instant).
stamp="$VENV/.requirements-runtime.sha256"
want="$(sha256sum <requirements.txt | cut -d' ' -f1)"
if [[ "$(cat "$stamp" 2>/dev/null || true)" != "$want" ]]; then
    echo "serve.sh: installing runtime dependencies into $VENV" >&2
    "$VENV/bin/python" -m pip install --quiet --disable-pip-version-check --upgrade pip
    "$VENV/bin/python" -m pip install --quiet --disable-pip-version-check -r requirements.txt
    echo "$want" >"$stamp"
fi

warm_kernels

export PESHKIN_HOST="${HOST:-${PESHKIN_HOST:-127.0.0.1}}"
export PESHKIN_PORT="${PORT:-${PESHKIN_PORT:-8000}}"
exec "$VENV/bin/python" -m service
