"""Per-thread solver objects, CasADi's lock and the warning filter (solver/core/threads.py)."""

from __future__ import annotations

import json
import subprocess
import sys
import threading
import warnings
from pathlib import Path

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


CASADI_THREADS = 16
CASADI_BUILDS = 400
"""Functions each thread builds, calls and frees: without the lock, 300 a thread crashed the
process in 3 runs of 4 (SIGSEGV in CasADi's symbolic core)."""

CASADI_CHILD = f"""
import json
import threading
import casadi as ca
from solver.core.threads import CasadiFunction

def build(i):
    tau = ca.SX.sym("tau")
    t = (1.0 + 0.1 * i) * tau
    power = (-2.0 * t + (1.0 + t * t) ** 1.5) / 3.0
    return ca.Function("f", [tau], [ca.gradient(power, tau)])

barrier = threading.Barrier({CASADI_THREADS})
values = [None] * {CASADI_THREADS}

def work(i):
    barrier.wait()
    for _ in range({CASADI_BUILDS}):
        f = CasadiFunction(lambda: build(i))
        values[i] = float(f(1.0))

threads = [threading.Thread(target=work, args=(i,)) for i in range({CASADI_THREADS})]
for t in threads:
    t.start()
for t in threads:
    t.join()
print(json.dumps(values))
"""


@pytest.mark.slow
def test_casadi_functions_are_built_and_freed_on_many_threads_at_once():
    """16 threads each building, calling and freeing CasADi Functions (in a child process,
    so that a crash fails the test): the process ends normally and every thread's value is
    the derivative of its function at tau = 1, checked by a central difference."""
    repo = Path(__file__).resolve().parents[3]
    proc = subprocess.run([sys.executable, "-X", "faulthandler", "-c", CASADI_CHILD], cwd=repo,
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-5000:]
    values = json.loads(proc.stdout.strip().splitlines()[-1])
    for i, got in enumerate(values):
        c = 1.0 + 0.1 * i

        def power(tau, c=c):
            t = c * tau
            return (-2.0 * t + (1.0 + t * t) ** 1.5) / 3.0

        h = 1e-6
        assert got == pytest.approx((power(1.0 + h) - power(1.0 - h)) / (2.0 * h), rel=1e-7)
