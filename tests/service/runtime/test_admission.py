"""Admission gates (service/runtime/admission.py): bounded, never blocking, counted, and
safe from many threads."""

from __future__ import annotations

import threading

import pytest

from service.runtime.admission import Gate


def test_a_full_gate_refuses_at_once_and_counts():
    g = Gate("expensive", 2)
    assert g.try_enter() and g.try_enter() and not g.try_enter()
    s = g.state()
    assert (s.in_use, s.capacity, s.admitted, s.refused, s.full) == (2, 2, 2, 1, True)
    g.leave()
    assert g.try_enter() and g.state().full


def test_leaving_more_than_entering_is_a_bug():
    g = Gate("cheap", 1)
    with pytest.raises(RuntimeError):
        g.leave()


def test_a_gate_needs_room():
    with pytest.raises(ValueError):
        Gate("none", 0)


def test_many_threads_never_exceed_the_capacity():
    g = Gate("cheap", 3)
    peak = []
    lock = threading.Lock()
    inside = [0]

    def worker():
        for _ in range(2000):
            if g.try_enter():
                with lock:
                    inside[0] += 1
                    peak.append(inside[0])
                with lock:
                    inside[0] -= 1
                g.leave()

    threads = [threading.Thread(target=worker) for _ in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    s = g.state()
    assert max(peak) <= 3 and s.in_use == 0 and s.admitted + s.refused == 16000
