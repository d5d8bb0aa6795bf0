"""The intake (service/runtime/intake.py): every request's arrival is stamped before the
app runs, a full gate of requests in flight answers 503 with Retry-After at once, and the
probes are never refused."""

from __future__ import annotations

import asyncio
import json
import time

from service.runtime.admission import Gate
from service.runtime.deadline import ARRIVAL_KEY, arrival
from service.runtime.intake import Intake


def _call(intake: Intake, path: str) -> list[dict]:
    sent: list[dict] = []

    async def send(message: dict) -> None:
        sent.append(message)

    asyncio.run(intake({"type": "http", "path": path}, None, send))
    return sent


def test_the_arrival_is_stamped_before_the_app_runs():
    seen = {}

    async def app(scope, receive, send):
        seen["arrived"] = arrival(scope)
        seen["in_use"] = gate.state().in_use

    gate = Gate("requests", 4)
    before = time.monotonic()
    scope = {"type": "http", "path": "/v1/cor/locus"}
    asyncio.run(Intake(app, gate, 1, {}, 1 << 20)(scope, None, None))
    assert scope["state"][ARRIVAL_KEY] == seen["arrived"] and before <= seen["arrived"] <= time.monotonic()
    assert seen["in_use"] == 1 and gate.state().in_use == 0


def test_a_full_gate_answers_503_with_retry_after_and_probes_pass():
    ran = []

    async def app(scope, receive, send):
        ran.append(scope["path"])

    gate = Gate("requests", 1)
    assert gate.try_enter()  # someone holds the only place
    start, body = _call(Intake(app, gate, 7, {}, 1 << 20), "/v1/cor/locus")
    assert start["status"] == 503 and (b"retry-after", b"7") in start["headers"]
    assert json.loads(body["body"])["detail"][0]["type"] == "busy"
    assert _call(Intake(app, gate, 7, {}, 1 << 20), "/readyz") == [] and ran == ["/readyz"]
    assert gate.state().refused == 1


def test_an_unexpected_error_is_a_500_answer_not_a_dropped_connection():
    async def app(scope, receive, send):
        raise KeyError("a bug")

    start, body = _call(Intake(app, Gate("requests", 2), 1, {}, 1 << 20), "/v1/cor/locus")
    assert start["status"] == 500 and json.loads(body["body"])["detail"][0]["type"] == "internal_error"
