"""Phase labels and brake-cycle index of recorded data, derived from the signals alone.

The four phases of a brake application are those of 000 Fig. 2 (interface.md section 4):
``clearance_elimination`` (screw turns in the apply direction, no clamp force yet: 004 eq. 5 with
x <= x_ag), ``force_generation`` (apply direction, force rising, x > x_ag), ``force_maintenance``
(screw at rest, force held: the stick branch of 004 eq. 9) and ``force_release`` (screw turns back).
Samples at rest without force are ``idle`` (between applications).

:func:`segment` is the diagnosis' entry to the *offline* mode of the project's segmenter,
:func:`ebm_wear_monitor.domain.segmentation.offline.segment` (its docstring teaches the rule:
centred smoothing, thresholds from the recording's noise, the shared per-sample classification,
look-ahead passes over the runs). What the diagnosis adds are the mode's inputs: the screw speed is
the angle's own derivative (:func:`.speed.angle_speed`), not the recorded velocity, whose lag depends on
how the drive estimates it, and the noise levels are measured on the recording
(:func:`.noise.signal_noise`). Why not the monitor's causal mode
(:mod:`ebm_wear_monitor.domain.segmentation.causal`)? It runs on the recorded velocity with thresholds
resolved from the unit parameters, where the diagnosis may assume nothing about the recording (the lag
of the drive's velocity estimate, a force tare); and, causal, it calls data that start inside an
application ``motion`` without phases, where the diagnosis needs the phases of the first cycle too
(:mod:`ebm_wear_monitor.domain.segmentation` lists which rules the two modes share).
"""

from __future__ import annotations

import numpy as np

from ebm_wear_monitor.diagnosis.noise import signal_noise
from ebm_wear_monitor.diagnosis.recording import Resampled
from ebm_wear_monitor.diagnosis.speed import angle_speed
from ebm_wear_monitor.domain.segmentation import offline
from ebm_wear_monitor.domain.segmentation.offline import Segmentation

__all__ = ["Segmentation", "segment"]


def segment(rec: Resampled, speed: np.ndarray | None = None, smooth_s: float = 0.01,
            min_run_s: float = 0.02) -> Segmentation:
    """Phase code and cycle index per sample of ``rec`` by the offline mode of the segmenter.

    ``speed``: screw speed per sample [rad/s]; default :func:`.speed.angle_speed` of the recording.
    """
    speed = angle_speed(rec)[0] if speed is None else speed
    return offline.segment(speed, rec.axial_force, rec.dt, speed_noise=signal_noise(speed),
                           force_noise=signal_noise(rec.axial_force), smooth_s=smooth_s, min_run_s=min_run_s)
