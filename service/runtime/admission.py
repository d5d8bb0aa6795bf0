"""Admission control. A request enters or is refused at once (HTTP 503 with
``Retry-After``); nothing waits without bound. Every request passes the gate of requests in
flight of its web process (:class:`Gate`, service.runtime.intake). Expensive work passes
the :class:`RunQueue` besides: it runs while it holds one of the server's slots
(service.runtime.slots) and waits for one in a bounded queue, which admits a request only
when its measured cost and the predicted wait leave it time to run; so a flood of expensive
requests is refused at once with the wait it would have met, never queued to die, and never
delays a cheap one, which is computed at once on the event loop."""

from __future__ import annotations

import asyncio
import dataclasses
import heapq
import threading
import time
from collections import deque
from dataclasses import dataclass, field

from service.runtime.deadline import Deadline
from service.runtime.slots import Slots


@dataclass(frozen=True)
class GateState:
    name: str
    in_use: int
    capacity: int
    admitted: int
    refused: int

    @property
    def full(self) -> bool:
        return self.in_use >= self.capacity


class Gate:
    """At most ``capacity`` holders at once; :meth:`try_enter` never blocks."""

    def __init__(self, name: str, capacity: int) -> None:
        if capacity < 1:
            raise ValueError(f"gate {name!r} needs a capacity >= 1, got {capacity}")
        self.name = name
        self.capacity = capacity
        self._lock = threading.Lock()
        self._in_use = 0
        self._admitted = 0
        self._refused = 0

    def try_enter(self) -> bool:
        with self._lock:
            if self._in_use >= self.capacity:
                self._refused += 1
                return False
            self._in_use += 1
            self._admitted += 1
            return True

    def leave(self) -> None:
        with self._lock:
            if self._in_use <= 0:
                raise RuntimeError(f"gate {self.name!r} left more often than entered")
            self._in_use -= 1

    def state(self) -> GateState:
        with self._lock:
            return GateState(self.name, self._in_use, self.capacity, self._admitted, self._refused)


@dataclass(frozen=True)
class AdmissionPolicy:
    """How the queue of expensive work (:class:`RunQueue`) decides.

    A kind of job's cost is the running mean of the run times measured for it (``weight``:
    the share of a new measurement), here or by another web process; before the first,
    ``unknown_share`` of the request's time limit (a job's kind, before its first run, takes
    the cost measured for the same operation as a request). A request is admitted only if
    its predicted wait, stretched by ``1 + wait_margin``, leaves time for what it needs: its
    cost and at least ``start_share`` of its limit; for *anytime* work (it refines until
    its limit and answers what it has: a certified locus, a catalogue), its cost or
    ``anytime_share`` of its limit, whichever is less, since it gives a useful answer in
    that time. A queued request that can no longer start so leaves the queue with a 503
    (nothing computed is never answered 200). The head of the queue looks for a slot freed
    by another web process every ``poll_s``; the others, and jobs waiting for a slot, every
    ``idle_poll_s``. A refusal whose predicted wait is under ``at_once_s`` says that the
    request would start at once but does not fit its limit, not that it would start late.

    ``max_wait_s`` bounds the queue: a request predicted to wait longer is refused at once,
    and one still without a slot ``refusal_margin_s`` before that time since it arrived
    leaves with a 503 then, so every expensive request gets its slot or its refusal within
    ``max_wait_s`` of arriving (a prediction that came out short never holds it longer)."""

    unknown_share: float = 0.5
    start_share: float = 0.25
    anytime_share: float = 0.25
    wait_margin: float = 0.25
    weight: float = 0.3
    poll_s: float = 0.005
    idle_poll_s: float = 0.05
    at_once_s: float = 0.5
    max_wait_s: float = 1.0
    refusal_margin_s: float = 0.25
    """A queued request leaves this long before ``max_wait_s``: its 503 still has to reach the
    client while the solver workers keep the machine's cores busy (a flood of designs on two
    cores: 0.1 s before it, refusals arrived after 1.18 s)."""


DEFAULT_ADMISSION = AdmissionPolicy()

