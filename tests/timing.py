"""Wall-clock bounds of live tests that hold on a busy machine (issue 35, point 10).

A live test checks promises made in seconds (a refusal within a second, a cancelled job's
worker freed within a second). On a machine whose cores other processes also use, every
process of the server gets a share of a core, and those seconds stretch by the same factor.
:func:`contention` measures that factor here and now: the wall time of a fixed spin of this
process over the CPU time it got (1 on an idle core, about 3 when three busy processes share
it), whatever the CPU's speed. :func:`stretched` scales a bound by it, so the bound is the
promise itself on an idle machine and no tighter than the machine can keep when it is busy.
"""

from __future__ import annotations

import time

SPIN_S = 0.05
"""CPU seconds of one measurement."""
MAX_FACTOR = 20.0
"""A factor past this is a stalled machine, not a busy one: the bound stops stretching."""


def contention(samples: int = 3) -> float:
    """How much slower than its CPU time this process's wall time runs now (>= 1)."""
    worst = 1.0
    for _ in range(samples):
        wall0, cpu0 = time.perf_counter(), time.process_time()
        while time.process_time() - cpu0 < SPIN_S:
            pass
        worst = max(worst, (time.perf_counter() - wall0) / max(time.process_time() - cpu0, 1e-9))
    return min(worst, MAX_FACTOR)


def stretched(bound_s: float, factor: float | None = None) -> float:
    """``bound_s`` stretched by the machine's contention (measured now unless given)."""
    return bound_s * (contention() if factor is None else factor)
