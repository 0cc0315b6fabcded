"""The open-set test of a torque depending on the screw position (diagnosis/openset.py): closed forms."""

from __future__ import annotations

import numpy as np
import pytest

from ebm_wear_monitor.diagnosis.openset import Periodic, block_basis, periodic_structure
from ebm_wear_monitor.diagnosis.ranking.verdict import open_set_verdict

from foreign_case import foreign_diagnosis

LEVEL = 0.05 / 4


def _blocks(n_blocks: int = 600, per_block: int = 20, seed: int = 0, step: float = 0.02):
    """A screw turning through many revolutions (with an arbitrary encoder zero), cut into blocks."""
    rng = np.random.default_rng(seed)
    angle = 123.4 + np.cumsum(rng.uniform(0.0, step, n_blocks * per_block))  # [rad]
    start = np.arange(n_blocks) * per_block
    stop = start + per_block - 1
    cal = np.zeros(n_blocks, bool)
    cal[::2] = True
    return angle, start, stop, cal, ~cal, rng


def _shapes(n: int, rng: np.random.Generator) -> np.ndarray:
    """Shape columns like ranking.verdict.screw_periodic's:
    direction indicators, force and speed per direction."""
    forward = (np.arange(n) % 3 != 2).astype(float)
    force = rng.uniform(0.0, 2e4, n)
    speed = rng.uniform(1.0, 30.0, n)
    return np.column_stack([forward, 1 - forward, forward * force, (1 - forward) * force,
                            forward * speed, (1 - forward) * speed])


def _run(angle, start, stop, z, sigma, cal, ho, shapes, drive=2.0):  # noqa: PLR0917
    return periodic_structure(angle, start, stop, z, sigma=sigma, shapes=shapes, calibration=cal,
                              heldout=ho, drive=np.full(start.size, drive))


def _block_mean(f, angle, start, stop):
    return np.array([np.mean(f(angle[a:b + 1])) for a, b in zip(start, stop, strict=True)])


def test_block_basis_is_the_block_mean_of_the_harmonic():
    angle, start, stop, *_ = _blocks(10)
    X = block_basis(angle, start, stop, 3)
    assert X[:, 0] == pytest.approx(_block_mean(lambda q: np.sin(3 * q), angle, start, stop), abs=1e-12)
    assert X[:, 1] == pytest.approx(_block_mean(lambda q: np.cos(3 * q), angle, start, stop), abs=1e-12)


@pytest.mark.parametrize("k", [1, 2, 3, 4])
def test_a_periodic_torque_is_found_beyond_force_and_speed_terms(k):
    angle, start, stop, cal, ho, rng = _blocks(seed=k)
    sigma = np.full(start.size, 0.01)  # block noise [N m]
    amp, phi = 0.08, 1.1  # [N m], [rad]
    shapes = _shapes(start.size, rng)
    catalog_like = shapes @ np.array([0.1, -0.1, 2e-6, -1e-6, 1e-3, -1e-3])  # shaped like the catalog [N m]
    true = _block_mean(lambda q: amp * np.sin(k * q + phi), angle, start, stop)
    z = (true + catalog_like + rng.normal(0.0, 0.01, start.size)) / sigma
    p = _run(angle, start, stop, z, sigma, cal, ho, shapes)
    assert p is not None and p.harmonic == k
    assert p.amplitude == pytest.approx(amp, rel=0.05)
    assert p.rms == pytest.approx(amp / np.sqrt(2), rel=0.08)  # many turns: RMS of a sinusoid
    assert p.floor == pytest.approx(0.04)  # 2 % of 2 N m
    assert p.p_value < 1e-6 and p.counts(LEVEL)
    assert p.sse_after < 0.2 * p.sse_before
    # the terms shaped like the catalog are no position torque: their part is not in 'beyond'
    assert np.std(p.beyond - true) < 0.02


def test_catalog_shaped_torque_alone_is_not_counted():
    angle, start, stop, cal, ho, rng = _blocks(seed=11, step=0.002)  # a short stroke: position ~ time
    sigma = np.full(start.size, 0.01)
    shapes = _shapes(start.size, rng)
    z = (shapes @ np.array([0.2, -0.2, 3e-6, -2e-6, 2e-3, -2e-3]) + rng.normal(0.0, 0.01, start.size)) / sigma
    p = _run(angle, start, stop, z, sigma, cal, ho, shapes)
    assert p is not None and not p.counts(LEVEL) and p.p_value > LEVEL


