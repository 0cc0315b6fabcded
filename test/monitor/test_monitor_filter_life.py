"""Kalman filter with wear-rate factor, remaining-life quantiles and ISO 3408-5 fatigue life."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ebm_wear_monitor.monitor.kalman import ClearanceFilter
from ebm_wear_monitor.monitor.life import (
    STATUS_INSUFFICIENT,
    STATUS_LIMIT,
    STATUS_OK,
    fatigue_life,
    limiting_mechanism,
    wear_life,
)

Z95 = 1.6448536269514722


@pytest.mark.parametrize("true_factor", [2.5, 0.4])
def test_filter_learns_injected_wear_rate_factor(true_factor):
    rng = np.random.default_rng(int(true_factor * 10))
    g, sigma, x0 = 1e-7, 1e-6, 0.2e-3  # model growth per application, observation noise, start
    kf = ClearanceFilter.prior(0.2e-3, 1e-4, 1.0)
    x = x0
    for _ in range(400):
        x += true_factor * g
        kf.predict(g, 0.0, 0.0)
        kf.update(x + rng.normal(0.0, sigma), sigma ** 2)
    # least squares on a line: sd(f) = sigma / g * sqrt(12 / N^3) = 0.0087
    assert kf.factor_std == pytest.approx(sigma / g * math.sqrt(12 / 400 ** 3), rel=0.1)
    assert abs(kf.factor - true_factor) < 4 * kf.factor_std
    assert abs(kf.clearance - x) < 4 * kf.clearance_std


def _monte_carlo_quantiles(mu, P, limit, g, *, n=400_000, seed=1):
    s = np.random.default_rng(seed).multivariate_normal(mu, P, size=n)
    with np.errstate(divide="ignore"):
        cycles = np.where(s[:, 1] > 0, (limit - s[:, 0]) / (g * s[:, 1]), np.inf)
    return np.percentile(cycles, [5, 50, 95])


@pytest.mark.parametrize("cov", [0.0, 0.6, -0.6])
def test_life_quantiles_match_monte_carlo(cov):
    sx, sf = 3e-6, 0.15
    mu = np.array([0.3e-3, 1.2])
    P = np.array([[sx * sx, cov * sx * sf], [cov * sx * sf, sf * sf]])
    life = wear_life(mu, P, 0.5e-3, 2e-10, observations=100, min_cycles=10, z=Z95)
    assert life.status == STATUS_OK
    ref = _monte_carlo_quantiles(mu, P, 0.5e-3, 2e-10)
    got = [life.cycles_p05, life.cycles_p50, life.cycles_p95]
    assert got == pytest.approx(ref, rel=0.01)


def test_life_of_a_known_state_is_the_linear_closed_form():
    mu = np.array([0.35e-3, 0.8])
    life = wear_life(mu, np.diag([1e-30, 1e-30]), 0.5e-3, 1e-9, observations=50, min_cycles=10, z=Z95)
    closed = (0.5e-3 - 0.35e-3) / (0.8 * 1e-9)
    assert (life.cycles_p05, life.cycles_p50, life.cycles_p95) == pytest.approx((closed,) * 3, rel=1e-9)


def test_no_made_up_life_before_growth_is_measurable():
    prior = ClearanceFilter.prior(0.2e-3, 1e-4, 1.0)
    life = wear_life(prior.x, prior.P, 0.5e-3, 1e-9, observations=1000, min_cycles=10, z=Z95)
    assert life.status == STATUS_INSUFFICIENT and life.cycles_p50 is None
    sharp = np.diag([1e-12, 1e-4])
    assert wear_life(prior.x, sharp, 0.5e-3, 1e-9, observations=3, min_cycles=10, z=Z95).cycles_p05 is None
    assert wear_life(prior.x, sharp, 0.5e-3, 0.0, observations=30, min_cycles=10, z=Z95).cycles_p05 is None
    done = wear_life(np.array([0.51e-3, 1.0]), sharp, 0.5e-3, 1e-9, observations=30, min_cycles=10, z=Z95)
    assert done.status == STATUS_LIMIT and done.cycles_p50 == 0.0


def test_fatigue_l10_of_constant_and_mixed_load():
    # constant 10 kN over 2 turns, C_a = 20 kN: L10 = 2^3 * 1e6 = 8e6 revolutions
    turns = 2 * 2 * math.pi
    fat = fatigue_life(20e3, 10e3 ** 3 * turns, turns, cycles=4)
    assert fat.l10_revolutions == pytest.approx(8e6, rel=1e-12)
    assert fat.cubic_mean_load_n == pytest.approx(10e3, rel=1e-12)
    assert fat.remaining_cycles == pytest.approx((8e6 - 2) / 0.5, rel=1e-12)
    # 1 turn at 5 kN and 3 turns at 15 kN: F_m = ((5^3 + 3 * 15^3) / 4)^(1/3) kN
    r1, r3 = 2 * math.pi, 6 * math.pi
    fat = fatigue_life(20e3, 5e3 ** 3 * r1 + 15e3 ** 3 * r3, r1 + r3, cycles=1)
    fm = ((5 ** 3 + 3 * 15 ** 3) / 4) ** (1 / 3) * 1e3
    assert fat.cubic_mean_load_n == pytest.approx(fm, rel=1e-12)
    assert fat.l10_revolutions == pytest.approx((20e3 / fm) ** 3 * 1e6, rel=1e-12)
    assert fatigue_life(None, 1.0, 1.0, 1).l10_revolutions is None


def test_limiting_mechanism_compares_wear_p05_with_fatigue():
    sharp = np.diag([1e-14, 1e-6])
    wear = wear_life(np.array([0.3e-3, 1.0]), sharp, 0.5e-3, 1e-9, observations=50, min_cycles=10, z=Z95)
    assert wear.cycles_p05 == pytest.approx(2e5, rel=0.01)
    fat_far = fatigue_life(20e3, 10e3 ** 3 * 1.0, 1.0, cycles=1)  # ~8e6 revolutions at 1 rad per cycle
    assert limiting_mechanism(wear, fat_far) == "wear"
    fat_near = fatigue_life(20e3, 60e3 ** 3 * 1e6, 1e6, cycles=1_000_000)  # L10 = 3.7e4 rev, far exceeded
    assert limiting_mechanism(wear, fat_near) == "fatigue"
    unknown = wear_life(np.array([0.3e-3, 1.0]), np.diag([1e-14, 1.0]), 0.5e-3, 1e-9, observations=50,
                        min_cycles=10, z=Z95)
    assert limiting_mechanism(unknown, fat_far) == "unknown"
