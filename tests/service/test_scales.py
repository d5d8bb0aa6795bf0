"""Hard cases of scale (issue 11): the documented disk examples with every length scaled by
5e-324 (subnormal) ... 1e300 answer 200, a 422 naming a field of the request, or a 504 —
never a 500. (A disk of 5e-324 once gave a 500 on membership: the forward solver's
length scale squared lengths and underflowed.)"""

from __future__ import annotations

import json

import pytest

from tests.service.docs_examples import EXAMPLES, split

LENGTH_KEYS = {"disk_radius", "contact_point", "cor", "points", "start_radius", "target", "radii", "offset", "center"}
SCALES = [5e-324, 1e-300, 1e-100, 1e-12, 1e12, 1e300]
CASES = [(u, b) for u, b in EXAMPLES
         if '"disk_radius"' in b and "footprint" not in b and "workpiece" not in b and "format=svg" not in u]


def _scaled(value, k, scale, keys=LENGTH_KEYS):
    if k in keys:
        return json.loads(json.dumps(value), parse_float=lambda x: float(x) * scale, parse_int=lambda x: int(x) * scale)
    if isinstance(value, dict):
        return {kk: _scaled(v, kk, scale, keys) for kk, v in value.items()}
    return value


@pytest.mark.slow
@pytest.mark.parametrize("scale", SCALES)
@pytest.mark.parametrize("url, body", CASES, ids=[f"{i}:{u}" for i, (u, _) in enumerate(CASES)])
def test_no_scale_is_a_server_error(client, url, body, scale):
    request = _scaled(json.loads(body), "", scale)
    if "time_limit_s" in request or "/spiral/" in url or "/push/" in url:
        request["time_limit_s"] = 2.0
    path, params = split(url)
    r = client.post(path, json=request, params=params)
    assert r.status_code in (200, 422, 504), r.text[:300]
    if r.status_code == 422:
        loc = r.json()["detail"][0]["loc"]
        assert loc[0] == "body" and (len(loc) == 1 or loc[1] in request), loc


EVERY_LENGTH_KEY = LENGTH_KEYS | {"footprint", "workpiece", "v_x", "mg", "speed", "g"}
"""Every length (and the quantities with a length in their unit: speeds, weights, g)."""
EVERY_CASE = [(u, b) for u, b in EXAMPLES if b and not u.startswith("/v1/jobs")]  # a job's body: its route's case


@pytest.mark.slow
@pytest.mark.parametrize("scale", [1e-12, 1e12])
@pytest.mark.parametrize("url, body", EVERY_CASE, ids=[f"{i}:{u}" for i, (u, _) in enumerate(EVERY_CASE)])
def test_every_documented_example_at_scales_1e_12_and_1e12_is_never_a_server_error(client, url, body, scale):
    """Issue 25: every documented example, footprints and pictures included, with every
    length scaled (the tripod statistics' histogram once answered 500 at 1e-12)."""
    request = _scaled(json.loads(body), "", scale, EVERY_LENGTH_KEY)
    assert request != json.loads(body)
    if "time_limit_s" in request or "/spiral/" in url or "/push/" in url or "/sketch" in url:
        request["time_limit_s"] = 2.0
    path, params = split(url)
    r = client.post(path, json=request, params=params)
    assert r.status_code in (200, 422, 504), r.text[:300]