def test_noise_alone_is_not_counted():
    hits = 0
    for seed in range(40):
        angle, start, stop, cal, ho, rng = _blocks(seed=100 + seed)
        sigma = np.full(start.size, 0.01)
        z = rng.normal(0.0, 1.0, start.size)
        p = _run(angle, start, stop, z, sigma, cal, ho, _shapes(start.size, rng))
        assert p is not None
        hits += p.p_value < LEVEL
        assert not p.counts(LEVEL)  # far below the materiality floor
    assert hits <= 3  # the held-out test keeps its level (expected 0.5 of 40)


def test_a_torque_below_the_materiality_floor_is_significant_but_not_counted():
    angle, start, stop, cal, ho, rng = _blocks(seed=7)
    sigma = np.full(start.size, 0.002)
    true = _block_mean(lambda q: 0.02 * np.sin(2 * q), angle, start, stop)  # RMS 14 mN m < 40 mN m
    z = (true + rng.normal(0.0, 0.002, start.size)) / sigma
    p = _run(angle, start, stop, z, sigma, cal, ho, _shapes(start.size, rng))
    assert p is not None and p.p_value < 1e-6
    assert not p.counts(LEVEL)


def _periodic(p_value: float, rms: float) -> Periodic:
    return Periodic(1, rms * np.sqrt(2), rms, 0.001, 0.04, p_value, 100.0, 50.0)


@pytest.mark.parametrize(("verdict", "p_value", "rms", "share", "expected"), [
    ("effect", 1e-9, 0.01, 0.3, "unexplained"),  # significant, effects close less than half (immaterial)
    ("effect", 1e-9, 0.1, 0.3, "unexplained"),  # ... material too
    ("effect", 1e-9, 0.1, 0.7, "effect"),  # effects close most of what is explainable, material or not
    ("effect", 0.2, 0.1, 0.1, "effect"),  # not significant
    ("effect", 0.9, 0.1, None, "effect"),  # the harmonic removes nothing held out (p > 1/2, no share)
    ("none", 1e-9, 0.1, None, "unexplained"),  # significant and material in the tolerant twin
    ("none", 1e-9, 0.01, None, "none"),  # significant but below the materiality floor
    ("unexplained", 1.0, 0.0, None, "unexplained"),
])
def test_open_set_verdict_rules(verdict, p_value, rms, share, expected):
    assert open_set_verdict(verdict, _periodic(p_value, rms), share) == expected
    assert open_set_verdict(verdict, None, share) == verdict


def test_a_foreign_torque_ripple_is_unexplained_by_the_open_set_test(tmp_path):
    """The foreign world's ripple periodic in the screw angle (validation/foreign/effects.py), which a catalog
    friction effect absorbs only in part, turns the verdict into unexplained through the position term."""
    # 20 applications, as in the foreign self-test. The ripple's part beyond the shape terms is
    # significant but below its 2 % materiality floor at either length (0.036 vs 0.042 N m over 10,
    # 0.033 vs 0.038 over 20), so the verdict turns on what the catalog does: over 20 load friction is
    # selected and the harmonic removes more than it did (the share rule, no materiality needed);
    # over 10, with the measured block noise, no effect is significant and the verdict is none
    res = foreign_diagnosis("full", "torque_ripple.screw_periodic.1", tmp_path, n_apps=20)
    assert res.verdict == "unexplained" and res.effects == []
    pt = res.position_torque
    assert pt is not None and pt.decided and pt.p_value < LEVEL
    assert pt.effects_share is not None and pt.effects_share < 0.5
    assert "depends on where the screw is" in res.summary


def test_a_foreign_healthy_unit_has_no_position_torque(tmp_path):
    res = foreign_diagnosis("full", "none_000", tmp_path, n_apps=10)
    assert res.verdict == "none"
    assert res.position_torque is not None and not res.position_torque.decided
