"""What the gross-motion workflows share (solver/push/bounds.py): the cost model of an
exact bound (n_nodes + n_nodes // 2 sketches, book 4.2's integrals by Gauss-Legendre), the
refusal before work, the bound record and the quasi-static check of 6.8."""

from __future__ import annotations

import pytest

from models.core.errors import InvalidInput
from models.push import quasistatic as qs
from solver.core.budget import UNLIMITED, Budget
from solver.push.bounds import (
    SKETCH_COST,
    Bound,
    QuasiStaticQuery,
    SketchCost,
    refuse_over_budget,
)


def test_cost_of_exact_bounds():
    cost = SketchCost(fixed_s=0.1, per_point_s=2.5e-4)
    assert cost.sketch_s(256) == pytest.approx(0.164)
    assert cost.bounds_s(2, 8, 256) == pytest.approx(2 * (8 + 4) * 0.164)
    assert cost.bounds_s(1, 4, 16) == pytest.approx((4 + 2) * 0.104)  # at least 2 nodes in the estimate
    assert cost.bounds_s(0, 64, 4096) == 0.0
    # the service's model (measured again after issue 26): about 1.5 times a sketch's time
    assert SKETCH_COST == SketchCost(fixed_s=0.05, per_point_s=4e-5)


def test_refusal():
    refuse_over_budget(1.0, Budget.of(1.0))
    refuse_over_budget(1e9, UNLIMITED)
    with pytest.raises(InvalidInput) as info:
        refuse_over_budget(1.5, Budget.of(1.0))
    assert info.value.field == "time_limit_s" and "1.5 s" in info.value.reason


def test_bound_difference_and_the_quasi_static_check_6_7():
    assert Bound(2.0, 0.1, 1.5, "(4.16)").difference == 0.5
    assert Bound(None, None, 1.5, "(4.16)").difference is None
    part = qs.ShapeMoments.disk(1.0)
    assert QuasiStaticQuery(1.0, 0.3, 9.81).assess(part) == qs.assess(1.0, 0.3, 9.81, part)
