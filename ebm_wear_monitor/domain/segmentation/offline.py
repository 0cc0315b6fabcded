"""The offline mode of the segmenter: phases and cycles of a whole recording, the diagnosis'.

Recordings carry no phase topic, so the diagnosis derives the phases of 000 Fig. 2 (interface.md
section 4) from the signals, over the whole recording at once. What this mode reads, and its
look-ahead passes:

* **inputs**: the screw speed (the diagnosis passes the angle's own derivative,
  :func:`ebm_wear_monitor.diagnosis.speed.angle_speed`, not the recorded velocity, whose lag depends
  on how the drive estimates it) and the axial force reading, both smoothed with a centred moving
  average over ``smooth_s`` (10 ms by default): v and F;
* **thresholds from the recording's own noise** (nothing assumed about the unit or a force tare):
  moving forward if v > eps_v, backward if v < -eps_v, stopped otherwise; in contact if
  F > F_0 + F_on, F_0 the reading without contact, taken as the 5th percentile of F (so that a
  force-sensor offset does not read as contact);
  eps_v = max(5 sigma_v / sqrt(w), 0.02 * P99(|v|)) and F_on = max(5 sigma_F / sqrt(w),
  0.02 * (P99(F) - F_0)), with sigma the measured white-noise level of the raw signals (the caller's,
  :func:`ebm_wear_monitor.diagnosis.noise.signal_noise`), w the smoothing window in samples and P99
  the 99th percentile: five standard deviations of the smoothed noise, or 2 % of the signal's range
  when the noise is smaller than that;
* **per sample**: the segmenter's shared classification
  (:func:`ebm_wear_monitor.domain.segmentation.classify`) of (direction, contact); a sample whose
  speed is undefined (NaN) has no direction and is idle;
* **look-ahead passes** over the runs of equal phase:

  1. runs shorter than ``min_run_s`` (20 ms) are merged into the run before them (controller dither
     in force maintenance would otherwise flicker the label);
  2. a forward run without contact that does not end in force generation (the ECU returning from an
     overshoot, repositioning) is idle time, not clearance elimination;
  3. a new brake cycle starts at the first forward run (clearance elimination or force generation)
     after a force-release run that took the force below half of the cycle's peak (or below F_on):
     a controller that backs off a little and re-applies (trimming the held force) is still in the
     same application, a release that stops with the pads still touching before the next
     application is not (:mod:`ebm_wear_monitor.diagnosis.conventions` flags that next application
     as not released). The cycle index is the segmenter's shared
     :func:`ebm_wear_monitor.domain.segmentation.cycle_index` of those starts.

Every sample is labelled, the first application of a recording included (the causal mode,
:mod:`.causal`, calls data that start inside an application ``motion``). The idle samples before a
cycle give the diagnosis its released rest angle and force tare.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import uniform_filter1d

from ebm_wear_monitor.arrays import FloatArray
from ebm_wear_monitor.domain.phases import Phase
from ebm_wear_monitor.domain.segmentation import (
    BACKWARD,
    FORWARD,
    STOPPED,
    Labels,
    classify,
    cycle_index,
    run_starts,
    runs,
)

_NO_DIRECTION = 2  # a NaN speed: in no row of the classification (idle)


@dataclass(frozen=True)
class Segmentation(Labels):
    """Phase code and brake-cycle index per sample (domain ``Labels``) and the thresholds that gave them."""

    eps_velocity: float  # rest band of the screw velocity [rad/s]
    force_on: float  # contact threshold of the axial force reading [N] (includes the no-contact reading)
    force_rise: float = 0.0  # the same threshold above the no-contact reading F_0 [N]


def segment(speed: FloatArray, force: FloatArray, dt: float, *, speed_noise: float, force_noise: float,
            smooth_s: float = 0.01, min_run_s: float = 0.02) -> Segmentation:
    """Phase code and cycle index per sample by the rule of the module docstring.

    ``speed`` [rad/s] and ``force`` [N] per sample, ``dt`` their sampling interval [s];
    ``speed_noise`` / ``force_noise``: white-noise standard deviation of the raw ``speed`` / ``force``.
    """
    CLEARANCE, GENERATION, _, RELEASE, IDLE = Phase
    w = max(1, round(smooth_s / dt))
    v = uniform_filter1d(speed, w, mode="nearest")
    f = uniform_filter1d(force, w, mode="nearest")
    eps_v = max(5.0 * speed_noise / np.sqrt(w), 0.02 * np.percentile(np.abs(v), 99))
    f0 = float(np.percentile(f, 5))
    f_on = max(5.0 * force_noise / np.sqrt(w), 0.02 * (np.percentile(f, 99) - f0))
    direction = np.select([v > eps_v, v < -eps_v, np.abs(v) <= eps_v], [FORWARD, BACKWARD, STOPPED],
                          _NO_DIRECTION)
    phase = classify(direction, f > f0 + f_on)

    # 1. merge short runs into the run before them
    min_run = max(1, round(min_run_s / dt))
    starts, lengths = runs(phase)
    codes = phase[starts].copy()
    for i in range(1, codes.size):
        if lengths[i] < min_run:
            codes[i] = codes[i - 1]
    phase = np.repeat(codes, lengths)

    # 2. a forward move that stops short of contact (the ECU returning from an overshoot, repositioning)
    # is no clearance elimination: it belongs to the idle time between applications
    starts, lengths = runs(phase)
    codes = phase[starts].copy()
    follows = np.append(codes[1:], IDLE)
    codes[(codes == CLEARANCE) & (follows != GENERATION)] = IDLE
    phase = np.repeat(codes, lengths)

    # 3. cycle boundaries: a forward run after a release that took the force below half its peak
    starts = run_starts(phase)
    codes = phase[starts]
    load = f - f0
    run_max = np.maximum.reduceat(load, starts)
    run_min = np.minimum.reduceat(load, starts)
    new_cycle = np.zeros(codes.size, dtype=bool)
    peak, released = 0.0, False
    for i, c in enumerate(codes):
        if c in (CLEARANCE, GENERATION) and released:
            new_cycle[i] = True
            peak, released = 0.0, False
        peak = max(peak, float(run_max[i]))
        if c == RELEASE and run_min[i] < max(0.5 * peak, f_on):
            released = True
    return Segmentation(phase, cycle_index(starts[new_cycle], phase.size), float(eps_v), float(f0 + f_on),
                        float(f_on))
