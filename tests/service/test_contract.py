"""Contract test: schemathesis drives every operation of the OpenAPI document in-process
(ASGI, no network) and checks that the service never answers 5xx other than the documented
504 of a time limit (TIME_LIMIT_STATUS; a 500 is never right), that every status code and
media type it answers is documented (so a 504 only where the operation documents it), and
that bodies conform to their schemas.

Bounded in time: derandomized (seeded) Hypothesis, a few dozen examples per operation
and generation mode (positive data from the schema and negative data that violates it).
Valid time budgets of the certificate searches (``time_limit_s``, default 10 s) are cut to
CONTRACT_TIME_LIMIT_S so that one example cannot take seconds. The gross-motion endpoints
(/v1/push/align, /v1/push/disk-encounter) build a COR sketch per quadrature node: their
valid n_nodes and n_points are cut to the minimum and their time budget to
CONTRACT_GROSS_TIME_LIMIT_S, which admits one exact bound of 6 small sketches (~0.5 s) and
refuses more by the service's cost model (a documented 422). The spiral endpoints get
CONTRACT_SPIRAL_TIME_LIMIT_S and at most one simulated support; the feeder endpoints
CONTRACT_FEEDER_TIME_LIMIT_S, at most CONTRACT_FEEDER_MAX_STEPS steps per fence and
CONTRACT_FEEDER_MAX_VALIDATION simulated parts per design.
Everything else is as generated.
"""

from __future__ import annotations

import os

import hypothesis
import msgpack
import pytest
import schemathesis
from schemathesis.checks import not_a_server_error
from schemathesis.specs.openapi.checks import (
    content_type_conformance,
    response_schema_conformance,
    status_code_conformance,
)

from service.app import app
from service.limits import (
    FEEDER_MAX_VALIDATION_PARTS,
    GROSS_MAX_N_NODES,
    GROSS_MIN_N_NODES,
    MAX_TIME_LIMIT_S,
    MIN_N_POINTS,
    SKETCH_MAX_N_POINTS,
)

MAX_EXAMPLES = int(os.environ.get("CONTRACT_MAX_EXAMPLES", "40"))
"""Per operation and generation mode; raise it (e.g. CONTRACT_MAX_EXAMPLES=400) for a
deeper, slower search."""

CONTRACT_TIME_LIMIT_S = 0.2
CONTRACT_GROSS_TIME_LIMIT_S = 0.7
GROSS_PATHS = ("/v1/push/align", "/v1/push/disk-encounter")
SPIRAL_PATHS = ("/v1/spiral/critical-radius", "/v1/spiral/schedule")
CONTRACT_SPIRAL_TIME_LIMIT_S = 0.3
FEEDER_PATHS = ("/v1/feeder/map", "/v1/feeder/simulate", "/v1/feeder/design")
CONTRACT_FEEDER_MAX_VALIDATION = 2
CONTRACT_FEEDER_TIME_LIMIT_S = 0.3
CONTRACT_FEEDER_MAX_STEPS = 200

SCENES_PATH = "/v1/scenes/analyze"
CATALOGUE_PATH = "/v1/feeder/catalogue"
CONTRACT_SCENES_TIME_LIMIT_S = 0.5

TIME_LIMIT_STATUS = "504"
"""A time limit that runs out (on a busy machine, within the capped budgets below) is
answered 504 with what was reached: documented, so not a server error."""

@schemathesis.serializer("application/msgpack")
def msgpack_body(ctx, value):
    """The batch routes take msgpack bodies (service.common.binary). msgpack carries
    integers of 64 bits at most: a larger one (a negative example) goes as a float."""
    return msgpack.packb(_floated(value))


def _floated(value):
    if isinstance(value, bool):
        return value
    if isinstance(value, int):
        return value if -(2**63) <= value < 2**64 else float(value)
    if isinstance(value, list):
        return [_floated(v) for v in value]
    if isinstance(value, dict):
        return {k: _floated(v) for k, v in value.items()}
    return value


@schemathesis.deserializer("application/msgpack")
def msgpack_answer(ctx, response):
    return msgpack.unpackb(response.content)


app.state.deferred.concurrency = 0  # jobs are queued and answered, never run here (they would load the suite)
schema = schemathesis.openapi.from_asgi("/openapi.json", app)
schema.config.generation.update(
    modes=[schemathesis.GenerationMode.POSITIVE, schemathesis.GenerationMode.NEGATIVE],
)
schema.config.checks.not_a_server_error.expected_statuses = ["2xx", "3xx", "4xx", TIME_LIMIT_STATUS]

CHECKS = [
    not_a_server_error,
    status_code_conformance,
    content_type_conformance,
    response_schema_conformance,
]


def test_every_operation_is_covered() -> None:
    ids = {op.ok().definition.raw.get("operationId") for op in schema.get_all_operations()}
    assert ids == {"healthz", "readyz", "metrics", "cor_locus", "cor_solve", "cor_membership", "cor_tripod_statistics", "mpp_particle",
                   "push_quasistatic", "cor_sketch", "push_align", "push_disk_encounter",
                   "spiral_critical_radius", "spiral_schedule", "feeder_map", "feeder_simulate",
                   "feeder_design", "scenes_analyze", "feeder_catalogue", "jobs_submit", "jobs_get", "jobs_cancel", "jobs_list"}


def contract_settings(max_examples: int) -> hypothesis.settings:
    """Seeded, no deadline, no example database, no health checks: the same run every time."""
    return hypothesis.settings(max_examples=max_examples, deadline=None, derandomize=True, database=None,
                               suppress_health_check=list(hypothesis.HealthCheck))


