"""The bag player's merge order (pure) and a real publish of a bag into a listening process."""

from __future__ import annotations

import numpy as np

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
