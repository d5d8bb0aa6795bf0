"""Runtime settings from the environment.

==============================  ==========  =====================================================
variable                        default     meaning
==============================  ==========  =====================================================
``PESHKIN_HOST``                127.0.0.1   interface the server listens on
``PESHKIN_PORT``                8000        TCP port
``PESHKIN_LOG_LEVEL``           info        server and ``service`` logger level
``PESHKIN_WEB_WORKERS``         2           web processes under the supervisor (``python -m service``)
``PESHKIN_SOLVER_WORKERS``      auto        expensive jobs running at once in the whole server (its
                                            slots, shared by the web processes: each has a solver
                                            worker per slot); 0 runs expensive work in the web
                                            process's threads (tests); auto: the CPUs the process
                                            may use (affinity, cgroup quota)
``PESHKIN_SOLVER_QUEUE``        16          expensive requests that may wait for a slot, per web
                                            process; beyond, or when one is predicted not to start
                                            in time, 503 at once with ``Retry-After``
``PESHKIN_SOLVER_QUEUE_WAIT_S``  1          longest an expensive request waits in the queue for a
                                            slot: predicted to wait longer, or not started by then,
                                            503 (so each gets its slot or its refusal within it)
``PESHKIN_MAX_REQUESTS_IN_FLIGHT`` 512     requests in flight per web process (cheap ones are
                                            computed at once, expensive ones wait in the queue
                                            for a slot); beyond, 503 at once
``PESHKIN_MAX_TIME_LIMIT_S``    30          the deadline of a request without its own time limit,
                                            and the cap of every time limit (up to 3600): past
                                            it 422; /openapi.json states it as the maximum
``PESHKIN_DEADLINE_GRACE_S``    0.25        how long past its deadline a worker's answer is awaited
                                            before the worker is stopped and the answer is a 504
``PESHKIN_RETRY_AFTER_S``       1           ``Retry-After`` of a 503 (seconds)
``PESHKIN_MAX_BODY_BYTES``      33554432    longest request body read, by the operations that take
                                            large bodies (``POST /v1/cor/solve``); longer: 413, unread
``PESHKIN_INLINE_BODY_BYTES``   2097152     longest body of every other operation, and the longest
                                            decoded in a web process: a longer body to
                                            ``/v1/cor/solve`` is decoded in its solver worker
``PESHKIN_WORKER_MAX_TASKS``    0           replace a solver worker after this many tasks (0: never)
``PESHKIN_HEADER_TIMEOUT_S``    10          a client must send a request's headers within this
``PESHKIN_BODY_TIMEOUT_S``      30          ... and its body within this after the headers
``PESHKIN_KEEP_ALIVE_S``        5           idle keep-alive connections are closed after this
``PESHKIN_GRACEFUL_TIMEOUT_S``  30          on shutdown, requests in flight get this long
``PESHKIN_STORE_PATH``          (tmp)       SQLite file of reusable results (r* rows of spiral
                                            localization), shared by all processes; "" for
                                            none; default <tmp>/peshkin-service/results.sqlite3
``PESHKIN_CONTROL_SOCKET``      (none)      gunicorn's control socket (``gunicornc``): a path of
                                            this instance's own; unset or "" for none (gunicorn's
                                            default, one path in the user's home, would be shared
                                            by every instance on the host)
``PESHKIN_LOG_FORMAT``          json        ``json``: one JSON object per log line (with the
                                            request id); ``text`` for people reading a terminal
``PESHKIN_ACCESS_LOG``          true        a log line per request (route, status, duration, the
                                            model that answered, the request id)
``PESHKIN_API_KEYS``            (none)      comma-separated API keys (16-256 printable characters,
                                            no spaces or commas); when set, every request but the
                                            probes and the API documents needs one (``X-API-Key``
                                            or ``Authorization: Bearer``), else 401
``PESHKIN_OPERATOR_KEYS``       (none)      comma-separated keys of the server's operators (as API
                                            keys; they are API keys too): with keys on, ``/metrics``
                                            answers only to one (403 to another key), and
                                            ``/readyz`` shows its counters and files only to one
``PESHKIN_RATE_LIMIT``          (none)      ``<requests>/<seconds>`` per API key, shared by the web
                                            processes (e.g. ``120/60``); past it 429 with
                                            ``Retry-After``; needs API keys
``PESHKIN_CORS_ORIGINS``        (none)      comma-separated origins allowed to call from a browser
                                            (``*`` for any); unset: no CORS headers (closed)
``PESHKIN_JOBS_PATH``           (tmp)       SQLite file of the jobs (``POST /v1/jobs``), shared by
                                            the web processes and kept across restarts; default
                                            <tmp>/peshkin-service/jobs.sqlite3; "" a file of the
                                            server's own (lost when it stops)
``PESHKIN_JOB_TTL_S``           86400       how long a finished job and its answer are kept
``PESHKIN_JOBS_MAX_BYTES``      1073741824  the jobs file's size cap (SQLite's page limit): past it,
                                            as with a full disk, submissions are refused 507 and
                                            ends wait until space returns
``PESHKIN_JOB_MAX_ANSWER_BYTES`` 33554432   the longest answer a job keeps (longer: the job fails,
                                            saying so)
``PESHKIN_JOB_MAX_CLIENT_BYTES`` 268435456  what one client's jobs may keep in all (bodies and
                                            answers): a submission past it is refused 507
``PESHKIN_JOB_MAX_TIME_S``      3600        the longest time limit of a job (its default)
``PESHKIN_JOB_WORKERS``         auto        jobs a web process runs at once (auto: the server's job
                                            places, all its slots but one, which the server's jobs
                                            together never exceed, so a job never takes the last
                                            slot from requests; one slot: that one); 0: this server
                                            queues jobs but runs none (another server on the same
                                            file does)
``PESHKIN_RAY_WORKERS``         auto        CPUs of the server's one local Ray that runs feeder
                                            catalogues' designs in parallel (its head started by
                                            the first solver worker that runs one, shared by all;
                                            auto: the server's slots; a catalogue runs as many
                                            designs at once as it holds slots); 0: no Ray, one
                                            design after the other
``PESHKIN_RAY_ADDRESS``         (none)      an existing Ray cluster for the catalogues instead
                                            (``host:port`` of its head; its ``RAY_AUTH_MODE`` and
                                            token as the cluster requires)
==============================  ==========  =====================================================

``python -m service`` starts the supervisor (gunicorn) with these; ``uvicorn
service.app:app`` runs one web process and takes host and port from its own command line.
"""

