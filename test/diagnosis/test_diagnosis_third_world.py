"""The diagnosis on recordings of the third world (:mod:`ebm_wear_monitor.validation.third`), written
independently of the twin, the diagnosis and the foreign generator, scored by the foreign self-test's
scorer (:func:`ebm_wear_monitor.diagnosis.foreign_selftest.run_third`).

Two recordings of its first draw (seed 3): a healthy unit whose force loop parks short of its rest target
within its angle tolerance (the contact comes 7-8 um of nut travel early), which read a clearance growth
of -8.4 um before the clearance's limit (wear only widens it; catalog module docstring, "Limits"), so this
case is not blind to that rule; and a clearance growth of the third world's own form (the contact point
moving out over the applications), which is.  The whole draws are in the README ("Third world").
"""

from __future__ import annotations

import pytest

from ebm_wear_monitor.diagnosis.foreign_selftest import run_third
from ebm_wear_monitor.errors import InputError

from third_case import third_diagnosis


@pytest.fixture(scope="module")
def third(tmp_path_factory):
    return third_diagnosis(tmp_path_factory.mktemp("third"), 3, "healthy_01", "clearance_growth_1", jobs=2)


def test_a_healthy_unit_parking_short_of_its_rest_target_reads_none(third):
    (row,) = [r for r in third.case_results if r.case == "healthy_01"]
    assert row.kind == "none" and row.true == "none"
    assert row.verdict == "none", row
    assert third.false_positive_rate == 0.0 and third.counts.none == 1


def test_a_clearance_growth_of_the_third_worlds_form_is_named(third):
    (row,) = [r for r in third.case_results if r.case == "clearance_growth_1"]
    assert row.effects_true == ["clearance_growth"] and row.relative_change["clearance_growth"] >= 0.1
    assert row.verdict == "effect" and row.top1_ok, row
    assert row.shrink >= 0.7  # the shrink target, met by this case alone
    assert third.confusion == {"none": {"none": 1}, "clearance_growth": {"clearance_growth": 1}}


def test_a_directory_without_third_world_recordings_is_refused(tmp_path):
    with pytest.raises(InputError, match="no third-world recordings"):
        run_third(tmp_path)
