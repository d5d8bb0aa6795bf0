"""Every curl example of docs/api.md is a valid request: run in-process, it answers 200.
Budgets are unlimited here (what is checked is the request, not how busy the machine is;
the 504 of a time limit has its own tests)."""

from __future__ import annotations

import json

import pytest

from service.runtime.deadline import Deadline
from tests.budgets import NoLimitBudgets, deadline_budgets
from tests.service.docs_examples import EXAMPLES, split


def test_the_examples_are_found():
    paths = {url.split("?")[0] for url, _ in EXAMPLES}
    assert paths == {"/v1/cor/locus", "/v1/cor/solve", "/v1/cor/membership", "/v1/cor/tripod-statistics",
                     "/v1/mpp/particle", "/v1/push/quasistatic", "/v1/cor/sketch", "/v1/push/align",
                     "/v1/push/disk-encounter", "/v1/spiral/critical-radius", "/v1/spiral/schedule",
                     "/v1/scenes/analyze"}


@pytest.mark.slow
@pytest.mark.parametrize("url, body", EXAMPLES, ids=[f"{i}:{u}" for i, (u, _) in enumerate(EXAMPLES)])
def test_doc_example_answers_200(client, monkeypatch, url, body):
    monkeypatch.setattr(Deadline, "budget", deadline_budgets(NoLimitBudgets))
    path, params = split(url)
    r = client.post(path, json=json.loads(body), params=params)
    assert r.status_code == 200, r.text
