"""An answer with nothing computed is not a success (issue 25): a request whose time limit
runs out before the first of what it asked for (a candidate map of a design, a fence map,
an r* value, a certified point) is answered 504 saying what was about to start, never 200
with an empty result."""

from __future__ import annotations

import pytest

from tests.service.live import DESIGN
from tests.service.runtime.test_live import SLOW_LOCUS

CASES = [
    ("/v1/feeder/design", DESIGN, "the first candidate fence's map"),
    ("/v1/feeder/map", {"part": DESIGN["part"], "fences": [{"angle": 0.7, "mu_c": 0.25}], "bound": "part"},
     "the first fence map"),
    ("/v1/spiral/critical-radius", {"disk_radius": 1, "mu_c": 0.37}, "the first collision parameter"),
    ("/v1/cor/locus", SLOW_LOCUS, "the first certified point"),
]


@pytest.mark.wall_clock  # about the time limit itself: its real deadline (tests/service/conftest.py)
@pytest.mark.parametrize("path, body, before", CASES, ids=[c[0] for c in CASES])
def test_a_limit_that_leaves_no_time_is_a_504_not_an_empty_200(client, path, body, before):
    r = client.post(path, json={**body, "time_limit_s": 1e-6})
    assert r.status_code == 504, r.text[:300]
    out = r.json()
    assert out["detail"][0]["type"] == "time_limit" and before in out["reached"]
