"""The wear_model facade: conventions, invariants, and the surrogate's accuracy against the direct solve."""

import math

import numpy as np
import pytest

from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.physics import ENVELOPE, WearRates, clearance_growth, wear_model

UNIT = load_unit()


@pytest.mark.parametrize("method", ["direct", "surrogate"])
def test_conventions_zero_speed_no_load_and_bad_samples(method):
    model = wear_model(UNIT, method)
    f = np.array([5e3, 5e3, 0.0, -5e3, np.nan, 5e3, np.inf, 5e3])
    w = np.array([0.0, 10.0, 10.0, 10.0, 10.0, np.nan, 10.0, -10.0])
    r = model.rates(f, w)
    assert isinstance(r, WearRates)
    for rate in r:
        assert np.all(np.isfinite(rate))
        assert rate[0] == 0.0  # zero speed: no sliding, no wear
        assert np.all(rate[[2, 3, 4, 5, 6]] == 0.0)  # no load (F <= 0) or non-finite input
        assert rate[1] > 0.0
        assert rate[7] == rate[1]  # direction of rotation does not matter


def test_broadcasting_and_shapes():
    model = wear_model(UNIT)
    r = model.rates(np.full((2, 3), 8e3), 12.0)
    assert r.screw.shape == (2, 3) and r.ball.shape == (2, 3)
    assert np.all(r.screw == r.screw[0, 0])
    assert model.rates(8e3, 12.0).nut.shape == ()


def test_models_are_cached_per_parameter_set_and_options():
    assert wear_model(UNIT) is wear_model(load_unit())
    assert wear_model(UNIT) is not wear_model(UNIT, kinematics="rolling")
    with pytest.raises(InputError):
        wear_model(UNIT, kinematic="rolling")
    with pytest.raises(InputError):
        wear_model(UNIT, kappa="c/d")
    with pytest.raises(InputError):
        wear_model(UNIT, "fastest")


def test_rate_is_monotone_in_force_and_speed_over_the_operating_envelope():
    model = wear_model(UNIT, "direct")
    env = model.operating_envelope
    assert 20e3 < env.force_max < ENVELOPE.force_max  # the reference duty cycle (20 kN) is inside
    f = np.exp(np.linspace(math.log(env.force_min), math.log(env.force_max), 120))
    w = np.linspace(0.0, env.speed_max, 60)
    ff, ww = np.meshgrid(f, w, indexing="ij")
    r = model.rates(ff, ww)
    for rate in (r.screw, r.nut, r.ball):
        assert np.all(np.diff(rate, axis=0) >= -1e-12 * rate[1:])
        assert np.all(np.diff(rate, axis=1) >= -1e-12 * rate[:, 1:])


@pytest.mark.parametrize(("name", "options"), [
    ("embu_000", {}), ("embu_000", {"kappa": "a/b"}), ("embu_000", {"radius": "asperity"}),
    ("screw_003", {}),
])
def test_surrogate_within_half_a_percent_of_direct_solve(name, options):
    """Over the table range (operating envelope and overloads past the elastic-plastic switch)."""
    unit = load_unit(name)
    rng = np.random.default_rng(7)
    n = 20_000
    f = np.exp(rng.uniform(math.log(ENVELOPE.force_min), math.log(ENVELOPE.force_max), n))
    w = rng.uniform(0.0, ENVELOPE.speed_max, n) * rng.choice([-1.0, 1.0], n)
    w[:500] = rng.uniform(0.0, 1e-2, 500)  # near standstill
    fast = wear_model(unit, "surrogate", **options).rates(f, w)
    exact = wear_model(unit, "direct", **options).rates(f, w)
    for a, b in zip(fast, exact, strict=True):
        assert np.max(np.abs(a / b - 1.0)) <= 0.005


def test_surrogate_falls_back_to_the_direct_solve_outside_the_table():
    f = np.array([0.05, 1.5e5, 5e3])
    w = np.array([10.0, 10.0, 500.0])
    fast = wear_model(UNIT).rates(f, w)
    exact = wear_model(UNIT, "direct").rates(f, w)
    assert np.array_equal(fast.screw, exact.screw) and np.all(fast.screw > 0)


def test_ball_share_and_clearance_geometry():
    r = wear_model(UNIT).rates(10e3, 20.0)
    share = UNIT.wear.raceway_share
    expected = (1 - share) / share * (float(r.screw) + float(r.nut)) / 2
    assert float(r.ball) == pytest.approx(expected, rel=1e-12)
    # only the screw raceway worn by 1 um: the nut moves back 1 um / (sin 45 deg cos phi)
    axial = math.sin(math.radians(45.0)) * math.cos(math.radians(2.8473))
    assert clearance_growth(UNIT, 1e-6, 0.0, 0.0) == pytest.approx(1e-6 / axial, rel=1e-12)
    # a ball radius loss opens the gap at both of its contacts
    assert clearance_growth(UNIT, 0.0, 0.0, 1e-6) == pytest.approx(2e-6 / axial, rel=1e-12)
    depths = np.array([[1e-6, 2e-6], [0.0, 1e-6]])
    assert clearance_growth(UNIT, depths, depths, 0.0).shape == (2, 2)
