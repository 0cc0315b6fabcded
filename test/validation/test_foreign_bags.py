"""Foreign-world bags open with plain rosbags and hold what their ground truth declares.

The checks are independent of the generator's code paths: conventions declared in the sidecar
(rest angles, tare, rates, clocks, lags) are re-measured from the recorded messages, and the
recorded force and angle must satisfy 004 eq. 5 with the nominal unit values.
"""

from __future__ import annotations

import filecmp
from pathlib import Path

import numpy as np
import pytest

from ebm_wear_monitor.validation.foreign import case_set, write_case

from .foreign_read import read_bag

SIGNALS = ("screw/angle", "screw/velocity", "axial_force", "motor/current")
QUICK = {c.case_id: c for c in case_set("quick")}
# one of each controller variant, both storages
PICK = ("none_q000", "none_q001", "none_q002", "none_q003")


@pytest.fixture(scope="module")
def bags(tmp_path_factory: pytest.TempPathFactory) -> dict[str, tuple[dict, dict]]:
    out = tmp_path_factory.mktemp("foreign")
    return {cid: read_bag(write_case(QUICK[cid], out)) for cid in PICK}


def _unit(truth: dict) -> tuple[str, dict]:
    (ns, unit), = truth["units"].items()
    return ns, unit


def test_controllers_and_storages_are_covered(bags: dict) -> None:
    variants = {_unit(t)[1]["foreign"]["controller"]["variant"] for _, t in bags.values()}
    storages = {_unit(t)[1]["foreign"]["storage"] for _, t in bags.values()}
    assert variants == {"cascade", "position", "voltage"}
    assert storages == {"sqlite3", "mcap"}


@pytest.mark.parametrize("cid", PICK)
def test_four_topics_with_declared_rates_frames_clocks_and_lags(bags: dict, cid: str) -> None:
    data, truth = bags[cid]
    ns, unit = _unit(truth)
    f = unit["foreign"]
    assert ns.startswith("/") and ns == f["namespace"]
    assert set(data) == {f"{ns}/{s}" for s in SIGNALS}
    lag = f["log_time_lag_s"]
    for topic, d in data.items():
        decl = f["topics"][topic]
        assert d["msgtype"] == "ebm_wear_msgs/msg/Float64Stamped"
        assert d["frames"] == {decl["frame_id"]} and decl["frame_id"]
        assert d["stamp"].size == decl["messages"]
        period = np.median(np.diff(d["stamp"]))
        assert 200.0 <= decl["rate_hz"] <= 2000.0
        assert 1.0 / period == pytest.approx(decl["rate_hz"], rel=2e-3)
        assert np.all(np.diff(d["stamp"]) > 0)  # each topic in order, own clock
        assert np.all(np.diff(d["log"]) >= 0)
        late = d["log"] - d["stamp"]
        assert late.min() >= lag["min"] - 2e-6 and late.max() <= lag["max"] + 2e-6 <= 2.002e-3
        # dropped samples show as gaps of whole periods
        missing = np.round(np.diff(d["stamp"]) * decl["rate_hz"]) - 1
        assert missing.sum() == decl["dropped"]
    first = {t: d["stamp"][0] for t, d in data.items()}
    assert len({round(v, 7) for v in first.values()}) > 1  # topics do not share stamps


@pytest.mark.parametrize("cid", PICK)
def test_ground_truth_is_complete(bags: dict, cid: str) -> None:
    _, truth = bags[cid]
    _, unit = _unit(truth)
    n = QUICK[cid].n_apps
    assert unit["clearance_limit_m"] == pytest.approx(0.5e-3)
    assert unit["cycles_at_start"] == 0
    assert unit["clearance_m"] == pytest.approx([0.2e-3] * n)
    assert unit["eol_cycles"] is None  # flat clearance never reaches the limit
    assert unit["effects"] == {}
    f = unit["foreign"]
    for key in ("case_id", "kind", "seed", "controller", "encoder", "rest_angle_sensor_rad",
                "velocity", "force", "current", "topics", "log_time_lag_s", "namespace", "storage",
                "applications", "nominal"):
        assert key in f, key
    apps = f["applications"]
    for key, values in apps.items():
        assert len(values) == n, key
    assert len(f["rest_angle_sensor_rad"]) == n
    on, con, rel, off = (np.array(apps[k]) for k in ("onset_stamp_s", "contact_stamp_s",
                                                       "release_stamp_s", "motor_off_stamp_s"))
    assert np.all(on < con) and np.all(con < rel) and np.all(rel < off) and np.all(off[:-1] < on[1:])


@pytest.mark.parametrize("cid", PICK)
def test_declared_conventions_are_what_the_messages_show(bags: dict, cid: str) -> None:
    """Rest angles, tare and the clamp law (004 eq. 5), re-measured from the recorded messages."""
    data, truth = bags[cid]
    ns, unit = _unit(truth)
    f = unit["foreign"]
    ang, frc = data[f"{ns}/screw/angle"], data[f"{ns}/axial_force"]
    apps = f["applications"]
    rest = np.array(f["rest_angle_sensor_rad"])
    quantum = f["encoder"]["quantum_screw_rad"]
    force = f["force"]
    nom = f["nominal"]
    for k, onset in enumerate(apps["onset_stamp_s"]):
        still = (ang["stamp"] > onset - 0.1) & (ang["stamp"] < onset)
        assert np.abs(ang["value"][still] - rest[k]).max() <= quantum
        idle = (frc["stamp"] > onset - 0.1) & (frc["stamp"] < onset)
        sigma = force["noise_std_N"] / np.sqrt(idle.sum())
        assert frc["value"][idle].mean() == pytest.approx(force["tare_N"], abs=5 * sigma + force["lsb_N"])
        # hold: the last 50 ms before the release command, the nut standing still
        cmd = apps["release_stamp_s"][k]
        hold = (frc["stamp"] > cmd - 0.05) & (frc["stamp"] < cmd)
        a = np.interp(frc["stamp"][hold], ang["stamp"], ang["value"])
        x = (a - rest[k]) * nom["lead"] / (2 * np.pi)
        model = nom["K_b"] * (x - unit["clearance_m"][k])
        tol = 4 * force["noise_std_N"] + force["lsb_N"] + nom["K_b"] * quantum * nom["lead"] / (2 * np.pi)
        assert np.median(frc["value"][hold] - force["tare_N"] - model) == pytest.approx(0.0, abs=tol)
    # rest angles differ from application to application by a few mrad at the screw
    step = np.abs(np.diff(rest))
    assert 2e-4 < np.median(step) < 1e-2


def test_generation_is_deterministic(tmp_path: Path) -> None:
    case = QUICK["none_q002"]
    a, b = write_case(case, tmp_path / "a"), write_case(case, tmp_path / "b")
    names = sorted(p.name for p in a.iterdir())
    assert names == sorted(p.name for p in b.iterdir())
    _match, mismatch, errors = filecmp.cmpfiles(a, b, names, shallow=False)
    assert not mismatch and not errors
