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
the image) makes it valid on any x86_64 machine. numba keys a function's code by its own
module's source only, while code from another kernel module is compiled into it (the fence
loop calls the forward solve): the whole cache is dropped when any kernel module changes
(:func:`sources_stamp`, kept beside the cache). Every entry point has explicit signatures:
it is compiled (or loaded) when its module is imported, never at a first call with
unforeseen argument types. Kernels hold no state and release nothing shared: they are
safe to call from many threads.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import tempfile
import threading
from pathlib import Path

HERE = Path(__file__).resolve().parent
CACHE_FILES = ("*.nbi", "*.nbc")
"""numba's cache: an index per function (.nbi) and its compiled code (.nbc)."""
STAMP_FILE = "kernels.sources.sha256"
"""Beside the cache: the :func:`sources_stamp` it was compiled from."""


def writable(folder: Path) -> bool:
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


def sources_stamp() -> str:
    """A hash of every kernel module's source: numba keys a function's cached code by its own
    module's source only, so code compiled into it from another kernel module (the fence
    loop calls the forward solve) would go stale unnoticed; the cache is dropped whole when
    this changes."""
    digest = hashlib.sha256()
    for path in sorted(HERE.glob("*.py")):
        digest.update(path.name.encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()


def drop_if_stale(folder: Path) -> None:
    stamp = folder / STAMP_FILE
    want = sources_stamp()
    try:
        if stamp.read_text() == want:
            return
    except OSError:
        pass
    try:
        for pattern in CACHE_FILES:
            for old in folder.glob(pattern):
                old.unlink(missing_ok=True)
        folder.mkdir(parents=True, exist_ok=True)
        stamp.write_text(want)
    except OSError:  # a folder numba cannot write either: it compiles in memory
        pass


def prepare_cache() -> Path | None:
    """Where numba keeps this package's compiled code: None for its default (next to the
    sources), or the writable copy made when that folder is read-only (module docstring).
    Called before the kernels are imported; a cache folder set by NUMBA_CACHE_DIR is
    kept. Compiled code of older sources is dropped (:func:`sources_stamp`)."""
    from numba.core.caching import UserProvidedCacheLocator

    subpath = UserProvidedCacheLocator.get_suitable_cache_subpath(str(HERE / "__init__.py"))
    if os.environ.get("NUMBA_CACHE_DIR"):
        root = Path(os.environ["NUMBA_CACHE_DIR"])
        drop_if_stale(root / subpath)
        return root
    in_tree = HERE / "__pycache__"
    if writable(in_tree):
        drop_if_stale(in_tree)
        return None
    from numba.core import config

    root = Path(tempfile.gettempdir()) / f"peshkin-kernels-{os.getuid()}"
    target = root / subpath
    target.mkdir(parents=True, exist_ok=True)
    for pattern in (*CACHE_FILES, STAMP_FILE):
        for src in in_tree.glob(pattern):
            dst = target / src.name
            if _stamp(dst) != _stamp(src):  # copied whole under another name, then renamed: another process may read it
                part = dst.with_name(f".{dst.name}.{os.getpid()}")
                shutil.copy2(src, part)
                os.replace(part, dst)
    drop_if_stale(target)
    os.environ["NUMBA_CACHE_DIR"] = str(root)
    config.CACHE_DIR = str(root)
    return root


_prepared: list[Path | None] = []
_prepared_lock = threading.Lock()


def ensure_cache() -> Path | None:
    """:func:`prepare_cache`, once per process (each kernel module calls it before it
    compiles or loads anything; importing this package loads no compiler)."""
    with _prepared_lock:
        if not _prepared:
            _prepared.append(prepare_cache())
        return _prepared[0]


KERNEL_MODULES = ("solver.kernels.forward", "solver.kernels.fence", "solver.kernels.disk", "solver.kernels.search")
"""Every module of compiled kernels (imported by :func:`compiled`; preloaded by the
service's solver workers, whose callers import them on first use)."""


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
