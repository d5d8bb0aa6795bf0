"""What the people who run the service see (issue 27, operations): the request id in the
answer, its errors and the log; the access log; the Prometheus metrics moving as requests
are served; API keys (401), per-key rate limits shared by the web processes (429 with
Retry-After); CORS closed unless configured."""

from __future__ import annotations

import json
import logging
import re
import subprocess
import sys
import warnings

import pytest
from prometheus_client.parser import text_string_to_metric_families
from starlette.exceptions import StarletteDeprecationWarning

from service.app import create_app
from service.runtime.access import KeyRates, key_id
from service.runtime.logs import ACCESS
from service.runtime.slots import SLOT_DIR_ENV
from service.settings import Settings

with warnings.catch_warnings():
    warnings.simplefilter("ignore", StarletteDeprecationWarning)
    from fastapi.testclient import TestClient

LOCUS = {"disk_radius": 1, "contact_point": [0.2, 0.3], "edge_angle": 1.5708, "outputs": ["tip"]}
MEMBERSHIP = {"disk_radius": 1, "contact_point": [-0.5, -0.3], "edge_angle": 1.5707963267948966, "cor": [0, 4]}
KEY_A, KEY_B = "a" * 16 + "-first-key", "b" * 16 + "-second-key"


def client_of(**settings):
    return TestClient(create_app(Settings(solver_workers=0, store_path="", **settings)),
                      raise_server_exceptions=False)


class Records(logging.Handler):
    def __init__(self):
        super().__init__()
        self.records: list[logging.LogRecord] = []

    def emit(self, record):
        self.records.append(record)


@pytest.fixture
def access_records():
    handler = Records()
    logger = logging.getLogger(ACCESS)
    logger.addHandler(handler)
    yield handler.records
    logger.removeHandler(handler)


def samples(text: str) -> dict[tuple[str, tuple], float]:
    out = {}
    for family in text_string_to_metric_families(text):
        for s in family.samples:
            out[(s.name, tuple(sorted(s.labels.items())))] = s.value
    return out


# --- the request id --------------------------------------------------------------------------


def test_the_request_id_is_echoed_or_made_and_is_in_every_error_body(access_records):
    with client_of() as c:
        ok = c.post("/v1/cor/locus", json=LOCUS, headers={"X-Request-ID": "line-7/part:42"})
        assert ok.status_code == 200 and ok.headers["x-request-id"] == "line-7/part:42"
        assert "request_id" not in ok.json()  # answers are not touched
        made = c.post("/v1/cor/locus", json=LOCUS, headers={"X-Request-ID": "no spaces please"})
        assert re.fullmatch(r"[0-9a-f]{32}", made.headers["x-request-id"])
        bad = c.post("/v1/cor/locus", json={**LOCUS, "disk_radius": -1}, headers={"X-Request-ID": "r-422"})
        assert bad.status_code == 422 and bad.json()["request_id"] == "r-422"
        assert bad.json()["detail"][0]["loc"][:2] == ["body", "disk_radius"]
        assert int(bad.headers["content-length"]) == len(bad.content)
        missing = c.get("/v1/nothing-here")
        assert missing.status_code == 404 and missing.json()["request_id"] == missing.headers["x-request-id"]
    by_id = {r.request_id: r for r in access_records}
    rec = by_id["line-7/part:42"]
    assert (rec.route, rec.method, rec.status, rec.model) == ("/v1/cor/locus", "POST", 200, "analytic")
    assert rec.duration_ms > 0.0
    assert by_id["r-422"].status == 422
    assert by_id[missing.headers["x-request-id"]].route == "other"


def test_the_json_log_line_carries_the_request_id():
    """The handler the service installs formats each record as one JSON object, with the
    request id, level, logger and message."""
    with client_of(log_format="json"):
        handler = next(h for h in logging.getLogger("service").handlers if getattr(h, "peshkin", False))
    record = logging.LogRecord(ACCESS, logging.INFO, __file__, 1, "POST %s 200", ("/v1/cor/locus",), None)
    record.request_id = "abc"
    record.status = 200
    assert handler.filter(record)
    line = json.loads(handler.format(record))
    assert line["request_id"] == "abc" and line["status"] == 200 and line["level"] == "INFO"
    assert line["logger"] == ACCESS and line["message"] == "POST /v1/cor/locus 200" and "time" in line


