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

    A route's cost is the running mean of the run times measured for it in this web process
    (``weight``: the share of a new measurement); before the first, ``unknown_share`` of the
    request's time limit. A job is admitted only if it is predicted to start with time left
    for its cost, and at least ``start_share`` of its limit; a queued job that can no longer
    start so leaves the queue with a 503 (nothing computed is never answered 200). The head
    of the queue looks for a slot freed by another web process every ``poll_s``; the others
    look at their deadline every ``idle_poll_s``."""

    unknown_share: float = 0.5
    start_share: float = 0.25
    weight: float = 0.3
    poll_s: float = 0.005
    idle_poll_s: float = 0.05


DEFAULT_ADMISSION = AdmissionPolicy()


class Refused(Exception):
    """An expensive request refused (503): ``retry_after_s`` is when to come back."""

    def __init__(self, reason: str, retry_after_s: float) -> None:
        super().__init__(reason)
        self.reason = reason
        self.retry_after_s = retry_after_s


@dataclass(eq=False)
class Ticket:
    """One admitted expensive request: its route (for the cost), deadline and slot."""

    route: str
    deadline: Deadline
    needed_s: float
    wake: asyncio.Event = field(default_factory=asyncio.Event)
    slot: int | None = None
    started: float = 0.0


class RunQueue:
    """Expensive work of one web process: at most ``capacity`` requests wait, in arrival
    order, for a slot of the server (:class:`~service.runtime.slots.Slots`); a request is
    refused at once when it is predicted not to start in time (its ``Retry-After`` the
    predicted wait)."""

    name = "expensive"

    def __init__(self, slots: Slots, capacity: int, policy: AdmissionPolicy = DEFAULT_ADMISSION) -> None:
        self.slots = slots
        self.capacity = capacity
        self.policy = policy
        self.waiting: deque[Ticket] = deque()
        self.running: list[Ticket] = []
        self.cost_s: dict[str, float] = {}
        self.peer_cost_s: dict[str, float] = {}
        self.peer_waiting_s = 0.0
        self.admitted = 0
        self.refused = 0
        self.last_wait_s = 0.0

    def estimate(self, route: str, limit_s: float) -> float:
        """Predicted run time of a job of ``route`` with a time limit of ``limit_s``: as
        measured here, or by another web process, or ``unknown_share`` of the limit."""
        cost = self.cost_s.get(route, self.peer_cost_s.get(route))
        return min(self.policy.unknown_share * limit_s if cost is None else cost, limit_s)

    def _publish(self) -> None:
        waiting = sum(self.estimate(t.route, t.deadline.limit_s) for t in self.waiting)
        self.slots.publish({"waiting_s": waiting, "costs": self.cost_s})

    def _read_peers(self) -> None:
        peers = self.slots.peers()
        self.peer_waiting_s = sum(float(p.get("waiting_s", 0.0)) for p in peers)
        self.peer_cost_s = {}
        for p in peers:
            for route, cost in p.get("costs", {}).items():
                self.peer_cost_s[route] = max(float(cost), self.peer_cost_s.get(route, 0.0))

    def predicted_wait(self, own_s: float = 0.0) -> float:
        """Seconds until a request arriving now would get a slot, behind the queue here and
        the work waiting in the other web processes (spread over the slots). A slot held by
        another web process is predicted to be held for the longest cost known, or
        ``own_s`` (the newcomer's) if longer."""
        now = time.monotonic()
        ends = [min(max(t.started + self.estimate(t.route, t.deadline.limit_s), now), t.deadline.at)
                for t in self.running]
        elsewhere = self.slots.held_elsewhere()
        typical = max([*self.cost_s.values(), *self.peer_cost_s.values()], default=own_s)
        ends += [now + max(typical, own_s)] * elsewhere
        ends += [now] * max(self.slots.count - len(ends), 0)
        heapq.heapify(ends)
        for t in self.waiting:
            start = heapq.heappop(ends)
            heapq.heappush(ends, start + self.estimate(t.route, t.deadline.limit_s))
        return max(ends[0] - now, 0.0) + self.peer_waiting_s / self.slots.count

    def _refuse(self, reason: str, wait_s: float) -> Refused:
        self.refused += 1
        return Refused(reason, wait_s)

    async def enter(self, route: str, deadline: Deadline) -> Ticket:
        """A slot for the request, or :class:`Refused`."""
        p = self.policy
        ticket = Ticket(route, deadline, 0.0)
        if not self.waiting and self._start(ticket):
            return ticket
        self._read_peers()
        own = self.estimate(route, deadline.limit_s)
        needed = ticket.needed_s = max(own, p.start_share * deadline.limit_s)
        wait = self.predicted_wait(own)
        if len(self.waiting) >= self.capacity:
            raise self._refuse(f"all {self.capacity} places in the queue are taken", wait)
        if wait + needed > deadline.solver_s():
            raise self._refuse(f"it would start in about {wait:.3g} s, too late for its time limit of "
                               f"{deadline.limit_s:g} s", wait)
        self.waiting.append(ticket)
        self.admitted += 1
        self._publish()
        try:
            while True:
                if self.waiting[0] is ticket and self._start(ticket):
                    self.waiting.popleft()
                    self._publish()
                    if self.waiting:
                        self.waiting[0].wake.set()
                    return ticket
                if deadline.solver_s() < needed:
                    self.waiting.remove(ticket)
                    self._publish()
                    raise self._refuse("it waited too long for a solver worker to start in time",
                                       self.predicted_wait())
                ticket.wake.clear()  # woken by a slot given back here, or after the poll
                poll = p.poll_s if self.waiting[0] is ticket else p.idle_poll_s
                timer = asyncio.get_running_loop().call_later(poll, ticket.wake.set)
                try:
                    await ticket.wake.wait()
                finally:
                    timer.cancel()
        except asyncio.CancelledError:
            if ticket in self.waiting:
                self.waiting.remove(ticket)
                self._publish()
            raise

    def _start(self, ticket: Ticket) -> bool:
        slot = self.slots.try_take()
        if slot is None:
            return False
        ticket.slot, ticket.started = slot, time.monotonic()
        self.last_wait_s = ticket.started - ticket.deadline.arrived
        self.running.append(ticket)
        if ticket not in self.waiting:
            self.admitted += 1
        return True

    def leave(self, ticket: Ticket, measured: bool = True) -> None:
        """The job of ``ticket`` ended: its slot is free, and its run time measured unless
        ``measured`` is False (a job cancelled when its client went away tells nothing of
        the route's cost)."""
        assert ticket.slot is not None
        self.running.remove(ticket)
        self.slots.give_back(ticket.slot)
        if measured:
            ran = time.monotonic() - ticket.started
            old = self.cost_s.get(ticket.route)
            self.cost_s[ticket.route] = ran if old is None else old + self.policy.weight * (ran - old)
            self._publish()
        if self.waiting:
            self.waiting[0].wake.set()

    def state(self) -> GateState:
        return GateState(self.name, len(self.running) + len(self.waiting), self.slots.count + self.capacity,
                         self.admitted, self.refused)
