"""Input alignment: exact fault counts on constructed bad input, chunk invariance, resume floor."""

from __future__ import annotations

import numpy as np
import pytest

from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.monitor import MonitorConfig
from ebm_wear_monitor.monitor.alignment import FAULT_KINDS, InputAligner, ros_stamp_ns, stamps_to_ns

N = 3000  # samples per topic, 1 kHz, 3 s of a unit at rest
GAP = slice(1500, 1700)  # 200 ms missing on every topic: one gap


def _aligner(unit, floor=None):
    cfg = MonitorConfig()
    return InputAligner(cfg, cfg.resolve(unit), release_floor_ns=floor)


def _bad_streams():
    """Per-topic arrival sequences (stamps [s], values) with a known number of each fault."""
    t = 100.0 + np.arange(N) * 1e-3
    keep = np.ones(N, bool)
    keep[GAP] = False
    streams = {}
    # angle: 3 NaN values, 1 infinite stamp, 5 samples never sent, 2 duplicates sent right after the original
    ta, va = t.copy(), np.zeros(N)
    va[[10, 20, 30]] = np.nan
    ta[40] = np.inf
    ka = keep.copy()
    ka[[50, 60, 70, 80, 90]] = False
    order = list(np.flatnonzero(ka))
    for i in (100, 200):
        order.insert(order.index(i) + 1, i)
    streams["angle"] = (ta[order], va[order])
    # velocity: 2 absurd values, 4 adjacent swaps (out of order), 1 sample arriving 0.5 s late
    vv = np.zeros(N)
    vv[[300, 310]] = 1e9
    order = list(np.flatnonzero(keep))
    for j in (400, 410, 420, 430):
        a, b = order.index(j), order.index(j + 1)
        order[a], order[b] = order[b], order[a]
    order.remove(600)
    order.insert(order.index(1100), 600)
    streams["velocity"] = (t[order], vv[order])
    # axial force: 3 negative, 1 absurd, then the first 10 samples sent again at the end (bag loop)
    vf = np.zeros(N)
    vf[[700, 710, 720]] = -1e4
    vf[730] = 2e6
    order = list(np.flatnonzero(keep)) + list(range(10))
    streams["axial_force"] = (t[order], vf[order])
    expected = {
        "angle": {"non_finite": 3, "bad_stamp": 1, "duplicate": 2, "missing": 3 + 1 + 5},
        "velocity": {"absurd": 2, "out_of_order": 4, "late": 1, "missing": 3},
        "axial_force": {"negative": 3, "absurd": 1, "stamp_backwards": 10, "missing": 4},
        "stream": {"gap": 1},
    }
    return streams, expected, int(keep.sum())


def _run(unit, streams, chunks):
    """Feed the streams in the given per-topic chunking, interleaved round-robin; return released arrays."""
    al = _aligner(unit)
    pos = {s: 0 for s in streams}
    out = []
    cursors = {s: iter(chunks[s]) for s in streams}
    active = set(streams)
    while active:
        for s in sorted(active):
            size = next(cursors[s], None)
            if size is None:
                active.discard(s)
                continue
            st, vals = streams[s]
            al.add(s, st[pos[s]:pos[s] + size], vals[pos[s]:pos[s] + size])
            pos[s] += size
        out.append(al.release())
    out.append(al.release(final=True))
    cat = {k: np.concatenate([getattr(b, k) for b in out]) for k in ("t_ns", "angle", "velocity", "force",
                                                                    "gap_before")}
    return al, cat


def _chunks(n, rng, max_size):
    sizes = []
    while sum(sizes) < n:
        sizes.append(int(rng.integers(1, max_size + 1)))
    sizes[-1] -= sum(sizes) - n
    return sizes


def test_fault_counts_are_exact(unit):
    streams, expected, kept = _bad_streams()
    al, cat = _run(unit, streams, {s: [len(v[0])] for s, v in streams.items()})
    got = {k: v for k, v in al.faults.items() if v}
    assert got == expected
    n_aligned = kept - (3 + 1 + 5) - 3 - 4
    assert cat["t_ns"].size == n_aligned
    assert np.all(np.diff(cat["t_ns"]) > 0)
    assert cat["gap_before"].sum() == 1


