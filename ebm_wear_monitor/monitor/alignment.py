"""Merge the three input topics of interface.md section 2 into one stream of aligned samples.

The topics ``screw/angle``, ``screw/velocity`` and ``axial_force`` are sampled
together, so an aligned sample is the set of the three values carrying the same
header stamp (after flooring to ``stamp_quantum_s``). Messages may arrive
interleaved, late, duplicated, with gaps, with bad values, or with stamps that
jump back (a bag played in a loop). Every sample that cannot be used is counted
under one fault kind (the first that applies, in this order):

``bad_stamp``        stamp not finite or not representable in int64 ns
``non_finite``       value NaN or +-inf
``negative``         axial force below -10 force_on (compression is positive; a sensor offset of
                     a few force_on is tolerated and removed by segmentation.py)
``absurd``           |angle|, |velocity| or force beyond the configured physical bounds
``stamp_backwards``  stamp more than ``backwards_jump_s`` behind its topic's newest
``late``             stamp more than ``reorder_window_s`` behind its topic's newest, or in the
                     time range already released to the segmenter
``duplicate``        stamp already received on that topic (the first one is kept)

and ``reanchored`` when a topic's clock is re-anchored after a run of backward stamps;

and, for samples that are kept but imperfect:

``out_of_order``     arrived behind its topic's newest stamp but within the window: sorted in
``missing``          at a released stamp, this topic had no value (the stamp is dropped)
``gap``              consecutive aligned samples further apart than ``gap_s``

Counted under "stream" by the core: ``interrupted_cycle`` (a gap inside a brake
application), ``observation_rejected`` (clearance observation outside the
filter's innovation gate) and ``clearance_reset`` (the clearance jumped).

Chunk invariance (why node and replay agree bit for bit): every decision about a
sample depends only on the order of arrival *within its own topic* (the running
maximum of that topic's stamps) and on the samples' values, never on how the
calls to :meth:`InputAligner.add` are grouped or interleaved across topics. The
release horizon ``H = min_topics(newest stamp) - window`` only decides *when*
samples leave, not *which*: a sample accepted later has a stamp of at least its
topic's newest minus the window, hence at least any horizon already used, so it
can never fall in a released range (proof in the test suite by construction:
one message at a time versus one call with the whole recording).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.monitor.config import MonitorConfig, Thresholds

SIGNALS = ("angle", "velocity", "axial_force")
IGNORED_SIGNALS = ("current",)  # optional topic of the twin; not used by the wear monitor
FAULT_KINDS = ("bad_stamp", "non_finite", "negative", "absurd", "stamp_backwards", "late", "duplicate",
               "out_of_order", "reanchored", "missing", "gap", "interrupted_cycle", "observation_rejected",
               "clearance_reset")
_NO_STAMP = np.iinfo(np.int64).min
NEGATIVE_FORCE_MULTIPLE = 10.0  # force below -10 x the contact threshold is a wiring / sign fault
_INT64_SECONDS = 9.2e9  # |stamp| [s] that still fits in int64 nanoseconds


def ros_stamp_ns(sec: np.ndarray | int, nanosec: np.ndarray | int) -> np.ndarray:
    """Exact int64 nanoseconds of ROS ``builtin_interfaces/Time`` (sec, nanosec); pass these to ``add``."""
    return np.asarray(sec, dtype=np.int64) * 1_000_000_000 + np.asarray(nanosec, dtype=np.int64)


def absurd_limits(config: MonitorConfig) -> dict[str, float]:
    """|value| of each input signal above which a sample is ``absurd`` [rad, rad/s, N]
    (also used by the diagnosis, which must not analyse what the monitor rejects)."""
    return {"angle": config.max_abs_angle_rad, "velocity": config.max_speed_rad_s,
            "axial_force": config.max_force_n}


def stamps_to_ns(stamps: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(int64 ns, usable mask) from stamps given as int64 ns (exact) or float seconds (rounded to 1 ns)."""
    stamps = np.asarray(stamps)
    if stamps.dtype.kind in "iu":
        return stamps.astype(np.int64), np.ones(stamps.shape, dtype=bool)
    seconds = stamps.astype(np.float64)
    ok = np.isfinite(seconds) & (np.abs(seconds) < _INT64_SECONDS)
    return np.rint(np.where(ok, seconds, 0.0) * 1e9).astype(np.int64), ok


