"""Velocity estimators against a ramp's closed form and for stability at every rate; case sets and
the command line."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from ebm_wear_monitor.validation.foreign import Case, case_set
from ebm_wear_monitor.validation.foreign.cases import SETS, TOPIC_RATES, VELOCITY_PARAMS, window_samples
from ebm_wear_monitor.validation.foreign.sensors import Acquisition, velocity


def _acq(kind: str, param: float) -> Acquisition:
    return Acquisition(clocks={}, encoder_side="screw", encoder_bits=20, encoder_offset=0.0,
                       velocity_kind=kind, velocity_param=param, tare=0.0, noise_F=0.0, lsb_F=1.0,
                       current_kind="centered", f_pwm=2e4, noise_I=0.0, lsb_I=1e-3, lag_min=0.0,
                       lag_max=0.0)


def _params(kind: str, rate: float) -> list[float]:
    """Both ends of the drawn parameter range of ``kind`` at ``rate``."""
    lo, hi = VELOCITY_PARAMS[kind]
    if kind == "moving_average":
        return [window_samples(lo, rate), window_samples(hi, rate)]
    return [lo, hi]


ESTIMATORS = [(kind, rate, param) for kind in VELOCITY_PARAMS for rate in TOPIC_RATES
              for param in _params(kind, rate)]


@pytest.mark.parametrize(("kind", "rate", "param"), ESTIMATORS)
def test_velocity_estimators_follow_a_speed_ramp_with_their_declared_lag(kind: str, rate: float,
                                                                          param: float) -> None:
    """Every estimator at every rate a clock can have and both ends of its parameter range: a
    still angle reads 0 (whatever the encoder offset); under a speed ramp alpha t (angle
    alpha t^2 / 2) the settled estimate is alpha (t - lag) with the declared lag."""
    alpha, offset = 40.0, 731.25
    t = np.arange(int(2.0 * rate)) / rate
    t0 = 1.0
    angle = offset + 0.5 * alpha * np.maximum(t - t0, 0.0) ** 2
    acq = _acq(kind, param)
    est = velocity(acq, angle, rate)
    assert np.abs(est[t < t0]).max() < 1e-9
    lag = (t[-1] - t0) - est[-1] / alpha
    assert lag == pytest.approx(acq.velocity_lag(rate), rel=1e-6)
    assert 0.0 < lag < 0.012  # every declared lag is a real delay of at most a few periods or tau


@pytest.mark.parametrize(("kind", "rate", "param"), ESTIMATORS)
def test_velocity_estimators_are_stable_and_bounded(kind: str, rate: float, param: float) -> None:
    """On an encoder (16 bit at the screw) following a trapezoid speed with a reversal step, and
    on 60 s of quantisation noise alone, every estimate stays finite and within 10 % of the
    largest true speed (plus one quantum per period of noise: a derivative's worst case); an
    explicit Euler observer at wn T > 1.4 grows without bound here (the bug this guards)."""
    T, q = 1.0 / rate, 2 * np.pi / 2**16
    t = np.arange(int(60.0 * rate)) * T
    w = np.interp(t, [0.1, 0.15, 0.5, 0.5 + T, 0.8], [0.0, 3.0, 3.0, -1.0, 0.0])
    angle = np.concatenate([[0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * T)])
    est = velocity(_acq(kind, param), np.round(angle / q) * q, rate)
    assert np.isfinite(est).all()
    assert np.abs(est).max() <= 1.1 * np.abs(w).max() + q / T
    assert np.abs(est[t > 1.0]).max() <= q / T  # quantisation noise only, nothing growing


def test_case_sets_are_deterministic_unique_and_sized() -> None:
    for name in SETS:
        a, b = case_set(name), case_set(name)
        assert a == b
        assert len({c.case_id for c in a}) == len(a)
    quick, full = case_set("quick"), case_set("full")
    assert sum(c.kind == "none" for c in full) >= 30
    assert 5 <= len(quick) <= 25
    with pytest.raises(ValueError, match="known"):
        case_set("nope")
    with pytest.raises(ValueError, match="kind"):
        Case("x", "bogus", 1)


def _cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "ebm_wear_monitor.validation.foreign", *args],
                          capture_output=True, text=True, timeout=300, check=False)


def test_cli_writes_with_progress_and_rejects_bad_input(tmp_path: Path) -> None:
    out = _cli("write", "--set", "quick", "--out", str(tmp_path), "--only", "none_q005")
    assert out.returncode == 0, out.stderr
    assert "[1/1] none_q005" in out.stdout
    assert (tmp_path / "none_q005" / "ground_truth.json").is_file()
    assert not list(tmp_path.glob(".*partial"))
    bad = _cli("write", "--set", "quick", "--out", str(tmp_path), "--only", "nope")
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and "nope" in bad.stderr
    listed = _cli("list", "--set", "full")
    assert listed.returncode == 0 and listed.stdout.count("\n") == len(case_set("full"))