def test_chunking_and_interleaving_do_not_change_anything(unit):
    streams, _expected, _ = _bad_streams()
    ref_al, ref = _run(unit, streams, {s: [len(v[0])] for s, v in streams.items()})
    rng = np.random.default_rng(3)
    for max_size in (1, 7, 400):
        chunks = {s: _chunks(len(v[0]), rng, max_size) for s, v in streams.items()}
        al, got = _run(unit, streams, chunks)
        assert al.faults == ref_al.faults
        for k in ref:
            assert np.array_equal(got[k], ref[k]), k


def test_resume_floor_drops_integrated_data(unit):
    al = _aligner(unit, floor=int(ros_stamp_ns(100, 500_000_000)))
    t = 100.0 + np.arange(1000) * 1e-3
    for s in ("angle", "velocity", "axial_force"):
        al.add(s, t, np.zeros_like(t))
    batch = al.release(final=True)
    assert batch.t_ns[0] == 100_501_000_000
    assert al.faults["angle"] == {"late": 501}


def test_stamps_int_ns_and_float_seconds_agree():
    sec = np.array([1_700_000_000, 1_700_000_000, 5])
    nsec = np.array([0, 999_999_999, 1])
    ns = ros_stamp_ns(sec, nsec)
    assert ns.tolist() == [1_700_000_000_000_000_000, 1_700_000_000_999_999_999, 5_000_000_001]
    got, ok = stamps_to_ns(np.array([1.5, np.nan, 1e12]))
    assert got[0] == 1_500_000_000 and ok.tolist() == [True, False, False]


def test_bad_shapes_and_unknown_topics_raise_input_error(unit):
    al = _aligner(unit)
    with pytest.raises(InputError):
        al.add("angle", np.zeros(3), np.zeros(2))
    with pytest.raises(InputError):
        al.add("torque", np.zeros(3), np.zeros(3))
    al.add("current", np.zeros(3), np.zeros(3))  # optional topic of the twin: ignored
    assert al.pending() == 0


def test_a_stamp_from_the_future_does_not_blind_a_topic(unit):
    al = _aligner(unit)
    t = 100.0 + np.arange(2000) * 1e-3
    glitch = t.copy()
    glitch[500] = 1e6  # one velocity stamp 11 days ahead
    al.add("angle", t, np.zeros_like(t))
    al.add("velocity", glitch, np.zeros_like(t))
    al.add("axial_force", t, np.zeros_like(t))
    batch = al.release(final=True)
    k = MonitorConfig().reanchor_after_samples
    # the 'k' samples after the glitch are dropped until the topic is re-anchored, then all is normal
    assert al.faults["velocity"] == {"stamp_backwards": k, "reanchored": 1, "missing": k + 1}
    assert set(al.fault_totals()) <= set(FAULT_KINDS)
    assert batch.t_ns.size == 2000 - 1 - k


def test_a_bag_played_again_is_not_counted_twice(unit):
    al = _aligner(unit)
    t = 100.0 + np.arange(3000) * 1e-3
    released = 0
    for _ in range(2):  # the same 3 s twice, with process calls as a live node makes them
        for a in range(0, t.size, 100):
            for s in ("angle", "velocity", "axial_force"):
                al.add(s, t[a:a + 100], np.zeros(100))
            released += len(al.release())
    released += len(al.release(final=True))
    assert released == 3000
    k = MonitorConfig().reanchor_after_samples
    # second play: k backwards before re-anchoring, then 'late' below the release horizon (newest - 0.2 s)
    # and 'duplicate' for the last 0.2 s, still waiting in the reorder window
    assert al.faults["angle"] == {"stamp_backwards": k, "reanchored": 1, "late": 3000 - k - 201,
                                  "duplicate": 201}
