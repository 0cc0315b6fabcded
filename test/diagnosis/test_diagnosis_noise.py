"""Noise estimators against known white noise on smooth signals (closed-form truth)."""

import numpy as np
import pytest

from ebm_wear_monitor.diagnosis.noise import mad_sigma, series_noise, signal_noise


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
