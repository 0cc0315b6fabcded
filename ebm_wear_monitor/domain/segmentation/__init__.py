"""Segmentation into brake applications: one segmenter, a causal and an offline mode.

A segmentation gives every sample of a recording a :class:`~ebm_wear_monitor.domain.phases.Phase`
code (one of the four phases of 000 Fig. 2, or ``idle`` outside any application) and the 0-based
index of the application (cycle) it belongs to; idle samples belong to the application before them,
those before the first one to application 0. :class:`Labels` is that pair.

The rules both modes apply live here, once:

* **the phase of a sample** from its direction of motion (apply direction = forward, stopped,
  backward) and whether the pads are in contact (:func:`phase_of`, :func:`classify`):

  =========  ===============================  ===========================
  direction  no contact                       contact
  =========  ===============================  ===========================
  forward    clearance elimination            force generation
  stopped    idle                             force maintenance
  backward   force release                    force release
  =========  ===============================  ===========================

  clearance elimination is 004 eq. 5 with x <= x_ag (the screw turns, no clamp force), force
  generation x > x_ag, force maintenance the stick branch of 004 eq. 9 (no sliding, hence no wear:
  000 Sec. 2), force release the screw turning back (000 Sec. 4.1);
* **the cycle index** from the first samples of the applications after the first
  (:func:`cycle_index`);
* **the run arithmetic** over per-sample codes (:func:`run_starts`, :func:`runs`, :func:`run_ids`).

What differs between the modes is what they read and when they may decide:

* **causal** (streaming), the monitor's: :class:`.causal.Segmenter`. Inputs: the recorded screw
  velocity and the force above the rest level, with the unit's hysteresis thresholds
  (:meth:`~ebm_wear_monitor.monitor.config.MonitorConfig.resolve`). Its direction and contact are
  read with hysteresis (moving above ``omega_on``, stopped below ``omega_off``; contact is held from
  the force onset until a released rest), every transition's target is :func:`phase_of` of those
  readings, and it decides a rest only once a stop has lasted ``rest_dwell_s`` (settle before
  deciding), so any chunking of the stream gives the same segments and only the moving samples are
  kept. It cannot know the phase of data that start inside an application (``motion``, idle).
  :func:`.causal.label_batch` (the monitor's ``label_samples``) gives its :class:`Labels`;
* **offline**, the diagnosis': :func:`.offline.segment`, over a whole recording at once. Inputs: the
  angle's own speed and the force, smoothed with a centred window, thresholds from the measured noise
  of the whole recording (nothing assumed about the recorded velocity or the force tare); per-sample
  :func:`classify`, then look-ahead passes: short runs merged into the run before them, a forward
  run without contact not followed by force generation made idle, a new cycle at the first forward
  run after a release below half the peak. Every sample is labelled, the first application included.

Rules that only one mode applies, and why the other does not (each would change that mode's outputs:
the monitor's segments and wear integral, the diagnosis' figures): the causal mode's rest dwell and
hysteresis, where the offline mode merges short runs after the fact (it can see a run's length;
the causal mode cannot wait for it without delaying every decision); the offline mode's idle
forward run and half-peak release, which need the runs after a sample, where the causal mode counts a
short approach as an ``incomplete`` application whose samples keep their clearance-elimination label
and starts an application at every start from rest.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ebm_wear_monitor.arrays import BoolArray, IntArray
from ebm_wear_monitor.domain.phases import Phase

#: direction of motion of the screw: apply direction, at rest, release direction
FORWARD, STOPPED, BACKWARD = 1, 0, -1

#: the phase of a sample by (direction of motion, in contact): the table of the module docstring
PHASE_OF: dict[tuple[int, bool], Phase] = {
    (FORWARD, False): Phase.CLEARANCE_ELIMINATION,
    (FORWARD, True): Phase.FORCE_GENERATION,
    (STOPPED, False): Phase.IDLE,
    (STOPPED, True): Phase.FORCE_MAINTENANCE,
    (BACKWARD, False): Phase.FORCE_RELEASE,
    (BACKWARD, True): Phase.FORCE_RELEASE,
}


def phase_of(direction: int, contact: bool) -> Phase:
    """Phase of a sample moving in ``direction`` (FORWARD, STOPPED, BACKWARD), pads in ``contact`` or not."""
    return PHASE_OF[direction, contact]


def classify(direction: IntArray, contact: BoolArray) -> IntArray:
    """:func:`phase_of` per sample (int8 Phase codes); a sample of no direction (other codes) is idle."""
    direction = np.asarray(direction)
    contact = np.asarray(contact, dtype=bool)
    phase = np.full(direction.shape, Phase.IDLE, dtype=np.int8)
    for (d, c), p in PHASE_OF.items():
        phase[(direction == d) & (contact == c)] = p
    return phase


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


def cycle_index(starts: IntArray, n: int) -> IntArray:
    """Cycle index of :class:`Labels` (int32 per sample 0..n-1) from the sorted first samples ``starts``
    of the applications after the first: how many of them are at or before the sample."""
    return np.searchsorted(np.asarray(starts), np.arange(n), side="right").astype(np.int32)
