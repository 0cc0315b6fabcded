"""``ebm-wear simulate``: a bag of the four input topics with the ground-truth sidecar; clean errors."""

from __future__ import annotations

import json

import numpy as np
import pytest

from ebm_wear_monitor.bagio import read_bags, read_ground_truth
from ebm_wear_monitor.cli.main import main


@pytest.mark.parametrize("storage", ["mcap", "sqlite3"])
def test_simulate_writes_bag_and_truth(tmp_path, storage, capsys):
    out = tmp_path / "bag"
    rc = main(["simulate", "--cycles", "2", "--demand", "12000", "--hold", "0.2", "--rest", "0.1",
               "--effect", "clearance_growth=5e-5", "--seed", "3", "--storage", storage, "--rate", "500",
               "--namespace", "/train1/car2/embu3", "--wear-acceleration", "1000", "--out", str(out)])
    assert rc == 0
    assert "2 applications" in capsys.readouterr().out
    unit = read_bags([out]).units["/train1/car2/embu3"]
    assert set(unit.signals) == {"angle", "velocity", "axial_force", "current"}
    stamps = unit.signals["axial_force"].stamps
    assert np.allclose(np.diff(stamps), 1 / 500)  # header stamps at the sample times
    held = unit.signals["axial_force"].values
    assert np.max(held) == pytest.approx(12000, rel=0.02)
    truth = read_ground_truth(out)["units"]["/train1/car2/embu3"]
    assert truth["effects"] == {"clearance_growth": 5e-5}
    assert truth["wear_acceleration"] == 1000
    assert len(truth["clearance_m"]) == 2
    assert truth["clearance_m"][0] >= 0.2e-3 + 5e-5
    assert truth["clearance_m"][1] > truth["clearance_m"][0]  # accelerated wear grows it
    json.dumps(truth)


@pytest.mark.parametrize("argv, message", [
    (["--effect", "nonsense=1"], "unknown effect"),
    (["--effect", "stribeck=-1"], "must be >= 0"),
    (["--rate", "1"], "rate"),
    (["--demand", "-5"], "demands"),
    (["--params", "/no/such/file.yaml"], "cannot read"),
    (["--namespace", "/car 3/embu"], "not a ROS 2 namespace"),
])
def test_simulate_bad_input_exits_2_and_writes_nothing(tmp_path, capsys, argv, message):
    out = tmp_path / "bag"
    assert main(["simulate", "--cycles", "1", "--out", str(out), *argv]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_simulate_checks_its_destination_before_simulating(tmp_path, capsys):
    (tmp_path / "afile").write_text("a file, not a directory")
    assert main(["simulate", "--cycles", "1", "--out", str(tmp_path / "afile" / "bag")]) == 2
    assert "afile is a file" in capsys.readouterr().err


def test_simulate_refuses_to_overwrite(tmp_path, capsys):
    out = tmp_path / "bag"
    out.mkdir()
    assert main(["simulate", "--cycles", "1", "--hold", "0.1", "--out", str(out)]) == 2
    assert "exists" in capsys.readouterr().err


def test_namespace_without_leading_slash_keeps_its_ground_truth(tmp_path):
    """The ground truth is keyed by the unit name readers derive from the topics ('/embu', not 'embu')."""
    out = tmp_path / "bag"
    argv = ["simulate", "--cycles", "1", "--hold", "0.1", "--rest", "0.1", "--rate", "200", "--no-noise"]
    assert main([*argv, "--namespace", "train1/embu2/", "--out", str(out)]) == 0
    assert list(read_bags([out]).units) == list(read_ground_truth(out)["units"]) == ["/train1/embu2"]
