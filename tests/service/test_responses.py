"""Every part of every answer is a ``service.common.responses.Out``: unknown fields refused
and every number finite, declared once. A NaN or an infinity in an answer is a 422
``numeric_range`` naming the part and the field, never a 500 and never JSON null."""

from __future__ import annotations

import importlib
import inspect
import json
import math
import typing

import pytest
from pydantic import BaseModel

from service.api import ROUTE_MODULES
from service.common.responses import ErrorItem, ErrorResponse, Out, TimeLimitResponse
from service.errors import response_for

ERROR_BODIES = {ErrorResponse, TimeLimitResponse, ErrorItem}


def _models(annotation, seen: set) -> None:
    if inspect.isclass(annotation) and issubclass(annotation, BaseModel):
        if annotation not in seen:
            seen.add(annotation)
            for field in annotation.model_fields.values():
                _models(field.annotation, seen)
        return
    for arg in typing.get_args(annotation):
        _models(arg, seen)


def answer_models() -> set[type[BaseModel]]:
    seen: set = set()
    for module in ROUTE_MODULES:
        for route in importlib.import_module(module).router.routes:
            _models(route.response_model, seen)
            for extra in route.responses.values():
                _models(extra.get("model"), seen)
    return seen - ERROR_BODIES


def test_every_part_of_every_answer_is_out():
    models = answer_models()
    assert len(models) > 50  # every resource's answers, not an empty walk
    others = sorted(m.__name__ for m in models if not issubclass(m, Out))
    assert others == [], f"answer parts not declared as Out: {others}"


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_a_non_finite_number_in_an_answer_is_422_numeric_range_naming_it(bad):
    from service.api.particle.schemas import ParticleResponse

    fields = {name: 1.0 for name, f in ParticleResponse.model_fields.items() if f.annotation is float}
    fields.update(agree=True, status="ok", iterations=1, message="m", power_mpp=bad)
    with pytest.raises(Exception) as info:
        ParticleResponse(**fields)
    answer = response_for(info.value, "POST /v1/mpp/particle")
    body = json.loads(answer.body)
    assert answer.status_code == 422 and body["detail"][0]["type"] == "numeric_range"
    assert "ParticleResponse.power_mpp is not finite" in body["detail"][0]["msg"]


def test_other_refusals_of_an_answer_are_bugs():
    from service.api.particle.schemas import ParticleResponse

    with pytest.raises(Exception) as info:
        ParticleResponse(unknown_field=1)
    assert response_for(info.value, "POST /v1/mpp/particle").status_code == 500
