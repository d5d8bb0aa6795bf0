"""Compiled kernels (numba): the per-problem loops the solver runs millions of times, written
as plain loops over floats and compiled to machine code (issue 36). Each kernel has a
reference in numpy elsewhere in the solver (or in models) that its tests compare it with.

Compiled code is kept on disk by numba's cache, so that no request pays for a compile:

* in a checkout or a venv, next to the sources (``solver/kernels/__pycache__``), written by
  ``python -m solver.kernels`` (scripts/serve.sh and scripts/test.sh run it after an
  install; it loads or compiles every kernel and says which);
* where that folder is read-only (the image: /app belongs to root, the service runs as
  another user), the files found there are copied once into a writable folder of the
  temporary directory and numba is pointed at it (:func:`prepare_cache`): numba refuses
  to read a cache folder it cannot write, and needs none once everything it needs is there.

The cache is keyed by the sources' contents and the CPU: ``NUMBA_CPU_NAME=generic`` (set in
the image) makes it valid on any x86_64 machine. Every entry point has explicit signatures:
it is compiled (or loaded) when its module is imported, never at a first call with
unforeseen argument types. Kernels hold no state and release nothing shared: they are
safe to call from many threads.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
CACHE_FILES = ("*.nbi", "*.nbc")
"""numba's cache: an index per function (.nbi) and its compiled code (.nbc)."""


def _writable(folder: Path) -> bool:
    try:
        folder.mkdir(exist_ok=True)
        with tempfile.TemporaryFile(dir=folder):
            return True
    except OSError:
        return False


def _stamp(path: Path) -> tuple[int, int] | None:
    try:
        st = path.stat()
    except OSError:
        return None
    return st.st_size, st.st_mtime_ns


def prepare_cache() -> Path | None:
    """Where numba keeps this package's compiled code: None for its default (next to the
    sources), or the writable copy made when that folder is read-only (module docstring).
    Called before the kernels are imported; a cache folder set by NUMBA_CACHE_DIR is
    kept."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return Path(os.environ["NUMBA_CACHE_DIR"])
    in_tree = HERE / "__pycache__"
    if _writable(in_tree):
        return None
    from numba.core import config
    from numba.core.caching import UserProvidedCacheLocator

    root = Path(tempfile.gettempdir()) / f"peshkin-kernels-{os.getuid()}"
    target = root / UserProvidedCacheLocator.get_suitable_cache_subpath(str(HERE / "__init__.py"))
    target.mkdir(parents=True, exist_ok=True)
    for pattern in CACHE_FILES:
        for src in in_tree.glob(pattern):
            dst = target / src.name
            if _stamp(dst) != _stamp(src):  # copied whole under another name, then renamed: another process may read it
                part = dst.with_name(f".{dst.name}.{os.getpid()}")
                shutil.copy2(src, part)
                os.replace(part, dst)
    os.environ["NUMBA_CACHE_DIR"] = str(root)
    config.CACHE_DIR = str(root)
    return root


CACHE_DIR = prepare_cache()


KERNEL_MODULES = ("solver.kernels.forward", "solver.kernels.fence")
"""Every module of compiled kernels (imported by :func:`compiled`)."""


def compiled() -> tuple[int, int]:
    """Import every kernel module (each entry point, listed in its ``ENTRY_POINTS``, is
    compiled or loaded from the cache on import) and count the entry points' signatures
    loaded from the cache and those compiled."""
    import importlib

    loaded = built = 0
    for name in KERNEL_MODULES:
        module = importlib.import_module(name)
        for entry in module.ENTRY_POINTS:
            stats = getattr(module, entry).stats
            loaded += sum(stats.cache_hits.values())
            built += sum(stats.cache_misses.values())
    return loaded, built
