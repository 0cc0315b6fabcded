"""The breakaway-band test at rest (diagnosis/stick.py) on closed-form recordings (diag_synth)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from ebm_wear_monitor.diagnosis.catalog import build_catalog
from ebm_wear_monitor.diagnosis.pipeline import residual_model, summary
from ebm_wear_monitor.diagnosis.ranking import ALPHA, Scorer, rank
from ebm_wear_monitor.diagnosis.residuals import Augment
from ebm_wear_monitor.diagnosis.stick import RestTorque, band_excess, rest_noise, rest_torque
from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.twin.dynamics import actuator_model

from diag_synth import synth

NOM = actuator_model(load_unit())
BRISK = (0.1, 0.14)  # applications as short as a brisk ECU makes them [s]


def ranked(**kw):
    rec = synth(NOM, Augment(), cycles=12, **kw)
    model = residual_model(rec, NOM)
    sensors = Scorer.sensors(model)
    sc = sensors.scaled(sensors.noise_scale())
    return sc, rank(sc, build_catalog(NOM, float(model.speed.max()), float(model.force.max())))


def test_a_held_clamp_sits_inside_the_band_by_the_breakaway_torque():
    # diag_synth's motor holds the load torque exactly at rest, so the torque the friction must take there
    # is ~0 and the excess is minus the breakaway torque T_fs + G F and the 2 % K_T allowance, from
    # 004 eq. 9 written out here
    sc, _ = ranked(seed=1)
    model, b = sc.model, sc.model.blocks
    _, excess, _ = band_excess(model, sc.base.aug)
    law = NOM.friction
    interior = np.r_[False, b.run[1:] == b.run[:-1]] & np.r_[b.run[:-1] == b.run[1:], False]
    hold = ~b.moving & (b.force > 5e3) & interior  # the first and last block of a hold move partly
    drive = b.mean(NOM.torque_constant * model.rec.current)
    expected = -(law.static + law.load_coefficient * b.force) - 0.02 * np.abs(drive)
    assert hold.sum() > 50
    # the held torque itself is the current noise over a block (0.015-0.017 N m here)
    dev = excess[hold] - expected[hold]
    assert abs(np.median(dev)) < 0.03 and np.max(np.abs(dev)) < 0.1


@pytest.mark.parametrize(("seed", "durations"), [(0, None), (1, None), (2, None), (0, BRISK), (1, BRISK)])
def test_a_healthy_unit_holds_its_rest_within_the_band(seed, durations):
    _, r = ranked(seed=seed, **({"durations": durations} if durations else {}))
    assert r.rest is not None and r.rest.cycles >= 4
    assert not r.rest.counts(ALPHA) and not r.rest_decided and r.verdict == "none"


def test_a_drive_at_rest_the_screw_does_not_feel_is_unexplained():
    # in every idle the motor makes a half sine of 1.5 N m the recorded screw does not feel (a motor turning
    # inside a play): nothing changes on the moving screw, so only the band test at rest can see it
    _, r = ranked(seed=2, rest_pulse=1.5)
    assert r.rest is not None and r.rest_decided and r.verdict == "unexplained"
    assert r.joint is None and r.open_set is not None and not r.open_set.decided  # it was "none" before
    assert r.rest.violated >= r.rest.cycles - 1
    # closed form: the 20 ms block at the pulse's peak holds 1.5 x (cos 0.4 pi - cos 0.6 pi) / (0.2 pi) =
    # 1.476 N m against the breakaway torque T_fs at zero force and the 2 % K_T allowance
    peak = 1.5 * (np.cos(0.4 * np.pi) - np.cos(0.6 * np.pi)) / (0.2 * np.pi)
    expected = peak - NOM.friction.static - 0.02 * peak
    assert abs(r.rest.excess - expected) < 0.1, (r.rest.excess, expected)
    assert r.rest.band == pytest.approx(NOM.friction.static, abs=0.02)
    assert "stays at rest while the motor drives" in summary(r)


def test_a_play_the_angle_does_not_see_violates_the_band():
    # a play of 20 % of the clearance between motor and screw, the angle measured on the screw: the motor
    # accelerates through it at the start of each application while the recorded screw stays at rest.
    # There the screw's jump onto the engaged flank alone already reads unexplained, so the test is asked
    # on its own, for its power: it counts for every seed 0-5 (with the torque channel's block noise in
    # place of the noise at rest, seed 1's jump inflated it until no application exceeded z = 2). Brisk
    # applications: diag_synth's minimum-jerk start crosses the play while the acceleration still rises,
    # and over 0.15-0.35 s the drive there exceeds the breakaway torque by less than itself in some seeds
    # (not material)
    for seed in range(6):
        sc, r = ranked(seed=seed, play=0.2 * NOM.clamp.clearance, durations=BRISK)
        assert r.verdict == "unexplained"
        rest = rest_torque(sc.model, sc.base.aug, sc.sigma_torque, sc.split.calibration, sc.split.heldout)
        assert rest is not None and rest.counts(ALPHA), (seed, rest)
        # the drive through the play: the rotor's inertia torque, beyond twice the breakaway torque
        assert rest.excess > rest.band


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_noise_at_rest_is_the_scatter_of_the_held_torque(seed):
    # measured on the calibration side, it must match the block-to-block scatter of the held torque at rest
    # on the held-out side (interior blocks: the first and last of a run move partly): measured 1.0-2.0
    # times it (the first and last blocks of a run at rest widen the curvature), never below half
    sc, _ = ranked(seed=seed)
    b = sc.model.blocks
    held, _, _ = band_excess(sc.model, sc.base.aug)
    noise = rest_noise(held, b.run, sc.split.calibration & ~b.moving)
    interior = np.r_[False, b.run[1:] == b.run[:-1]] & np.r_[b.run[:-1] == b.run[1:], False]
    scatter = float(np.std(held[~b.moving & interior & sc.split.heldout]))
    assert 0.5 * scatter < noise < 2.5 * scatter, (noise, scatter)


def test_the_summary_says_the_screw_stays_at_rest():
    _, r = ranked(seed=5)
    decided = dataclasses.replace(r, verdict="unexplained", rest=RestTorque(10, 9, 1.23, 0.4, 0.04, 1e-8))
    assert decided.rest_decided  # 1.23 N m beyond a 0.4 N m band, p = 1e-8
    text = summary(decided)
    assert "In 9 of 10 held-out applications the recorded screw stays at rest" in text
    assert "1.23 N m beyond the breakaway torque of the twin within its tolerance" in text
    assert "sticks far harder" in text  # the other cause the data cannot rule out
