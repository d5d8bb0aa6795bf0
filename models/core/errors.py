"""The project's own error types for the pure-mechanics layer."""

from __future__ import annotations


class ModelError(Exception):
    """Base class of every error raised by :mod:`models`."""


class InvalidInput(ModelError, ValueError):
    """An input that describes no physical pushing scene.

    ``field`` names the offending input (as the API calls it) and ``reason`` says what is
    wrong with it and how to fix it, so the service can answer HTTP 422 with both.
    """

    def __init__(self, field: str, reason: str) -> None:
        super().__init__(f"{field}: {reason}")
        self.field = field
        self.reason = reason