@dataclass
class AlignedBatch:
    """Aligned samples released by :meth:`InputAligner.release`, in increasing stamp order."""

    t_ns: np.ndarray  # header stamp (floored to the quantum) [ns], int64
    angle: np.ndarray  # screw angle theta [rad]
    velocity: np.ndarray  # screw speed omega [rad/s]
    force: np.ndarray  # axial force F_a [N]
    gap_before: np.ndarray  # bool: a gap precedes this sample

    def __len__(self) -> int:
        return int(self.t_ns.size)


@dataclass
class _Topic:
    raw: list[tuple[np.ndarray, np.ndarray]] = field(default_factory=list)
    keys: np.ndarray = field(default_factory=lambda: np.empty(0, np.int64))  # pending, sorted, unique
    values: np.ndarray = field(default_factory=lambda: np.empty(0))
    newest: int = _NO_STAMP  # newest finite stamp key seen on this topic
    backwards_run: int = 0  # samples in a row (at the end so far) that were 'stamp_backwards'
    accepted: int = 0
    first_ns: int | None = None
    last_ns: int | None = None


class InputAligner:
    """Per-topic validation, de-duplication and reordering, then merge by header stamp.

    ``release_floor_ns``: samples at or before this stamp are dropped as 'late'
    (the last stamp a resumed state already integrated).
    """

    def __init__(self, config: MonitorConfig, thresholds: Thresholds, release_floor_ns: int | None = None):
        self._topics = {s: _Topic() for s in SIGNALS}
        # counts per topic, plus "stream" for faults of the aligned stream (gap, interrupted_cycle)
        self.faults: dict[str, dict[str, int]] = {s: {} for s in (*SIGNALS, "stream")}
        self.configure(config, thresholds)
        q = self._quantum
        # first key that may still be released; everything below has been released (or predates the state)
        self._released_key = _NO_STAMP if release_floor_ns is None else release_floor_ns // q + 1
        self._last_released_key: int | None = None

    def configure(self, config: MonitorConfig, thresholds: Thresholds) -> None:
        """Apply (possibly changed) thresholds from the next :meth:`release` on."""
        q = max(1, round(config.stamp_quantum_s * 1e9))
        self._quantum = q
        self._window = int(np.ceil(config.reorder_window_s * 1e9 / q))
        self._jump = int(np.ceil(config.backwards_jump_s * 1e9 / q))
        self._stale = int(np.ceil(config.stale_after_s * 1e9 / q))
        self._gap = int(np.floor(config.gap_s * 1e9 / q))
        self._reanchor = int(config.reanchor_after_samples)
        limit = absurd_limits(config)
        self._bounds = {
            "angle": (-limit["angle"], limit["angle"]),
            "velocity": (-limit["velocity"], limit["velocity"]),
            "axial_force": (-NEGATIVE_FORCE_MULTIPLE * thresholds.force_on, limit["axial_force"]),
        }

    # ------------------------------------------------------------------ input
    def add(self, signal: str, stamps: np.ndarray, values: np.ndarray) -> None:
        """Queue samples of one topic in arrival order (cheap: all checks happen in :meth:`release`)."""
        if signal in IGNORED_SIGNALS:
            return
        if signal not in self._topics:
            known = ", ".join((*SIGNALS, *IGNORED_SIGNALS))
            raise InputError(f"unknown signal '{signal}' (expected one of {known})")
        stamps = np.atleast_1d(np.asarray(stamps))
        values = np.atleast_1d(np.asarray(values, dtype=np.float64))
        if stamps.ndim != 1 or stamps.shape != values.shape:
            raise InputError(f"signal '{signal}': stamps and values must be 1-D arrays of equal length, "
                             f"got shapes {stamps.shape} and {values.shape}")
        if stamps.size:
            self._topics[signal].raw.append((stamps.copy(), values.copy()))

    def count(self, signal: str, kind: str, n: int) -> None:
        """Add ``n`` faults of ``kind`` to topic ``signal`` (or "stream")."""
        if n:
            self.faults[signal][kind] = self.faults[signal].get(kind, 0) + int(n)

    def _accept(self, signal: str, topic: _Topic) -> None:
        """Classify the queued samples of one topic and merge the good ones into its pending buffer.

        A topic whose stamps stay behind its newest by more than ``backwards_jump_s`` for
        ``reanchor_after_samples`` samples in a row is re-anchored at the latest of them: one
        glitched stamp from the future cannot blind it for ever (data before the release
        horizon, e.g. a bag played again, is still dropped as late).
        """
        if not topic.raw:
            return
        stamps = np.concatenate([r[0] for r in topic.raw]) if len(topic.raw) > 1 else topic.raw[0][0]
        values = np.concatenate([r[1] for r in topic.raw]) if len(topic.raw) > 1 else topic.raw[0][1]
        topic.raw.clear()
        ns, ok_stamp = stamps_to_ns(stamps)
        keys = ns // self._quantum
        start, n = 0, keys.size
        while start < n:
            sl = slice(start, n)
            # newest key seen *before* each sample, in arrival order (running maximum over finite stamps)
            running = np.maximum.accumulate(np.where(ok_stamp[sl], keys[sl], _NO_STAMP))
            before = np.empty_like(running)
            before[0] = topic.newest
            np.maximum(running[:-1], topic.newest, out=before[1:])
            back = ok_stamp[sl] & (before != _NO_STAMP) & (before - keys[sl] > max(self._jump, self._window))
            pos = np.arange(back.size)
            last_forward = np.maximum.accumulate(np.where(back, -1, pos))
            run = np.where(last_forward < 0, pos + 1 + topic.backwards_run, pos - last_forward)
            hit = np.flatnonzero(back & (run >= self._reanchor))
            end = start + int(hit[0]) + 1 if hit.size else n
            part = slice(start, end)
            self._classify(signal, topic, ns=ns[part], ok_stamp=ok_stamp[part], keys=keys[part],
                           values=values[part], before=before[: end - start])
            if hit.size:
                topic.newest, topic.backwards_run = int(keys[end - 1]), 0
                self.count(signal, "reanchored", 1)
            else:
                topic.newest = int(max(topic.newest, running[-1]))
                topic.backwards_run = int(run[-1]) if back[-1] else 0
            start = end

    def _classify(self, signal: str, topic: _Topic, *, ns: np.ndarray, ok_stamp: np.ndarray,
                  keys: np.ndarray, values: np.ndarray, before: np.ndarray) -> None:
        """Count the faults of samples (newest key before each: ``before``); merge the good ones."""
        lo, hi = self._bounds[signal]
        finite = np.isfinite(values)
        bad = ~ok_stamp
        self.count(signal, "bad_stamp", np.count_nonzero(bad))
        kind = ~bad & ~finite
        self.count(signal, "non_finite", np.count_nonzero(kind))
        bad |= kind
        if signal == "axial_force":
            kind = ~bad & (values < lo)
            self.count(signal, "negative", np.count_nonzero(kind))
            bad |= kind
            kind = ~bad & (values > hi)
        else:
            kind = ~bad & ((values < lo) | (values > hi))
        self.count(signal, "absurd", np.count_nonzero(kind))
        bad |= kind
        has_before = before != _NO_STAMP
        behind = np.where(has_before, before - keys, 0)
        kind = ~bad & has_before & (behind > self._jump) & (behind > self._window)
        self.count(signal, "stamp_backwards", np.count_nonzero(kind))
        bad |= kind
        kind = ~bad & ((has_before & (behind > self._window)) | (keys < self._released_key))
        self.count(signal, "late", np.count_nonzero(kind))
        bad |= kind
        good = np.flatnonzero(~bad)
        merged = np.concatenate([topic.keys, keys[good]])
        _, first = np.unique(merged, return_index=True)
        is_first = np.zeros(merged.size, dtype=bool)
        is_first[first] = True
        new_first = is_first[topic.keys.size:]
        self.count(signal, "duplicate", np.count_nonzero(~new_first))
        good = good[new_first]
        self.count(signal, "out_of_order", np.count_nonzero(has_before[good] & (behind[good] > 0)))
        if good.size:
            topic.accepted += int(good.size)
            first_ns, last_ns = int(ns[good].min()), int(ns[good].max())
            topic.first_ns = first_ns if topic.first_ns is None else min(topic.first_ns, first_ns)
            topic.last_ns = last_ns if topic.last_ns is None else max(topic.last_ns, last_ns)
            all_keys = np.concatenate([topic.keys, keys[good]])
            all_values = np.concatenate([topic.values, values[good]])
            order = np.argsort(all_keys, kind="stable")
            topic.keys, topic.values = all_keys[order], all_values[order]

    # ------------------------------------------------------------------ output
    def release(self, final: bool = False) -> AlignedBatch:
        """Aligned samples whose stamps can no longer be completed by later arrivals (all if ``final``)."""
        for signal, topic in self._topics.items():
            self._accept(signal, topic)
        newest = sorted(t.newest for t in self._topics.values())
        if final:
            horizon = np.iinfo(np.int64).max
        else:
            # a topic lagging the median topic by more than stale_after_s no longer holds the others
            # back (a dead sensor); the median ignores one topic running ahead (a glitched stamp)
            median = newest[len(newest) // 2]
            live = [n for n in newest if n != _NO_STAMP and median - n <= self._stale]
            horizon = min(live) - self._window if live and median != _NO_STAMP else _NO_STAMP
        horizon = max(horizon, self._released_key)
        released = {}
        for signal, topic in self._topics.items():
            cut = int(np.searchsorted(topic.keys, horizon, side="left"))
            released[signal] = (topic.keys[:cut], topic.values[:cut])
            topic.keys, topic.values = topic.keys[cut:], topic.values[cut:]
        if final:
            union_max = max((int(k[-1]) for k, _ in released.values() if k.size), default=None)
            if union_max is not None:
                self._released_key = max(self._released_key, union_max + 1)
        else:
            self._released_key = horizon
        union = np.sort(np.concatenate([k for k, _ in released.values()]))
        first = np.ones(union.size, dtype=bool)
        first[1:] = union[1:] != union[:-1]
        # each topic's keys are unique, so a key present in all three topics appears three times
        counts = np.diff(np.flatnonzero(np.append(first, True)))
        union = union[first]
        common = union[counts == len(released)]
        for signal, (keys, _) in released.items():
            self.count(signal, "missing", union.size - keys.size)
        picked = {}
        for signal, (keys, vals) in released.items():
            picked[signal] = vals[np.searchsorted(keys, common)]
        t_ns = common * self._quantum
        gap_before = np.zeros(common.size, dtype=bool)
        if common.size:
            prev = np.empty_like(common)
            prev[0] = common[0] if self._last_released_key is None else self._last_released_key
            prev[1:] = common[:-1]
            gap_before = (common - prev) > self._gap
            self._last_released_key = int(common[-1])
            self.count("stream", "gap", gap_before.sum())
        return AlignedBatch(t_ns, picked["angle"], picked["velocity"], picked["axial_force"], gap_before)

    # ------------------------------------------------------------------ reporting
    def fault_counts(self) -> dict[str, dict[str, int]]:
        """A copy of the counts per topic (and "stream") and kind; topics without faults omitted."""
        return {signal: dict(per) for signal, per in self.faults.items() if per}

    def fault_totals(self) -> dict[str, int]:
        """Counts per fault kind summed over topics (kinds with zero count omitted)."""
        out: dict[str, int] = {}
        for per in self.faults.values():
            for kind, n in per.items():
                out[kind] = out.get(kind, 0) + n
        return dict(sorted(out.items()))

    def input_rates_hz(self) -> dict[str, float | None]:
        """Accepted samples per second of stamp span, per topic (None before two samples)."""
        out: dict[str, float | None] = {}
        for signal, t in self._topics.items():
            span = (t.last_ns - t.first_ns) * 1e-9 if t.first_ns is not None else 0.0
            out[signal] = (t.accepted - 1) / span if span > 0 else None
        return out

    def pending(self) -> int:
        """Samples waiting (queued or in the reorder window), all topics."""
        return sum(t.keys.size + sum(r[0].size for r in t.raw) for t in self._topics.values())
