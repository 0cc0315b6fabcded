"""Life histories and multi-rate recordings: the schedule is in the data, the clocks are as declared."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import yaml

from ebm_wear_monitor.validation.foreign import case_set, write_case
from ebm_wear_monitor.validation.foreign.life import clearance, end_of_life
from ebm_wear_monitor.validation.foreign.unit import REFERENCE_UNIT, load_actuator

from .foreign_read import read_bag

ACT = load_actuator()
UM = 1e-6


def test_schedules_and_their_end_of_life_agree_with_closed_forms() -> None:
    L = 0.5e-3
    lin = ("linear", 0.2e-3, 0.9 * UM)
    assert clearance(lin, 4) == pytest.approx([0.2e-3, 0.2009e-3, 0.2018e-3, 0.2027e-3])
    assert end_of_life(lin, L) == pytest.approx(300e-6 / 0.9e-6)
    exp = ("exponential", 0.21e-3, 0.2 * UM, 0.015)
    n = end_of_life(exp, L)
    assert 0.21e-3 + 0.2 * UM * np.expm1(0.015 * n) / 0.015 == pytest.approx(L, rel=1e-12)
    assert clearance(exp, int(n) + 2)[int(n)] <= L <= clearance(exp, int(n) + 2)[int(n) + 1]
    assert end_of_life(("step", 0.24e-3, 30 * UM, 90), L) is None
    assert end_of_life(("step", 0.48e-3, 30 * UM, 90), L) == 90.0
    assert end_of_life(("flat", 0.3e-3), L) is None
    assert end_of_life(("flat", 0.6e-3), L) == 0.0


def test_the_life_set_is_the_one_issue_11_describes() -> None:
    cases = case_set("life")
    assert len(cases) >= 11
    for c in cases:
        assert c.kind == "life" and 150 <= c.n_apps <= 240 and c.option("storage") == "sqlite3"
    specs = {c.case_id: c.option("clearance") for c in cases}
    rates = [s[2] for s in specs.values() if s[0] == "linear" and s[2] >= 0.3 * UM]
    assert min(rates) == pytest.approx(0.3 * UM) and max(rates) == pytest.approx(1.5 * UM)
    assert any(s[0] == "exponential" for s in specs.values())
    assert any(s[0] == "step" and s[2] == pytest.approx(30 * UM) for s in specs.values())
    flats = [c for c in cases if specs[c.case_id][0] == "flat"]
    assert len(flats) >= 3 and len({c.option("gap") for c in flats}) == len(flats)  # usages
    slow = specs["life.slow_rul_5800"]
    n = next(c.n_apps for c in cases if c.case_id == "life.slow_rul_5800")
    assert end_of_life(slow, 0.5e-3) - (n - 1) == pytest.approx(5800, abs=2)
    assert {c.option("rates")[0] for c in cases} >= {1000.0, 500.0}


@pytest.fixture(scope="module")
def short_life(tmp_path_factory: pytest.TempPathFactory) -> tuple:
    """The 0.9 um/application history with a 0.4 mm limit, cut to 25 applications."""
    (case,) = [c for c in case_set("life") if c.case_id == "life.linear_0.9_limit_0.4mm"]
    path = write_case(replace(case, n_apps=25), tmp_path_factory.mktemp("life"))
    return path, *read_bag(path)


def test_life_truth_unit_file_and_recorded_clearance_follow_the_schedule(short_life: tuple) -> None:
    path, data, truth = short_life
    (ns, unit), = truth["units"].items()
    f = unit["foreign"]
    spec = tuple(f["clearance_schedule"]["spec"])
    assert unit["clearance_m"] == pytest.approx(clearance(spec, 25).tolist())
    assert unit["eol_cycles"] == pytest.approx((0.4e-3 - 0.2e-3) / 0.9e-6)
    assert unit["clearance_limit_m"] == pytest.approx(0.4e-3)
    # the unit file beside it: embu_000's values, only the monitor block changed
    written = yaml.safe_load((path / "unit.yaml").read_text())
    original = yaml.safe_load(REFERENCE_UNIT.read_text())
    assert written["monitor"] == {"clearance_limit": 0.4e-3}
    assert {k: v for k, v in written.items() if k != "monitor"} == \
        {k: v for k, v in original.items() if k != "monitor"}
    # clearance re-measured from the recording: nut travel at hold minus (force - tare) / K_b
    ang, frc = data[f"{ns}/screw/angle"], data[f"{ns}/axial_force"]
    rest = np.array(f["rest_angle_sensor_rad"])
    est = []
    for k, cmd in enumerate(f["applications"]["release_stamp_s"]):
        m = (frc["stamp"] > cmd - 0.05) & (frc["stamp"] < cmd)
        x = (np.interp(frc["stamp"][m], ang["stamp"], ang["value"]) - rest[k]) * ACT.lead / (2 * np.pi)
        est.append(np.median(x - (frc["value"][m] - f["force"]["tare_N"]) / ACT.K_b))
    est = np.array(est)
    quantum = f["encoder"]["quantum_screw_rad"] * ACT.lead / (2 * np.pi)
    tol = 4 * f["force"]["noise_std_N"] / ACT.K_b + 2 * quantum + 0.5 * UM
    assert np.abs(est - np.array(unit["clearance_m"])).max() < tol
    slope = np.polyfit(np.arange(25), est, 1)[0]
    assert slope == pytest.approx(0.9 * UM, rel=0.1)


def test_multirate_recording_has_the_declared_clocks(tmp_path) -> None:
    cases = case_set("multirate")
    assert len(cases) >= 4 and any(c.effects for c in cases) and any(not c.effects for c in cases)
    data, truth = read_bag(write_case(cases[0], tmp_path))
    (ns, unit), = truth["units"].items()
    assert ns == "/train5/car3/embu2"
    want = {"screw/angle": 2000.0, "screw/velocity": 2000.0, "axial_force": 1000.0,
            "motor/current": 500.0}
    lag = unit["foreign"]["log_time_lag_s"]
    assert 0 < lag["max"] <= 1.6e-3
    for sig, rate in want.items():
        d = data[f"{ns}/{sig}"]
        decl = unit["foreign"]["topics"][f"{ns}/{sig}"]
        assert decl["rate_hz"] == rate and decl["frame_id"]
        assert 1 / np.median(np.diff(d["stamp"])) == pytest.approx(rate, rel=1e-3)
        assert decl["dropped"] >= 1 and decl["jitter_std_s"] > 0 and decl["phase_s"] < 1e-3
        assert np.all(d["log"] - d["stamp"] <= 1.6e-3 + 1e-9)
        assert np.std(np.diff(d["stamp"])[np.diff(d["stamp"]) < 1.5 / rate]) > 0  # jitter shows
