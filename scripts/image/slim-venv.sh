#!/bin/bash
# Slim the service's virtual environment for the image (Dockerfile, builder stage).
#   bash scripts/image/slim-venv.sh VENV APP_SOURCE_DIR
# Removes what the service never loads; each step says why it is safe. SLIM_STEPS
# (default: all) picks the steps, for measuring them one by one.
# Not removed: pandas (the service never uses it, but ortools.sat.python.cp_model imports
# it at import time), fontTools (matplotlib imports it), the wheels' bundled OpenBLAS copies
# (numpy's ILP64 and scipy's LP64 builds are different libraries).
set -euo pipefail
VENV=${1:?venv}; APP=${2:?app source}
SP=$(echo "$VENV"/lib/python3.*/site-packages)
STEPS=${SLIM_STEPS:-tests pip scs_mkl casadi ortools pillow scs build_files sparsediffpy mpl_data ray pyc strip}
has() { case " $STEPS " in *" $1 "*) return 0;; esac; return 1; }
size() { echo "slim-venv: after $1: $(du -sm "$VENV" | cut -f1) MB"; }
size start

# test suites of the packages: nothing outside a tests/ folder imports one
if has tests; then
  find "$SP" -depth -type d -name tests -prune -exec rm -rf {} +
  size tests
fi

# pip, setuptools (with pkg_resources and its distutils-precedence.pth): install tools only
if has pip; then
  "$VENV"/bin/python -m pip uninstall --quiet --yes setuptools wheel pip 2>/dev/null \
    || "$VENV"/bin/python -m pip uninstall --quiet --yes setuptools pip
  size pip
fi

# SCS's MKL build (107 MB, MKL linked in): the service never calls SCS (Clarabel only);
# without it SCS's default linear solver is its bundled QDLDL (scs._resolve_auto)
if has scs_mkl; then
  rm -f "$SP"/scs/_scs_mkl*.so
  size scs_mkl
fi

# CasADi: the service uses nlpsol "ipopt" only (never the HiGHS plugin, whose library
# clashes with OR-Tools'). Keep the extension, the IPOPT plugin and the shared libraries
# they load (ldd, under the names they are loaded by), drop every other plugin, its
# libraries, the duplicate copies of each library (wheels cannot hold symlinks) and the
# C++ headers, CMake and pkg-config files and static libraries.
if has casadi; then
  (
    cd "$SP"/casadi
    keep=" _casadi.so libcasadi_nlpsol_ipopt.so "
    keep+=$(ldd _casadi.so libcasadi_nlpsol_ipopt.so | awk '$3 ~ /\/casadi\// {printf "%s ", $1}')
    for f in *.so *.so.* *.a; do
      [ -e "$f" ] || continue
      case "$keep" in *" $f "*) ;; *) rm -f "$f" ;; esac
    done
    rm -rf include cmake pkgconfig
    # what was kept must still resolve
    ! ldd _casadi.so libcasadi_nlpsol_ipopt.so | grep -q 'not found'
  )
  size casadi
fi

# OR-Tools: the service uses CP-SAT (ortools.sat) and min cost flow (ortools.graph) only;
# they import ortools.sat and ortools.util and nothing else of the package. The shared
# libraries (.libs) stay whole: libortools.so needs all of them.
if has ortools; then
  for d in "$SP"/ortools/*/; do
    case "$(basename "$d")" in graph|sat|util|__pycache__) ;; *) rm -rf "$d" ;; esac
  done
  size ortools
fi

# Pillow's AVIF and WebP codecs (optional plugins: PIL imports them in try/except);
# matplotlib only hands PIL PNG, and the service draws SVG
if has pillow; then
  rm -f "$SP"/PIL/_avif.*.so "$SP"/PIL/_webp.*.so "$SP"/pillow.libs/libavif-* "$SP"/pillow.libs/libwebp* \
    "$SP"/pillow.libs/libsharpyuv-*
  size pillow
fi

# SCS: no code of the service calls it (every cvxpy solve names CLARABEL); cvxpy lists the
# solvers it finds and goes on without it. Its OpenBLAS alone is 37 MB.
if has scs; then
  rm -rf "$SP"/scs "$SP"/scs.libs "$SP"/scs-*.dist-info "$SP"/_scs_*
  size scs
fi

# build-time only: C headers, static libraries, Cython and C sources, type stubs
if has build_files; then
  find "$SP" -type d -name include -prune -path '*/numpy/_core/include' -exec rm -rf {} +
  find "$SP" -type f \( -name '*.a' -o -name '*.pyi' -o -name '*.pxd' -o -name '*.pyx' -o -name '*.c' \
    -o -name '*.h' -o -name '*.hpp' -o -name '*.cpp' \) -delete
  size build_files
