"""Per-sample labels (label_samples) against known phase boundaries and against MonitorCore's own segments."""

from __future__ import annotations

import numpy as np
import pytest

from ebm_wear_monitor.domain.phases import Phase
from ebm_wear_monitor.domain.segmentation import run_starts
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.monitor import MonitorConfig, MonitorCore
from ebm_wear_monitor.monitor.segmentation import CE, FG, FM, FR, label_samples

from monitor_synth import linear_rates, screw_growth, synth_cycles


def _labels(unit, synth, config=None):
    config = config or MonitorConfig()
    return label_samples(synth.t, synth.angle, synth.velocity, synth.force, config=config,
                         thresholds=config.resolve(unit))


def _runs(code: np.ndarray) -> list[int]:
    return code[run_starts(code)].tolist()


def test_every_sample_labelled_in_phase_order_with_cycle_index(unit):
    synth = synth_cycles(5, noise=True, seed=4, peak_force=lambda k: 8e3 + 3e3 * k)
    lab = _labels(unit, synth)
    assert lab.phase.shape == lab.cycle.shape == synth.t.shape
    assert lab.kinds == ("cycle",) * 5
    assert list(np.unique(lab.cycle)) == list(range(5))
    assert np.all(np.diff(lab.cycle) >= 0)
    for c, mk in enumerate(synth.marks):
        codes = lab.phase[lab.cycle == c]
        runs = [r for r in _runs(codes) if r != Phase.IDLE]
        assert runs == [CE, FG, FM, FR]
        # the segment's samples lie inside the true motion (up to the threshold crossings), rest outside
        t = synth.t[lab.cycle == c]
        active = t[codes != Phase.IDLE]
        assert mk["start"] - 1e-9 <= active[0] <= mk["start"] + 5e-3
        assert mk["release_end"] - 5e-3 <= active[-1] <= mk["release_end"]
        held = t[codes == FM]
        assert held[0] == pytest.approx(mk["apply_end"], abs=5e-3)
        assert held[-1] == pytest.approx(mk["release_start"], abs=5e-3)
    # the stretch before the first application is rest and belongs to cycle 0
    first = np.flatnonzero(lab.phase != Phase.IDLE)[0]
    assert first > 0 and np.all(lab.cycle[:first] == 0)


@pytest.mark.parametrize("rate_hz", [1000.0, 100.0])
def test_phase_durations_equal_those_of_monitor_core(unit, rate_hz):
    """Same state machine: per application, the time covered by each label is MonitorCore's duration."""
    synth = synth_cycles(6, rate_hz=rate_hz, noise=True, seed=7, steps=2)
    core = MonitorCore(unit, wear_rates=linear_rates(1e-9), clearance_growth=screw_growth)
    for s, (t, v) in synth.signals().items():
        core.add(s, t, v)
    cycles = core.process(final=True)
    lab = _labels(unit, synth)
    t_ns = np.rint(synth.t * 1e9).astype(np.int64)
    span = np.append(np.diff(t_ns), 0)  # each sample holds its label until the next sample
    assert len(cycles) == lab.n_segments == 6
    for c, summary in enumerate(cycles):
        in_cycle = lab.cycle == c
        durations = [int(span[in_cycle & (lab.phase == k)].sum()) * 1e-9 for k in (CE, FG, FM, FR)]
        assert durations == pytest.approx(list(summary.phase_durations_s), abs=1e-12)
        assert t_ns[in_cycle & (lab.phase != Phase.IDLE)][0] == summary.start_ns


def test_data_starting_inside_an_application_is_motion(unit):
    synth = synth_cycles(3, noise=False)
    a = np.flatnonzero(synth.velocity > 0)[5]  # cut inside the first apply move
    lab = label_samples(synth.t[a:], synth.angle[a:], synth.velocity[a:], synth.force[a:],
                        config=MonitorConfig(), thresholds=MonitorConfig().resolve(unit))
    assert lab.phase[0] == Phase.IDLE and lab.kinds[0] == "motion"  # motion outside an application: idle
    assert lab.kinds[1:] == ("cycle", "cycle")
    assert np.all(lab.phase[lab.cycle == 0] == Phase.IDLE)


def test_gap_closes_the_application_as_interrupted(unit):
    synth = synth_cycles(2, noise=False)
    t = synth.t.copy()
    mid = np.flatnonzero(synth.velocity < 0)[3]  # inside the first release
    t[mid:] += 1.0  # a 1 s hole in the data
    lab = label_samples(t, synth.angle, synth.velocity, synth.force, config=MonitorConfig(),
                        thresholds=MonitorConfig().resolve(unit))
    assert lab.kinds[0] == "interrupted" and lab.kinds[-1] == "cycle"
    assert lab.cycle[mid - 1] != lab.cycle[mid]


def test_rejects_bad_stamps(unit):
    synth = synth_cycles(1)
    th = MonitorConfig().resolve(unit)
    t = synth.t.copy()
    t[10] = t[9]
    with pytest.raises(InputError, match="increase"):
        label_samples(t, synth.angle, synth.velocity, synth.force, config=MonitorConfig(), thresholds=th)
    with pytest.raises(InputError, match="length"):
        label_samples(synth.t[:-1], synth.angle, synth.velocity, synth.force, config=MonitorConfig(),
                      thresholds=th)
