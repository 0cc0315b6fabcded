"""An accelerated-life unit file: k_slip scaled, everything else identical, and Archard-linear wear."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from ebm_wear_monitor.params import ParamError, accelerated, load_unit, save_unit
from ebm_wear_monitor.physics import wear_model

UNIT = load_unit("embu_000")


def test_saved_accelerated_unit_loads_back_with_only_k_slip_scaled(tmp_path):
    path = save_unit(tmp_path / "rig.yaml", accelerated(UNIT, 1e5), "accelerated rig\nsecond line")
    text = path.read_text()
    assert text.startswith("# accelerated rig\n# second line\n")
    back = load_unit(path)
    assert back.wear.k_slip == pytest.approx(UNIT.wear.k_slip * 1e5, rel=1e-15)
    assert dataclasses.replace(back.wear, k_slip=UNIT.wear.k_slip) == UNIT.wear
    assert (back.ball_screw, back.materials, back.actuator, back.monitor) == (
        UNIT.ball_screw, UNIT.materials, UNIT.actuator, UNIT.monitor)
    assert back.digest() != UNIT.digest()


def test_wear_rates_scale_exactly_with_k_slip():
    """Archard (000 eq. 23) is linear in k_slip and nothing else in the chain depends on it."""
    force, speed = np.array([2e3, 1e4, 3e4]), np.array([5.0, 20.0, 60.0])
    base = wear_model(UNIT, "direct").rates(force, speed)
    fast = wear_model(accelerated(UNIT, 250.0), "direct").rates(force, speed)
    for a, b in zip(base, fast, strict=True):
        np.testing.assert_allclose(b, 250.0 * a, rtol=1e-12)


@pytest.mark.parametrize("scale", [0.0, -2.0, float("nan"), float("inf")])
def test_impossible_scale_is_a_param_error(scale):
    with pytest.raises(ParamError):
        accelerated(UNIT, scale)
