"""000 validation: per-cycle wear of the reconstructed Fig. 5 duty cycle vs Table 3 and the endurance test."""

import math

import numpy as np
import pytest

from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.physics import clearance_growth, wear_model
from ebm_wear_monitor.validation.papers.paper000 import DutyCycle000, cycle_wear

UNIT = load_unit()
TABLE3_SCREW, TABLE3_NUT = 1.4843e-10, 1.3787e-10  # 000 Table 3, m per duty cycle
ENDURANCE_PER_SIDE = 1.65e-10  # 000 Sec. 5: ball + raceway, one side, m per cycle
CYCLES, TOTAL_SIDE = 200_000, 0.033e-3  # 000 Sec. 5: after 200,000 cycles, 2/3 of it on the raceway


@pytest.fixture(scope="module")
def default_cycle():
    return cycle_wear(wear_model(UNIT, "direct").rates)


def within_factor(value, reference, factor=2.0):
    return reference / factor <= value <= reference * factor


def test_duty_cycle_reconstruction_is_consistent():
    cyc = DutyCycle000()
    _, f, w, phase = cyc.sample()
    assert np.all(np.diff(phase) >= 0) and set(phase) == {0, 1, 2, 3}
    assert np.all(f >= 0) and f.max() == pytest.approx(cyc.f_max, rel=0.02)
    assert f[-1] < 0.02 * cyc.f_max and abs(w[-1]) < 0.15 * cyc.w_max  # both end at zero (Fig. 5b)
    apply = np.sum(w[phase == 1]) * cyc.dt
    release = -np.sum(w[phase == 3]) * cyc.dt
    assert release == pytest.approx(apply, rel=0.05)  # the nut returns along the same stiffness line
    assert np.all(w[phase == 2] == 0.0)  # force maintenance: no sliding, no wear


def test_per_cycle_wear_against_000_table_3(default_cycle):
    ratio_s = default_cycle["screw"] / TABLE3_SCREW
    ratio_n = default_cycle["nut"] / TABLE3_NUT
    assert within_factor(default_cycle["screw"], TABLE3_SCREW), ratio_s
    assert within_factor(default_cycle["nut"], TABLE3_NUT), ratio_n
    assert default_cycle["screw"] > default_cycle["nut"]  # 000 Sec. 5 and Table 3
    # both phase groups of Table 3 contribute, the apply stroke more than the release
    assert default_cycle["screw_apply"] > default_cycle["screw_release"] > 0.0


def test_per_cycle_wear_against_the_endurance_test(default_cycle):
    per_side = default_cycle["screw"] + default_cycle["ball"]
    assert within_factor(per_side, ENDURANCE_PER_SIDE), per_side / ENDURANCE_PER_SIDE
    assert within_factor(CYCLES * default_cycle["screw"], 2.0 / 3.0 * TOTAL_SIDE)
    assert within_factor(CYCLES * default_cycle["ball"], 1.0 / 3.0 * TOTAL_SIDE)
    # the ball takes (1 - 2/3)/(2/3) = 1/2 of the mean raceway depth
    assert default_cycle["ball"] == pytest.approx(0.25 * (default_cycle["screw"] + default_cycle["nut"]),
                                                  rel=1e-3)


def test_clearance_growth_after_the_endurance_test(default_cycle):
    """(h_s + h_n + 2 h_b) / (sin a0 cos phi): tenths of a millimetre after 200,000 cycles."""
    growth = clearance_growth(UNIT, CYCLES * default_cycle["screw"], CYCLES * default_cycle["nut"],
                              CYCLES * default_cycle["ball"])
    depth = CYCLES * (default_cycle["screw"] + default_cycle["nut"] + 2 * default_cycle["ball"])
    assert growth == pytest.approx(depth * math.sqrt(2.0) / math.cos(math.radians(2.8473)), rel=1e-9)
    assert 0.03e-3 < growth < 0.5e-3


def _elasticity(model, **scale):
    base = cycle_wear(model.rates)
    up = cycle_wear(model.rates, DutyCycle000().scaled(**{k: v * 1.1 for k, v in scale.items()}))
    return math.log(up["screw"] / base["screw"]) / math.log(1.1)


def test_velocity_matters_more_than_force_at_fixed_durations():
    """000 Sec. 5: scaling the speed profile (fixed durations) beats scaling the force profile."""
    model = wear_model(UNIT, "direct")
    e_speed = _elasticity(model, speed=1.0)
    e_force = _elasticity(model, force=1.0)
    assert e_speed == pytest.approx(1.0, abs=0.05)
    assert e_force == pytest.approx(1.0 / 3.0, abs=0.1)
    assert e_speed > e_force


def test_at_fixed_stroke_speed_matters_less_than_force():
    """Scaling the speed at a fixed stroke shortens the motion by the same factor: elasticity ~0."""
    model = wear_model(UNIT, "direct")
    base = cycle_wear(model.rates)
    fast = cycle_wear(model.rates, DutyCycle000().scaled(speed=1.1, time=1.0 / 1.1))
    e_stroke = math.log(fast["screw"] / base["screw"]) / math.log(1.1)
    assert abs(e_stroke) < 0.1 < _elasticity(model, force=1.0)


def test_readings_side_by_side():
    """The alternative readings of 000 change the per-cycle wear by the orders of magnitude claimed."""
    default = cycle_wear(wear_model(UNIT, "direct").rates)
    kappa_ab = cycle_wear(wear_model(UNIT, "direct", kappa="a/b").rates)
    asperity = cycle_wear(wear_model(UNIT, "direct", radius="asperity").rates)
    roughness = cycle_wear(wear_model(UNIT, "direct", radius="roughness").rates)
    rolling = cycle_wear(wear_model(UNIT, "direct", kinematics="rolling").rates)
    assert 20.0 < kappa_ab["screw"] / default["screw"] < 200.0  # ~two orders (kappa^2)
    assert roughness["screw"] / asperity["screw"] > 100.0  # R_A: roughness vs asperity radius
    assert asperity["screw"] > default["screw"]
    assert rolling["nut"] == 0.0 and 0.0 < rolling["screw"] < 0.05 * default["screw"]
