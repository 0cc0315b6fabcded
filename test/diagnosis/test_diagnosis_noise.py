"""Noise estimators against known white noise on smooth signals (closed-form truth)."""

import numpy as np
import pytest

from ebm_wear_monitor.diagnosis.noise import mad_sigma, median_scale, quantum, series_noise, signal_noise


@pytest.mark.parametrize("sigma", [0.01, 1.0, 50.0])
def test_signal_noise_recovers_white_noise_on_smooth_signal(sigma):
    rng = np.random.default_rng(3)
    t = np.linspace(0.0, 10.0, 20000)
    x = 100.0 * np.sin(2.0 * np.pi * 0.5 * t) + rng.normal(0.0, sigma, t.size)
    assert signal_noise(x) == pytest.approx(sigma, rel=0.05)


def test_signal_noise_ignores_kinks():
    rng = np.random.default_rng(4)
    x = np.concatenate([np.zeros(5000), np.linspace(0, 500, 5000), np.full(5000, 500.0)])
    assert signal_noise(x + rng.normal(0, 2.0, x.size)) == pytest.approx(2.0, rel=0.05)


def test_series_noise_cancels_smooth_part_and_respects_groups():
    rng = np.random.default_rng(5)
    r = np.concatenate([np.linspace(0, 30, 400), np.linspace(-50, 50, 400)]) + rng.normal(0, 1.0, 800)
    group = np.repeat([0, 1], 400)
    assert series_noise(r, group) == pytest.approx(1.0, rel=0.1)
    assert mad_sigma(np.array([])) == 0.0


@pytest.mark.parametrize("c", [0.3, 1.0, 2.5])
def test_median_scale_recovers_the_scale_of_two_noise_components(c):
    """r ~ N(0, c^2 s^2 + e^2) with s and e varying from block to block: the scale c of s is recovered."""
    rng = np.random.default_rng(3)
    s = rng.uniform(0.5, 2.0, 4000)
    e = np.where(rng.random(4000) < 0.3, rng.uniform(0.0, 1.0, 4000), 0.0)
    r = rng.normal(size=4000) * np.sqrt(c * c * s * s + e * e)
    assert median_scale(r, s, e) == pytest.approx(c, rel=0.06)


def test_median_scale_ignores_a_minority_of_model_error_and_is_zero_when_extra_explains_all():
    rng = np.random.default_rng(4)
    s = np.full(3000, 0.1)
    r = rng.normal(scale=0.1, size=3000)
    r[:300] += 5.0  # 10 % of the blocks carry a model error of 50 noise levels (transients)
    assert median_scale(r, s) == pytest.approx(1.0, abs=0.12)  # the mean square would say ~16
    assert np.sqrt(np.mean((r / s) ** 2)) > 10.0
    assert median_scale(r[300:], s[300:], np.full(2700, 1.0)) == 0.0  # e = 10 s explains it all


def test_series_noise_needs_enough_differences():
    """Groups of five blocks offer one lag-2 difference each: three groups give no scale, 300 do."""
    rng = np.random.default_rng(6)
    few, many = (rng.normal(0.0, 1.0, 5 * n) for n in (3, 300))
    assert series_noise(few, np.repeat(np.arange(3), 5), min_diffs=12) == 0.0
    assert series_noise(many, np.repeat(np.arange(300), 5), min_diffs=12) == pytest.approx(1.0, rel=0.15)


def test_quantum_is_the_count_of_a_quantised_signal():
    # a slow random walk read by a 12-bit encoder (count 2 pi / 4096) moves by 0 or 1 count per sample
    # mostly: its smallest nonzero step is the count; with an offset of many turns the count still reads
    count = 2.0 * np.pi / 4096
    walk = np.cumsum(np.random.default_rng(0).normal(0.0, 0.5 * count, 2000))
    for offset in (0.0, 494.1):
        assert quantum(offset + count * np.round(walk / count)) == pytest.approx(count, rel=1e-6)
    assert quantum(walk) < 0.01 * count  # continuous: some step far below any count
    assert quantum(np.full(10, 3.0)) == 0.0  # never moves
    assert quantum(np.array([])) == 0.0 and quantum(np.array([1.0])) == 0.0