def test_the_access_log_can_be_turned_off(access_records):
    with client_of(access_log=False) as c:
        assert c.post("/v1/cor/locus", json=LOCUS).status_code == 200
    assert access_records == []


# --- metrics ---------------------------------------------------------------------------------


def test_metrics_move_when_requests_are_served():
    with client_of() as c:
        before = samples(c.get("/metrics").text)
        for _ in range(3):
            assert c.post("/v1/cor/locus", json=LOCUS).status_code == 200
        assert c.post("/v1/cor/locus", json={**LOCUS, "disk_radius": 0}).status_code == 422
        assert c.post("/v1/cor/membership", json=MEMBERSHIP).status_code == 200  # a certified query
        page = c.get("/metrics")
    assert page.status_code == 200 and page.headers["content-type"].startswith("text/plain")
    after = samples(page.text)

    def delta(name, **labels):
        key = (name, tuple(sorted(labels.items())))
        return after.get(key, 0.0) - before.get(key, 0.0)

    route = "/v1/cor/locus"
    assert delta("peshkin_http_requests_total", route=route, method="POST", status="200") == 3
    assert delta("peshkin_http_requests_total", route=route, method="POST", status="422") == 1
    assert delta("peshkin_http_request_duration_seconds_count", route=route) == 4
    assert delta("peshkin_solver_seconds_count", backend="clarabel") >= 1
    assert delta("peshkin_solver_seconds_sum", backend="clarabel") > 0.0
    for gauge in ("peshkin_queue_depth", "peshkin_workers_busy"):
        assert after[(gauge, ())] == 0.0  # nothing waits or runs once the answers are in
    assert after[("peshkin_jobs", (("state", "running"),))] == 0.0  # no job submitted


# --- API keys, rate limits, CORS ---------------------------------------------------------------


def test_a_request_without_a_key_is_refused_when_keys_are_on():
    with client_of(api_keys=(KEY_A, KEY_B)) as c:
        none = c.post("/v1/cor/locus", json=LOCUS)
        assert none.status_code == 401 and none.headers["www-authenticate"].startswith("Bearer")
        assert none.json()["detail"][0]["type"] == "unauthorized" and "request_id" in none.json()
        wrong = c.post("/v1/cor/locus", json=LOCUS, headers={"X-API-Key": "z" * 20})
        assert wrong.status_code == 401 and "not known" in wrong.json()["detail"][0]["msg"]
        assert c.post("/v1/cor/locus", json=LOCUS, headers={"X-API-Key": KEY_A}).status_code == 200
        assert c.post("/v1/cor/locus", json=LOCUS, headers={"Authorization": f"Bearer {KEY_B}"}).status_code == 200
        assert c.get("/metrics").status_code == 401
        assert c.get("/metrics", headers={"X-API-Key": KEY_A}).status_code == 403  # an API key is not an operator's
        for open_path in ("/healthz", "/readyz", "/openapi.json", "/docs"):
            assert c.get(open_path).status_code == 200, open_path
    with client_of() as c:  # keys off: open
        assert c.post("/v1/cor/locus", json=LOCUS).status_code == 200


OPERATOR = "o" * 24


def test_metrics_and_the_readiness_counters_are_for_operators_only():
    """Issue 35, point 9: with keys on, /metrics (every key's routes and jobs) answers only an
    operator key, and /readyz shows its gates and files only to one; anyone sees its status."""
    with client_of(api_keys=(KEY_A,), operator_keys=(OPERATOR,)) as c:
        assert c.get("/metrics", headers={"X-API-Key": KEY_A}).status_code == 403
        assert c.get("/metrics", headers={"X-API-Key": OPERATOR}).status_code == 200
        public = c.get("/readyz").json()
        assert public["status"] == "ready" and public["gates"] is None and public["storage"] is None
        assert c.get("/readyz", headers={"X-API-Key": KEY_A}).json()["gates"] is None
        shown = c.get("/readyz", headers={"X-API-Key": OPERATOR}).json()
        assert [g["name"] for g in shown["gates"]] == ["requests", "expensive"]
        assert shown["storage"][0]["name"] == "jobs" and shown["storage"][0]["state"] == "ok"
        assert c.post("/v1/cor/locus", json=LOCUS, headers={"X-API-Key": OPERATOR}).status_code == 200
    with client_of() as c:  # keys off: open to all
        assert c.get("/metrics").status_code == 200 and c.get("/readyz").json()["gates"] is not None


