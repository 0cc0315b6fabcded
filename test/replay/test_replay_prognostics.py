"""Prognostics metrics (Saxena et al. 2010) against closed-form cases."""

from __future__ import annotations

import numpy as np
import pytest

from ebm_wear_monitor.replay.prognostics import prognostics_metrics

EOL = 1000.0
K = np.arange(100.0, 900.0, 10.0)


def test_perfect_predictor():
    m = prognostics_metrics(K, EOL - K, EOL)
    assert m["prognostic_horizon_cycles"] == EOL - K[0]
    assert m["alpha_lambda_pass"] is True
    assert m["relative_accuracy"] == 1.0
    assert m["cumulative_relative_accuracy"] == 1.0
    assert m["alpha_lambda_fraction"] == 1.0
    assert m["first_prediction_cycles"] == K[0]


@pytest.mark.parametrize("bias", [0.1, 0.3, -0.3])
def test_constant_relative_bias(bias):
    """r = (1 + b) r*: RA = 1 - |b| everywhere; inside the alpha cone iff |b| <= alpha (0.2)."""
    m = prognostics_metrics(K, (1 + bias) * (EOL - K), EOL)
    assert m["relative_accuracy"] == pytest.approx(1 - abs(bias))
    assert m["cumulative_relative_accuracy"] == pytest.approx(1 - abs(bias))
    assert m["alpha_lambda_pass"] is (abs(bias) <= 0.2)
    # PH band is +-0.1 EOL = +-100 cycles in absolute terms: |b| r* <= 100 once r* <= 100/|b|
    k_in = K[np.abs(bias) * (EOL - K) <= 0.1 * EOL + 1e-9][0]
    assert m["prognostic_horizon_cycles"] == pytest.approx(EOL - k_in)


def test_predictions_that_leave_the_band_at_the_end_have_no_horizon():
    r = EOL - K
    r[-1] += 0.5 * EOL
    assert prognostics_metrics(K, r, EOL)["prognostic_horizon_cycles"] is None


def test_short_recordings_and_missing_predictions():
    k = np.arange(10.0, 50.0)
    r = np.where(k < 20, np.nan, EOL - k)
    m = prognostics_metrics(k, r, EOL)
    assert m["first_prediction_cycles"] == 20.0
    assert m["predictions"] == 30
    assert m["alpha_lambda_pass"] is None  # k_lambda = 510 lies beyond the recording
    assert m["relative_accuracy"] is None
    none = prognostics_metrics(k, np.full_like(k, np.nan), EOL)
    assert none["predictions"] == 0
    assert none["prognostic_horizon_cycles"] is None
