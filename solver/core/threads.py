"""What lets solves run on many threads at once (a web server's worker threads).

* Compiled solver objects are kept per thread (:class:`PerThreadCache`). A compiled cvxpy
  problem (its Parameters are set, then it is solved) and a CasADi ``nlpsol`` Function
  (it keeps its working memory and the ``stats()`` of its last call) must never be used by
  two threads at once: two threads sharing one cvxpy problem overwrite each other's
  parameter values and Clarabel refuses the second call ("Already mutably borrowed"); two
  threads sharing one IPOPT Function crash the process. Each thread builds and re-uses its
  own objects, and a thread's objects are freed when it ends. IPOPT (3.14, bundled with
  CasADi) serialises its calls into MUMPS with a process-wide mutex of its own, so
  separate Functions are called with no lock of ours.
* CasADi's symbolic core is not thread-safe, and its Python calls release the
  interpreter's lock: building SX expressions on two threads at once crashes the process
  (the reference counts of shared nodes; 16 threads building small expressions for 3 s
  crashed 2 runs of 3). Every CasADi Function is built and freed under one process-wide
  lock (:class:`CasadiFunction`); only its numeric calls run unlocked.
* Warnings are filtered process-wide, never with ``warnings.catch_warnings`` around a
  solve: that context manager swaps the process-wide filter list and is not thread-safe
  before Python 3.14 (concurrent solves left a blanket "ignore UserWarning" behind).
  :func:`ignore_inaccurate_solution_warning` silences the one warning the conic solves
  expect, cvxpy's "Solution may be inaccurate" (the callers check the status themselves).
"""

from __future__ import annotations

import re
import threading
import warnings
from collections.abc import Callable, Hashable
from typing import Any, Generic, TypeVar

K = TypeVar("K", bound=Hashable)
V = TypeVar("V")


class PerThreadCache(Generic[K, V]):
    """Objects built on first use by ``build`` and kept per (thread, key).

    ``max_entries`` (None: unbounded) caps the entries of one thread; beyond it the
    oldest entry is dropped (keys such as support sizes are chosen by clients)."""

    def __init__(self, max_entries: int | None = None) -> None:
        if max_entries is not None and max_entries < 1:
            raise ValueError("max_entries must be at least 1")
        self.max_entries = max_entries
        self._local = threading.local()

    def _entries(self) -> dict[K, V]:
        entries: dict[K, V] | None = getattr(self._local, "entries", None)
        if entries is None:
            entries = {}
            self._local.entries = entries
        return entries

    def get(self, key: K, build: Callable[[], V]) -> V:
        """This thread's object for ``key``, built by ``build()`` if it has none yet."""
        entries = self._entries()
        if key in entries:
            return entries[key]
        value = build()
        if self.max_entries is not None and len(entries) >= self.max_entries:
            entries.pop(next(iter(entries)))
        entries[key] = value
        return value

    def __len__(self) -> int:
        """Entries held by the calling thread."""
        return len(self._entries())


CASADI_LOCK = threading.RLock()
"""Held while CasADi builds or frees symbolic expressions and Functions (module docstring)."""


class CasadiFunction:
    """A CasADi Function (an ``nlpsol``, say) made by ``build()`` under :data:`CASADI_LOCK`
    (every SX expression ``build`` makes is made and freed there) and freed under it; called
    without it. Like the Function itself, it must not be called by two threads at once."""

    __slots__ = ("_fn",)

    def __init__(self, build: Callable[[], Any]) -> None:
        with CASADI_LOCK:
            self._fn: Any = build()

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        return self._fn(*args, **kwargs)

    def stats(self) -> dict[str, Any]:
        """The Function's statistics of its last call (IPOPT's status, iterations)."""
        return dict(self._fn.stats())

    def __del__(self) -> None:
        fn = getattr(self, "_fn", None)
        if fn is None:
            return
        with CASADI_LOCK:
            self._fn = None
            del fn  # the last reference: CasADi frees the Function's expressions here


INACCURATE_SOLUTION_WARNING = "Solution may be inaccurate"
"""The start of cvxpy's UserWarning for the status OPTIMAL_INACCURATE."""

_FILTER_LOCK = threading.Lock()


def ignore_inaccurate_solution_warning() -> None:
    """Silence cvxpy's "Solution may be inaccurate" UserWarning process-wide (idempotent;
    call it before a solve: a test runner may reset the filters between tests)."""
    with _FILTER_LOCK:
        if not any(_is_inaccurate_filter(f) for f in warnings.filters):
            warnings.filterwarnings("ignore", message=INACCURATE_SOLUTION_WARNING, category=UserWarning)


def _is_inaccurate_filter(
    entry: tuple[str, re.Pattern[str] | None, type[Warning] | tuple[type[Warning], ...], re.Pattern[str] | None, int],
) -> bool:
    action, message, category, _, _ = entry
    return action == "ignore" and category is UserWarning and message is not None and message.pattern == INACCURATE_SOLUTION_WARNING
