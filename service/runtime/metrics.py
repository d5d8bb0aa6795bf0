"""Prometheus metrics (prometheus-client), served at ``GET /metrics``.

Under the supervisor (``python -m service``) every web process writes its samples to the
server's directory (``PROMETHEUS_MULTIPROC_DIR``, made at start by :mod:`service.server`)
and ``/metrics`` answers for the whole server, whichever process takes the scrape:
counters and histograms summed over the processes (those that have ended included),
gauges summed over the live ones. A web process run alone (``uvicorn service.app:app``,
the tests) keeps its samples in memory.

* ``peshkin_http_requests_total{route, method, status}``: answers sent (a route's path
  template; ``other`` for paths the service does not have);
* ``peshkin_http_request_duration_seconds{route}``: from arrival to the last byte;
* ``peshkin_queue_depth``: expensive requests waiting for a solver slot;
* ``peshkin_workers_busy``: solver slots running a job;
* ``peshkin_jobs{state}``: the jobs of ``POST /v1/jobs`` by state (queued, running,
  succeeded, failed, cancelled), read from the server's jobs file at the scrape;
* ``peshkin_solver_seconds{backend}``: each job's time in each numerical back end
  (``clarabel``, ``casadi``, ``ortools``; ``other``: the rest, numpy and Python;
  :mod:`solver.core.backends`).
"""

from __future__ import annotations

import os

from prometheus_client import (
    CONTENT_TYPE_LATEST,
    REGISTRY,
    CollectorRegistry,
    Counter,
    Gauge,
    Histogram,
    generate_latest,
    multiprocess,
)

from service.runtime.admission import Gate, RunQueue
from service.runtime.slots import METRICS_DIR_ENV

CONTENT_TYPE = CONTENT_TYPE_LATEST

LATENCY_BUCKETS = (0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1.0, 2.5, 5.0, 10.0, 30.0, 60.0, 120.0,
                   300.0, 900.0, 3600.0)
"""Seconds: from a closed form (a millisecond) to a job at the largest time limit."""

REQUESTS = Counter("peshkin_http_requests", "HTTP answers sent, by route template, method and status.",
                   ["route", "method", "status"])
LATENCY = Histogram("peshkin_http_request_duration_seconds", "Time from a request's arrival to its answer's "
                    "last byte, by route template.", ["route"], buckets=LATENCY_BUCKETS)
QUEUE_DEPTH = Gauge("peshkin_queue_depth", "Expensive requests waiting for a solver slot.",
                    multiprocess_mode="livesum")
WORKERS_BUSY = Gauge("peshkin_workers_busy", "Solver slots running a job.", multiprocess_mode="livesum")
JOBS = Gauge("peshkin_jobs", "Jobs (POST /v1/jobs) by state, in the server's jobs file.", ["state"],
             multiprocess_mode="mostrecent")
SOLVER_SECONDS = Histogram("peshkin_solver_seconds", "A job's time in each numerical back end (other: numpy "
                           "and Python).", ["backend"], buckets=LATENCY_BUCKETS)


def observe_request(route: str, method: str, status: int, seconds: float) -> None:
    REQUESTS.labels(route, method, str(status)).inc()
    LATENCY.labels(route).observe(seconds)


def observe_backends(spent: dict[str, float]) -> None:
    """One job's seconds per back end (:func:`solver.core.backends.close_ledger`, with
    ``other``)."""
    for backend, seconds in spent.items():
        SOLVER_SECONDS.labels(backend).observe(seconds)


_last_work: list[tuple[int, int] | None] = [None]


def observe_work(expensive: Gate | RunQueue) -> None:
    """This web process's expensive work now: waiting and running (written only when it
    changed: under the supervisor each write goes to the samples' file)."""
    if isinstance(expensive, RunQueue):
        now = (len(expensive.waiting), len(expensive.running))
    else:
        now = (0, expensive.state().in_use)
    if now == _last_work[0]:
        return
    _last_work[0] = now
    QUEUE_DEPTH.set(now[0])
    WORKERS_BUSY.set(now[1])


def observe_jobs(counts: dict[str, int], states: tuple[str, ...]) -> None:
    """The jobs by state (read from the jobs file when scraped)."""
    for state in states:
        JOBS.labels(state).set(counts.get(state, 0))


def exposition() -> bytes:
    """The samples in Prometheus's text format: the whole server's when it has a samples
    directory, else this process's."""
    directory = os.environ.get(METRICS_DIR_ENV)
    if not directory:
        return generate_latest(REGISTRY)
    registry = CollectorRegistry()
    multiprocess.MultiProcessCollector(registry, path=directory)
    return generate_latest(registry)


def process_ended(pid: int) -> None:
    """Drop a web process's live gauges (gunicorn's ``child_exit``)."""
    if os.environ.get(METRICS_DIR_ENV):
        multiprocess.mark_process_dead(pid)
