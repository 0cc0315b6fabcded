"""The two-path test (diagnosis/hysteresis.py) on closed-form recordings (diag_synth): a play between motor
and screw, with the angle on the motor side, taken up while the pads still press puts the release on a
second force-travel path below that force; a lagging force reading, a clearance, a hardening clamp or a play
crossed after the pads let go keep one path."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.signal import lfilter

from ebm_wear_monitor.diagnosis.catalog import build_catalog
from ebm_wear_monitor.diagnosis.hysteresis import hysteresis, level_differences
from ebm_wear_monitor.diagnosis.pipeline import diagnose_with_state, residual_model, summary
from ebm_wear_monitor.diagnosis.ranking import ALPHA, Scorer, rank
from ebm_wear_monitor.diagnosis.residuals import Augment
from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.twin.dynamics import actuator_model

from diag_synth import synth

NOM = actuator_model(load_unit())
PLAY = 0.1 * NOM.clamp.clearance  # 20 µm of nut travel
F_S = 3e3  # force below which the clamp no longer pushes the screw back onto the forward flank [N]
RATE = 1000.0


def recording(seed: int, *, lag: float = 0.0, low_pass: float = 0.0, rate: float = RATE, **kw):
    """diag_synth's recording with the force reading delayed by ``lag`` [s] (a stamp skew) or seen through a
    first-order low pass of time constant ``low_pass`` [s] (a load cell's amplifier), exact discretisation
    for a reading held over each interval, written out here."""
    rec = synth(NOM, kw.pop("aug", Augment()), cycles=kw.pop("cycles", 12), rate=rate, seed=seed, **kw)
    force = rec.axial_force
    if lag:
        force = np.interp(rec.t - lag, rec.t, force)
    if low_pass:
        a = np.exp(-(1.0 / rate) / low_pass)
        force = lfilter([1.0 - a], [1.0, -a], force, zi=[a * force[0]])[0]
    return dataclasses.replace(rec, axial_force=force)


def held_out(m):
    return Scorer.sensors(m).split.heldout_cycles


def test_levels_of_a_single_path_differ_by_the_lag_times_the_speeds():
    # closed form of the module docstring without noise, against the model without a lag: h = tau (|v_a| +
    # |v_r|) at every level, to first order in the speed
    rec = recording(0, lag=2e-3, noise={"angle": 0.0, "velocity": 0.0, "axial_force": 0.0, "current": 0.0})
    m = residual_model(rec, NOM)
    _, h, s = level_differences(m, Augment(), np.geomspace(1e3, 6e3, 6))
    ok = np.isfinite(h)
    assert ok.mean() > 0.9
    assert np.allclose(h[ok], 2e-3 * s[ok], rtol=0.15, atol=0.3e-6), (h[ok] - 2e-3 * s[ok]).max()


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_play_taken_up_in_contact_is_a_step_of_its_width(seed):
    m = residual_model(recording(seed, lag=1.5e-3, play=PLAY, play_force=F_S, angle_side="motor"), NOM)
    r = hysteresis(m, Augment(), held_out(m))
    assert r is not None and r.applications >= 4
    assert r.counts(ALPHA), r
    assert r.step == pytest.approx(PLAY, rel=0.15), r.step
    assert F_S / 1.5 < r.split < 1.5 * F_S  # the step lies below the force where the screw stops
    assert r.lag == pytest.approx(1.5e-3, rel=0.3)  # the model given has none


@pytest.mark.parametrize("case", ["lag", "clearance", "stiffness", "play after contact", "screw side",
                                  "200 Hz"])
def test_one_force_travel_path_is_no_step(case):
    kw = {"lag": dict(lag=3e-3),
          "clearance": dict(aug=Augment(clearance=PLAY), lag=1e-3),
          "stiffness": dict(aug=Augment(stiffness_quad=2e11)),
          "play after contact": dict(play=PLAY, angle_side="motor"),  # the play test's case (play.py)
          "screw side": dict(play=PLAY, play_force=F_S),  # the angle does not see the play
          "200 Hz": dict(rate=200.0, durations=(0.08, 0.15), cycles=30)}[case]  # the chord across contact
    for seed in (0, 1):
        m = residual_model(recording(seed, **kw), NOM)
        r = hysteresis(m, Augment(), held_out(m))
        assert r is not None and not r.counts(ALPHA), (case, r)
        assert abs(r.step) < 1e-6 + 3.0 * r.step_std, (case, r)


@pytest.mark.parametrize("seed", [0, 1])
def test_a_low_pass_force_reading_keeps_one_path_against_the_fitted_lag(seed):
    # a load cell's 5 ms low pass with brisk applies: after the pads let go its tail holds the low levels
    # (a step of 18-33 um against a pure delay); the diagnosis fits the lag with every model, and the
    # verdict model's predicted reading has the same tail
    rec = recording(seed, low_pass=5e-3, durations=(0.08, 0.15))
    res, _, ranking = diagnose_with_state(rec, load_unit())
    assert ranking.hysteresis is not None and not ranking.hysteresis_decided, ranking.hysteresis
    assert abs(ranking.hysteresis.step) < 2e-6, ranking.hysteresis
    assert res.verdict != "unexplained", res.summary  # a healthy unit with a slow load cell


def test_a_play_taken_up_in_contact_turns_the_verdict_unexplained():
    rec = recording(0, play=PLAY, play_force=F_S, angle_side="motor")
    sensors = Scorer.sensors(residual_model(rec, NOM))
    sc = sensors.scaled(sensors.noise_scale())
    r = rank(sc, build_catalog(NOM, float(sc.model.speed.max()), float(sc.model.force.max())))
    assert r.hysteresis is not None and r.hysteresis_decided and r.verdict == "unexplained"
    text = summary(r)
    assert f"{1e6 * r.hysteresis.step:.1f} ± " in text and "one force-travel path" in text
    res, _, ranking = diagnose_with_state(rec, load_unit())
    assert res.verdict == "unexplained" and res.hysteresis is not None and res.hysteresis.decided
    assert ranking.hysteresis is not None
    assert res.to_json_dict()["hysteresis"]["step_m"] == ranking.hysteresis.step
