"""Per-thread solver objects and the warning filter (solver/core/threads.py)."""

from __future__ import annotations

import threading
import warnings

import pytest

from solver.core.threads import INACCURATE_SOLUTION_WARNING, PerThreadCache, ignore_inaccurate_solution_warning


def in_other_thread(task):
    out = []
    t = threading.Thread(target=lambda: out.append(task()))
    t.start()
    t.join()
    return out[0]


def test_each_thread_builds_and_keeps_its_own_object():
    cache: PerThreadCache[str, object] = PerThreadCache()
    mine = cache.get("k", object)
    assert cache.get("k", object) is mine
    other = in_other_thread(lambda: cache.get("k", object))
    assert other is not mine and cache.get("k", object) is mine
    assert len(cache) == 1 and in_other_thread(lambda: len(cache)) == 0


def test_the_oldest_entry_is_dropped_beyond_the_cap():
    cache: PerThreadCache[int, object] = PerThreadCache(max_entries=2)
    first = cache.get(1, object)
    cache.get(2, object)
    cache.get(3, object)
    assert len(cache) == 2
    assert cache.get(1, object) is not first  # rebuilt
    with pytest.raises(ValueError):
        PerThreadCache(max_entries=0)


def test_the_inaccurate_solution_warning_is_silenced_once_and_nothing_else():
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        ignore_inaccurate_solution_warning()
        ignore_inaccurate_solution_warning()
        n = len(warnings.filters)
        ignore_inaccurate_solution_warning()
        assert len(warnings.filters) == n
        warnings.warn(INACCURATE_SOLUTION_WARNING + ". Try another solver", UserWarning)
        warnings.warn("another warning", UserWarning)
    assert [str(w.message) for w in seen] == ["another warning"]
