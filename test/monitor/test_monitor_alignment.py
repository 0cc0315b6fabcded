"""Input alignment: exact fault counts on constructed bad input, chunk invariance, resume floor, and
interpolation of topics at their own rates onto the base topic's stamps."""

from __future__ import annotations

import numpy as np
import pytest

from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.monitor import MonitorConfig
from ebm_wear_monitor.monitor.alignment import FAULT_KINDS, InputAligner, stamps_to_ns
from ebm_wear_monitor.monitor.wire import stamp_ns as ros_stamp_ns

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
    # velocity: 2 absurd values, 4 adjacent swaps (out of order), 1 sample arriving 0.5 s late, and a
    # 30 ms hole (wider than max_interpolation_s = 25 ms): the 30 force stamps inside it are missing
    vv = np.zeros(N)
    vv[[300, 310]] = 1e9
    order = [i for i in np.flatnonzero(keep) if not 2000 <= i < 2030]
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
    # single samples missing from angle or velocity are interpolated from their neighbours (1-2 ms apart):
    # not missing; the force is the time base, so its 4 dropped samples just are no aligned samples
    expected = {
        "angle": {"non_finite": 3, "bad_stamp": 1, "duplicate": 2},
        "velocity": {"absurd": 2, "out_of_order": 4, "late": 1, "missing": 30},
        "axial_force": {"negative": 3, "absurd": 1, "stamp_backwards": 10},
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
    n_aligned = kept - 4 - 30
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
    # the glitch is not confirmed by the samples after it: dropped alone, its neighbours fill in for it
    assert al.faults["velocity"] == {"stamp_glitch": 1}
    assert set(al.fault_totals()) <= set(FAULT_KINDS)
    assert batch.t_ns.size == 2000


def test_a_confirmed_clock_jump_is_followed(unit):
    """All topics jump 1 h ahead (a recording resumed later): confirmed after reanchor_after_samples."""
    al = _aligner(unit)
    t = 100.0 + np.arange(2000) * 1e-3
    t[1000:] += 3600.0
    for s in ("angle", "velocity", "axial_force"):
        al.add(s, t, np.zeros_like(t))
    batch = al.release(final=True)
    assert batch.t_ns.size == 2000
    assert al.fault_totals() == {"gap": 1, "reanchored": 3}


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
    # second play: 'stamp_backwards' while more than backwards_jump_s (1 s) behind the newest stamp, then
    # 'late' below the floor (newest - 0.2 s), then 'duplicate' for the last 0.2 s still pending
    assert al.faults["angle"] == {"stamp_backwards": 1999, "late": 800, "duplicate": 201}


def _multirate(t_end: float, rng: np.random.Generator):
    """Angle and velocity at 2 kHz, force at 1 kHz, each with its own phase and jitter; smooth signals."""
    def stamps(rate, phase):
        n = int(t_end * rate)
        # whole microseconds: the default stamp quantum, so the closed form is evaluated where the core is
        return np.round(50.0 + phase + np.arange(n) / rate + rng.uniform(-20e-6, 20e-6, n), 6)
    f = {"angle": lambda x: 3.0 * np.sin(2.0 * x), "velocity": lambda x: 6.0 * np.cos(2.0 * x),
         "axial_force": lambda x: 1e4 * (1.0 + np.sin(x))}
    times = {"angle": stamps(2000.0, 0.13e-3), "velocity": stamps(2000.0, 0.31e-3),
             "axial_force": stamps(1000.0, 0.77e-3)}
    return f, times


def test_topics_at_their_own_rates_are_interpolated_at_the_force_stamps(unit):
    """Exact stamps in ns: the aligned angle and velocity equal the closed form at each force stamp within
    the linear-interpolation bound h^2/8 max|x''| (h <= 0.54 ms), and nothing is counted but the edges."""
    rng = np.random.default_rng(5)
    f, times = _multirate(5.0, rng)
    al = _aligner(unit)
    for s, t in times.items():
        al.add(s, np.rint(t * 1e9).astype(np.int64), f[s](t))
    batch = al.release(final=True)
    t = batch.t_ns * 1e-9
    h = 0.54e-3
    assert np.max(np.abs(batch.force - f["axial_force"](t))) < 1e-6  # the base: its own samples
    assert np.max(np.abs(batch.angle - f["angle"](t))) <= h**2 / 8 * 12.0 + 1e-12
    assert np.max(np.abs(batch.velocity - f["velocity"](t))) <= h**2 / 8 * 24.0 + 1e-12
    # only force stamps before the first / after the last angle or velocity sample are missing
    assert batch.t_ns.size >= times["axial_force"].size - 2
    assert set(al.fault_totals()) <= {"missing"} and sum(al.fault_totals().values()) <= 2


@pytest.mark.parametrize("base", ["angle", "velocity", "axial_force"])
def test_any_topic_can_be_the_time_base_and_chunking_does_not_matter(unit, base):
    rng = np.random.default_rng(6)
    f, times = _multirate(3.0, rng)
    cfg = MonitorConfig().updated(time_base=base)
    out = []
    for chunk in (None, 37):
        al = InputAligner(cfg, cfg.resolve(unit))
        parts = []
        n = max(t.size for t in times.values())
        for a in range(0, n, chunk or n):
            for s, t in times.items():
                sl = slice(a * t.size // n, (a + (chunk or n)) * t.size // n)
                al.add(s, np.rint(t[sl] * 1e9).astype(np.int64), f[s](t[sl]))
            parts.append(al.release())
        parts.append(al.release(final=True))
        out.append((np.concatenate([p.t_ns for p in parts]), np.concatenate([p.angle for p in parts]),
                    al.fault_counts()))
    assert np.array_equal(out[0][0], out[1][0]) and np.array_equal(out[0][1], out[1][1])
    assert out[0][2] == out[1][2]
    assert out[0][0].size >= times[base].size - 2



@pytest.mark.parametrize("stale_s", [0.5, 2.0])
def test_a_topic_lagging_beyond_stale_after_s_stops_holding_the_others(unit, stale_s):
    # the velocity stalls after 1.0 s of stamps while angle and force go on to 4.0 s, in 0.5 s chunks. While
    # its lag is within stale_after_s the aligner waits (nothing missing yet); beyond, its floor is raised to
    # the others' (newest - reorder_window_s) and every force stamp from its last sample up to there is
    # 'missing' for it; when its old samples then arrive, those below that floor are 'late'
    cfg = MonitorConfig(stale_after_s=stale_s)
    al = InputAligner(cfg, cfg.resolve(unit))
    t = 100.0 + np.arange(4000) * 1e-3
    zeros = np.zeros(t.size)
    stop = 1000  # samples the velocity sends before it stalls
    al.add("velocity", t[:stop], zeros[:stop])
    for end in range(500, t.size + 1, 500):
        for s in ("angle", "axial_force"):
            al.add(s, t[end - 500:end], zeros[end - 500:end])
        al.release()
        if t[end - 1] - t[stop - 1] <= stale_s:
            assert al.faults["velocity"].get("missing", 0) == 0, end
    floor = t[-1] - cfg.reorder_window_s  # the others' floor once the last chunk is in [s]
    behind = int(np.count_nonzero((t >= t[stop]) & (t < floor - 1e-9)))  # 2799 force stamps, 1 kHz
    assert al.faults["velocity"]["missing"] == behind
    al.add("velocity", t[stop:], zeros[stop:])  # the stalled topic comes back with its old samples
    al.release(final=True)
    assert al.faults["velocity"]["late"] == behind
    assert al.faults["angle"] == {} and al.faults["axial_force"] == {}
