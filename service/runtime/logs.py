"""The service's log: one line per record on standard error, as JSON (python-json-logger)
or as text, each carrying the id of the request it belongs to.

The request id lives in a context variable set by :class:`service.runtime.context.RequestContext`
for the life of the request (asyncio copies it into the tasks and threads the request
starts), and :class:`RequestIdFilter` puts it on every record. The access log
(``service.access``) has one record per request with its route, status, duration, the
model that answered and the API key's id.
"""

from __future__ import annotations

import logging
import sys
from contextvars import ContextVar

from pythonjsonlogger.json import JsonFormatter

REQUEST_ID: ContextVar[str | None] = ContextVar("peshkin_request_id", default=None)
"""The id of the request being served (None outside a request)."""

ACCESS = "service.access"
"""The logger of the access log."""

JSON_FORMAT = {"fmt": "{levelname}{name}{message}", "style": "{", "timestamp": "time",
               "rename_fields": {"levelname": "level", "name": "logger"}}
"""python-json-logger's settings: the service's records and (service.server) gunicorn's own."""

TEXT_FORMAT = "%(asctime)s %(levelname)s %(name)s [%(request_id)s] %(message)s"


class RequestIdFilter(logging.Filter):
    """Adds ``request_id`` (the current request's, or None) to every record."""

    def filter(self, record: logging.LogRecord) -> bool:
        if not hasattr(record, "request_id"):
            record.request_id = REQUEST_ID.get()
        return True


def configure(level: str, fmt: str) -> None:
    """Send the ``service`` loggers to standard error in ``fmt`` ("json" or "text") at
    ``level``; called once per web process (again: the handler is replaced, not added)."""
    logger = logging.getLogger("service")
    logger.setLevel(level.upper().replace("TRACE", "DEBUG"))
    handler = logging.StreamHandler(sys.stderr)
    handler.addFilter(RequestIdFilter())
    if fmt == "json":
        handler.setFormatter(JsonFormatter(**JSON_FORMAT))  # type: ignore[arg-type]
    else:
        handler.setFormatter(logging.Formatter(TEXT_FORMAT))
    for old in [h for h in logger.handlers if getattr(h, "peshkin", False)]:
        logger.removeHandler(old)
    handler.peshkin = True  # type: ignore[attr-defined]
    logger.addHandler(handler)
