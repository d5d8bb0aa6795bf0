"""The server: gunicorn supervises ``web_workers`` uvicorn processes (a web process that
dies is replaced), each running the app with its own solver workers; the server's slots
of expensive work are shared by them all (service.runtime.slots), so expensive requests
use every CPU whichever web process took them.

What a hostile or broken client cannot do here:

* hold a connection by sending nothing, or its headers byte by byte: the headers must
  arrive within ``header_timeout_s`` of the connection (or of the request's first byte on
  a kept-alive connection), the body within ``body_timeout_s`` of the headers; past that
  the answer is 408 and the connection is closed (:class:`ReadTimeoutProtocol`);
* keep an idle connection: closed after ``keep_alive_s``;
* send an endless request line or endless headers: gunicorn's and uvicorn's limits;
* stop the server from shutting down: requests in flight get ``graceful_timeout_s``.

``python -m service`` runs it; ``scripts/serve.sh`` and the Dockerfile call that.
"""

from __future__ import annotations

import asyncio
import errno
import logging
import math
import os
import shutil
import socket
from typing import Any, ClassVar

from gunicorn.app.base import BaseApplication
from uvicorn.protocols.http.httptools_impl import HttpToolsProtocol
from uvicorn_worker import UvicornWorker

from service.runtime.logs import JSON_FORMAT
from service.runtime.slots import METRICS_DIR_ENV, SERVER_PID_ENV, SLOT_DIR_ENV, make_slot_directory
from service.settings import Settings

log = logging.getLogger("service")

_TIMEOUT_BODY = b'{"detail":[{"loc":[],"msg":"the request was not sent in time","type":"request_timeout"}]}'
REQUEST_TIMEOUT_RESPONSE = (
    b"HTTP/1.1 408 Request Timeout\r\ncontent-type: application/json\r\nconnection: close\r\n"
    + b"content-length: " + str(len(_TIMEOUT_BODY)).encode() + b"\r\n\r\n" + _TIMEOUT_BODY
)
"""What a client that did not send its request in time gets before the connection closes."""


class ReadTimeoutProtocol(HttpToolsProtocol):
    """uvicorn's httptools protocol with read deadlines for the headers and the body
    (uvicorn has a keep-alive timeout but none for a request being received)."""

    header_timeout_s: ClassVar[float] = Settings.header_timeout_s
    body_timeout_s: ClassVar[float] = Settings.body_timeout_s

    def connection_made(self, transport: asyncio.Transport) -> None:  # type: ignore[override]
        self.read_timer: asyncio.TimerHandle | None = None
        super().connection_made(transport)
        self._arm(self.header_timeout_s)

    def on_message_begin(self) -> None:
        super().on_message_begin()
        if self.read_timer is None:  # a kept-alive connection's next request
            self._arm(self.header_timeout_s)

    def on_headers_complete(self) -> None:
        super().on_headers_complete()
        self._arm(self.body_timeout_s)

    def on_message_complete(self) -> None:
        super().on_message_complete()
        self._disarm()

    def connection_lost(self, exc: Exception | None) -> None:
        self._disarm()
        super().connection_lost(exc)

    def _arm(self, seconds: float) -> None:
        self._disarm()
        self.read_timer = self.loop.call_later(seconds, self._read_timed_out)

    def _disarm(self) -> None:
        timer = getattr(self, "read_timer", None)
        if timer is not None:
            timer.cancel()
            self.read_timer = None

    def _read_timed_out(self) -> None:
        self.read_timer = None
        if self.transport.is_closing():
            return
        cycle = self.cycle
        if cycle is None or not cycle.response_started:
            self.transport.write(REQUEST_TIMEOUT_RESPONSE)
        log.info("closed a connection from %s: the request was not sent in time", self.client)
        self.transport.close()


class Worker(UvicornWorker):
    """A gunicorn worker running uvicorn with :class:`ReadTimeoutProtocol` on the standard
    asyncio loop: under 128 connections per process uvloop let some connections wait over
    2 s (wrk timeouts; p99 0.7-0.9 s) where asyncio's loop kept p99 at 0.27 s, for the same
    throughput. No access log (gunicorn's is off too): a log record per request cost 5-15 %
    of the analytic locus's throughput (interleaved runs, a slow moment of the machine)."""

    CONFIG_KWARGS: ClassVar[dict[str, Any]] = {"loop": "asyncio", "http": ReadTimeoutProtocol, "access_log": False}


