"""Admission control: bounded gates. A request enters its gate or is refused at once (HTTP
503 with ``Retry-After``); nothing waits without bound. Every request passes the gate of
requests in flight of its web process (service.runtime.intake); expensive work (solver
workers, plus a bounded queue in front of them) has its own gate besides, so a flood of
expensive requests is refused before it can fill the web process, and never delays a
cheap one, which is computed at once on the event loop."""

from __future__ import annotations

import threading
from dataclasses import dataclass


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
