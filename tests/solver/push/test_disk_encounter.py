"""A point pushing a disk aside in one call (solver/push/disk_encounter.py; book 4.4): the
closed forms (4.16), (4.18), (4.17), (4.24) and the exact bounds of models/gross, the
refusal before work, and the closed forms carried by TimeLimitReached when the exact
bounds run out of budget."""

from __future__ import annotations

import math

import pytest

from models.core.errors import InvalidInput
from models.push import fence_geometry as fg
from models.push import gross_bounds as gb
from models.push import gross_motion as gm
from solver.core.budget import Budget
from solver.core.errors import TimeLimitReached
from solver.core.outcome import Outcome
from solver.push.bounds import ENCOUNTER_SKETCH_COST
from solver.push.disk_encounter import DiskEncounterProblem, disk_encounter
from tests.budgets import TickingClock, checks_budget

FAST = dict(n_nodes=4, n_points=16)


@pytest.mark.slow
def test_closed_forms_4_16_4_18_and_the_exact_bounds():
    res = disk_encounter(DiskEncounterProblem(1.0, 0.5, beta_initial=0.7, **FAST))
    assert isinstance(res, Outcome) and res.complete and res.status == "done"
    assert res.length_max.closed_form == gm.encounter_length_max(0.7, 1.0) and res.length_max.equation == "(4.16)"
    assert res.rotation_max.closed_form == gm.rotation_max(0.7) == pytest.approx(0.5 * math.pi - 0.7)
    assert res.length_min.closed_form is None and res.rotation_min.closed_form is None
    exact = gb.encounter_bounds_exact(1.0, 0.7, 0.5, **FAST)
    for key in ("length_max", "length_min", "rotation_max", "rotation_min"):
        got = getattr(res, key)
        assert (got.exact, got.quadrature_error) == (exact[key].value, exact[key].quadrature_error)
    assert res.length_frictionless == gm.encounter_length_frictionless(0.7, 1.0)
    assert res.sketch_i_onset == gm.sketch_i_onset(0.5) == pytest.approx(math.atan(1.0))  # (4.17): tan beta = 2 mu_c
    assert res.sketch_i_at_start is False and res.predicted_time_s == ENCOUNTER_SKETCH_COST.bounds_s(1, 4, 16)


def test_offset_and_collision_parameter_4_24():
    """d = a (1 - sin beta): either gives the other."""
    by_offset = disk_encounter(DiskEncounterProblem(2.0, 0.5, offset=0.5, method="closed_form"))
    assert by_offset.beta_source == "offset" and by_offset.beta_initial == fg.encounter_beta_from_offset(2.0, 0.5)
    by_beta = disk_encounter(DiskEncounterProblem(2.0, 0.5, beta_initial=by_offset.beta_initial, method="closed_form"))
    assert by_beta.offset == pytest.approx(0.5, rel=1e-14) and by_beta.length_max.exact is None
    with pytest.raises(InvalidInput):
        DiskEncounterProblem(2.0, 0.5)  # neither
    with pytest.raises(InvalidInput):
        DiskEncounterProblem(2.0, 0.5, beta_initial=0.5, offset=0.5)  # both


def test_refused_before_any_work():
    clock = TickingClock()
    with pytest.raises(InvalidInput) as info:
        disk_encounter(DiskEncounterProblem(1.0, 0.5, beta_initial=0.7), Budget.of(0.5, clock=clock))
    assert info.value.field == "time_limit_s" and clock.readings == 1


def test_running_out_carries_the_closed_forms():
    with pytest.raises(TimeLimitReached) as info:
        disk_encounter(DiskEncounterProblem(1.0, 0.5, beta_initial=0.7, **FAST), checks_budget(2))
    exc = info.value
    assert "node 3" in exc.where  # two sketches were allowed
    done = exc.partial
    assert isinstance(done, Outcome) and not done.complete and done.status == "time_limited"
    assert done.length_max.closed_form == gm.encounter_length_max(0.7, 1.0) and done.length_max.exact is None
