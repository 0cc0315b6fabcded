"""Phase labels and brake-cycle index of recorded data, derived from the signals alone.

The four phases of a brake application are those of 000 Fig. 2 (interface.md
section 4): ``clearance_elimination`` (screw turns in the apply direction, no
clamp force yet: 004 eq. 5 with x <= x_ag), ``force_generation`` (apply
direction, force rising, x > x_ag), ``force_maintenance`` (screw at rest,
force held: the stick branch of 004 eq. 9) and ``force_release`` (screw turns
back).  Samples at rest without force are ``idle`` (between applications).

Recordings carry no phase topic, so the labels are derived here with a small
rule on the smoothed speed v and force F (a moving average over ``smooth_s``,
10 ms by default).  The speed is the angle's own derivative
(:func:`.speed.angle_speed`), not the recorded velocity, whose lag depends on how
the drive estimates it:

* moving forward if v > eps_v, backward if v < -eps_v, at rest otherwise;
* in contact if F > F_0 + F_on, F_0 the force reading without contact, taken as
  the 5th percentile of F (so that a force-sensor offset does not read as contact);
* eps_v = max(5 sigma_v / sqrt(w), 0.02 * P99(|v|)) and
  F_on = max(5 sigma_F / sqrt(w), 0.02 * (P99(F) - F_0)), with sigma the measured
  noise (:func:`.noise.signal_noise`), w the smoothing window in samples and
  P99 the 99th percentile: five standard deviations of the smoothed noise, or
  2 % of the signal's range when the noise is smaller than that;
* runs shorter than ``min_run_s`` (20 ms) are merged into the run before them
  (controller dither in force maintenance would otherwise flicker the label).

A forward run without contact that does not end in force generation (the ECU returning
from an overshoot, repositioning) is idle time, not clearance elimination.
A new brake cycle starts at the first forward run (``clearance_elimination``
or ``force_generation``) after a ``force_release`` run that took the force below half
of the cycle's peak: a controller that backs off a little and re-applies (trimming the
held force) is still in the same application, a release that stops with the pads still
touching before the next application is not (:mod:`.conventions` flags that next
application as not released).  The idle samples before a
cycle give its released rest angle and force tare (:mod:`.conventions`).

This is the *offline* mode of the project's segmentation (:mod:`ebm_wear_monitor.domain.segmentation`:
the labels, runs and cycle index it shares with the monitor's causal mode). Why not the monitor's
state machine (:mod:`ebm_wear_monitor.monitor.segmentation`; its ``label_samples`` labels every
sample)? It runs on the recorded velocity with thresholds resolved from the unit
parameters, where the diagnosis may assume nothing about the recording (the lag of the drive's
velocity estimate, a force tare); and, causal, it calls data that start inside an application
``motion`` without phases, where the diagnosis needs the phases of the first cycle too.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import uniform_filter1d

from ebm_wear_monitor.diagnosis.noise import signal_noise
from ebm_wear_monitor.diagnosis.recording import Resampled
from ebm_wear_monitor.diagnosis.speed import angle_speed
from ebm_wear_monitor.domain.phases import Phase
from ebm_wear_monitor.domain.segmentation import Labels, run_starts, runs, starts_up_to


@dataclass(frozen=True)
class Segmentation(Labels):
    """Phase code and brake-cycle index per sample (domain ``Labels``) and the thresholds that gave them."""

    eps_velocity: float  # rest band of the screw velocity [rad/s]
    force_on: float  # contact threshold of the axial force reading [N] (includes the no-contact reading)
    force_rise: float = 0.0  # the same threshold above the no-contact reading F_0 [N]


def segment(rec: Resampled, speed: np.ndarray | None = None, smooth_s: float = 0.01,
            min_run_s: float = 0.02) -> Segmentation:
    """Phase code and cycle index per sample by the rule of the module docstring.

    ``speed``: screw speed per sample [rad/s]; default :func:`.speed.angle_speed` of the recording.
    """
    CLEARANCE, GENERATION, MAINTENANCE, RELEASE, IDLE = Phase
    speed = angle_speed(rec)[0] if speed is None else speed
    w = max(1, round(smooth_s / rec.dt))
    v = uniform_filter1d(speed, w, mode="nearest")
    f = uniform_filter1d(rec.axial_force, w, mode="nearest")
    eps_v = max(5.0 * signal_noise(speed) / np.sqrt(w), 0.02 * np.percentile(np.abs(v), 99))
    f0 = float(np.percentile(f, 5))
    f_on = max(5.0 * signal_noise(rec.axial_force) / np.sqrt(w), 0.02 * (np.percentile(f, 99) - f0))
    contact = f > f0 + f_on
    phase = np.full(rec.t.size, IDLE, dtype=np.int8)
    phase[(v > eps_v) & ~contact] = CLEARANCE
    phase[(v > eps_v) & contact] = GENERATION
    phase[(np.abs(v) <= eps_v) & contact] = MAINTENANCE
    phase[v < -eps_v] = RELEASE

    # merge short runs into the run before them
    min_run = max(1, round(min_run_s / rec.dt))
    starts, lengths = runs(phase)
    codes = phase[starts].copy()
    for i in range(1, codes.size):
        if lengths[i] < min_run:
            codes[i] = codes[i - 1]
    phase = np.repeat(codes, lengths)

    # a forward move that stops short of contact (the ECU returning from an overshoot, repositioning)
    # is no clearance elimination: it belongs to the idle time between applications
    starts, lengths = runs(phase)
    codes = phase[starts].copy()
    follows = np.append(codes[1:], IDLE)
    codes[(codes == CLEARANCE) & (follows != GENERATION)] = IDLE
    phase = np.repeat(codes, lengths)

    # cycle boundaries: a forward run after a release that took the force below half its peak
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
    cycle = starts_up_to(starts[new_cycle], phase.size).astype(np.int32)
    return Segmentation(phase, cycle, float(eps_v), float(f0 + f_on), float(f_on))
