"""The causal (streaming) mode of the segmenter: the monitor's phases of 000 Fig. 2 / Fig. 5.

000 Sec. 4.1 describes one brake application (duty cycle) as:

* **clearance elimination**: the screw accelerates in the apply direction and
  runs at speed; the axial force stays near zero while the pads close the gap;
* **force generation**: the pads touch, the axial force rises to its maximum
  while the screw decelerates to zero;
* **force maintenance**: the screw is stopped, the force is held (no sliding
  between balls and raceways, hence no wear: 000 Sec. 2);
* **force release**: the screw turns back, the force falls to zero and the nut
  retracts until the screw stops at the release rest position.

This module turns the aligned sample stream into those phases with a causal
state machine on two hysteresis pairs, both *relative to the unit*
(:meth:`~ebm_wear_monitor.monitor.config.MonitorConfig.resolve`): screw speed
(moving above ``omega_on``, stopped below ``omega_off``) and axial force above
the rest level b (contact above ``b + force_on``, released below ``b + force_off``).
The phase a transition enters is the segmenter's shared classification
(:func:`ebm_wear_monitor.domain.segmentation.phase_of`) of the direction and
contact as the state machine reads them, with hysteresis: the direction is the
one whose threshold the event crossed (forward above ``omega_on``, backward below
``-omega_on``, stopped below ``omega_off``; clearance elimination holds the
apply direction until a released stop), the contact is *held*: none from rest
until the force onset, then contact until the application ends at a rest (a
release is FR whatever the force, a stop after force generation is FM). Only the
start from rest differs from the table: a move there in the release direction is
``motion`` outside any application (idle), as no application is open to
release. Transitions:

====================  =========================================================
rest -> CE            omega > omega_on  (omega < -omega_on from rest: 'motion')
CE -> FG              F - b > force_on
FG -> FM              |omega| < omega_off
FG, FM -> FR          omega < -omega_on
FM, FR -> FG          omega > omega_on (and F - b > force_on from FR): a stepped
                      or repeated demand re-enters force generation
CE -> rest            stopped and F - b < force_off for rest_dwell_s (an approach
                      that stops in contact is force generation, not a rest)
FR -> rest            stopped (|omega| < omega_off) for rest_dwell_s
FM -> rest            stopped and F - b < force_off for rest_dwell_s (force lost
                      without a release motion)
====================  =========================================================

The rest angle of an application (the release rest position its clearance is
counted from, observation.py) is the median angle over the last rest samples
before it, except after an approach that stopped short of the pads
(``incomplete``: a controller easing in, then a force trim, perhaps creeping
into contact below the moving threshold): the clearance is still counted from
the home position before that approach, and the force level b is that rest's.

The rest level b (offset of the force sensor, the ``force_sensor_bias`` of the
effect catalog) is the median force over the last rest samples before the
application: at rest the pads are open and the true axial force is zero. Forces
are used as F - b everywhere (thresholds, wear, peak, onset fit), so an offset
neither merges applications nor biases the clearance observation. The end of
an application is a *stop after the release motion*, independent of the force,
for the same reason.

An application that reached force generation and came back to rest is a
``cycle``; one that never reached force is ``incomplete``; motion that did not
start from rest in the apply direction (or follows the start of data or a gap,
where the context is unknown) is ``motion``, which ends at the first stop after
a release-direction move (or at a stop with released force before any move); a
gap inside an application makes it ``interrupted``; data ending inside one
(``final``) makes it ``partial``. All of them carry their samples so their wear
is integrated; only ``cycle`` counts as a duty cycle.

Only samples where the screw moves (|omega| >= omega_off) are kept for the
wear integral (Archard wear needs sliding, 000 eq. 20-23); each keeps the time
``dt`` since the previous aligned sample (0 after a gap), so the kept samples
integrate exactly the moving time. Memory is therefore bounded by moving time,
not by how long a brake is held.

Chunk invariance: decisions are taken only when the data settle them (a rest
run shorter than the dwell at the end of the available data waits for more
samples, kept as the carry), and every sum is over integer stamps or done later
on whole-segment arrays, so feeding one sample at a time or everything at once
gives the same segments bit for bit. The event loop visits transitions, not
samples: each step is a binary search in index arrays precomputed per batch
(speed conditions) or per window and rest level (force conditions).

Users that need a label on *every* sample of a recording (plots, analysis)
call :func:`label_batch` (the monitor's
:func:`ebm_wear_monitor.monitor.segmentation.label_samples`): the same state
machine and thresholds run once over the whole recording, and the stretches it
consumes (every sample of every segment, moving or not) are recorded as index
spans; samples outside any segment are ``idle``. The monitor's own path does not
record them. This module is the *causal* mode of the segmenter of
:mod:`ebm_wear_monitor.domain.segmentation` (labels, classification, cycle index
shared with the offline mode, :mod:`.offline`; that package says which rules
only one mode applies and why).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from ebm_wear_monitor.arrays import FloatArray
from ebm_wear_monitor.domain.phases import APPLICATION_PHASES, Phase
from ebm_wear_monitor.domain.segmentation import BACKWARD, FORWARD, STOPPED, Labels, cycle_index, phase_of

if TYPE_CHECKING:  # the monitor's input types (the monitor imports this module: no runtime import back)
    from ebm_wear_monitor.monitor.alignment import AlignedBatch
    from ebm_wear_monitor.monitor.config import MonitorConfig, Thresholds

_BATCH_FIELDS = ("t_ns", "angle", "velocity", "force", "gap_before")

# states of the machine: the four phases of an application, MOTION (moving outside any application: its
# samples are labelled idle), REST and UNKNOWN; a kept sample's label is its state, a Phase code
CE, FG, FM, FR, MOTION = Phase
N_LABELS = len(Phase)  # labels a kept sample can carry (per-label sums have this length)
REST = -1
UNKNOWN = -2  # at the start of data and after a gap: the first sample decides (at rest or moving)
_CONFIRMED, _BROKEN, _UNDECIDED = 0, 1, 2
#: force condition that sends a moving state to force generation
_TO_FG: dict[int, str] = {CE: "i_fon", FR: "i_posf"}
_FORCE_WINDOW = 4096  # samples over which force conditions are evaluated at once (doubled on demand)


@dataclass
class Segment:
    """One closed stretch of motion between two rests, with its kept (moving) samples."""

    kind: str  # "cycle" | "incomplete" | "motion" | "interrupted" | "partial"
    start_ns: int  # stamp of the first sample [ns]
    end_ns: int  # stamp of the first rest sample after it (or the last sample) [ns]
    phase_ns: np.ndarray  # int64[N_LABELS]: time spent per label CE, FG, FM, FR, MOTION [ns]
    angle: np.ndarray  # kept samples: screw angle [rad]
    velocity: np.ndarray  # screw speed [rad/s]
    force: np.ndarray  # axial force above the rest level, F - b [N]
    dt: np.ndarray  # time since the previous aligned sample [s] (0 after a gap)
    dangle: np.ndarray  # angle change since the previous aligned sample [rad] (0 after a gap)
    label: np.ndarray  # int8 phase label of each kept sample
    peak_force: float  # max of F - b over all samples of the segment [N]
    angle_at_peak_force: float  # screw angle at that sample [rad]
    rest_angle: float  # median rest angle before the segment [rad]; NaN when unknown
    force_baseline: float  # rest level b subtracted from the force [N]

    @property
    def phase_durations_s(self) -> tuple[float, float, float, float]:
        """Durations of the four phases of 000 Fig. 2 [s]."""
        ce, fg, fm, fr = (float(v) * 1e-9 for v in self.phase_ns[:4])
        return ce, fg, fm, fr


@dataclass
class _Open:
    """The segment being built."""

    rest_angle: float
    baseline: float
    start_ns: int | None = None
    label: int | None = None
    label_start: int = 0
    phase_ns: np.ndarray = field(default_factory=lambda: np.zeros(N_LABELS, np.int64))
    parts: list[tuple[np.ndarray, ...]] = field(default_factory=list)
    peak_force: float = -np.inf
    angle_at_peak: float = np.nan
    reached_force: bool = False
    last_direction: float = 0.0  # sign of the last moving sample (0: no move yet)


class _ForceWindow(NamedTuple):
    """Force conditions over samples [lo, hi) of a batch at rest level ``b`` [N]: name -> indices."""

    b: float
    lo: int
    hi: int
    at: dict[str, np.ndarray]


class Segmenter:
    """Streaming state machine over aligned samples; :meth:`feed` returns the segments it closed.

    ``force_baseline``: the rest level b of the force to start with [N] (persisted with the state).
    """

    def __init__(self, config: MonitorConfig, thresholds: Thresholds, force_baseline: float = 0.0):
        self.configure(config, thresholds)
        self.state = UNKNOWN
        self.force_baseline = float(force_baseline)
        self._open = _Open(np.nan, self.force_baseline)
        self._ring = np.empty(0)  # angles of the latest rest samples [rad]
        self._ring_force = np.empty(0)  # their forces [N]
        self._home = (np.nan, np.nan)  # rest angle [rad] and force level [N] before an approach that
        # stopped short of the pads
        self._carry: AlignedBatch | None = None
        self._prev_ns: int | None = None
        self._prev_angle = 0.0
        self._gap_ns: int | None = None  # stamp of the last gap already handled
        self._fc: _ForceWindow | None = None

    def configure(self, config: MonitorConfig, thresholds: Thresholds) -> None:
        """Apply (possibly changed) thresholds from the next :meth:`feed` on."""
        self.th = thresholds
        self._dwell_ns = round(config.rest_dwell_s * 1e9)
        self._ring_size = int(config.rest_angle_samples)

    # ------------------------------------------------------------------ helpers
    def _consume(self, a: int, b: int, label: int) -> None:
        if b <= a:
            return
        seg, s = self._open, self._s
        if seg.start_ns is None:
            seg.start_ns = int(s["t"][a])
        if seg.label != label:
            if seg.label is not None:
                seg.phase_ns[seg.label] += int(s["t"][a]) - seg.label_start
            seg.label, seg.label_start = label, int(s["t"][a])
        force = s["force"][a:b] - seg.baseline
        keep = ~s["slow"][a:b]
        if keep.any():
            kept = [s[k][a:b][keep] for k in ("angle", "velocity")]
            kept += [force[keep], s["dt"][a:b][keep], s["dangle"][a:b][keep]]
            seg.parts.append((*kept, np.full(int(keep.sum()), label, np.int8)))
        i = int(np.argmax(force))
        if force[i] > seg.peak_force:
            seg.peak_force, seg.angle_at_peak = float(force[i]), float(s["angle"][a + i])
        moving = s["i_moving"]
        j = int(np.searchsorted(moving, b)) - 1
        if j >= 0 and moving[j] >= a:
            seg.last_direction = float(np.sign(s["velocity"][moving[j]]))
        if label in (FG, FM, FR):
            seg.reached_force = True

    def _close(self, end_ns: int, kind: str, out: list[Segment]) -> None:
        seg = self._open
        self._open = _Open(np.nan, self.force_baseline)
        if seg.start_ns is None:
            return
        if seg.label is not None:
            seg.phase_ns[seg.label] += end_ns - seg.label_start
        dtypes = (*(np.float64,) * 5, np.int8)
        arrays = [np.concatenate([part[j] for part in seg.parts]) if seg.parts else np.empty(0, d)
                  for j, d in enumerate(dtypes)]
        # an approach that stopped short of the pads (incomplete) leaves the home position where it
        # was: the next application's clearance is counted from there, not from the stop on the way
        self._home = (seg.rest_angle, seg.baseline) if kind == "incomplete" else (np.nan, np.nan)
        angle, velocity, force, dt, dangle, label = arrays
        out.append(Segment(kind, seg.start_ns, end_ns, seg.phase_ns, angle, velocity, force, dt, dangle,
                           label, peak_force=float(seg.peak_force), angle_at_peak_force=seg.angle_at_peak,
                           rest_angle=seg.rest_angle, force_baseline=seg.baseline))

    def _kind_at_rest(self) -> str:
        if self.state == MOTION:
            return "motion"
        return "cycle" if self._open.reached_force else "incomplete"

    def _next(self, name: str, p: int) -> int:
        """First index >= p of a speed condition precomputed for the batch (n if none)."""
        idx = self._s[name]
        j = int(np.searchsorted(idx, p))
        return int(idx[j]) if j < idx.size else self._n

    def _force_window(self, lo: int, hi: int) -> _ForceWindow:
        """Index arrays of the force conditions over [lo, hi) at the open segment's rest level."""
        s, th, b = self._s, self.th, self._open.baseline
        f = s["force"][lo:hi] - b
        slow = s["slow"][lo:hi]
        held_rest = slow & (f < th.force_off)
        self._fc = _ForceWindow(b, lo, hi, {
            "i_fon": np.flatnonzero(f > th.force_on) + lo,
            "i_posf": np.flatnonzero((s["velocity"][lo:hi] > th.omega_on) & (f > th.force_on)) + lo,
            "i_released": np.flatnonzero(held_rest) + lo,
            "i_notreleased": np.flatnonzero(~held_rest) + lo,
        })
        return self._fc

    def _next_force(self, name: str, p: int) -> int:
        """First index >= p of a force condition (relative to the rest level), evaluated lazily."""
        n, c = self._n, self._fc
        if c is None or c.b != self._open.baseline or not c.lo <= p < c.hi:
            c = self._force_window(p, min(n, p + _FORCE_WINDOW))
        while True:
            idx = c.at[name]
            j = int(np.searchsorted(idx, p))
            if j < idx.size:
                return int(idx[j])
            if c.hi >= n:
                return n
            c = self._force_window(c.lo, min(n, c.lo + 2 * (c.hi - c.lo)))

    def _dwell(self, r: int, e: int, run_end: int) -> tuple[int, int]:
        """Does the stop starting at ``r`` (ending at ``run_end``, gap-free range up to ``e``) last?"""
        t = self._s["t"]
        k = min(run_end, e)
        if int(t[k - 1]) - int(t[r]) >= self._dwell_ns:
            return _CONFIRMED, r
        if k < e or e < self._n:
            return _BROKEN, k
        return (_CONFIRMED, r) if self._final else (_UNDECIDED, r)

    # ------------------------------------------------------------------ main loop
    def feed(self, batch: AlignedBatch, final: bool = False) -> list[Segment]:
        """Consume ``batch`` (after any carried samples); return the segments closed on the way."""
        if self._carry is not None and len(self._carry):
            c = self._carry
            batch = replace(batch, **{k: np.concatenate([getattr(c, k), getattr(batch, k)])
                                      for k in _BATCH_FIELDS})
        self._carry = None
        out: list[Segment] = []
        n = len(batch)
        if n == 0:
            if final:
                self._finish(out)
            return out
        th = self.th
        t, ang, vel, frc, gap = batch.t_ns, batch.angle, batch.velocity, batch.force, batch.gap_before
        prev_t = np.empty(n, np.int64)
        prev_t[0] = t[0] if self._prev_ns is None else self._prev_ns
        prev_t[1:] = t[:-1]
        prev_a = np.empty(n)
        prev_a[0] = ang[0] if self._prev_ns is None else self._prev_angle
        prev_a[1:] = ang[:-1]
        speed = np.abs(vel)
        slow = speed < th.omega_off
        self._s = {
            "t": t, "angle": ang, "velocity": vel, "force": frc, "slow": slow,
            "dt": np.where(gap, 0, t - prev_t) * 1e-9, "dangle": np.where(gap, 0.0, ang - prev_a),
            "i_moving": np.flatnonzero(speed > th.omega_on),
            "i_pos": np.flatnonzero(vel > th.omega_on),
            "i_neg": np.flatnonzero(vel < -th.omega_on),
            "i_slow": np.flatnonzero(slow),
            "i_notslow": np.flatnonzero(~slow),
            "i_gap": np.flatnonzero(gap),
        }
        self._fc = None
        self._n, self._final = n, final
        p = 0
        while p < n:
            if gap[p] and self._gap_ns != int(t[p]):
                self._gap_ns = int(t[p])
                before = int(t[p - 1]) if p > 0 else self._prev_ns
                if before is not None:  # (a gap is seen only after released samples: always)
                    self._on_gap(before, out)
            e = self._next("i_gap", p + 1)
            p, stop = self._step(p, e, out)
            if stop:
                break
        if p > 0:
            self._prev_ns, self._prev_angle = int(t[p - 1]), float(ang[p - 1])
        if p < n:
            self._carry = replace(batch, t_ns=t[p:], angle=ang[p:], velocity=vel[p:], force=frc[p:],
                                  gap_before=gap[p:])
        if final:
            self._finish(out)
        self._s, self._fc = {}, None
        return out

    def _finish(self, out: list[Segment]) -> None:
        """End of data: close whatever is open."""
        if self._prev_ns is None:
            return
        if self.state in APPLICATION_PHASES:
            self._close(self._prev_ns, "partial", out)
        elif self.state == MOTION:
            self._close(self._prev_ns, "motion", out)
        self.state = UNKNOWN

    def _on_gap(self, end_ns: int, out: list[Segment]) -> None:
        """A gap: no knowledge of what happened in it. Close any segment and resynchronise."""
        self._ring, self._ring_force, self._home = np.empty(0), np.empty(0), (np.nan, np.nan)
        if self.state == REST:
            return
        self._close(end_ns, "interrupted" if self.state in APPLICATION_PHASES else "motion", out)
        self.state = UNKNOWN

    def _start(self, s: int) -> None:
        """Leave rest at sample ``s``: a new application (apply direction) or other motion."""
        if np.isfinite(self._home[0]) and self._s["velocity"][s] > 0:
            # an apply move continuing an approach that stopped short (maybe creeping into contact since):
            # home angle and force level from the rest before that approach
            rest_angle, self.force_baseline = self._home
        else:
            if self._ring.size:
                self.force_baseline = float(np.median(self._ring_force))
            rest_angle = float(np.median(self._ring)) if self._ring.size else np.nan
        self._open = _Open(rest_angle, self.force_baseline)
        self._ring, self._ring_force = np.empty(0), np.empty(0)
        # from rest (pads open), an apply move enters an application, any other move is motion outside one
        self.state = phase_of(FORWARD, False) if self._s["velocity"][s] > 0 else MOTION

    def _settle(self, p: int, r: int, run_end: int, out: list[Segment], accept: bool = True
                ) -> tuple[int, bool]:
        """A stop starts at ``r`` after the samples [p, r) of the current state: rest, or carry on?"""
        status, k = self._dwell(r, self._gap_end, run_end)
        if status == _CONFIRMED and accept:
            self._consume(p, r, self.state)
            self._close(int(self._s["t"][r]), self._kind_at_rest(), out)
            self.state = REST
            return r, False
        if status == _CONFIRMED:  # a lasting stop that is not a rest (a hold seen without context)
            k = min(self._next("i_notslow", r), self._gap_end)
            self._consume(p, k, self.state)
            return k, k == self._n and not self._final
        self._consume(p, k, self.state)
        return k, status == _UNDECIDED

    def _step(self, p: int, e: int, out: list[Segment]) -> tuple[int, bool]:
        """Advance from ``p`` in the current state to the next event before ``e``; (new p, stop)."""
        self._gap_end = e
        nx, nf = self._next, self._next_force
        if self.state == UNKNOWN:
            at_rest = self._s["slow"][p] and self._s["force"][p] - self.force_baseline < self.th.force_off
            self.state = REST if at_rest else MOTION
        st = self.state
        if st == REST:
            s = min(nx("i_moving", p), e)
            self._ring = np.concatenate([self._ring, self._s["angle"][p:s]])[-self._ring_size:]
            self._ring_force = np.concatenate([self._ring_force, self._s["force"][p:s]])[-self._ring_size:]
            if s < e:
                self._start(s)
            return s, False
        if st == FG:
            m, q = nx("i_slow", p), nx("i_neg", p)
            ev = min(m, q, e)
            if ev < e:
                self._consume(p, ev, FG)
                self.state = phase_of(BACKWARD if q < m else STOPPED, True)
                return ev, False
            self._consume(p, e, FG)
            return e, False
        if st == FM:
            a, q, r = nx("i_pos", p), nx("i_neg", p), nf("i_released", p)
            ev = min(a, q)
            if ev < min(r, e):
                self._consume(p, ev, FM)
                self.state = phase_of(FORWARD if a < q else BACKWARD, True)
                return ev, False
            if r < e:
                return self._settle(p, r, nf("i_notreleased", r), out)
            self._consume(p, e, FM)
            return e, False
        # CE ends at a stop with the force released: a slow approach that stops in contact (a position
        # loop easing in, a force trim) is force generation, never a rest beside the pads
        r = nf("i_released", p) if st == CE else nx("i_slow", p)
        if st in _TO_FG:  # CE: force onset; FR: a new apply move under force
            g = nf(_TO_FG[st], p)
            if g < min(r, e):
                self._consume(p, g, st)
                self.state = phase_of(FORWARD, True)
                return g, False
        if r < e:
            accept = True
            if st == MOTION:  # context unknown: a stop is a rest after a release-direction move only
                self._consume(p, r, MOTION)
                p, seg = r, self._open
                released = self._s["force"][r] - seg.baseline < self.th.force_off
                accept = seg.last_direction < 0 or (seg.last_direction == 0 and released)
            run_end = nf("i_notreleased", r) if st == CE else nx("i_notslow", r)
            return self._settle(p, r, run_end, out, accept)
        self._consume(p, e, st)
        return e, False