class PortInUse(SystemExit):
    """Another program listens on the port: the server does not start."""


def ensure_port_free(host: str, port: int) -> None:
    """Refuse to start when anything listens on ``host:port``. With SO_REUSEPORT the web
    processes would otherwise bind beside another server of the same user and share its
    connections without a word; a plain bind (SO_REUSEADDR only, so connections of a
    previous run in TIME_WAIT do not count) fails on any listener."""
    for family, kind, proto, _, address in socket.getaddrinfo(host, port, type=socket.SOCK_STREAM):
        with socket.socket(family, kind, proto) as probe:
            probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            try:
                probe.bind(address)
            except OSError as exc:
                if exc.errno == errno.EADDRINUSE:
                    raise PortInUse(f"cannot listen on {host}:{port}: {exc.strerror}; is another server running "
                                    "there?") from exc


def listen_when_ready(arbiter: Any, worker: Any) -> None:
    """gunicorn's ``post_fork``: with SO_REUSEPORT each web process's socket is made, and
    listening, right after its fork, so while it imports the app and starts its solver
    workers (seconds; 24-48 s on a loaded machine) the kernel queued connections that hung.
    Its sockets are replaced by ones bound to the same address but not listening; asyncio
    listens on them when uvicorn serves, after the app's startup. Until then a connection
    goes to another web process that listens, or is refused at once."""
    bound = []
    for listening in worker.sockets:
        real = getattr(listening, "sock", listening)
        fresh = socket.socket(real.family, socket.SOCK_STREAM)
        fresh.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        fresh.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEPORT, 1)
        fresh.bind(real.getsockname())
        fresh.setblocking(False)
        listening.close()
        bound.append(fresh)
    worker.sockets = bound


class ControlSocketInUse(SystemExit):
    """Another server answers on the control socket's path: this one does not start."""


def ensure_control_socket_free(path: str) -> None:
    """Refuse to start when a server answers on the control socket ``path`` (gunicorn would
    take the path over and delete it on exit, leaving the first server without one); a path
    left by a server that is gone is fine (gunicorn replaces it)."""
    if not path or not os.path.exists(path):
        return
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as probe:
        probe.settimeout(1.0)
        try:
            probe.connect(path)
        except OSError:
            return  # nobody listens there: a stale path
    raise ControlSocketInUse(f"the control socket {path} is in use by another server; give this one a path of its "
                             "own (PESHKIN_CONTROL_SOCKET) or none")


class NoEmptyListening(logging.Filter):
    """gunicorn's supervisor logs "Listening at:  (<pid>)" with no address when each web
    process listens on a socket of its own (SO_REUSEPORT); share_slots logs the address."""

    def filter(self, record: logging.LogRecord) -> bool:
        return not (isinstance(record.msg, str) and record.msg.startswith("Listening at:")
                    and record.args and not record.args[0])  # type: ignore[index]


def share_slots(arbiter: Any) -> None:
    """gunicorn's ``on_starting``: the slot directory of this server, for its web processes,
    with the directory of their metrics' samples in it (before any of them imports
    prometheus-client, which reads it then; service.runtime.metrics), and the address in
    the log: with SO_REUSEPORT the supervisor itself listens on none, so gunicorn's own
    "Listening at" line shows no address."""
    logging.getLogger("gunicorn.error").addFilter(NoEmptyListening())
    os.environ[SLOT_DIR_ENV] = make_slot_directory()
    os.environ[SERVER_PID_ENV] = str(os.getpid())  # the server's one Ray (solver.core.ray_head) ends with it
    samples = os.path.join(os.environ[SLOT_DIR_ENV], "metrics")
    os.makedirs(samples)
    os.environ[METRICS_DIR_ENV] = samples
    arbiter.log.info("each web process listens on %s (SO_REUSEPORT); slots of expensive work in %s",
                     ", ".join(arbiter.cfg.bind), os.environ[SLOT_DIR_ENV])