from __future__ import annotations

import math
import os
import tempfile
from collections.abc import Callable, Mapping
from dataclasses import dataclass, fields
from typing import Any

from service.limits import MAX_TIME_LIMIT_S, TIME_LIMIT_HARD_MAX_S
from service.runtime.slots import job_places_of, usable_cpus

DEFAULT_JOBS_PATH = os.path.join(tempfile.gettempdir(), "peshkin-service", "jobs.sqlite3")
"""The jobs file of a server whose environment names none (shared by its web processes and
kept across its restarts). A ``Settings`` made in code without one, and "" in the
environment, give each app a file of its own in a new temporary directory."""

LOG_LEVELS = ("critical", "error", "warning", "info", "debug", "trace")
AUTO = -1
"""``solver_workers`` chosen from the CPUs (:meth:`Settings.solver_processes`)."""


@dataclass(frozen=True)
class Settings:
    host: str = "127.0.0.1"
    port: int = 8000
    log_level: str = "info"
    web_workers: int = 2
    solver_workers: int = AUTO
    solver_queue: int = 16
    solver_queue_wait_s: float = 1.0
    max_requests_in_flight: int = 512
    max_time_limit_s: float = MAX_TIME_LIMIT_S
    deadline_grace_s: float = 0.25
    retry_after_s: int = 1
    max_body_bytes: int = 32 * 1024 * 1024
    inline_body_bytes: int = 2 * 1024 * 1024
    worker_max_tasks: int = 0
    header_timeout_s: float = 10.0
    body_timeout_s: float = 30.0
    keep_alive_s: float = 5.0
    graceful_timeout_s: float = 30.0
    store_path: str = os.path.join(tempfile.gettempdir(), "peshkin-service", "results.sqlite3")
    control_socket: str = ""
    log_format: str = "json"
    access_log: bool = True
    api_keys: tuple[str, ...] = ()
    operator_keys: tuple[str, ...] = ()
    rate_limit: tuple[int, float] | None = None
    cors_origins: tuple[str, ...] = ()
    jobs_path: str = ""  # from the environment: DEFAULT_JOBS_PATH unless set (Settings() in code: its own)
    job_ttl_s: float = 86400.0
    jobs_max_bytes: int = 1 << 30
    job_max_answer_bytes: int = 32 * 1024 * 1024
    job_max_client_bytes: int = 256 * 1024 * 1024
    job_max_time_s: float = 3600.0
    job_workers: int = AUTO
    ray_workers: int = AUTO
    ray_address: str = ""

    def job_concurrency(self) -> int:
        """Jobs a web process runs at once: the setting, or (auto) the server's job places
        (all its slots but one: the server's jobs together never hold more)."""
        if self.job_workers != AUTO:
            return self.job_workers
        return job_places_of(max(1, self.solver_processes()))

    def ray_cpus(self, cpus: int | None = None) -> int:
        """CPUs of the server's local Ray for catalogues: the setting, or (auto) the server's
        slots (one account of the CPUs: a catalogue runs as many tasks at once as it holds
        slots)."""
        if self.ray_workers != AUTO:
            return self.ray_workers
        return self.solver_processes(cpus)

    def __repr__(self) -> str:  # the keys never reach a log
        shown = {f.name: getattr(self, f.name) for f in fields(self)}
        shown["api_keys"] = f"<{len(self.api_keys)} keys>"
        shown["operator_keys"] = f"<{len(self.operator_keys)} keys>"
        return "Settings(" + ", ".join(f"{k}={v!r}" for k, v in shown.items()) + ")"

    @classmethod
    def from_env(cls, environ: Mapping[str, str] | None = None) -> Settings:
        env = os.environ if environ is None else environ
        values: dict[str, Any] = {}
        for f in fields(cls):
            name = f"PESHKIN_{f.name.upper()}"
            text = env.get(name)
            if text is None or (not text.strip() and f.name != "store_path"):  # "" turns the store off
                continue
            values[f.name] = _PARSERS[f.name](name, text.strip())
        if env.get("PESHKIN_JOBS_PATH") is None:
            values["jobs_path"] = DEFAULT_JOBS_PATH
        return cls(**values)

    def solver_processes(self, cpus: int | None = None) -> int:
        """Slots of the server (expensive jobs running at once, whichever web process took
        them), and so solver workers per web process: the setting, or (auto) the CPUs the
        process may use (affinity and a container's CPU quota, not the host's count)."""
        if self.solver_workers != AUTO:
            return self.solver_workers
        return max(1, cpus if cpus is not None else usable_cpus())


