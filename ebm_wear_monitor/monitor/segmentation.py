"""The monitor's segmentation: the causal mode of the segmenter, over the monitor's inputs.

The state machine (the four phases of 000 Fig. 2 from the recorded screw speed and the force above
the rest level, with the unit's hysteresis thresholds) is
:mod:`ebm_wear_monitor.domain.segmentation.causal`; :class:`~ebm_wear_monitor.monitor.core.MonitorCore`
streams aligned batches through its :class:`Segmenter`. This module keeps the monitor's names for it
and :func:`label_samples`, which labels every sample of a recording given as plain arrays (gaps as the
aligner finds them).
"""

from __future__ import annotations

import numpy as np

from ebm_wear_monitor.domain.segmentation.causal import (
    CE,
    FG,
    FM,
    FR,
    MOTION,
    N_LABELS,
    SampleLabels,
    Segment,
    Segmenter,
    label_batch,
)
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.monitor.alignment import AlignedBatch, stamps_to_ns
from ebm_wear_monitor.monitor.config import MonitorConfig, Thresholds

__all__ = ["CE", "FG", "FM", "FR", "MOTION", "N_LABELS", "SampleLabels", "Segment", "Segmenter",
           "label_samples"]


def label_samples(t: np.ndarray, angle: np.ndarray, velocity: np.ndarray, force: np.ndarray, *,
                  config: MonitorConfig, thresholds: Thresholds, force_baseline: float = 0.0) -> SampleLabels:
    """Label every sample of an aligned recording with the monitor's state machine.

    ``t``: strictly increasing stamps, int64 ns or float s; ``angle`` [rad], ``velocity`` [rad/s] and
    ``force`` [N] of the screw at those stamps; ``config`` / ``thresholds`` as for :class:`MonitorCore`
    (``thresholds = config.resolve(unit)``); ``force_baseline``: rest level b of the force before the
    first rest is seen [N] (the monitor's persisted value; 0 for a new unit). Consecutive samples more
    than ``config.gap_s`` apart are a gap, as in the aligner. The samples are fed in one batch with
    ``final=True`` (:func:`~ebm_wear_monitor.domain.segmentation.causal.label_batch`), so the labels are
    those of the segments :class:`MonitorCore` would integrate.
    """
    t_ns, ok = stamps_to_ns(t)
    n = t_ns.size
    arrays = [np.asarray(a, dtype=float) for a in (angle, velocity, force)]
    if any(a.shape != (n,) for a in arrays) or not ok.all():
        raise InputError("label_samples: stamps must be finite and match the signals in length")
    dt_ns = np.diff(t_ns)
    if np.any(dt_ns <= 0):
        raise InputError("label_samples: stamps must increase strictly")
    gap = np.concatenate(([False], dt_ns > round(config.gap_s * 1e9)))
    angle_, velocity_, force_ = arrays
    return label_batch(AlignedBatch(t_ns, angle_, velocity_, force_, gap), config=config,
                       thresholds=thresholds, force_baseline=force_baseline)
