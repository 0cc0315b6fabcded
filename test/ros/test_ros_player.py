"""The bag player's merge order (pure) and a real publish of a bag into a listening process."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np

from ebm_wear_monitor.ros.parameters import SPECS
from ebm_wear_monitor.ros.player import publish_order, unrolled_time


def test_unrolled_time_is_identity_for_ordered_stamps_and_monotone_through_a_loop() -> None:
    t = np.arange(10) * 0.01
    assert np.array_equal(unrolled_time(t), t)
    looped = np.concatenate([t, t])  # a bag played twice: the stamps jump back by 0.09 s
    key = unrolled_time(looped)
    assert np.all(np.diff(key) >= 0)
    assert np.allclose(np.diff(key), np.concatenate([np.diff(t), [0.0], np.diff(t)]))


def test_merge_keeps_each_signals_order_and_interleaves_by_time() -> None:
    t = np.arange(5) * 0.001
    signals = {"angle": (t, t), "velocity": (t + 0.0005, t), "axial_force": (t[::-1], t)}  # last one reversed
    which, key = publish_order(signals)
    assert np.all(np.diff(key) >= 0) and key[0] == 0.0
    assert sorted(np.bincount(which).tolist()) == [5, 5, 5]
    # angle and velocity alternate: both regular, velocity half a sample later
    av = which[which < 2]
    assert av.tolist() == [0, 1] * 5


def test_player_reports_a_missing_bag_in_one_line_with_status_2(tmp_path) -> None:
    run = subprocess.run([sys.executable, "-m", "ebm_wear_monitor.ros.player", str(tmp_path / "nope")],
                         capture_output=True, text=True, timeout=60, check=False)
    assert run.returncode == 2
    assert run.stderr.count("\n") == 1 and "nope" in run.stderr


def test_node_help_lists_every_parameter() -> None:
    run = subprocess.run([str(Path(sys.executable).parent / "ebm-wear-monitor"), "--help"],
                         capture_output=True, text=True, timeout=60, check=False)
    assert run.returncode == 0
    for spec in SPECS:
        assert f"  {spec.name} (default" in run.stdout
