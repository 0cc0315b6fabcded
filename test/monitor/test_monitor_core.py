"""MonitorCore end to end: chunk invariance (node == replay by construction), learning, twin, JSON."""

from __future__ import annotations

import json
import math
from dataclasses import asdict

import numpy as np
import pytest

from ebm_wear_monitor.monitor import FAULT_KINDS, MonitorConfig, MonitorCore, load_state, save_state
from ebm_wear_monitor.physics import clearance_growth, wear_model

from monitor_synth import linear_rates, screw_growth, synth_cycles


def _faulty_arrivals(synth):
    """Per-topic arrival sequences with every kind of input fault, and a 300 ms gap in one hold."""
    t = synth.t
    n = t.size
    keep = np.ones(n, bool)
    mk = synth.marks[10]
    keep[(t > mk["apply_end"] + 0.02) & (t < mk["apply_end"] + 0.32)] = False
    out = {}
    idx = list(np.flatnonzero(keep))
    # single samples are interpolated; a 40 ms hole (> max_interpolation_s) is 'missing'
    a_idx = [i for i in idx if i not in (500, 1500, 2500) and not 4000 <= i < 4040]
    a_val = synth.angle.copy()
    a_val[[700, 1700]] = np.nan
    out["angle"] = (t[a_idx], a_val[a_idx])
    v_idx = list(idx)
    for j in (3000, 4000, 5000):
        v_idx.insert(v_idx.index(j) + 1, j)
    for j in (600, 1600, 2600, 3600, 4600):
        a, b = v_idx.index(j), v_idx.index(j + 1)
        v_idx[a], v_idx[b] = v_idx[b], v_idx[a]
    out["velocity"] = (t[v_idx], synth.velocity[v_idx])
    f_val = synth.force.copy()
    f_val[[800, 1800]] = -5e3
    f_idx = list(idx)
    f_idx.remove(900)
    f_idx.insert(f_idx.index(1300), 900)
    out["axial_force"] = (t[f_idx], f_val[f_idx])
    return out


def _feed(unit, arrivals, windows, process_mask, **kw):
    core = MonitorCore(unit, **kw)
    cycles = []
    lengths = {s: len(v[0]) for s, v in arrivals.items()}
    for w, (lo, hi) in enumerate(windows):
        for s, (t, v) in arrivals.items():
            a, b = int(lo * lengths[s]), int(hi * lengths[s])
            core.add(s, t[a:b], v[a:b])
        if process_mask[w]:
            cycles += core.process()
    cycles += core.process(final=True)
    return core, cycles


def _fingerprint(core, cycles):
    return ([repr(asdict(c)) for c in cycles], json.dumps(core.to_json_dict(), sort_keys=True),
            json.dumps(core.state.to_dict(), sort_keys=True))


def test_bit_identical_whatever_the_chunking(unit):
    synth = synth_cycles(20, noise=True, seed=11, clearance=lambda k: 0.2e-3 + 1e-6 * k,
                         peak_force=lambda k: 6e3 + 1.5e3 * (k % 7))
    arrivals = _faulty_arrivals(synth)
    whole_core, whole = _feed(unit, arrivals, [(0.0, 1.0)], [False])
    ref = _fingerprint(whole_core, whole)
    snap = whole_core.snapshot()
    assert snap.duty_cycles == 19 and snap.segments["interrupted"] == 1
    assert set(snap.input_faults) >= {"missing", "non_finite", "duplicate", "out_of_order", "negative",
                                      "late", "gap", "interrupted_cycle"}
    assert set(snap.input_faults) <= set(FAULT_KINDS)  # the documented catalogue covers every count
    rng = np.random.default_rng(0)
    n = synth.t.size
    for trial in range(4):
        # trial 0: one message per topic at a time, processed after each; then random chunk mixes
        mixed = np.where(rng.random(4000) < 0.3, 1, rng.integers(2, 400, 4000))
        sizes = np.ones(n, int) if trial == 0 else mixed
        edges = np.concatenate([[0], np.cumsum(sizes)])
        edges = edges[edges < n] / n
        windows = list(zip(edges, [*edges[1:], 1.0], strict=True))
        mask = rng.random(len(windows)) < (0.5 if trial > 1 else 1.0)
        core, cycles = _feed(unit, arrivals, windows, mask)
        assert _fingerprint(core, cycles) == ref


