"""Integrator of 004 eq. 1-9: against scipy's solve_ivp, closed forms and invariants."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.twin import actuator_model, simulate_current_driven, simulate_voltage_driven
from ebm_wear_monitor.twin.dynamics import equivalent_inertia
from ebm_wear_monitor.twin.friction import friction_torque
from ebm_wear_monitor.validation.papers.paper004 import paper_unit

UNIT = paper_unit()
MODEL = actuator_model(UNIT)


def test_equivalent_inertia_eq2():
    r = 2.5e-3 / (2 * math.pi * 5.05)
    assert equivalent_inertia(UNIT) == pytest.approx(2.0e-3 + 1.5e-5 + 1.64e-5 / 5.05**2 + r * r * 0.66,
                                                     rel=1e-12)


def test_voltage_step_free_run_matches_solve_ivp():
    """Before contact (F = 0) the model is smooth: eq. 1, 8, 9 (sliding) integrated by RK45."""
    m = MODEL
    e = 40.0
    t = np.arange(0.0, 0.06, 1e-3)
    ours = simulate_voltage_driven(m, t, np.full(t.size, e), substeps=4)
    law = m.friction

    def rhs(_, y):
        i, w = y
        torque = m.torque_constant * i - (law.coulomb + law.viscous * w)
        return [(e - m.resistance * i - m.back_emf_constant * w) / m.inductance,
                torque / m.inertia if torque > 0 or w > 0 else 0.0]

    ref = solve_ivp(rhs, (0, t[-1]), [0.0, 0.0], t_eval=t, rtol=1e-9, atol=1e-12, max_step=1e-4)
    speed = ours.velocity * m.gear_ratio
    assert np.max(np.abs(speed - ref.y[1])) < 0.01 * np.max(ref.y[1])
    assert np.max(np.abs(ours.current - ref.y[0])) < 0.02 * np.max(ref.y[0])
    assert ours.axial_force.max() == 0.0


def test_eq9_three_cases():
    law = MODEL.friction
    # sliding
    assert friction_torque(law, 10.0, 1e4, 0.8, 5.0, zero_speed_band=0.01) == pytest.approx(
        law.coulomb + law.load_coefficient * 1e4 + law.viscous * 10)
    # stuck: balances the drive exactly
    assert friction_torque(law, 0.0, 1e4, 0.8, 0.3, zero_speed_band=0.01) == pytest.approx(0.3)
    # breakaway: the static level in the direction of the drive
    assert friction_torque(law, 0.0, 1e4, 0.8, -5.0, zero_speed_band=0.01) == pytest.approx(
        -(law.static + law.load_coefficient * 1e4))


def test_stick_below_breakaway_and_motion_above():
    t = np.arange(0.0, 0.5, 1e-3)
    below = law_current = MODEL.friction.static * 0.95 / MODEL.torque_constant
    run = simulate_current_driven(MODEL, t, np.full(t.size, below))
    assert np.all(run.velocity == 0.0) and np.all(run.angle == 0.0)
    law_current = MODEL.friction.static * 1.05 / MODEL.torque_constant
    run = simulate_current_driven(MODEL, t, np.full(t.size, law_current))
    assert run.velocity[-1] > 0.0


def test_held_force_has_no_chatter_and_satisfies_the_stick_band():
    t = np.arange(0.0, 3.0, 1e-3)
    current = np.where(t < 1.0, 2.6, 1.9)  # push to ~30 kN, then back off within the stick band
    run = simulate_current_driven(MODEL, t, current)
    tail = run.velocity[t > 2.0]
    assert np.count_nonzero(tail) == 0  # no chatter once stuck
    f = run.axial_force[-1]
    drive = MODEL.torque_constant * 1.9 - MODEL.load_torque(f)
    assert abs(drive) <= MODEL.friction.static + MODEL.friction.load_coefficient * f
    motion = np.abs(np.diff(np.sign(run.velocity)))
    assert np.count_nonzero(motion) < 10  # a few start/stop events, not a limit cycle


def test_current_driven_replays_a_voltage_driven_run():
    """What the diagnosis does: feed the recorded current back; the motion and force must follow."""
    t = np.arange(0.0, 0.4, 1e-3)
    volts = np.where(t < 0.25, 30.0, -30.0)
    run = simulate_voltage_driven(MODEL, t, volts, substeps=4)
    replay = simulate_current_driven(MODEL, t, run.current, substeps=4)
    # open-loop integration of a current trace accumulates torque error (the recorded current is
    # point samples, the voltage run used step means), so compare over the first 0.1 s
    early = t < 0.1
    assert np.max(np.abs(replay.angle[early] - run.angle[early])) < 0.01 * np.max(run.angle)


def test_batch_equals_separate_runs():
    t = np.arange(0.0, 0.3, 1e-3)
    volts = np.stack([np.full(t.size, 20.0), np.full(t.size, 35.0)], axis=1)
    both = simulate_voltage_driven(MODEL, t, volts)
    for j in range(2):
        alone = simulate_voltage_driven(MODEL, t, volts[:, j])
        assert np.array_equal(both.axial_force[:, j], alone.axial_force)


def test_energy_balance_closes_to_round_off():
    t = np.arange(0.0, 0.5, 1e-3)
    run = simulate_voltage_driven(MODEL, t, np.where(t < 0.3, 25.0, -10.0))
    w = np.diff(run.angle * MODEL.gear_ratio)
    wi = np.sum(run.motor_torque[:-1] * w)
    wf = np.sum(run.friction_torque[:-1] * w)
    wl = np.sum(MODEL.load_torque(run.axial_force[:-1]) * w)
    kinetic = 0.5 * MODEL.inertia * (run.velocity[-1] * MODEL.gear_ratio) ** 2
    assert wi == pytest.approx(wf + wl + kinetic, rel=1e-9, abs=1e-12)
    assert wf > 0  # friction only dissipates


def test_nonuniform_time_grid_is_refused():
    with pytest.raises(InputError):
        simulate_current_driven(MODEL, np.array([0.0, 0.001, 0.003]), np.zeros(3))


def test_stiffer_clamp_needs_less_travel():
    stiff = dataclasses.replace(MODEL, clamp=dataclasses.replace(MODEL.clamp, stiffening=1.0))
    f = 20e3
    assert stiff.clamp.travel(f) < MODEL.clamp.travel(f)
    assert stiff.clamp.force(stiff.clamp.travel(f)) == pytest.approx(f, rel=1e-12)
