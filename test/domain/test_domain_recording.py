"""One recording type (domain.recording): exact int64 ns stamps per signal, float-seconds views."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ebm_wear_monitor.bagio import read_bags
from ebm_wear_monitor.domain.recording import Recording, Signal
from ebm_wear_monitor.domain.signals import SIGNALS

REPO = Path(__file__).resolve().parents[2]


def test_stamps_stay_exact_ns_and_seconds_are_a_view():
    ns = np.array([1_700_000_000_123_456_789, 1_700_000_000_124_456_789], np.int64)  # beyond float64's 2^53
    sig = Signal(ns, np.array([1.0, 2.0]))
    assert sig.stamps_ns.dtype == np.int64 and int(sig.stamps_ns[1] - sig.stamps_ns[0]) == 1_000_000
    assert np.allclose(sig.stamps, [1_700_000_000.123456789, 1_700_000_000.124456789], rtol=0, atol=1e-6)
    rec = Recording("/u", {"angle": sig, "axial_force": Signal(ns[:1], np.array([5.0]))})
    assert rec.messages == 3 and rec.bags == [] and rec.faults == {}
    seconds = rec.seconds()
    assert set(seconds) == {"angle", "axial_force"}
    assert seconds["angle"][0] is not sig.stamps_ns and np.array_equal(seconds["angle"][1], [1.0, 2.0])


def test_the_bag_reader_gives_one_recording_per_unit():
    bags = read_bags([REPO / "bags" / "healthy"])
    (unit, rec), = bags.units.items()
    assert isinstance(rec, Recording) and rec.unit == unit == "/embu"
    assert set(rec.signals) == set(SIGNALS) and rec.bags == [REPO / "bags" / "healthy"]
    for s in rec.signals.values():
        assert s.stamps_ns.dtype == np.int64 and s.values.dtype == np.float64
        assert s.stamps_ns.size == s.values.size > 1000
    assert bags.messages == rec.messages == sum(s.stamps_ns.size for s in rec.signals.values())