def web_process_ended(arbiter: Any, worker: Any) -> None:
    """gunicorn's ``child_exit``: the ended web process's live gauges leave the metrics."""
    from service.runtime.metrics import process_ended

    process_ended(worker.pid)


def remove_slots(arbiter: Any) -> None:
    """gunicorn's ``on_exit`` (the server's Ray, if a catalogue started it, sees its
    directory gone and stops within a second: solver.core.ray_head)."""
    os.environ.pop(METRICS_DIR_ENV, None)
    directory = os.environ.pop(SLOT_DIR_ENV, "")
    if directory:
        shutil.rmtree(directory, ignore_errors=True)


def gunicorn_json_logging(level: str) -> dict[str, Any]:
    """gunicorn's logging (the supervisor's and uvicorn's own lines) in the service's JSON
    format (service.runtime.logs), on standard error; no access log, nothing on the root
    logger (the service's records have their own handler)."""
    return {
        "version": 1,
        "disable_existing_loggers": False,
        "root": {"level": "WARNING", "handlers": []},
        "loggers": {
            "gunicorn.error": {"level": level.upper(), "handlers": ["stderr"], "propagate": False,
                               "qualname": "gunicorn.error"},
            "gunicorn.access": {"level": "WARNING", "handlers": [], "propagate": False, "qualname": "gunicorn.access"},
        },
        "handlers": {"stderr": {"class": "logging.StreamHandler", "formatter": "json", "stream": "ext://sys.stderr"}},
        "formatters": {"json": {"()": "pythonjsonlogger.json.JsonFormatter", **JSON_FORMAT}},
    }


class Server(BaseApplication):  # type: ignore[misc]
    """gunicorn, configured from :class:`Settings`, serving ``service.app:app``."""

    def __init__(self, settings: Settings) -> None:
        self.settings = settings
        super().__init__()

    def load_config(self) -> None:
        s = self.settings
        ReadTimeoutProtocol.header_timeout_s = s.header_timeout_s
        ReadTimeoutProtocol.body_timeout_s = s.body_timeout_s
        Worker.CONFIG_KWARGS = {**Worker.CONFIG_KWARGS, "timeout_graceful_shutdown": s.graceful_timeout_s}
        options = {
            "bind": f"{s.host}:{s.port}",
            "workers": s.web_workers,
            "worker_class": f"{Worker.__module__}.{Worker.__qualname__}",
            "keepalive": math.ceil(s.keep_alive_s),  # gunicorn takes whole seconds
            "graceful_timeout": math.ceil(s.graceful_timeout_s),
            "timeout": math.ceil(max(60.0, 2 * s.max_time_limit_s)),  # a web process silent this long is replaced
            "loglevel": s.log_level if s.log_level != "trace" else "debug",
            # each web process listens on a socket of its own (SO_REUSEPORT) and the kernel
            # spreads new connections over them: on one shared socket the first process to
            # wake accepted every connection of a burst (at 128 connections, 2 runs of 3: one
            # process did all the work, 970 requests/s against 1,920 spread)
            "reuse_port": True,
            "limit_request_line": 8190,
            "limit_request_fields": 100,
            "limit_request_field_size": 8190,
            "accesslog": None,
        }
        # gunicorn's control socket defaults to one path in the user's home, shared by every
        # instance on the host (and unwritable in the image): a path of this instance's own,
        # or none
        if s.control_socket:
            options["control_socket"] = s.control_socket
        else:
            options["control_socket_disable"] = True
        # the slots of expensive work, shared by the web processes (service.runtime.slots):
        # a directory of this instance's own, made when the supervisor starts (before the
        # web processes are forked; a reload keeps it), removed when it exits
        options["on_starting"] = share_slots
        options["post_fork"] = listen_when_ready
        options["on_exit"] = remove_slots
        options["child_exit"] = web_process_ended
        if s.log_format == "json":
            options["logconfig_dict"] = gunicorn_json_logging(options["loglevel"])
        for key, value in options.items():
            self.cfg.set(key, value)

    def run(self) -> None:
        ensure_port_free(self.settings.host, self.settings.port)
        ensure_control_socket_free(self.settings.control_socket)
        super().run()

    def load(self) -> Any:
        from service.app import app

        return app
