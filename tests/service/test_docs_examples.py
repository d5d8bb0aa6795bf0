"""Every curl example of docs/api.md and the README is a valid request: run in-process, it
answers 200 (a job 202) without a deprecation warning; and every relative link of the docs
points to a file that exists (issue 35: seven pointed to files moved away). Budgets are
unlimited here (what is checked is the request, not how busy the machine is; the 504 of a
time limit has its own tests)."""

from __future__ import annotations

import json
import re

import pytest

from service.runtime.deadline import Deadline
from tests.budgets import NoLimitBudgets, deadline_budgets
from tests.service.docs_examples import EXAMPLES, README_EXAMPLES, REPO, split

DOCS = [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]
LINK = re.compile(r"\]\(([^)\s]+)\)")


def test_the_examples_are_found():
    paths = {url.split("?")[0] for url, _ in EXAMPLES}
    assert paths == {"/v1/cor/locus", "/v1/cor/solve", "/v1/cor/membership", "/v1/cor/tripod-statistics",
                     "/v1/mpp/particle", "/v1/push/quasistatic", "/v1/cor/sketch", "/v1/push/align",
                     "/v1/push/disk-encounter", "/v1/spiral/critical-radius", "/v1/spiral/schedule",
                     "/v1/scenes/analyze", "/v1/jobs"}
    assert README_EXAMPLES


@pytest.mark.slow
@pytest.mark.parametrize("url, body", EXAMPLES + README_EXAMPLES,
                         ids=[f"{i}:{u}" for i, (u, _) in enumerate(EXAMPLES + README_EXAMPLES)])
def test_doc_example_answers_200(client, monkeypatch, url, body):
    monkeypatch.setattr(Deadline, "budget", deadline_budgets(NoLimitBudgets))
    path, params = split(url)
    r = client.post(path, json=json.loads(body), params=params)
    assert r.status_code == (202 if path == "/v1/jobs" else 200), r.text
    if r.headers["content-type"].startswith("application/json"):
        assert not [w for w in r.json().get("warnings") or [] if "deprecated" in w], r.json()["warnings"]


@pytest.mark.parametrize("doc", DOCS, ids=[d.name for d in DOCS])
def test_every_relative_link_of_the_docs_points_to_a_file(doc):
    missing = []
    for link in LINK.findall(doc.read_text(encoding="utf-8")):
        target = link.split("#", 1)[0]
        if target and not target.startswith(("http://", "https://", "mailto:")):
            if not (doc.parent / target).exists():
                missing.append(link)
    assert not missing, f"{doc.name} links to files that do not exist: {missing}"
