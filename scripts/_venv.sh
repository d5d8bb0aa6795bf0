# Sourced by serve.sh and test.sh: make sure ./.venv is a Python 3.11 venv.
# Expects SCRIPT (the caller's name, for messages); sets VENV.

VENV="${VENV:-.venv}"

die() { echo "$SCRIPT: $*" >&2; exit 1; }

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
    echo "$SCRIPT: creating $VENV with $py" >&2
    "$py" -m venv "$VENV"
fi
"$VENV/bin/python" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))' ||
    die "$VENV is not a Python 3.11 venv; remove it and rerun"

# Compile the solver's kernels into numba's cache (solver/kernels/__init__.py) when their
# sources, the installed packages or the cache changed since the last time, so that neither
# a request nor a test pays for a compile.
warm_kernels() {
    local stamp="$VENV/.kernels.sha256" want
    want="$(cat solver/kernels/*.py requirements.txt | sha256sum | cut -d' ' -f1)"
    if [[ "$(cat "$stamp" 2>/dev/null || true)" != "$want" ]] ||
        ! compgen -G "solver/kernels/__pycache__/*.nbi" >/dev/null; then
        echo "$SCRIPT: compiling the solver's kernels (once per change, about a minute)" >&2
        "$VENV/bin/python" -m solver.kernels >&2
        echo "$want" >"$stamp"
    fi
}
