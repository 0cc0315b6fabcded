"""The people's view: units people read, the life view's caveat, axis choice, the fleet ranking, the
projection geometry (issue 13 deliverable 2). Expected values are written out by hand."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from ebm_wear_monitor.fleet.tables import rank_units
from ebm_wear_monitor.reports.figures import axis_type, clearance_figure, faults_figure
from ebm_wear_monitor.reports.humanize import NA, count, duration, kn, mm, percent, um
from ebm_wear_monitor.reports.life import life_view


def test_units_people_read():
    assert mm(3.8564e-4) == "0.386 mm" and um(2.0424e-5) == "20.4 µm" and kn(20000.0) == "20.0 kN"
    assert count(21.94) == "22" and count(4.9e7) == "49.0 million" and count(1234.4) == "1,234"
    assert duration(24.5) == "24.5 s" and duration(0.5 * 3600) == "30.0 min"
    assert duration(5 * 3600) == "5.00 h"
    assert duration(3 * 86400) == "3.00 days" and duration(3 * 365.25 * 86400) == "3.00 years"
    assert percent(0.771) == "77 %"
    for f in (mm, um, kn, count, duration, percent):
        assert f(None) == NA and f(float("nan")) == NA


def _rl(**kw):
    return {"status": "ok", "limit_m": 5e-4, "cycles_p05": 180.0, "cycles_p50": 220.0, "cycles_p95": 280.0,
            "applications_per_hour": 20.0, **kw}


def test_life_view_calendar_time_and_the_under_a_day_caveat():
    clearance = {"estimate_m": 3.855e-4, "std_m": 1.1e-6}
    v = life_view(_rl(seconds_p05=180 / 20 * 3600, seconds_p50=11 * 3600, seconds_p95=14 * 3600,
                      usage_span_s=6 * 3600.0), clearance)
    assert v.applications == "220 applications (p05 180 – p95 280)"
    assert v.calendar == "11.0 h (p05 9.00 h – p95 14.0 h)"
    assert "observed over only 6.00 h" in v.caveat and v.fraction_text == "77 %"
    v = life_view(_rl(seconds_p50=11 * 3600, usage_span_s=3 * 86400.0), clearance)
    assert v.caveat == "" and v.calendar == "11.0 h"  # no p05/p95 seconds: only the median shown
    none = {"cycles_p05": None, "cycles_p50": None, "cycles_p95": None}
    v = life_view(_rl(status="insufficient_data", **none), clearance)
    assert v.calendar == NA and "no measurable clearance growth" in v.applications and v.caveat == ""
    assert life_view(_rl(hours_p50=2.0), clearance).calendar == "2.00 h"  # before issue 11's seconds_*


def test_axes_are_linear_below_a_decade():
    assert axis_type([20.0, 40.0]) == "linear" and axis_type([20.0, 199.0]) == "linear"
    assert axis_type([20.0, 200.0]) == "log" and axis_type([np.nan, -1.0, 5.0]) == "linear"


def test_fleet_ranking_status_then_p05_then_clearance_fraction():
    units = pd.DataFrame({
        "unit": ["a", "b", "c", "d", "e", "f"],
        "status": ["ok", "insufficient_data", "insufficient_data", "warn", "failed", "ok"],
        "cycles_p05": [5000.0, np.nan, np.nan, 9000.0, np.nan, 300.0],
        "clearance_fraction": [0.5, 0.59, 0.9, 0.8, np.nan, 0.45]})
    assert list(rank_units(units)["unit"]) == ["d", "f", "a", "c", "b", "e"]
    assert list(rank_units(units)["rank"]) == [1, 2, 3, 4, 5, 6]


def test_projection_fan_reaches_the_limit_at_p05_p50_p95():
    k = np.arange(1, 11, dtype=float)
    app = pd.DataFrame({"index": k, "clearance_estimate_m": 3e-4 + 1e-6 * k, "clearance_std_m": 1e-6,
                        "clearance_model_m": 2e-4 + 1e-6 * k, "clearance_observed_m": 3e-4 + 1e-6 * k})
    fig = clearance_figure(app, _rl(cycles_p05=150.0, cycles_p50=190.0, cycles_p95=240.0))
    traces = {t["name"]: t for t in fig["data"]}
    fan = traces["projection p05–p95"]
    assert fan["x"] == [10.0, 160.0, 250.0, 10.0] and fan["y"] == pytest.approx([0.31, 0.5, 0.5, 0.31])
    median = next(t for n, t in traces.items() if n.startswith("projection p50"))
    assert median["x"] == [10.0, 200.0] and median["y"] == pytest.approx([0.31, 0.5])
    assert fig["data"][-1]["name"] == "observed in the application"  # drawn last: on top
    no_trend = clearance_figure(app, _rl(cycles_p05=None, cycles_p50=None, cycles_p95=None))
    assert not any(t["name"].startswith("projection") for t in no_trend["data"])


def test_faults_per_signal_or_none():
    assert faults_figure({}) is None and faults_figure({"angle": {"gap": 0}}) is None
    fig = faults_figure({"angle": {"absurd": 3}, "axial_force": {"absurd": 1, "duplicate": 40}})
    assert [t["name"] for t in fig["data"]] == ["angle", "axial_force"]
    assert fig["data"][1]["y"] == [1, 40] and fig["layout"]["yaxis"]["type"] == "log"