def _integer(low: int, high: int, auto: bool = False) -> Callable[[str, str], int]:
    def parse(name: str, text: str) -> int:
        if auto and text.lower() == "auto":
            return AUTO
        try:
            value = int(text)
        except ValueError:
            raise ValueError(f"{name} must be an integer, got {text!r}") from None
        if not low <= value <= high:
            raise ValueError(f"{name} must be in {low}..{high}, got {value}")
        return value

    return parse


def _seconds(low: float, high: float) -> Callable[[str, str], float]:
    def parse(name: str, text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise ValueError(f"{name} must be a number of seconds, got {text!r}") from None
        if not (math.isfinite(value) and low < value <= high):
            raise ValueError(f"{name} must be in ({low:g}, {high:g}] s, got {text}")
        return value

    return parse


def _log_level(name: str, text: str) -> str:
    level = text.lower()
    if level not in LOG_LEVELS:
        raise ValueError(f"{name} must be one of {LOG_LEVELS}, got {text!r}")
    return level


def _choice(*allowed: str) -> Callable[[str, str], str]:
    def parse(name: str, text: str) -> str:
        if text.lower() not in allowed:
            raise ValueError(f"{name} must be one of {allowed}, got {text!r}")
        return text.lower()

    return parse


def _flag(name: str, text: str) -> bool:
    value = text.lower()
    if value not in ("true", "false", "1", "0", "yes", "no", "on", "off"):
        raise ValueError(f"{name} must be true or false, got {text!r}")
    return value in ("true", "1", "yes", "on")


def _api_keys(name: str, text: str) -> tuple[str, ...]:
    keys = tuple(k.strip() for k in text.split(",") if k.strip())
    for i, key in enumerate(keys):
        if not (16 <= len(key) <= 256 and key.isascii() and key.isprintable() and " " not in key):
            raise ValueError(f"{name}: key {i + 1} must be 16-256 printable ASCII characters without spaces")
    return keys


def _rate(name: str, text: str) -> tuple[int, float]:
    count, _, seconds = text.partition("/")
    try:
        n, s = int(count), float(seconds)
    except ValueError:
        raise ValueError(f"{name} must be <requests>/<seconds>, e.g. 120/60, got {text!r}") from None
    if not (1 <= n <= 10**9 and math.isfinite(s) and 0.001 <= s <= 86400.0):
        raise ValueError(f"{name}: 1..1e9 requests per 0.001..86400 s, got {text!r}")
    return n, s


def _origins(name: str, text: str) -> tuple[str, ...]:
    origins = tuple(o.strip().rstrip("/") for o in text.split(",") if o.strip())
    for o in origins:
        if o != "*" and not (o.startswith("http://") or o.startswith("https://")):
            raise ValueError(f"{name}: {o!r} is not an origin (http[s]://host[:port], or *)")
    return origins


_PARSERS: dict[str, Callable[[str, str], Any]] = {
    "host": lambda name, text: text,
    "port": _integer(1, 65535),
    "log_level": _log_level,
    "control_socket": lambda name, text: text,
    "web_workers": _integer(1, 256),
    "solver_workers": _integer(0, 1024, auto=True),
    "solver_queue": _integer(0, 100_000),
    "solver_queue_wait_s": _seconds(0.0, 3600.0),
    "max_requests_in_flight": _integer(1, 100_000),
    "max_time_limit_s": _seconds(0.0, TIME_LIMIT_HARD_MAX_S),
    "deadline_grace_s": _seconds(0.0, 60.0),
    "retry_after_s": _integer(1, 3600),
    "max_body_bytes": _integer(1024, 1 << 31),
    "inline_body_bytes": _integer(1024, 1 << 31),
    "worker_max_tasks": _integer(0, 10**9),
    "header_timeout_s": _seconds(0.0, 3600.0),
    "body_timeout_s": _seconds(0.0, 3600.0),
    "keep_alive_s": _seconds(0.0, 3600.0),
    "graceful_timeout_s": _seconds(0.0, 3600.0),
    "store_path": lambda name, text: text,
    "log_format": _choice("json", "text"),
    "access_log": _flag,
    "api_keys": _api_keys,
    "operator_keys": _api_keys,
    "rate_limit": _rate,
    "cors_origins": _origins,
    "jobs_path": lambda name, text: text,
    "job_ttl_s": _seconds(0.0, 365 * 86400.0),
    "jobs_max_bytes": _integer(65536, 1 << 50),
    "job_max_answer_bytes": _integer(1024, 1 << 40),
    "job_max_client_bytes": _integer(1024, 1 << 50),
    "job_max_time_s": _seconds(0.0, TIME_LIMIT_HARD_MAX_S),
    "job_workers": _integer(0, 1024, auto=True),
    "ray_workers": _integer(0, 1024, auto=True),
    "ray_address": lambda name, text: text,
}