JOB_KIND = "job "
"""The prefix of a job's kind of work: jobs' run times are measured apart from requests'."""


class Refused(Exception):
    """An expensive request refused (503): ``retry_after_s`` is when to come back."""

    def __init__(self, reason: str, retry_after_s: float) -> None:
        super().__init__(reason)
        self.reason = reason
        self.retry_after_s = retry_after_s


@dataclass(eq=False)
class Ticket:
    """One admitted piece of expensive work: its kind (for the cost), deadline, whether it
    is ``anytime`` work, the most slots it can use (``width``: a catalogue's parallel
    tasks), whether it is a job, and the slots it holds (and, a job, the places beyond the
    one it came with)."""

    kind: str
    deadline: Deadline
    anytime: bool = False
    width: int = 1
    job: bool = False
    wake: asyncio.Event = field(default_factory=asyncio.Event)
    slots: list[int] = field(default_factory=list)
    places: list[int] = field(default_factory=list)
    started: float = 0.0

    @property
    def granted(self) -> Deadline:
        """The deadline the work runs under, with the slots it was given."""
        return dataclasses.replace(self.deadline, slots=max(len(self.slots), 1))


@dataclass(frozen=True)
class Peers:
    """What the other web processes published: when their running jobs are predicted to
    end (``time.monotonic``, one clock for the machine; one entry per slot held), the work
    waiting in their queues, and the costs they measured."""

    running_ends: tuple[float, ...] = ()
    waiting_s: float = 0.0
    cost_s: dict[str, float] = field(default_factory=dict)

    @classmethod
    def of(cls, published: list[dict]) -> Peers:
        ends: list[float] = []
        costs: dict[str, float] = {}
        for p in published:
            ends += [float(e) for e in p.get("running_ends", ())]
            for kind, cost in p.get("costs", {}).items():
                costs[kind] = max(float(cost), costs.get(kind, 0.0))
        return cls(tuple(ends), sum(float(p.get("waiting_s", 0.0)) for p in published), costs)