fi

# sparsediffpy: cvxpy's NLP differentiation engine (cvxpy/reductions/solvers/nlp_solvers/
# diff_engine only), with a 37 MB OpenBLAS of its own; the service solves cones only
if has sparsediffpy; then
  rm -rf "$SP"/sparsediffpy "$SP"/sparsediffpy.libs "$SP"/sparsediffpy-*.dist-info
  size sparsediffpy
fi

# matplotlib's sample data (its examples' files, cbook.get_sample_data only)
if has mpl_data; then
  rm -rf "$SP"/matplotlib/mpl-data/sample_data
  size mpl_data
fi

# Ray: the catalogues run Ray core only (solver/core/parallel.py: ray.init, remote tasks,
# wait, cancel). Its Java jars, its libraries (RLlib, Data, Serve, Tune, Train, LLM,
# workflows) and the dashboard's web client are not imported by the core; ray/widgets stays
# (import ray needs it). Checked: a local Ray and a two-node cluster run tasks without them.
# WITH_RAY=false (the image's build argument): no Ray at all; the catalogues then run their
# designs one after the other (solver/core/parallel.py finds no Ray).
if has ray; then
  if [ "${WITH_RAY:-true}" = false ]; then
    rm -rf "$SP"/ray "$SP"/ray-*.dist-info "$VENV"/bin/ray "$VENV"/bin/serve "$VENV"/bin/tune
  else
    for d in jars rllib data serve tune train llm workflow dashboard/client/build; do rm -rf "$SP/ray/$d"; done
    find "$SP"/ray -name '*.js.map' -delete
    # its two daemons are executables, not *.so: the strip step below would miss them
    strip --strip-unneeded "$SP"/ray/core/src/ray/gcs/gcs_server "$SP"/ray/core/src/ray/raylet/raylet
  fi
  size ray
fi

# bytecode: pip compiled every module; keep the .pyc of the modules the service imports
# (scripts/image/pyc_keep.py, which also runs a small solve with each back end: a step
# above that broke one fails here), drop the rest (the .py files stay: a module not kept is
# compiled in memory when something imports it). The kept ones are compiled again as
# unchecked-hash pycs: pip's are checked against the source's mtime in seconds, and
# `podman build --layers=false` rounds the mtimes of the copied venv (about half of the
# pycs were stale, and the start took 60 % more CPU); the image's files never change.
if has pyc; then
  keep=$(mktemp)
  (cd "$APP" && "$VENV"/bin/python -c 'import runpy, sys; sys.path.insert(0, "."); runpy.run_path(sys.argv[1], run_name="__main__")' \
      "$APP"/scripts/image/pyc_keep.py) > "$keep"
  find "$SP" -name '*.pyc' -delete
  find "$SP" -depth -type d -name __pycache__ -empty -delete
  "$VENV"/bin/python - "$keep" "$SP" <<'PY'
import py_compile, sys
sp, n = sys.argv[2] + "/", 0
for path in sorted({line.strip() for line in open(sys.argv[1])}):
    if path.startswith(sp):
        py_compile.compile(path, doraise=True, invalidation_mode=py_compile.PycInvalidationMode.UNCHECKED_HASH)
        n += 1
print(f"slim-venv: kept the bytecode of {n} modules (unchecked-hash)")
PY
  rm -f "$keep"
  size pyc
fi

# debug symbols and symbol tables not needed for dynamic linking; not the libraries
# auditwheel grafted into the wheels (NAME.libs/ folders, NAME-<8 hex>.so names: patchelf
# rewrote them, and strip can corrupt such files). A missing strip fails the build.
if has strip; then
  find "$SP" -regextype posix-extended \( -regex '.*/[^/]+\.libs/.*' -o -regex '.*-[0-9a-f]{8}\.so[.0-9]*' \) -prune \
    -o -type f -name '*.so*' -print0 | xargs -0 -r strip --strip-unneeded
  size strip
fi