@dataclass(frozen=True)
class SampleLabels(Labels):
    """:class:`~ebm_wear_monitor.domain.segmentation.Labels` of every sample (:func:`label_batch`).

    ``phase``: the Phase of the state that consumed the sample; IDLE for rest and for ``motion`` outside
    an application. ``cycle``: 0-based index of its segment (of any kind); rest belongs to the segment
    before it, the rest before the first segment to segment 0.
    """

    kinds: tuple[str, ...]  # Segment.kind of each segment, in order
    force_baseline: FloatArray  # rest level b of each segment [N]

    @property
    def n_segments(self) -> int:
        return len(self.kinds)


class _LabellingSegmenter(Segmenter):
    """:class:`Segmenter` that also records every consumed stretch [a, b) of batch indices with its label."""

    def __init__(self, config: MonitorConfig, thresholds: Thresholds, force_baseline: float = 0.0):
        super().__init__(config, thresholds, force_baseline)
        self.spans: list[tuple[int, int, int]] = []

    def _consume(self, a: int, b: int, label: int) -> None:
        if b > a:
            self.spans.append((a, b, label))
        super()._consume(a, b, label)


def label_batch(batch: AlignedBatch, *, config: MonitorConfig, thresholds: Thresholds,
                force_baseline: float = 0.0) -> SampleLabels:
    """Label every sample of a whole aligned recording (one batch, ``final=True``) with the state machine.

    ``config`` / ``thresholds`` as for the monitor (``thresholds = config.resolve(unit)``);
    ``force_baseline``: rest level b of the force before the first rest is seen [N]. The labels are those
    of the segments the monitor would integrate.
    """
    seg = _LabellingSegmenter(config, thresholds, force_baseline)
    segments = seg.feed(batch, final=True)
    n = len(batch)
    phase = np.full(n, Phase.IDLE, np.int8)
    for a, b, label in seg.spans:  # one entry per phase stretch, not per sample
        phase[a:b] = label
    starts = np.searchsorted(batch.t_ns, [s.start_ns for s in segments])
    return SampleLabels(phase, cycle_index(starts[1:], n), tuple(s.kind for s in segments),
                        np.array([s.force_baseline for s in segments], dtype=float))