@pytest.mark.slow
@schema.parametrize()
@pytest.mark.filterwarnings("ignore::RuntimeWarning")  # numpy overflow inside models on extreme sizes
@contract_settings(MAX_EXAMPLES)
def test_api_contract(case: schemathesis.Case) -> None:
    _cap_time_limit(case)
    case.call_and_validate(checks=CHECKS)


def cap_time_limit(case: schemathesis.Case) -> None:
    """Cut a valid case's work to what the contract tests afford (module docstring)."""
    _cap_time_limit(case)


def _cap_time_limit(case: schemathesis.Case) -> None:
    body = case.body
    if isinstance(body, dict) and case.path in GROSS_PATHS:
        _cap_gross(body)
        return
    if isinstance(body, dict) and case.path in SPIRAL_PATHS:
        _cap_spiral(body)
        return
    if isinstance(body, dict) and case.path in FEEDER_PATHS:
        _cap_feeder(body, simulate=case.path.endswith("simulate"))
        return
    if isinstance(body, dict) and case.path == CATALOGUE_PATH:
        _cap_limit(body, CONTRACT_FEEDER_TIME_LIMIT_S)
        if isinstance(body.get("parts"), list):
            del body["parts"][2:]  # a catalogue is its parts' designs: two show it
        if isinstance(body.get("design"), dict):
            _cap_feeder(body["design"], simulate=False)
        return
    if isinstance(body, dict) and case.path == SCENES_PATH:
        _cap_limit(body, CONTRACT_SCENES_TIME_LIMIT_S)
        questions = body.get("questions")
        for q in questions if isinstance(questions, list) else ():
            if isinstance(q, dict) and isinstance(q.get("validation_parts"), int) and q["validation_parts"] > 2:
                q["validation_parts"] = 2
        return
    if not isinstance(body, dict) or case.path not in ("/v1/cor/locus", "/v1/cor/membership", "/v1/cor/sketch"):
        return
    if case.path in ("/v1/cor/locus", "/v1/cor/sketch") and body.get("method") != "certified":
        return
    _cap_limit(body, CONTRACT_TIME_LIMIT_S)


def _cap_limit(body: dict, cap: float) -> None:
    """A valid time_limit_s (absent: the default, at most the maximum) above ``cap``
    becomes ``cap``; an invalid one stays, for the negative examples."""
    limit = body.get("time_limit_s", MAX_TIME_LIMIT_S)
    valid = isinstance(limit, (int, float)) and not isinstance(limit, bool) and limit <= MAX_TIME_LIMIT_S
    if valid and limit > cap:
        body["time_limit_s"] = cap


def _is_int(value) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _cap_gross(body: dict) -> None:
    """Valid n_nodes / n_points become the minimum, a valid (or absent) time budget at most
    CONTRACT_GROSS_TIME_LIMIT_S; invalid values stay, for the negative examples."""
    if _is_int(body.get("n_nodes", GROSS_MIN_N_NODES)) and GROSS_MIN_N_NODES <= body.get("n_nodes", GROSS_MIN_N_NODES) <= GROSS_MAX_N_NODES:
        body["n_nodes"] = GROSS_MIN_N_NODES
    if _is_int(body.get("n_points", MIN_N_POINTS)) and MIN_N_POINTS <= body.get("n_points", MIN_N_POINTS) <= SKETCH_MAX_N_POINTS:
        body["n_points"] = MIN_N_POINTS
    _cap_limit(body, CONTRACT_GROSS_TIME_LIMIT_S)


def _cap_feeder(body: dict, simulate: bool) -> None:
    """A valid (or absent) time budget at most CONTRACT_FEEDER_TIME_LIMIT_S (a map or a
    run cut short answers what it finished, status time_limit) and a simulation's valid
    max_steps at most CONTRACT_FEEDER_MAX_STEPS, a design's valid validation_parts at most
    CONTRACT_FEEDER_MAX_VALIDATION."""
    _cap_limit(body, CONTRACT_FEEDER_TIME_LIMIT_S)
    parts = body.get("validation_parts", 0)
    if _is_int(parts) and CONTRACT_FEEDER_MAX_VALIDATION < parts <= FEEDER_MAX_VALIDATION_PARTS:
        body["validation_parts"] = CONTRACT_FEEDER_MAX_VALIDATION
    steps = body.get("max_steps", CONTRACT_FEEDER_MAX_STEPS + 1)
    if simulate and _is_int(steps) and steps > CONTRACT_FEEDER_MAX_STEPS:
        body["max_steps"] = CONTRACT_FEEDER_MAX_STEPS


def _cap_spiral(body: dict) -> None:
    """A valid (or absent) time budget at most CONTRACT_SPIRAL_TIME_LIMIT_S (a first r*
    table takes seconds: cut short, it is answered from what it covers), a valid
    simulation cut to one support, 8 path points per revolution, and the tip-line method (its
    r* table costs nothing, so the examples exercise the schedule rather than a table that
    never finishes in the budget)."""
    _cap_limit(body, CONTRACT_SPIRAL_TIME_LIMIT_S)
    if body.get("method", "sweep") in ("sweep", "exact"):
        body["method"] = "tip_line"  # a table in no time: the schedule, the path and the checks still run
    ppr = body.get("points_per_revolution", 64)
    if _is_int(ppr) and 8 <= ppr <= 720:  # valid: the fewest, so that the returned path stays small to validate
        body["points_per_revolution"] = 8
    sim = body.get("simulate")
    if isinstance(sim, dict) and _is_int(sim.get("n_supports", 1)) and 1 <= sim.get("n_supports", 1) <= 64:
        sim["n_supports"] = 1
