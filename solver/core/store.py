"""A place where expensive results outlive the process (the service keeps them in SQLite,
service/store.py): the solver layer sees only this interface, never a file or a clock.
Values are small JSON-able dicts under (namespace, key); a namespace names what computed
them, with a version, so that a change of the computation makes old values unreachable."""

from __future__ import annotations

from typing import Any, Protocol


class ResultStore(Protocol):
    """get: the value stored, or None (also when the store cannot be read); put: keep it
    (a store that cannot be written drops it). Neither raises."""

    def get(self, namespace: str, key: str) -> dict[str, Any] | None: ...

    def put(self, namespace: str, key: str, value: dict[str, Any]) -> None: ...
