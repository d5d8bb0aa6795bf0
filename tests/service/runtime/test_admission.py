"""Admission (service/runtime/admission.py, slots.py): gates bounded, never blocking,
counted, and safe from many threads; the queue of expensive work admits only what is
predicted to start in time, by the measured cost, and shares the server's slots with the
other web processes."""

from __future__ import annotations

import asyncio
import subprocess
import sys
import threading
import time

import pytest

from service.runtime.admission import Gate, Refused, RunQueue
from service.runtime.deadline import Deadline
from service.runtime.jobs import abandon
from service.runtime.slots import Slots


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


# --- the queue of expensive work and the server's slots ---------------------------------

def _deadline(limit_s: float) -> Deadline:
    return Deadline.starting(time.monotonic(), limit_s)


def test_slots_are_shared_by_every_holder_of_the_directory_and_freed_when_a_holder_closes():
    one = Slots(2).open()
    other = Slots(2, one.directory).open()  # as a second web process would see them
    try:
        assert one.try_take() is not None and other.try_take() is not None
        assert one.try_take() is None and other.try_take() is None
        other.publish({"waiting_s": 1.5})
        assert one.peers() == [{"waiting_s": 1.5}] and other.peers() == []
        other.close()  # a web process that ends (or dies: the kernel drops its locks) frees what it held
        assert one.try_take() is not None and one.peers() == []
    finally:
        one.close()


def test_nothing_is_made_before_the_slots_are_opened():
    slots = Slots(1)
    assert slots.directory is None and slots.try_take() is None and slots.peers() == []
    slots.publish({"waiting_s": 1.0})  # advisory: ignored before open
    slots.close()


def test_the_cpu_count_follows_the_affinity_not_the_machine():
    code = ("import os; os.sched_setaffinity(0, {min(os.sched_getaffinity(0))}); "
            "from service.settings import Settings; print(Settings().solver_processes())")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "1"


def test_a_request_waits_for_a_slot_freed_by_another_web_process():
    async def scenario() -> tuple[float, int]:
        here = RunQueue(Slots(1).open(), capacity=4)
        there = RunQueue(Slots(1, here.slots.directory).open(), capacity=4)
        try:
            here.cost_s["POST /x"] = there.cost_s["POST /x"] = 0.2
            held = await there.enter("POST /x", _deadline(10.0))
            waiting = asyncio.ensure_future(here.enter("POST /x", _deadline(10.0)))
            await asyncio.sleep(0.1)
            assert not waiting.done() and here.state().in_use == 1
            freed = time.monotonic()
            there.leave(held)
            ticket = await waiting
            got = time.monotonic() - freed
            here.leave(ticket)
            return got, here.admitted
        finally:
            here.slots.close()
            there.slots.close()

    got, admitted = asyncio.run(scenario())
    assert got < 0.5 and admitted == 1  # the head polls every 5 ms


def test_the_predicted_wait_uses_the_measured_cost_and_refuses_what_would_start_too_late():
    async def scenario() -> None:
        queue = RunQueue(Slots(1).open(), capacity=4)
        try:
            queue.cost_s["POST /x"] = 5.0
            running = await queue.enter("POST /x", _deadline(30.0))
            assert 4.5 < queue.predicted_wait() <= 5.0
            with pytest.raises(Refused) as refused:  # 5 s of wait and 5 s of work do not fit in 8 s
                await queue.enter("POST /x", _deadline(8.0))
            assert 4.5 < refused.value.retry_after_s <= 5.0
            queued = asyncio.ensure_future(queue.enter("POST /x", _deadline(30.0)))
            await asyncio.sleep(0.05)
            assert 9.0 < queue.predicted_wait() <= 10.0  # behind the running job and the queued one
            queue.cost_s["POST /y"] = 0.1
            for _ in range(3):  # the queue holds at most `capacity`
                asyncio.ensure_future(queue.enter("POST /y", _deadline(1000.0)))
            await asyncio.sleep(0.05)
            with pytest.raises(Refused, match="places in the queue"):
                await queue.enter("POST /y", _deadline(1000.0))
            assert queue.refused == 2
            queue.leave(running)
            queue.leave(await queued)
            assert queue.cost_s["POST /x"] < 5.0  # the measured run times pull the mean down
        finally:
            queue.slots.close()

    asyncio.run(scenario())


