"""Segmentation into brake applications: the labels both segmenters produce, and their run arithmetic.

A segmentation gives every sample of a recording a :class:`~.phases.Phase` code (one of the four
phases of 000 Fig. 2, or ``idle`` outside any application) and the 0-based index of the application
(cycle) it belongs to; idle samples belong to the application before them, those before the first
one to application 0. :class:`Labels` is that pair. The project has one segmentation in two modes:

* **causal** (streaming), the monitor's: :class:`ebm_wear_monitor.monitor.segmentation.Segmenter`,
  a hysteresis state machine on the recorded screw speed and the force above the rest level, with
  the unit's thresholds (:meth:`~ebm_wear_monitor.monitor.config.MonitorConfig.resolve`). It decides
  only when the data settle a decision, so any chunking of the stream gives the same segments, and
  keeps only the moving samples (memory bounded by moving time). Its offline replay,
  :func:`ebm_wear_monitor.monitor.segmentation.label_samples`, returns these :class:`Labels` for the
  segments the monitor integrates;
* **offline**, the diagnosis': :func:`ebm_wear_monitor.diagnosis.phases.segment`, over the whole
  recording at once: centred smoothing of the angle's own derivative and of the force, thresholds
  from the measured noise of the whole recording (nothing assumed about the recorded velocity or
  the force tare), every sample labelled, the first application of a recording included.

The two modes share this vocabulary (phase codes, labels, runs, cycle index) but not their decision
rules, on purpose: the causal mode cannot see the noise of a whole recording or smooth with future
samples, and cannot know the phase of data that start inside an application (it calls that
``motion``); the offline mode's rules (run merging, a new cycle after a release below half the
peak) look ahead. Either rule in the other mode would change its outputs (the monitor's segments
and wear integral; the diagnosis' figures).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ebm_wear_monitor.arrays import IntArray
from ebm_wear_monitor.domain.phases import Phase


@dataclass(frozen=True)
class Labels:
    """Per-sample phase and application of a recording."""

    phase: IntArray  # int8 per sample: a Phase code (IDLE outside any application)
    cycle: IntArray  # int32 per sample: 0-based index of the application (idle: the one before it)

    @property
    def n_cycles(self) -> int:
        """Number of applications the labels index (0 for no samples)."""
        return int(self.cycle.max()) + 1 if self.cycle.size else 0


def run_starts(code: IntArray) -> IntArray:
    """Indices at which a run of equal values starts in ``code`` (0 first; empty for empty input)."""
    code = np.asarray(code)
    if code.size == 0:
        return np.empty(0, np.intp)
    return np.flatnonzero(np.concatenate(([True], code[1:] != code[:-1])))


def runs(code: IntArray) -> tuple[IntArray, IntArray]:
    """Start indices and lengths of the runs of equal values in ``code``."""
    starts = run_starts(code)
    return starts, np.diff(np.append(starts, np.asarray(code).size))


def run_ids(phase: IntArray, cycle: IntArray) -> IntArray:
    """Id (0, 1, ...) of the run of equal (cycle, phase) each sample belongs to (int64 per sample)."""
    key = np.asarray(cycle).astype(np.int64) * len(Phase) + np.asarray(phase).astype(np.int64)
    return np.cumsum(np.concatenate(([0], (key[1:] != key[:-1]).astype(np.int64))))


def starts_up_to(starts: IntArray, n: int) -> IntArray:
    """Per sample 0..n-1: how many of the sorted indices ``starts`` are at or before it (int64).

    With ``starts`` the first samples of the applications after the first, this is the cycle index
    of :class:`Labels`.
    """
    return np.searchsorted(np.asarray(starts), np.arange(n), side="right").astype(np.int64)