class RunQueue:
    """Expensive work of one web process: at most ``capacity`` requests wait, in arrival
    order, for a slot of the server (:class:`~service.runtime.slots.Slots`); a request is
    refused at once when it is predicted not to start in time (its ``Retry-After`` the
    predicted wait). Jobs wait apart (:meth:`enter_job`), behind every waiting request, and
    hold at most the server's job places. Costs are kept per kind of work (the caller's key:
    a route, and what of the request decides its cost)."""

    name = "expensive"

    def __init__(self, slots: Slots, capacity: int, policy: AdmissionPolicy = DEFAULT_ADMISSION) -> None:
        self.slots = slots
        self.capacity = capacity
        self.policy = policy
        self.waiting: deque[Ticket] = deque()
        self.running: list[Ticket] = []
        self.cost_s: dict[str, float] = {}
        self.peers = Peers()
        self.admitted = 0
        self.refused = 0

    def _cost(self, kind: str) -> float | None:
        cost = self.cost_s.get(kind, self.peers.cost_s.get(kind))
        if cost is None and kind.startswith(JOB_KIND):  # a job not run yet: the operation's cost as a request
            return self._cost(kind[len(JOB_KIND):])
        return cost

    def measured(self, kind: str) -> bool:
        return self._cost(kind) is not None

    def estimate(self, kind: str, limit_s: float) -> float:
        """Predicted run time of work of ``kind`` with a time limit of ``limit_s``: as
        measured here, or by another web process, or ``unknown_share`` of the limit."""
        cost = self._cost(kind)
        return min(self.policy.unknown_share * limit_s if cost is None else cost, limit_s)

    def needed(self, kind: str, limit_s: float, anytime: bool) -> float:
        """The run time a request must be able to get to be admitted (AdmissionPolicy)."""
        own = self.estimate(kind, limit_s)
        if anytime:
            return min(own, self.policy.anytime_share * limit_s)
        return max(own, self.policy.start_share * limit_s)

    def _end(self, t: Ticket) -> float:
        return min(t.started + self.estimate(t.kind, t.deadline.limit_s), t.deadline.at)

    def _publish(self) -> None:
        self.slots.publish({
            "running_ends": [self._end(t) for t in self.running for _ in t.slots],
            "waiting_s": sum(self.estimate(t.kind, t.deadline.limit_s) for t in self.waiting),
            "costs": self.cost_s,
        })

    def predicted_wait(self) -> float:
        """Seconds until a request arriving now would get a slot: behind the running work
        of every web process (at its predicted end), the queue here, and the work waiting in
        the other web processes' queues (spread over the slots)."""
        now = time.monotonic()
        mine = [self._end(t) for t in self.running for _ in t.slots]
        ends = sorted(max(e, now) for e in [*mine, *self.peers.running_ends])
        ends = [now] * max(self.slots.count - len(ends), 0) + ends[: self.slots.count]
        heapq.heapify(ends)
        for t in self.waiting:
            start = heapq.heappop(ends)
            heapq.heappush(ends, start + self.estimate(t.kind, t.deadline.limit_s))
        return max(ends[0] - now, 0.0) + self.peers.waiting_s / self.slots.count

    def _refuse(self, reason: str, wait_s: float) -> Refused:
        self.refused += 1
        return Refused(reason, wait_s)

    def _too_late(self, ticket: Ticket, wait: float, needed: float) -> str:
        """Why ``ticket``, predicted to wait ``wait`` s and to need ``needed`` s, is refused."""
        limit = ticket.deadline.limit_s
        if ticket.anytime and needed < self.estimate(ticket.kind, limit):
            basis = f"the {self.policy.anytime_share:.0%} of its time limit that gives a useful answer"
        elif self.measured(ticket.kind):
            basis = "its run time as measured"
        else:
            basis = f"its run time is not measured yet: {self.policy.unknown_share:.0%} of its time limit assumed"
        if wait < self.policy.at_once_s:
            return (f"it needs about {needed:.2g} s ({basis}), more than the {ticket.deadline.solver_s():.2g} s "
                    f"its time limit of {limit:g} s leaves for solving")
        return (f"it would start in about {wait:.2g} s, too late for the {needed:.2g} s it needs ({basis}) within "
                f"its time limit of {limit:g} s")

    def _dequeue(self, ticket: Ticket) -> None:
        """Take ``ticket`` out of the queue, waking the next head when it was the head."""
        head = self.waiting[0] is ticket
        self.waiting.remove(ticket)
        if head and self.waiting:
            self.waiting[0].wake.set()

    def _refusal(self, ticket: Ticket, needed: float) -> Refused | None:
        """Why ``ticket``, needing ``needed`` s, may not wait for a slot (None: it may)."""
        p = self.policy
        wait = self.predicted_wait()
        if len(self.waiting) >= self.capacity:
            return Refused(f"all {self.capacity} places in the queue are taken", wait)
        if wait * (1.0 + p.wait_margin) + needed > ticket.deadline.solver_s():
            return Refused(self._too_late(ticket, wait, needed), wait)
        if wait > p.max_wait_s:
            return Refused(f"it would wait about {wait:.2g} s for a solver slot, more than the {p.max_wait_s:g} s a "
                           "request waits here", wait)
        return None

    def refusal_now(self, kind: str, deadline: Deadline, anytime: bool = False) -> Refused | None:
        """What :meth:`enter` would refuse now, without waiting or taking anything (counted as
        a refusal when it is one): a route asks it before it reads a large body, so that a
        request refused anyway is not read."""
        self.peers = Peers.of(self.slots.peers())
        if not self.waiting and self.peers.waiting_s == 0.0 and self.slots.free() > 0:
            return None
        refused = self._refusal(Ticket(kind, deadline, anytime), self.needed(kind, deadline.limit_s, anytime))
        if refused is not None:
            self.refused += 1
        return refused

    async def enter(self, kind: str, deadline: Deadline, anytime: bool = False, width: int = 1) -> Ticket:
        """A slot for the request (and more, up to ``width``, while others stay free), or
        :class:`Refused`."""
        p = self.policy
        self.peers = Peers.of(self.slots.peers())
        ticket = Ticket(kind, deadline, anytime, width)
        if not self.waiting and self.peers.waiting_s == 0.0 and self._start(ticket):
            return ticket
        needed = self.needed(kind, deadline.limit_s, anytime)
        refused = self._refusal(ticket, needed)
        if refused is not None:
            self.refused += 1
            raise refused
        self.waiting.append(ticket)
        self.admitted += 1
        self._publish()
        try:
            while True:
                if self.waiting[0] is ticket and self._start(ticket):
                    return ticket
                if deadline.solver_s() < needed or deadline.elapsed() >= p.max_wait_s - p.refusal_margin_s:
                    self._dequeue(ticket)
                    self._publish()
                    self.peers = Peers.of(self.slots.peers())
                    why = ("it waited too long for a solver worker to start in time" if deadline.solver_s() < needed
                           else f"no solver slot came free within {p.max_wait_s:g} s, as predicted it would")
                    raise self._refuse(why, self.predicted_wait())
                ticket.wake.clear()  # woken by a slot given back here, or after the poll
                poll = p.poll_s if self.waiting[0] is ticket else p.idle_poll_s
                timer = asyncio.get_running_loop().call_later(poll, ticket.wake.set)
                try:
                    await ticket.wake.wait()
                finally:
                    timer.cancel()
        except asyncio.CancelledError:
            if ticket in self.waiting:
                self._dequeue(ticket)
                self._publish()
            raise

    async def enter_job(self, kind: str, limit_s: float, width: int = 1) -> Ticket:
        """A slot for a job that holds one of the server's job places already: it waits
        (never refused) until no request waits for a slot anywhere in the server and a slot
        is free; more slots, up to ``width``, while others stay free and job places last.
        Its deadline, ``limit_s``, counts from when it gets the slot."""
        ticket = Ticket(JOB_KIND + kind, Deadline.starting(time.monotonic(), limit_s), width=width, job=True)
        while True:
            self.peers = Peers.of(self.slots.peers())
            ticket.deadline = Deadline.starting(time.monotonic(), limit_s)
            if not self.waiting and self.peers.waiting_s == 0.0 and self._start(ticket):
                return ticket
            await asyncio.sleep(self.policy.idle_poll_s)

    def _start(self, ticket: Ticket) -> bool:
        """Take a slot for ``ticket`` (from the head of the queue, or work that found the
        queues empty), and more up to its width while another slot stays free; False when
        none is free."""
        slot = self.slots.try_take()
        if slot is None:
            return False
        ticket.slots, ticket.started = [slot], time.monotonic()
        while len(ticket.slots) < ticket.width and self.slots.free() > 1:
            place = self.slots.try_take_place() if ticket.job else None
            more = None if ticket.job and place is None else self.slots.try_take()
            if more is None:
                if place is not None:
                    self.slots.give_back_place(place)
                break
            ticket.slots.append(more)
            if place is not None:
                ticket.places.append(place)
        self.running.append(ticket)
        if ticket in self.waiting:
            self._dequeue(ticket)
        else:
            self.admitted += 1
        self._publish()
        return True

    def leave(self, ticket: Ticket, measured: bool = True) -> None:
        """The work of ``ticket`` ended: its slots (and a job's extra places) are free, and
        its run time measured unless ``measured`` is False (work cancelled or refused tells
        nothing of its cost)."""
        assert ticket.slots
        self.running.remove(ticket)
        for slot in ticket.slots:
            self.slots.give_back(slot)
        for place in ticket.places:
            self.slots.give_back_place(place)
        if measured:
            ran = time.monotonic() - ticket.started
            old = self.cost_s.get(ticket.kind)
            self.cost_s[ticket.kind] = ran if old is None else old + self.policy.weight * (ran - old)
        self._publish()
        if self.waiting:
            self.waiting[0].wake.set()

    def state(self) -> GateState:
        held = sum(len(t.slots) for t in self.running)
        return GateState(self.name, held + len(self.waiting), self.slots.count + self.capacity,
                         self.admitted, self.refused)