def test_a_queued_request_that_can_no_longer_start_in_time_leaves_with_a_refusal():
    async def scenario() -> float:
        queue = RunQueue(Slots(1).open(), capacity=4)
        try:
            queue.cost_s["POST /x"] = 0.0  # predicted to start at once: admitted
            running = await queue.enter("POST /x", _deadline(30.0))
            t0 = time.monotonic()
            with pytest.raises(Refused, match="waited too long"):
                await queue.enter("POST /x", _deadline(0.4))
            queue.leave(running)
            return time.monotonic() - t0
        finally:
            queue.slots.close()

    took = asyncio.run(scenario())
    assert took < 0.4  # it left when a quarter of its limit (and the reserve) remained


def test_a_web_process_admits_by_the_whole_servers_backlog_and_learns_costs_from_the_others():
    """Queue A holds the only slot and has three requests waiting, 4 s each by its measured
    cost; queue B (another web process) has measured nothing: it takes A's cost for the
    route and adds A's waiting work to its predicted wait (4 s for the slot + 3 x 4 s), so
    it refuses a request with a 20 s limit at once, with that wait as Retry-After."""
    async def scenario() -> float:
        a = RunQueue(Slots(1).open(), capacity=8)
        b = RunQueue(Slots(1, a.slots.directory).open(), capacity=8)
        try:
            a.cost_s["POST /x"] = 4.0
            held = await a.enter("POST /x", _deadline(1000.0))
            waiting = [asyncio.ensure_future(a.enter("POST /x", _deadline(1000.0))) for _ in range(3)]
            await asyncio.sleep(0.05)
            with pytest.raises(Refused) as refused:
                await b.enter("POST /x", _deadline(20.0))
            assert b.estimate("POST /x", 20.0) == 4.0 and b.peers.waiting_s == 12.0
            for w in waiting:
                w.cancel()
            await asyncio.gather(*waiting, return_exceptions=True)
            a.leave(held)
            return refused.value.retry_after_s
        finally:
            a.slots.close()
            b.slots.close()

    retry = asyncio.run(scenario())
    assert 15.5 < retry <= 16.0


def test_a_wait_given_up_leaves_the_queue_or_gives_its_slot_back_unmeasured():
    """A request whose wait is abandoned (its client gone, or its task cancelled at a
    shutdown) must not keep a place in the queue nor, when the slot came just then, the
    slot: service.runtime.jobs.abandon."""
    async def scenario() -> None:
        queue = RunQueue(Slots(1).open(), capacity=4)
        try:
            queue.cost_s["POST /x"] = 0.1
            held = await queue.enter("POST /x", _deadline(30.0))
            waiting = asyncio.ensure_future(queue.enter("POST /x", _deadline(30.0)))
            await asyncio.sleep(0.02)
            abandon(queue, waiting)  # still queued: cancelled, it leaves the queue
            await asyncio.gather(waiting, return_exceptions=True)
            assert waiting.cancelled() and not queue.waiting
            queue.leave(held)
            measured = queue.cost_s["POST /x"]
            got = asyncio.ensure_future(queue.enter("POST /x", _deadline(30.0)))
            await asyncio.sleep(0.02)
            assert got.done()  # it had its slot when its waiter gave up
            abandon(queue, got)
            assert not queue.running and queue.slots.try_take() is not None
            assert queue.cost_s["POST /x"] == measured  # the abandoned run tells nothing of the cost
        finally:
            queue.slots.close()

    asyncio.run(scenario())
