"""The open-set test of a screw-periodic torque (diagnosis/openset.py) against closed forms."""

from __future__ import annotations

import numpy as np
import pytest

from ebm_wear_monitor.diagnosis.openset import block_basis, periodic_structure
from ebm_wear_monitor.diagnosis.ranking import improvement_p


def _blocks(n_blocks: int = 600, per_block: int = 20, seed: int = 0):
    """A screw turning through many revolutions (with an arbitrary encoder zero), cut into blocks."""
    rng = np.random.default_rng(seed)
    angle = 123.4 + np.cumsum(rng.uniform(0.0, 0.02, n_blocks * per_block))  # [rad]
    start = np.arange(n_blocks) * per_block
    stop = start + per_block - 1
    cal = np.zeros(n_blocks, bool)
    cal[::2] = True
    return angle, start, stop, cal, ~cal, rng


def test_block_basis_is_the_block_mean_of_the_harmonic():
    angle, start, stop, *_ = _blocks(10)
    X = block_basis(angle, start, stop, 3)
    for j in range(10):
        q = angle[start[j]:stop[j] + 1]
        assert X[j, 0] == pytest.approx(np.sin(3 * q).mean(), abs=1e-12)
        assert X[j, 1] == pytest.approx(np.cos(3 * q).mean(), abs=1e-12)


@pytest.mark.parametrize("k", [1, 2, 3, 4])
def test_a_periodic_torque_is_found_with_its_harmonic_and_amplitude(k):
    angle, start, stop, cal, ho, rng = _blocks(seed=k)
    sigma = np.full(start.size, 0.01)  # block noise [N m]
    amp, phi = 0.08, 1.1  # [N m], [rad]
    true = np.array([np.mean(amp * np.sin(k * angle[a:b + 1] + phi))
                     for a, b in zip(start, stop, strict=True)])
    z = (true + rng.normal(0.0, 0.01, start.size)) / sigma
    drive = np.full(start.size, 2.0)  # RMS motor torque 2 N m: materiality floor 2 % = 0.04 N m
    p = periodic_structure(angle, start, stop, z, sigma=sigma, calibration=cal, heldout=ho, drive=drive,
                           test=improvement_p)
    assert p is not None and p.harmonic == k
    assert p.amplitude == pytest.approx(amp, rel=0.05)
    assert p.floor == pytest.approx(0.04)
    assert p.p_value < 1e-6 and p.counts(0.0125)
    assert p.sse_after < 0.2 * p.sse_before


def test_noise_alone_is_not_counted():
    hits = 0
    for seed in range(40):
        angle, start, stop, cal, ho, rng = _blocks(seed=100 + seed)
        sigma = np.full(start.size, 0.01)
        z = rng.normal(0.0, 1.0, start.size)
        p = periodic_structure(angle, start, stop, z, sigma=sigma, calibration=cal, heldout=ho,
                           drive=np.full(start.size, 2.0), test=improvement_p)
        assert p is not None
        hits += p.p_value < 0.0125
        assert not p.counts(0.0125)  # far below the materiality floor
    assert hits <= 3  # the held-out test keeps its level (expected 0.5 of 40)


def test_a_periodic_torque_below_the_materiality_floor_is_significant_but_not_counted():
    angle, start, stop, cal, ho, rng = _blocks(seed=7)
    sigma = np.full(start.size, 0.002)
    true = np.array([np.mean(0.02 * np.sin(2 * angle[a:b + 1])) for a, b in zip(start, stop, strict=True)])
    z = (true + rng.normal(0.0, 0.002, start.size)) / sigma
    p = periodic_structure(angle, start, stop, z, sigma=sigma, calibration=cal, heldout=ho,
                           drive=np.full(start.size, 2.0), test=improvement_p)
    assert p is not None and p.p_value < 1e-6
    assert not p.counts(0.0125)  # 0.02 N m < 2 % of 2 N m
