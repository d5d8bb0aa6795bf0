"""One part, one verdict (issue 25): every route that takes an outline (feeder map with
either bound, simulation, design; locus, sketch, alignment, tripod statistics) refuses the
same bad outline with the same true reason, 422 at the outline's field, by the one check of
models.core.footprint.Footprint.create; the schema states the rules it can (uniqueItems)."""

from __future__ import annotations

import pytest

BAD = {  # outline, centre of mass, what the reason must say
    "bow-tie": ([[0, 0], [2, 2], [2, 0], [0, 2]], [1, 1], "self-intersecting, not a simple polygon: its edges 0-1 and 2-3"),
    "clockwise, crossing": ([[0, 2], [2, 0], [2, 2], [0, 0]], [1, 1], "self-intersecting"),
    "repeated vertex": ([[0, 0], [2, 0], [2, 2], [0, 0], [0, 2]], [0.5, 0.5],
                        "repeats a vertex: vertices 0 and 3 are the same point"),
    "three equal vertices": ([[0, 0], [0, 0], [0, 0]], [0, 0], "repeats a vertex: vertices 0 and 1"),
    "underflow": ([[0, 0], [1e-300, 0], [1e-300, 1e-300], [0, 1e-300]], [5e-301, 5e-301],
                  "spans 1e-300: outside"),
    "collinear": ([[0, 0], [1, 0], [2, 0]], [1, 0], "is degenerate: its vertices are (nearly) collinear"),
}
FENCE = [{"angle": 0.7, "mu_c": 0.25}]


def routes(v, cm):
    part = {"vertices": v, "center_of_mass": cm}
    return [
        ("/v1/feeder/map", {"part": part, "fences": FENCE}, ["body", "part", "vertices"]),
        ("/v1/feeder/map", {"part": part, "fences": FENCE, "bound": "part", "time_limit_s": 5}, ["body", "part", "vertices"]),
        ("/v1/feeder/simulate", {"part": part, "fences": FENCE, "theta_initial": 0.3,
                                 "support": {"points": [cm], "weights": [1]}}, ["body", "part", "vertices"]),
        ("/v1/feeder/design", {"part": part, "angles": {"min": 0.35, "max": 1.2, "step": 0.17}, "mu_c": 0.25},
         ["body", "part", "vertices"]),
        ("/v1/cor/locus", {"footprint": v, "center_of_mass": cm, "contact_point": v[0], "edge_angle": 1.57},
         ["body", "footprint"]),
        ("/v1/cor/sketch", {"footprint": v, "center_of_mass": cm, "contact_point": v[0], "edge_angle": 1.57,
                            "mu_c": 0.3}, ["body", "footprint"]),
        ("/v1/push/align", {"footprint": v, "center_of_mass": cm, "orientation": 0.5, "fence_angle": 1.57,
                            "mu_c": 0.25}, ["body", "footprint"]),
        ("/v1/cor/tripod-statistics", {"footprint": v, "center_of_mass": cm, "contact_point": v[0],
                                       "edge_angle": 1.57, "n_tripods": 10, "seed": 1}, ["body", "footprint"]),
    ]


@pytest.mark.parametrize("name", list(BAD))
def test_every_route_refuses_a_bad_outline_with_the_same_true_reason(client, name):
    v, cm, reason = BAD[name]
    messages = set()
    for url, body, loc in routes(v, cm):
        r = client.post(url, json=body)
        assert r.status_code == 422, (url, r.text)
        detail = r.json()["detail"][0]
        assert detail["loc"] == loc, (url, detail)
        assert reason in detail["msg"], (url, detail["msg"])
        messages.add(detail["msg"])
    assert len(messages) == 1, messages


def test_the_schemas_say_an_outline_repeats_no_vertex(client):
    schemas = client.get("/openapi.json").json()["components"]["schemas"]
    part = schemas["FeederPartIn"]["properties"]["vertices"]
    locus = schemas["CorLocusRequest"]["properties"]["footprint"]["anyOf"][0]
    assert part["uniqueItems"] is True and locus["uniqueItems"] is True
    assert "no vertex repeated" in part["description"]
