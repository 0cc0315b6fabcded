"""Reduced blind self-test (the CI version of ``ebm-wear diagnose --selftest --quick``).

Targets asserted here are those the method meets on the quick case set (one
magnitude per effect, no-effect and two-effect cases); the full self-test's
figures are in build/notes/diagnosis.md.
"""

import pytest

from ebm_wear_monitor.diagnosis.selftest import case_set, run_selftest


@pytest.fixture(scope="module")
def result():
    return run_selftest(quick=True)


def test_case_set_covers_every_effect_none_and_pairs():
    labels = {c.label for c in case_set(quick=True)}
    assert "none" in labels and any("+" in lab for lab in labels)
    full = case_set()
    assert len({c.seed for c in full}) >= 3 and len({c.demands for c in full}) >= 2
    assert len({c.label for c in full}) >= 13


def test_quick_selftest_meets_targets(result):
    assert result["false_positive_rate"] == 0.0
    assert result["top1_accuracy"] >= 0.9
    assert result["top2_accuracy"] >= 0.9
    assert result["median_shrink"] >= 0.7
    assert result["cases"] == sum(sum(r.values()) for r in result["confusion"].values())
