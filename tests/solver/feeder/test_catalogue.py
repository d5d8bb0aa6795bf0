"""A feeder catalogue (solver/feeder/catalogue.py; issue 27): each part's design is what the
design workflow (5.3-5.4) answers for that part alone, whichever way the catalogue runs, and
a catalogue cut by its deadline reports only the designs that finished."""

from __future__ import annotations

import math

import pytest

from models.feeder.fence import feeder_part
from solver import FeederCatalogueProblem, FeederDesignProblem, RayPool, feeder_catalogue, feeder_design
from tests.budgets import checks_budget

PARTS = (
    feeder_part([[0, 0], [3, 0], [3.5, 1.5], [1.5, 2.5], [-0.5, 1.2]], [1.4, 1.0]),
    feeder_part([[0, 0], [2.5, 0], [2.5, 1], [0, 1]], [1.25, 0.5]),
    feeder_part([[0, 0], [2, 0], [0.4, 1.5]], [0.8, 0.5]),
)
TEMPLATE = FeederDesignProblem(PARTS[0], math.radians(20), math.radians(70), math.radians(10), (0.25, 0.25),
                               max_depth=8, alternate=False, validation_parts=4, seed=5)


@pytest.mark.slow
def test_each_design_is_the_parts_own_5_3():
    result = feeder_catalogue(FeederCatalogueProblem(PARTS, TEMPLATE))
    assert result.complete and result.status == "complete" and result.run.backend == "in_process"
    assert result.run.finished == len(PARTS)
    for part, got in zip(PARTS, result.designs):
        alone = feeder_design(FeederDesignProblem(part, TEMPLATE.angle_min, TEMPLATE.angle_max, TEMPLATE.angle_step,
                                                  TEMPLATE.mu_c, max_depth=8, alternate=False, validation_parts=4,
                                                  seed=5))
        assert got.design == alone.design
        assert (got.validation.parts, got.validation.in_band) == (alone.validation.parts, alone.validation.in_band)


@pytest.mark.slow
@pytest.mark.parametrize("checks", [0, 3])
def test_a_catalogue_cut_short_reports_only_what_finished(checks):
    """A budget that expires after a fixed number of clock readings (any machine): the parts
    not reached are None, and the catalogue is not complete."""
    result = feeder_catalogue(FeederCatalogueProblem(PARTS, TEMPLATE), checks_budget(checks))
    assert not result.complete and result.status == "time_limit"
    assert result.run.finished == sum(d is not None for d in result.designs) < len(PARTS)
    assert result.designs[-1] is None


def test_a_pool_without_workers_or_address_runs_in_process():
    assert not RayPool().on_ray and RayPool(workers=2).on_ray and RayPool(address="10.0.0.1:6379").on_ray