def test_filter_learns_a_model_that_under_predicts_and_predicts_life(unit):
    f_true, growth = 1.7, 2e-7  # true growth is 1.7x the model's 2e-7 m per application
    synth0 = synth_cycles(1)
    c = growth / synth0.loaded_rotation[0]  # model wear rate per rad of loaded rotation
    x0 = 0.2e-3
    synth = synth_cycles(250, noise=True, seed=4, clearance=lambda k: x0 + f_true * growth * k)
    core = MonitorCore(unit, wear_rates=linear_rates(c), clearance_growth=screw_growth)
    for s, (t, v) in synth.signals().items():
        core.add(s, t, v)
    cycles = core.process(final=True)
    snap = core.snapshot()
    assert len(cycles) == 250
    model_growth = (snap.clearance_model_m - 0.2e-3) / 250
    assert model_growth == pytest.approx(growth, rel=0.01)
    assert abs(snap.wear_rate_factor - f_true) < max(4 * snap.wear_rate_factor_std, 0.02)
    assert snap.wear_rate_factor_std < 0.05
    assert snap.growth_rate_m_per_cycle == pytest.approx(f_true * growth, rel=0.03)
    x_now = synth.clearance[-1]
    assert abs(snap.clearance_estimate_m - x_now) < 4 * snap.clearance_std_m
    closed = (unit.monitor.clearance_limit - x_now) / (f_true * growth)
    assert snap.life_status == "due"  # ~630 applications left: p05 below the unit file's due_cycles (1000)
    assert snap.cycles_p05 < snap.cycles_p50 < snap.cycles_p95
    assert snap.cycles_p50 == pytest.approx(closed, rel=0.05)
    assert snap.cycles_p05 < closed < snap.cycles_p95
    # usage rate: mean period between application starts of the construction
    period = (synth.marks[-1]["start"] - synth.marks[0]["start"]) / 249
    assert snap.applications_per_hour == pytest.approx(3600 / period, rel=1e-4)
    assert snap.hours_p50 == pytest.approx(snap.cycles_p50 * period / 3600, rel=1e-4)
    assert snap.seconds_p05 == pytest.approx(snap.cycles_p05 * period, rel=1e-4)
    assert snap.usage_span_s == pytest.approx(249 * period, rel=1e-6)


def test_wear_is_the_physics_integral_over_moving_samples(unit):
    synth = synth_cycles(5, noise=True, seed=8)
    core = MonitorCore(unit)
    for s, (t, v) in synth.signals().items():
        core.add(s, t, v)
    core.process(final=True)
    snap = core.snapshot()
    # independent integral: backward rectangle rule of the physics rates where the screw turns
    th = MonitorConfig().resolve(unit)
    moving = np.abs(synth.velocity) >= th.omega_off
    dt = np.diff(synth.t, prepend=synth.t[0])
    r = wear_model(unit).rates(synth.force[moving], synth.velocity[moving])
    for name, total in (("screw", snap.screw_raceway_m), ("nut", snap.nut_raceway_m), ("ball", snap.ball_m)):
        assert total == pytest.approx(float(np.sum(getattr(r, name) * dt[moving])), rel=1e-9)
    growth = float(clearance_growth(unit, snap.screw_raceway_m, snap.nut_raceway_m, snap.ball_m))
    assert snap.clearance_model_m == pytest.approx(unit.actuator.clearance + growth, rel=1e-12)


@pytest.mark.parametrize("rate_hz", [1000.0, 100.0])
def test_twin_recording_end_to_end(unit, rate_hz):
    from ebm_wear_monitor.twin import simulate_unit

    sim = simulate_unit(unit, 10, seed=3, rate_hz=rate_hz)
    core = MonitorCore(unit)
    for s in ("angle", "velocity", "axial_force", "current"):
        core.add(s, sim.t, getattr(sim, s))
    cycles = core.process(final=True)
    assert len(cycles) == 10
    observed = [c for c in cycles if math.isfinite(c.clearance_observed_m)]
    assert len(observed) >= 8
    for c in observed:
        x = sim.truth["clearance_m"][c.index - 1]
        assert abs(c.clearance_observed_m - x) < 3 * c.clearance_observed_std_m
    snap = core.snapshot()
    wear = {"screw": snap.screw_raceway_m, "nut": snap.nut_raceway_m, "ball": snap.ball_m}
    for name, depth in wear.items():  # measured (noisy) signals vs the twin's true ones
        assert depth == pytest.approx(sim.truth["wear_m"][name][-1], rel=0.1)


