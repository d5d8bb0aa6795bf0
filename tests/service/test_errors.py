"""Error handling (service/errors.py): input problems are 422 naming the field, solver
failures 422 ``solver_error``, a time limit that runs out is 504 with what was reached and
what was finished, arithmetic trouble 422 ``numeric_range``, and a bug is a 500 that
never carries a traceback. Exercised through POST /v1/cor/locus with its solver replaced."""

from __future__ import annotations

import math

import pytest

from models.locus.cor_disk import BoundaryNotConverged
from service.errors import TimeLimitAnswer, json_safe, time_limit_body, time_limited
from solver.core.errors import NotConverged, TimeLimitReached

URL = "/v1/cor/locus"
BASE = {"disk_radius": 1.0, "contact_point": [-0.5, -0.3], "edge_angle": math.pi / 2}


def post(client, body, params=None):
    return client.post(URL, json=body, params=params)


def test_body_not_utf8_is_422(client):
    r = client.post(URL, content=b"\xff\xfe{\x00", headers={"content-type": "application/json"})
    assert r.status_code == 422
    assert r.json()["detail"][0]["type"] == "json_invalid"


def test_other_model_errors_are_422(client, monkeypatch):
    import solver.locus.cor_locus as cor

    def fail(*args, **kwargs):
        raise BoundaryNotConverged("outer COR boundary (3.35) did not converge")

    monkeypatch.setattr(cor, "disk_cor_locus", fail)
    r = post(client, BASE)
    assert r.status_code == 422
    d = r.json()["detail"][0]
    assert d["loc"] == ["body"] and d["type"] == "model_error" and "did not converge" in d["msg"]


def test_float_arithmetic_errors_are_422(client, monkeypatch):
    import solver.locus.cor_locus as cor

    def overflow(*args, **kwargs):
        raise OverflowError("math range error")

    monkeypatch.setattr(cor, "disk_cor_locus", overflow)
    r = post(client, BASE)
    assert r.status_code == 422
    d = r.json()["detail"][0]
    assert d["loc"] == ["body"] and d["type"] == "numeric_range" and "Traceback" not in d["msg"]


def test_unexpected_errors_are_500_without_traceback(client, monkeypatch):
    import solver.locus.cor_locus as cor

    def boom(*args, **kwargs):
        raise RuntimeError("secret internals")

    monkeypatch.setattr(cor, "disk_cor_locus", boom)
    r = post(client, BASE)
    assert r.status_code == 500
    assert r.json()["detail"][0]["type"] == "internal_error"
    assert "secret internals" not in r.text and "Traceback" not in r.text


def test_json_safe_replaces_non_finite_numbers():
    assert json_safe({"a": [1.0, float("nan")], "b": (float("inf"), "x", None, True)}) == {
        "a": [1.0, "nan"], "b": ["inf", "x", None, True],
    }


def _replace_locus(monkeypatch, error: Exception) -> None:
    import service.api.locus.routes as routes

    def fail(*args, **kwargs):
        raise error

    monkeypatch.setattr(routes, "locus_of", fail)


def test_solver_errors_are_422(client, monkeypatch):
    _replace_locus(monkeypatch, NotConverged("IPOPT ended with status Maximum_Iterations_Exceeded"))
    r = post(client, BASE)
    assert r.status_code == 422
    d = r.json()["detail"][0]
    assert d["loc"] == ["body"] and d["type"] == "solver_error" and "Maximum_Iterations_Exceeded" in d["msg"]


def test_a_time_limit_is_504_saying_where(client, monkeypatch):
    """A TimeLimitReached that no route converted: 504, where it stopped, no partial."""
    _replace_locus(monkeypatch, TimeLimitReached("the sketch at beta = 0.5", 2.0, 2.5, partial=("not", "json")))
    r = post(client, BASE)
    assert r.status_code == 504
    body = r.json()
    assert body.pop("request_id") == r.headers["x-request-id"]
    assert body == {
        "detail": [{"loc": ["body", "time_limit_s"], "type": "time_limit",
                    "msg": "ran out after 2.5 s (time_limit_s = 2 s) before the sketch at beta = 0.5: "
                           "ask for less work; or raise time_limit_s (up to 30 s on this deployment), or submit "
                           "it as a job (POST /v1/jobs, up to 3600 s)"}],
        "reached": "the sketch at beta = 0.5", "time_limit_s": 2.0, "elapsed_s": 2.5, "partial": None,
    }


def test_time_limited_converts_the_partial_result():
    reached = TimeLimitReached("stage 2", 1.0, 1.25, partial=(1.0, 2.0))
    with pytest.raises(TimeLimitAnswer) as info:
        with time_limited(lambda done: {"stages": list(done), "nan": float("nan")}, hint="lower n_nodes"):
            raise reached
    ans = info.value
    assert ans.reached is reached and ans.partial == {"stages": [1.0, 2.0], "nan": ans.partial["nan"]}
    body = time_limit_body(ans.reached, ans.partial, ans.hint)
    assert body["partial"] == {"stages": [1.0, 2.0], "nan": "nan"}  # JSON-safe
    assert "before stage 2: lower n_nodes; or raise time_limit_s" in body["detail"][0]["msg"]
    with pytest.raises(TimeLimitAnswer) as info:  # nothing finished: no partial
        with time_limited(lambda done: {"never": done}):
            raise TimeLimitReached("stage 1", None, 0.5)
    assert info.value.partial is None
    assert "no time limit" in time_limit_body(info.value.reached, None, "x")["detail"][0]["msg"]


def test_a_504_at_the_deployments_cap_points_to_a_job_not_a_longer_limit():
    """Issue 35, point 11: raising time_limit_s past the cap is a 422, so a 504 at the cap
    says to submit a job instead."""
    from service.errors import limit_advice

    assert "raise time_limit_s (up to 30 s" in limit_advice(10.0)
    at_cap = limit_advice(30.0)
    assert "raise" not in at_cap and "POST /v1/jobs" in at_cap and "30 s is this deployment's cap" in at_cap