def test_the_access_log_names_the_key_never_the_key(access_records):
    with client_of(api_keys=(KEY_A,)) as c:
        c.post("/v1/cor/locus", json=LOCUS, headers={"X-API-Key": KEY_A})
    assert access_records[-1].client == key_id(KEY_A) and KEY_A not in repr(vars(access_records[-1]))
    assert KEY_A not in repr(Settings(api_keys=(KEY_A,)))


def test_rate_limits_are_per_key_and_answered_429_with_retry_after(tmp_path, monkeypatch):
    monkeypatch.setenv(SLOT_DIR_ENV, str(tmp_path))  # one server's slot directory: shared counts
    with client_of(api_keys=(KEY_A, KEY_B), rate_limit=(3, 60.0)) as c, \
            client_of(api_keys=(KEY_A, KEY_B), rate_limit=(3, 60.0)) as other_process:
        a = {"X-API-Key": KEY_A}
        assert [c.post("/v1/cor/locus", json=LOCUS, headers=a).status_code for _ in range(2)] == [200, 200]
        assert other_process.post("/v1/cor/locus", json=LOCUS, headers=a).status_code == 200
        over = c.post("/v1/cor/locus", json=LOCUS, headers=a)
        assert over.status_code == 429 and over.json()["detail"][0]["type"] == "rate_limited"
        assert 1 <= int(over.headers["retry-after"]) <= 60
        assert other_process.post("/v1/cor/locus", json=LOCUS, headers=a).status_code == 429
        assert c.post("/v1/cor/locus", json=LOCUS, headers={"X-API-Key": KEY_B}).status_code == 200
        assert c.get("/healthz").status_code == 200  # probes are never counted


def test_rate_counts_are_shared_with_another_process(tmp_path):
    """Two admissions made by another Python process count against the same key here."""
    code = ("import sys; from service.runtime.access import KeyRates; "
            f"r = KeyRates(3, 60.0, {str(tmp_path)!r}); "
            "print([r.admit('k1') for _ in range(2)]); r.close()")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, check=True)
    assert out.stdout.strip() == "[None, None]"
    here = KeyRates(3, 60.0, str(tmp_path))
    try:
        assert here.admit("k1") is None
        wait = here.admit("k1")
        assert wait is not None and 0.0 < wait <= 60.0
        assert here.admit("k2") is None
    finally:
        here.close()


def test_cors_is_closed_unless_configured():
    origin = {"Origin": "https://hmi.example.org"}
    preflight = {**origin, "Access-Control-Request-Method": "POST", "Access-Control-Request-Headers": "content-type"}
    with client_of() as c:
        r = c.post("/v1/cor/locus", json=LOCUS, headers=origin)
        assert r.status_code == 200 and "access-control-allow-origin" not in r.headers
        assert "access-control-allow-origin" not in c.options("/v1/cor/locus", headers=preflight).headers
    with client_of(cors_origins=("https://hmi.example.org",), api_keys=(KEY_A,)) as c:
        pre = c.options("/v1/cor/locus", headers=preflight)  # a preflight carries no key
        assert pre.status_code == 200 and pre.headers["access-control-allow-origin"] == "https://hmi.example.org"
        r = c.post("/v1/cor/locus", json=LOCUS, headers={**origin, "X-API-Key": KEY_A})
        assert r.headers["access-control-allow-origin"] == "https://hmi.example.org"
        assert "x-request-id" in r.headers["access-control-expose-headers"]
        cancel = c.options("/v1/jobs/x", headers={**preflight, "Access-Control-Request-Method": "DELETE"})
        assert cancel.status_code == 200 and "DELETE" in cancel.headers["access-control-allow-methods"]
        other = c.options("/v1/cor/locus", headers={**preflight, "Origin": "https://evil.example.com"})
        assert "access-control-allow-origin" not in other.headers


def test_a_rate_limit_needs_keys():
    with pytest.raises(ValueError, match="PESHKIN_API_KEYS"):
        create_app(Settings(solver_workers=0, store_path="", rate_limit=(10, 1.0)))
