"""Residuals of the nominal twin vanish on data that obey 004 eq. 1-9 exactly; effects show where expected."""

from dataclasses import fields, replace

import numpy as np
import pytest

from ebm_wear_monitor.diagnosis.pipeline import residual_model
from ebm_wear_monitor.diagnosis.recording import Resampled, recording_from_signals
from ebm_wear_monitor.diagnosis.residuals import FORCE_INPUTS, NOMINAL, TORQUE_INPUTS, Augment
from ebm_wear_monitor.domain.phases import Phase
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.twin.dynamics import actuator_model

from diag_synth import synth

QUIET = {"angle": 0.0, "velocity": 0.0, "axial_force": 0.0, "current": 0.0}


@pytest.fixture(scope="module")
def nom():
    return actuator_model(load_unit())


def test_equivalent_inertia_is_004_eq2(nom):
    # 004 Table 1 with the unit's 5 mm lead: J_m + J_g + J_s / i_g^2 + (l / (2 pi i_g))^2 m_n
    expected = 2.0e-3 + 1.5e-5 + 1.64e-5 / 5.05**2 + (5e-3 / (2 * np.pi * 5.05)) ** 2 * 0.66
    assert nom.inertia == pytest.approx(expected, rel=1e-12)


def test_nominal_residual_vanishes_on_exact_data(nom):
    m = residual_model(synth(nom, cycles=4, noise=QUIET), nom)
    r = m.residuals()
    # discretisation of the angle-speed regression only (a quadratic over 5 samples at 500 Hz, worst where
    # a move starts): below 6 % of the Coulomb torque, typically below 0.5 %, and below 1 N of force
    assert np.abs(r["torque"]).max() < 0.06 * nom.friction.coulomb
    assert np.median(np.abs(r["torque"])) < 0.005 * nom.friction.coulomb
    released = m.conv.released[m.blocks.cycle]  # the first application starts with the recording: no rest
    assert np.abs(r["force"][released]).max() < 1.0
    assert not m.conv.released[0] and m.conv.released[1:].all()


def test_viscous_effect_appears_as_torque_proportional_to_speed(nom):
    dB = 1e-3
    m = residual_model(synth(nom, Augment(dB=dB), cycles=4, noise=QUIET), nom)
    b, r = m.blocks, m.residuals()
    mv = b.moving & (b.speed > 0.2 * b.speed.max())
    w_m = b.speed[mv] * np.sign(r["torque"][mv])
    # R_T = dB * w_m within the block averaging of the speed
    assert np.median(r["torque"][mv] / w_m) == pytest.approx(dB, rel=0.05)
    # the re-anchored speed error is R_T dt / J_me at the screw: same sign, size from the block length
    sig = m.signal_residuals()
    dt = m.rec.t[b.stop] - m.rec.t[b.start]
    assert np.allclose(sig["velocity"], r["torque"] * dt / nom.inertia / nom.gear_ratio)


def test_clearance_shows_in_force_channel_only_during_contact(nom):
    m = residual_model(synth(nom, Augment(clearance=2e-5), cycles=4, noise=QUIET), nom)
    b, r = m.blocks, m.residuals()
    gen = (b.phase == Phase.FORCE_GENERATION) & (b.force > 2e3)
    # F_meas - K_b (x - x_ag) = -K_b dx once both laws are in contact
    assert np.median(r["force"][gen]) == pytest.approx(-nom.clamp.stiffness * 2e-5, rel=0.02)
    assert np.median(np.abs(r["torque"])) < 0.005 * nom.friction.coulomb


def test_recording_from_signals_rejects_missing_topic():
    t = np.linspace(0, 1, 100)
    with pytest.raises(InputError, match="motor/current"):
        recording_from_signals({"angle": (t, t), "velocity": (t, t), "axial_force": (t, t)})


def test_recording_from_signals_sorts_dedups_and_keeps_native_intervals():
    t = np.linspace(0, 1, 200)
    rev = t[::-1]
    slow = t[::4]  # a topic at a quarter of the rate, interpolated onto the angle's stamps
    sig = {"angle": (rev, 2 * rev), "velocity": (np.concatenate([t, t[:5]]), np.concatenate([t, t[:5]])),
           "axial_force": (slow, 3 * slow), "current": (t, -t)}
    rec = recording_from_signals(sig)
    assert np.allclose(rec.angle, 2 * rec.t) and np.allclose(rec.current, -rec.t)
    assert np.allclose(rec.axial_force, 3 * rec.t)
    assert rec.interval("axial_force") == pytest.approx(4 * rec.interval("angle"))


def test_force_channel_ignores_encoder_zero_and_tare(nom):
    rec = synth(nom, Augment(clearance=2e-5), cycles=4, seed=1)
    moved = Resampled(rec.t, rec.angle + 57.3, rec.velocity, rec.axial_force + 321.0, rec.current)
    r0 = residual_model(rec, nom).residuals()["force"]
    r1 = residual_model(moved, nom).residuals()["force"]
    # the tare is estimated per application from its idle readings: equal to well within the noise
    assert np.max(np.abs(r0 - r1)) < 3.0


def test_remembered_residuals_are_keyed_by_every_field_they_read(nom):
    # ResidualModel remembers each channel's residual under its *_INPUTS fields: no other field may change it,
    # and every field listed there does change it (a field added to Augment but left out of the friction
    # law or the clamp law would otherwise fit as nothing, silently)
    m = residual_model(synth(nom, cycles=4, noise=QUIET), nom)
    # every conditional branch on: Stribeck, direction asymmetry, sensor lag and skews
    start = Augment(stribeck_torque=0.01, stribeck_speed=2.0, reverse_dT_fc=1e-3, reverse_dG=1e-6,
                    force_lag=1e-3, force_skew=1e-3, current_shift=1e-3, load_shift=1e-3)
    torque, force = m.signal_residuals(start)["current"], m.force_model(start)  # neither is remembered
    for f in fields(Augment):
        aug = replace(start, **{f.name: getattr(start, f.name) * 1.1 + 1e-3})
        moved_torque = not np.array_equal(m.signal_residuals(aug)["current"], torque)
        moved_force = not np.array_equal(m.force_model(aug), force)
        # T_fs is read only by the band test at rest (stick.band_excess): the torque channel's blocks at rest
        # take whatever friction balances the drive (residuals module docstring)
        assert moved_torque == (f.name in TORQUE_INPUTS and f.name != "dT_fs"), f.name
        assert moved_force == (f.name in FORCE_INPUTS), f.name
        assert moved_torque or moved_force or f.name == "dT_fs", f.name  # no field that nothing reads
    r = m.torque_residual(NOMINAL)
    assert m.torque_residual(NOMINAL) is r and not r.flags.writeable