def test_json_layout_of_the_spec(unit):
    synth = synth_cycles(3)
    core = MonitorCore(unit, wear_rates=linear_rates(1e-9), clearance_growth=screw_growth)
    for s, (t, v) in synth.signals().items():
        core.add(s, t, v)
    core.process(final=True)
    doc = json.loads(json.dumps(core.to_json_dict(), allow_nan=False))
    assert doc["duty_cycles"] == 3
    assert set(doc["wear"]) == {"screw_raceway_m", "nut_raceway_m", "ball_m"}
    assert {"model_m", "estimate_m", "std_m"} <= set(doc["clearance"])
    life = doc["remaining_life"]
    assert {"limit_m", "cycles_p05", "cycles_p50", "cycles_p95"} <= set(life)
    assert life["limit_m"] == unit.monitor.clearance_limit
    assert life["status"] == "insufficient_data" and life["cycles_p50"] is None
    assert isinstance(doc["input_faults"], dict)


def test_resume_from_checkpoint_continues_without_double_counting(unit, tmp_path):
    synth = synth_cycles(12, noise=True, seed=6)
    kw = {"wear_rates": linear_rates(1e-9), "clearance_growth": screw_growth}
    ref = MonitorCore(unit, **kw)
    for s, (t, v) in synth.signals().items():
        ref.add(s, t, v)
    ref.process(final=True)
    # first run stops (killed) in the middle of application 7, after checkpointing at every application
    cut = synth.marks[6]["contact"]
    first = MonitorCore(unit, MonitorConfig(checkpoint_every_cycles=1), state_path=tmp_path / "s.json", **kw)
    for s, (t, v) in synth.signals().items():
        first.add(s, t[t < cut], v[t < cut])
    first.process()
    state, problems = load_state(tmp_path / "s.json")
    assert state.duty_cycles == 6 and not [p for p in problems if "corrupt" in p]
    # the restarted monitor is fed everything again (a bag replayed from its start): old data is dropped
    second = MonitorCore(unit, state=state, **kw)
    for s, (t, v) in synth.signals().items():
        second.add(s, t, v)
    second.process(final=True)
    a, b = second.snapshot(), ref.snapshot()
    assert a.duty_cycles == b.duty_cycles == 12
    assert a.screw_raceway_m == pytest.approx(b.screw_raceway_m, rel=1e-12)
    assert a.input_faults["late"] == 3 * int(np.sum(synth.t <= state.last_stamp_ns * 1e-9 + 1e-9))
    save_state(tmp_path / "s.json", second.state)
    assert load_state(tmp_path / "s.json")[0].duty_cycles == 12


def test_bad_input_never_breaks_the_core(unit):
    rng = np.random.default_rng(1)
    core = MonitorCore(unit, wear_rates=linear_rates(1e-9), clearance_growth=screw_growth)
    for _ in range(200):
        n = int(rng.integers(1, 50))
        odd = rng.choice([np.nan, np.inf, -1.0, 1e30, 5.0], n)
        stamps = odd if rng.random() < 0.2 else rng.random(n) * 100
        for s in ("angle", "velocity", "axial_force"):
            values = rng.normal(0, 1, n) * 10 ** rng.integers(0, 12)
            values[rng.random(n) < 0.1] = np.nan
            core.add(s, stamps, values)
        core.process()
    core.process(final=True)
    snap = core.snapshot()
    assert math.isfinite(snap.screw_raceway_m) and snap.screw_raceway_m >= 0
    assert sum(snap.input_faults.values()) > 0


def test_outlier_rejected_and_clearance_jump_followed(unit):
    def clearance(k):
        return 0.2e-3 + (50e-6 if k == 8 else 0.0) + (100e-6 if k >= 20 else 0.0)

    synth = synth_cycles(30, noise=True, seed=12, clearance=clearance)
    core = MonitorCore(unit, wear_rates=linear_rates(1e-12), clearance_growth=screw_growth)
    for s, (t, v) in synth.signals().items():
        core.add(s, t, v)
    cycles = core.process(final=True)
    snap = core.snapshot()
    assert snap.input_faults["observation_rejected"] == 1 + 3  # the outlier, then 3 in a row: a step
    assert (snap.clearance_steps, snap.growth_changes) == (1, 0)
    assert set(snap.input_faults) <= set(FAULT_KINDS)
    assert abs(cycles[8].clearance_estimate_m - 0.2e-3) < 2e-6  # the outlier did not move the estimate
    assert abs(cycles[19].clearance_estimate_m - 0.2e-3) < 2e-6
    assert abs(snap.clearance_estimate_m - 0.3e-3) < 3 * snap.clearance_std_m
