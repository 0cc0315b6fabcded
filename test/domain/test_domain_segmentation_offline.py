"""The offline mode of the segmenter (domain.segmentation.offline) on a hand-built trace whose labels
follow from its docstring: classification, short-run merging, idle forward runs, half-peak cycles."""

from __future__ import annotations

import numpy as np

from ebm_wear_monitor.domain.phases import Phase
from ebm_wear_monitor.domain.segmentation.offline import segment

CE, FG, FM, FR, IDLE = Phase
# (samples, speed [rad/s], force [N], expected phase, expected cycle); 1 ms samples, no smoothing
# (w = 1), min run 20 samples; thresholds: eps_v = 2 % of P99|v| = 0.2, F_0 = 0, F_on = 2 % of 1000 = 20
TRACE = [
    (100, 0.0, 0.0, IDLE, 0),
    (100, 10.0, 0.0, CE, 0),
    (100, 5.0, 1000.0, FG, 0),
    (100, 0.0, 1000.0, FM, 0),
    (5, 10.0, 1000.0, FM, 0),  # a 5-sample dither: merged into the maintenance before it
    (100, 0.0, 1000.0, FM, 0),
    (100, -10.0, 0.0, FR, 0),  # released below half the peak: the next forward run starts a cycle
    (100, 0.0, 0.0, IDLE, 0),
    (50, 10.0, 0.0, IDLE, 0),  # forward without contact, not followed by force generation: idle
    (100, 0.0, 0.0, IDLE, 0),
    (100, 10.0, 0.0, CE, 1),
    (100, 5.0, 1000.0, FG, 1),
    (100, 0.0, 1000.0, FM, 1),
    (30, -10.0, 800.0, FR, 1),  # a back-off that keeps the force above half the peak ...
    (100, 5.0, 1000.0, FG, 1),  # ... and re-applies: the same application
    (100, 0.0, 1000.0, FM, 1),
    (100, -10.0, 0.0, FR, 1),
    (100, 0.0, 0.0, IDLE, 1),
    (100, 10.0, 0.0, CE, 2),
    (100, 5.0, 1000.0, FG, 2),
    (100, -10.0, 0.0, FR, 2),
    (200, 0.0, 0.0, IDLE, 2),
]


def _column(j: int, dtype: type = float) -> np.ndarray:
    return np.repeat(np.array([row[j] for row in TRACE], dtype=dtype), [row[0] for row in TRACE])


def test_offline_mode_labels_the_documented_phases_and_cycles():
    seg = segment(_column(1), _column(2), 1e-3, speed_noise=0.0, force_noise=0.0, smooth_s=1e-3,
                  min_run_s=0.02)
    assert seg.eps_velocity == 0.2 and seg.force_rise == 20.0
    assert seg.phase.tolist() == _column(3, int).tolist()
    assert seg.cycle.tolist() == _column(4, int).tolist()
    assert seg.n_cycles == 3
