"""Issue 11 item 2: remaining life on life histories that are not the wear model, against the targets.

The set, its noise (calibrated from twin recordings through the bag writer and the core) and the
code path are described in life_histories.py. Targets of the issue:

* p50 within +-30 % of the true remaining life at 50 % and 80 % of every growing unit's record;
* the truth inside p05..p95 in 80-98 % of the predictions (pooled over the growing units);
* zero alarms (p05 < 1000 applications) on flat units (and units whose clearance only steps) over
  2,000 applications;
* finite numbers within 30 applications of growth being resolvable (accumulated growth above
  3 sigma of the measured observation noise).

bench/bench_life.py runs the same set with every prediction and prints the prognostics metrics
next to the naive least-squares line.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from life_histories import calibrate, checkpoints, histories, observe, resolvable_at, track

pytestmark = pytest.mark.slow

ALARM_CYCLES = 1000.0  # p05 below this is an alarm (the issue's definition)
EVERY = 5  # remaining life evaluated every 5th application (plus the target points)


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Every history tracked once: {name: (history, forecast, resolvable application)}."""
    pools = calibrate(tmp_path_factory.mktemp("calibration"))
    out = {}
    for j, h in enumerate(histories()):
        pool = pools[h.rate_hz]
        z, var = observe(h, pools, seed=100 + j)
        out[h.name] = (h, track(h, z, var, pool.model_growth_m, at=checkpoints(h, pool.sigma_m, EVERY)),
                       resolvable_at(h, pool.sigma_m))
    return out


def test_the_set_has_the_units_the_issue_asks_for(runs):
    kinds = [h.kind for h, _, _ in runs.values()]
    linear = [h for h, _, _ in runs.values() if h.kind == "linear"]
    rates = [(h.truth_m[-1] - h.truth_m[0]) / (h.truth_m.size - 1) for h in linear]
    assert len(linear) >= 20 and min(rates) == pytest.approx(0.1e-6, rel=0.01)
    assert max(rates) == pytest.approx(2e-6, rel=0.01)
    assert kinds.count("exponential") + kinds.count("climbing") >= 2
    assert kinds.count("step") >= 1 and kinds.count("flat") >= 5
    slow = [h for h, _, _ in runs.values() if h.kind == "slow"]
    assert slow and all(h.eol - h.truth_m.size > 10_000 for h in slow)
    flat = [h for h, _, _ in runs.values() if h.kind == "flat"]
    assert len({(h.rate_hz, h.applications_per_hour) for h in flat}) == len(flat)  # different usage
    assert all(h.truth_m.size >= 2000 for h in flat)


@pytest.mark.parametrize("fraction", [0.5, 0.8])
def test_p50_within_30_percent_at_50_and_80_percent_of_the_history(runs, fraction):
    off = {}
    for name, (h, f, _) in runs.items():
        if not h.grows:
            continue
        i = int(fraction * h.truth_m.size) - 1
        true_rul = h.eol - f.k[i]
        off[name] = f.p50[i] / true_rul - 1.0
    bad = {k: round(v, 3) for k, v in off.items() if not abs(v) <= 0.3}
    assert not bad, bad
    assert len(off) >= 28


def test_truth_inside_p05_p95_in_80_to_98_percent_of_the_predictions(runs):
    inside, per_unit = [], {}
    for name, (h, f, _) in runs.items():
        if not h.grows:
            continue
        true_rul = h.eol - f.k
        banded = np.isfinite(f.p05) & np.isfinite(f.p95) & (true_rul > 0)
        hits = (f.p05 <= true_rul) & (true_rul <= f.p95)
        inside += list(hits[banded])
        per_unit[name] = round(float(hits[banded].mean()), 2)
    coverage = float(np.mean(inside))
    assert 0.80 <= coverage <= 0.98, (coverage, per_unit)


def test_no_alarm_on_flat_units_and_clearance_steps_over_2000_applications(runs):
    alarms = {}
    for name, (h, f, _) in runs.items():
        if h.grows:
            continue
        assert h.truth_m.size >= 2000
        alarms[name] = int(np.sum(f.p05[np.isfinite(f.p05)] < ALARM_CYCLES))
        assert abs(f.clearance_m[-1] - h.truth_m[-1]) < 1e-6  # the estimate followed the steps
    assert all(v == 0 for v in alarms.values()), alarms
    steps = {name: f.steps for name, (h, f, _) in runs.items() if h.kind == "step"}
    assert all(v >= 1 for v in steps.values()), steps
    changes = {name: f.changes for name, (h, f, _) in runs.items() if not h.grows}
    assert all(v == 0 for v in changes.values()), changes  # a step is never read as a growth change


def test_finite_numbers_within_30_applications_of_growth_being_resolvable(runs):
    late = {}
    for name, (h, f, res) in runs.items():
        if not h.grows:
            continue
        finite = np.flatnonzero(f.finite())
        first = int(f.k[finite[0]]) if finite.size else math.inf
        if first - res > 30:
            late[name] = (res, first)
    assert not late, late
