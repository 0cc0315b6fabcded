"""Duty cycles of the twin: phases of 000 Fig. 2, wear coupling, effects, sensor noise, determinism."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ebm_wear_monitor.domain.phases import PHASE_NAMES as PHASES
from ebm_wear_monitor.domain.phases import Phase
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.twin import CATALOG, NOISELESS, SensorNoise, simulate_unit

CLEARANCE, GENERATION, MAINTENANCE, RELEASE, IDLE = Phase

UNIT = load_unit("embu_000")
KW = {"hold_s": 0.3, "rest_s": 0.2, "noise": NOISELESS, "wear": False}


@pytest.fixture(scope="module")
def nominal():
    return simulate_unit(UNIT, 3, demands=[8e3, 16e3, 24e3], **KW)


def test_phases_in_order_and_named_as_the_spec(nominal):
    assert PHASES[:4] == ("clearance_elimination", "force_generation", "force_maintenance", "force_release")
    for c in range(3):
        phase = nominal.phase[nominal.cycle == c]
        changes = phase[np.r_[True, np.diff(phase) != 0]]
        assert changes.tolist() == [CLEARANCE, GENERATION, MAINTENANCE, RELEASE, IDLE]
        assert np.count_nonzero(phase == MAINTENANCE) == pytest.approx(300, abs=1)  # hold_s at 1 kHz


def test_phase_start_times_in_the_ground_truth(nominal):
    starts = nominal.truth["phase_start_s"]
    for c in range(3):
        for p in range(len(PHASES)):
            first = np.flatnonzero((nominal.cycle == c) & (nominal.phase == p))[0]
            assert starts[c, p] == pytest.approx(nominal.t[first])
    assert nominal.ground_truth()["phase_start_s"][0][0] == 0.0


def test_force_held_at_demand_and_released_to_rest(nominal):
    clean = nominal.clean
    for c, demand in enumerate([8e3, 16e3, 24e3]):
        sel = nominal.cycle == c
        held = clean["axial_force"][sel & (nominal.phase == MAINTENANCE)]
        assert np.all(np.abs(held - demand) <= 0.01 * demand + 50)
        idle = sel & (nominal.phase == IDLE)
        assert np.all(clean["axial_force"][idle] == 0.0)
        assert np.all(np.abs(clean["angle"][idle]) < 0.01 / UNIT.actuator.gear_ratio + 1e-12)


def test_clearance_phase_runs_at_full_speed_and_closes_the_clearance(nominal):
    clean = nominal.clean
    sel = (nominal.cycle == 0) & (nominal.phase == CLEARANCE)
    top = clean["velocity"][sel].max() * UNIT.actuator.gear_ratio
    a = UNIT.actuator
    expected = (a.motor.torque_constant * a.supply_voltage - a.friction.coulomb * a.motor.resistance) / (
        a.friction.viscous * a.motor.resistance + a.motor.back_emf_constant * a.motor.torque_constant)
    assert top == pytest.approx(expected, rel=0.01)  # eq. 14's K
    travel = clean["angle"][nominal.phase == GENERATION][0] * UNIT.ball_screw.lead / (2 * math.pi)
    assert travel == pytest.approx(a.clearance, rel=0.05)
    # signs: apply positive, release negative, force compressive positive
    assert clean["velocity"][nominal.phase == RELEASE].min() < 0 < clean["velocity"][sel].max()


def test_sensor_noise_is_the_documented_one():
    noise = SensorNoise()
    run = simulate_unit(UNIT, 1, demands=[10e3], hold_s=0.5, rest_s=0.2, noise=noise, wear=False, seed=5)
    for name in ("angle", "velocity", "axial_force", "current"):
        err = getattr(run, name) - run.clean[name]
        assert np.std(err) == pytest.approx(getattr(noise, name), rel=0.1), name


def test_same_seed_same_data_other_seed_other_noise():
    a = simulate_unit(UNIT, 1, demands=[10e3], hold_s=0.1, rest_s=0.1, wear=False, seed=1)
    b = simulate_unit(UNIT, 1, demands=[10e3], hold_s=0.1, rest_s=0.1, wear=False, seed=1)
    c = simulate_unit(UNIT, 1, demands=[10e3], hold_s=0.1, rest_s=0.1, wear=False, seed=2)
    assert np.array_equal(a.axial_force, b.axial_force)
    assert not np.array_equal(a.axial_force, c.axial_force)
    assert np.array_equal(a.clean["axial_force"], c.clean["axial_force"])


def _phase_mean(run, signal, phase, source="clean"):
    values = run.clean[signal] if source == "clean" else getattr(run, signal)
    return float(np.mean(values[run.phase == phase]))


@pytest.fixture(scope="module")
def effect_runs():
    base = dict(demands=[15e3], hold_s=0.3, rest_s=0.2, noise=NOISELESS, wear=False)
    runs = {"none": simulate_unit(UNIT, 1, **base)}
    magnitudes = {"viscous_friction": 1.0, "load_friction": 1.0, "efficiency_variation": 0.3,
                  "preload_change": 0.5, "stribeck": 5.0, "stiffness_nonlinearity": 1.0,
                  "clearance_growth": 1e-4, "force_sensor_bias": 500.0, "force_sensor_gain": 0.05}
    assert set(magnitudes) == set(CATALOG)
    for name, m in magnitudes.items():
        runs[name] = simulate_unit(UNIT, 1, effects={name: m}, **base)
    return runs


def test_every_effect_changes_the_data_in_its_physical_direction(effect_runs):
    r = effect_runs
    none = r["none"]
    current_clearance = _phase_mean(none, "current", CLEARANCE)
    # more drag: more current at the full-speed run-out
    assert _phase_mean(r["viscous_friction"], "current", CLEARANCE) > current_clearance + 0.01
    # preload: friction up at zero load
    assert _phase_mean(r["preload_change"], "current", CLEARANCE) > current_clearance + 0.05
    # load friction and low-speed efficiency loss: more current while pushing force up
    gen = _phase_mean(none, "current", GENERATION)
    assert _phase_mean(r["load_friction"], "current", GENERATION) > gen + 0.05
    assert _phase_mean(r["efficiency_variation"], "current", GENERATION) > gen + 0.05
    # a larger clearance: contact later, at a larger angle
    first_contact = {k: run.clean["angle"][run.clean["axial_force"] > 0][0] for k, run in r.items()}
    assert first_contact["clearance_growth"] > first_contact["none"] * 1.3
    # a stiffening clamp: less angle for the same held force
    held_angle = {k: _phase_mean(run, "angle", MAINTENANCE) for k, run in r.items()}
    assert held_angle["stiffness_nonlinearity"] < held_angle["none"] - 0.01
    # sensor offset: the measured force holds the demand, the real clamp force is lower by the offset
    biased = r["force_sensor_bias"]
    assert _phase_mean(biased, "axial_force", MAINTENANCE, "measured") == pytest.approx(15e3, abs=200)
    assert _phase_mean(biased, "axial_force", MAINTENANCE) == pytest.approx(15e3 - 500, abs=200)
    gained = r["force_sensor_gain"]
    assert _phase_mean(gained, "axial_force", MAINTENANCE) == pytest.approx(15e3 / 1.05, rel=0.015)
    # Stribeck: friction above the Coulomb level at low sliding speed only
    assert not np.array_equal(r["stribeck"].clean["current"], none.clean["current"])


def test_wear_coupling_grows_the_clearance_and_scales_with_acceleration():
    kw = {"demands": [20e3], "hold_s": 0.2, "rest_s": 0.1, "noise": NOISELESS, "batch": 4}
    slow = simulate_unit(UNIT, 8, wear_acceleration=1.0, **kw)
    fast = simulate_unit(UNIT, 8, wear_acceleration=1e6, **kw)
    wear1, wear2 = slow.truth["wear_m"], fast.truth["wear_m"]
    for s in ("screw", "nut", "ball"):
        assert np.all(np.diff(wear1[s]) > 0)
    assert wear1["screw"][-1] > wear1["nut"][-1]  # 000: screw wears more than the nut
    # acceleration multiplies the first application's wear exactly (same clearance)
    assert wear2["screw"][0] == pytest.approx(1e6 * wear1["screw"][0], rel=1e-9)
    grown = fast.truth["clearance_after_m"]
    assert np.all(np.diff(grown) > 0) and grown[-1] > UNIT.actuator.clearance + 1e-5
    # later applications make contact further out: the clearance the twin used follows the growth
    used = fast.truth["clearance_m"]
    assert np.all(np.diff(used) > 0)
    assert np.allclose(used[1:], grown[:-1], rtol=0.05)
    assert fast.truth["eol_cycles"] < slow.truth["eol_cycles"]


def test_prior_cycles_start_worn():
    kw = {"demands": [15e3], "hold_s": 0.2, "rest_s": 0.1, "noise": NOISELESS}
    new = simulate_unit(UNIT, 2, **kw)
    worn = simulate_unit(UNIT, 2, prior_cycles=1_000_000, **kw)
    per_cycle = new.truth["wear_m"]["screw"][0]
    assert worn.truth["wear_m"]["screw"][0] == pytest.approx(1_000_001 * per_cycle, rel=0.01)
    assert worn.truth["clearance_m"][0] > new.truth["clearance_m"][0]
    assert worn.ground_truth()["cycles_at_start"] == 1_000_000


@pytest.mark.parametrize("kwargs", [{"cycles": 0}, {"cycles": 1, "rate_hz": 1.0},
                                    {"cycles": 1, "wear_acceleration": -1.0},
                                    {"cycles": 1, "demands": [0.0]},
                                    {"cycles": 1, "effects": {"clearance_growth": -1.0}},
                                    {"cycles": 1, "effects": {"stiffness_nonlinearity": -0.5}},
                                    {"cycles": 1, "effects": {"efficiency_variation": 1.0}},
                                    {"cycles": 1, "effects": {"viscous_friction": "much"}}])
def test_bad_input(kwargs):
    with pytest.raises(InputError):
        simulate_unit(UNIT, **kwargs)


def test_slow_recording_is_the_1kHz_drive_decimated():
    kw = {"demands": [15e3], "hold_s": 0.3, "rest_s": 0.2, "noise": NOISELESS, "wear": False}
    fast = simulate_unit(UNIT, 2, rate_hz=1000.0, **kw)
    slow = simulate_unit(UNIT, 2, rate_hz=100.0, **kw)
    assert np.allclose(np.diff(slow.t), 0.01)
    for name in ("angle", "axial_force", "current"):
        assert np.array_equal(slow.clean[name], fast.clean[name][::10])
    assert np.array_equal(slow.phase, fast.phase[::10])


def test_sensor_that_never_reads_the_onset_force_still_ends_every_application():
    """A force sensor biased far below the onset force: clearance elimination ends at its timeout
    (it used to run for ever) and the application goes through every phase in order."""
    from ebm_wear_monitor.twin.controller import BrakeController
    controller = BrakeController(clearance_timeout=0.2)
    run = simulate_unit(UNIT, 1, demands=[10e3], effects={"force_sensor_bias": -1e6}, controller=controller,
                        **KW)
    phase = run.phase
    order = [CLEARANCE, GENERATION, MAINTENANCE, RELEASE, IDLE]
    assert phase[np.r_[True, np.diff(phase) != 0]].tolist() == order
    assert run.truth["phase_start_s"][0, GENERATION] == pytest.approx(0.2, abs=2e-3)
    assert np.all(np.isfinite(run.clean["axial_force"]))


def test_ground_truth_clearance_is_the_wear_law_and_end_of_life_extrapolates_it():
    """clearance_after_m = x_ag,nominal + clearance_growth(wear_m) (physics core), and eol_cycles is
    where a least-squares line through it reaches the limit (growth per application nearly constant)."""
    from ebm_wear_monitor.physics import clearance_growth
    kw = {"demands": [20e3], "hold_s": 0.2, "rest_s": 0.1, "noise": NOISELESS, "batch": 4}
    truth = simulate_unit(UNIT, 8, wear_acceleration=1e6, prior_cycles=3, **kw).truth
    wear, after = truth["wear_m"], truth["clearance_after_m"]
    growth = clearance_growth(UNIT, wear["screw"], wear["nut"], wear["ball"])
    assert np.allclose(after, UNIT.actuator.clearance + growth, rtol=1e-12, atol=0)
    since_new = 3 + np.arange(1, 9)
    slope, intercept = np.polyfit(since_new, after, 1)
    assert truth["eol_cycles"] == pytest.approx((truth["clearance_limit_m"] - intercept) / slope, rel=0.01)


def test_each_application_starts_at_the_clearance_the_previous_one_left_under_unequal_wear():
    """Batched applications with demands of unequal wear (accelerated x1e5): the clearance the plant
    ran each application with is the clearance after the previous one (within the simulator's
    tolerance), not a linear extrapolation from the first application's growth."""
    from ebm_wear_monitor.twin.simulator import CLEARANCE_TOLERANCE_M

    truth = simulate_unit(UNIT, 12, demands=[8e3, 20e3, 14e3], hold_s=0.2, rest_s=0.1, noise=NOISELESS,
                          wear_acceleration=1e5, batch=6).truth
    during, after = np.asarray(truth["clearance_m"]), np.asarray(truth["clearance_after_m"])
    steps = np.diff(after)
    assert steps.max() > 1.5 * steps.min() > 0.0  # unequal growth per application: the case at stake
    assert steps.min() > 20 * CLEARANCE_TOLERANCE_M  # and large against the tolerance
    np.testing.assert_allclose(during[1:], after[:-1], rtol=0.0, atol=2 * CLEARANCE_TOLERANCE_M)
