"""Merge the three input topics of interface.md section 2 onto one time base, by header stamp.

The topics ``screw/angle``, ``screw/velocity`` and ``axial_force`` need not
share rates or stamps (interface.md section 2: e.g. angle and velocity at
2 kHz, force at 1 kHz, each with its own phase and jitter). Each topic is first
cleaned on its own (validated, de-duplicated, reordered); then the topic named
by ``MonitorConfig.time_base`` (the force by default) gives the common time
base and the two others are interpolated linearly at its stamps:

    x_s(t_b) = x_s(t_0) + (x_s(t_1) - x_s(t_0)) (t_b - t_0) / (t_1 - t_0),  t_0 <= t_b <= t_1

between the two samples of topic ``s`` around each base stamp ``t_b``, only if
``t_1 - t_0 <= max_interpolation_s`` (exactly ``x_s(t_0)`` when ``t_0 = t_b``, so
topics sampled together align exactly as before). Otherwise topic ``s`` is
``missing`` at ``t_b`` and the base stamp is dropped.

Every sample that cannot be used is counted under one fault kind (the first that applies):

``bad_stamp``        stamp not a valid time (non-finite, beyond int64 ns, or nanosec >= 1e9)
``non_finite``       value NaN or +-inf
``negative``         axial force below -10 force_on (compression is positive; a sensor offset of
                     a few force_on is tolerated and removed by segmentation.py)
``absurd``           |angle|, |velocity| or force beyond the configured physical bounds
``stamp_glitch``     a stamp more than ``backwards_jump_s`` ahead of its topic's newest (or a
                     topic's first stamp) that the next ``reanchor_after_samples`` samples do not
                     continue (each within ``backwards_jump_s`` of the one before)
``stamp_backwards``  stamp more than ``backwards_jump_s`` behind its topic's newest (and below its floor)
``late``             stamp below its topic's floor: more than ``reorder_window_s`` behind the
                     topic's newest, or in a range already integrated (a resumed state)
``duplicate``        stamp already received on that topic (the first one is kept)

``reanchored`` counts confirmed clock jumps ahead; for samples that are kept but imperfect:

``out_of_order``     arrived behind its topic's newest stamp but within the window: sorted in
``missing``          at a base stamp, this topic could not be interpolated (the stamp is dropped)
``gap``              consecutive aligned samples further apart than ``gap_s``

The adapters add ``undecodable`` (a record that did not decode) and ``lost`` (records of a
damaged storage chunk); the core counts under "stream": ``interrupted_cycle`` (a gap inside a
brake application) and ``observation_rejected`` (a clearance observation outside the filter's
innovation gate, monitor/tracker.py).

Why node and replay agree (any chunking, any interleaving of the topics): every
decision about a sample is a function of its own topic's arrival sequence only.
Each topic keeps a *floor* ``W = max(floor, newest - window)`` that never
decreases; a sample below it is dropped, so samples below ``W`` are final. A
clock jump ahead moves ``newest`` only once confirmed by the following samples
(bounded latency: ``reanchor_after_samples`` periods), so one glitched stamp
cannot move a floor. A base stamp ``t_b`` is released only when it and its
bracket in every other topic are final: ``t_b < W_base`` and, per other topic,
``t_b <= L_s`` (its last sample below ``W_s``) or ``W_s - L_s >
max_interpolation_s`` (no later sample can close the bracket: missing either
way). When each call is made changes *when* a stamp is released, never what is
released. The one exception is the dead-sensor rule: a topic whose newest lags
the median topic's by more than ``stale_after_s`` stops holding the others back
(its floor is raised to theirs); node and replay feed within
``reorder_window_s`` of each other across topics, far inside that bound.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ebm_wear_monitor.domain.signals import MONITOR_SIGNALS, SIGNALS
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.monitor.config import MonitorConfig, Thresholds
from ebm_wear_monitor.monitor.wire import BAD_STAMP_NS

#: input signals of interface.md section 2 the wear monitor does not use (the motor current)
IGNORED_SIGNALS = tuple(s for s in SIGNALS if s not in MONITOR_SIGNALS)
FAULT_KINDS = ("bad_stamp", "non_finite", "negative", "absurd", "stamp_glitch", "stamp_backwards", "late",
               "duplicate", "out_of_order", "reanchored", "missing", "gap", "undecodable", "lost",
               "interrupted_cycle", "observation_rejected")
_NO_STAMP = int(np.iinfo(np.int64).min)
_MAX_KEY = int(np.iinfo(np.int64).max)
NEGATIVE_FORCE_MULTIPLE = 10.0  # force below -10 x the contact threshold is a wiring / sign fault
_INT64_SECONDS = 9.2e9  # |stamp| [s] that still fits in int64 nanoseconds
# order classes of a sample with a valid stamp
_KEEP, _GLITCH, _BACKWARDS, _LATE = 0, 1, 2, 3


def absurd_limits(config: MonitorConfig) -> dict[str, float]:
    """|value| of each input signal above which a sample is ``absurd`` [rad, rad/s, N]
    (also used by the diagnosis, which must not analyse what the monitor rejects)."""
    return {"angle": config.max_abs_angle_rad, "velocity": config.max_speed_rad_s,
            "axial_force": config.max_force_n}


def stamps_to_ns(stamps: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(int64 ns, usable mask) from stamps as int64 ns (exact; ``wire.BAD_STAMP_NS`` is unusable) or float
    seconds (rounded to 1 ns)."""
    stamps = np.asarray(stamps)
    if stamps.dtype.kind in "iu":
        ns = stamps.astype(np.int64)
        return ns, ns != BAD_STAMP_NS
    seconds = stamps.astype(np.float64)
    ok = np.isfinite(seconds) & (np.abs(seconds) < _INT64_SECONDS)
    return np.rint(np.where(ok, seconds, 0.0) * 1e9).astype(np.int64), ok


@dataclass
class AlignedBatch:
    """Aligned samples released by :meth:`InputAligner.release`, in increasing stamp order."""

    t_ns: np.ndarray  # base stamp (floored to the quantum) [ns], int64
    angle: np.ndarray  # screw angle theta [rad]
    velocity: np.ndarray  # screw speed omega [rad/s]
    force: np.ndarray  # axial force F_a [N]
    gap_before: np.ndarray  # bool: a gap precedes this sample

    def __len__(self) -> int:
        return int(self.t_ns.size)


@dataclass
class _Topic:
    raw: list[tuple[np.ndarray, np.ndarray]] = field(default_factory=list)  # queued (and held) samples
    keys: np.ndarray = field(default_factory=lambda: np.empty(0, np.int64))  # pending, sorted, unique
    values: np.ndarray = field(default_factory=lambda: np.empty(0))
    newest: int = _NO_STAMP  # newest confirmed stamp key of this topic
    floor: int = _NO_STAMP  # keys below are final: later samples below it are dropped (never decreases)
    accepted: int = 0
    first_ns: int | None = None
    last_ns: int | None = None


class InputAligner:
    """Per-topic validation, de-duplication and reordering, then interpolation onto the base topic's stamps.

    ``release_floor_ns``: samples at or before this stamp are dropped as 'late'
    (the last stamp a resumed state already integrated).
    """

    def __init__(self, config: MonitorConfig, thresholds: Thresholds, release_floor_ns: int | None = None):
        self._topics = {s: _Topic() for s in MONITOR_SIGNALS}
        # counts per topic, plus "stream" for faults of the aligned stream (gap, interrupted_cycle)
        self.faults: dict[str, dict[str, int]] = {s: {} for s in (*MONITOR_SIGNALS, "stream")}
        self.configure(config, thresholds)
        if release_floor_ns is not None:
            for topic in self._topics.values():
                topic.floor = release_floor_ns // self._quantum + 1
        self._released = _NO_STAMP  # base keys below this have been released
        self._last_released_key: int | None = None

    def configure(self, config: MonitorConfig, thresholds: Thresholds) -> None:
        """Apply (possibly changed) thresholds from the next :meth:`release` on."""
        q = max(1, round(config.stamp_quantum_s * 1e9))
        self._quantum = q
        self._window = int(np.ceil(config.reorder_window_s * 1e9 / q))
        self._jump = int(np.ceil(config.backwards_jump_s * 1e9 / q))
        self._stale = int(np.ceil(config.stale_after_s * 1e9 / q))
        self._gap = int(np.floor(config.gap_s * 1e9 / q))
        self._bracket = int(np.floor(config.max_interpolation_s * 1e9 / q))
        self._confirm = int(config.reanchor_after_samples)
        self._base = config.time_base
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
            known = ", ".join((*MONITOR_SIGNALS, *IGNORED_SIGNALS))
            raise InputError(f"unknown signal '{signal}' (expected one of {known})")
        stamps = np.atleast_1d(np.asarray(stamps))
        values = np.atleast_1d(np.asarray(values, dtype=np.float64))
        if stamps.ndim != 1 or stamps.shape != values.shape:
            raise InputError(f"signal '{signal}': stamps and values must be 1-D arrays of equal length, "
                             f"got shapes {stamps.shape} and {values.shape}")
        if stamps.size:
            self._topics[signal].raw.append((stamps.copy(), values.copy()))

    def count(self, signal: str, kind: str, n: int | np.integer[Any]) -> None:
        """Add ``n`` faults of ``kind`` to topic ``signal`` (or "stream")."""
        if n:
            self.faults[signal][kind] = self.faults[signal].get(kind, 0) + int(n)

    def _order(self, signal: str, topic: _Topic, keys: np.ndarray, valid: np.ndarray, final: bool
               ) -> tuple[np.ndarray, np.ndarray, int]:
        """Order class of each sample (arrival order) and whether it is behind its topic's newest.

        Returns (class per sample, behind-newest mask, number of samples decided); samples from a
        clock-jump candidate on whose confirmation is still open are left undecided (held) unless
        ``final``. Updates the topic's ``newest`` and ``floor``.
        """
        n = keys.size
        cls = np.full(n, _KEEP, np.int8)
        behind = np.zeros(n, bool)
        jump, window = self._jump, self._window
        pos = 0
        while pos < n:
            k, ok = keys[pos:], valid[pos:]
            masked = np.where(ok, k, _NO_STAMP)
            running = np.maximum.accumulate(masked)
            before = np.empty_like(running)
            before[0] = topic.newest
            np.maximum(running[:-1], topic.newest, out=before[1:])
            ahead = ok & ((before == _NO_STAMP) | (k > np.where(before == _NO_STAMP, 0, before) + jump))
            stop = int(np.argmax(ahead)) if ahead.any() else k.size
            if stop:  # ordinary samples: late/backwards below the running floor, else kept
                b, kk, okk = before[:stop], k[:stop], ok[:stop]
                floor = np.maximum(topic.floor, np.where(b == _NO_STAMP, _NO_STAMP, b - window))
                low = okk & (kk < floor)
                back = low & (b != _NO_STAMP) & (b - kk > jump)
                cls[pos:pos + stop] = np.where(back, _BACKWARDS, np.where(low, _LATE, _KEEP))
                behind[pos:pos + stop] = okk & ~low & (b != _NO_STAMP) & (kk < b)
                topic.newest = max(topic.newest, int(running[stop - 1]))
                topic.floor = max(topic.floor, topic.newest - window)
            pos += stop
            if pos >= n:
                break
            # a candidate clock jump at pos: confirmed by the next samples continuing from it?
            followers = pos + 1 + np.flatnonzero(valid[pos + 1:])[: self._confirm - 1]
            chain = keys[np.concatenate(([pos], followers))]
            steady = np.abs(np.diff(chain)) <= jump
            if steady.all() and followers.size < self._confirm - 1 and not final:
                return cls, behind, pos  # hold from here until enough samples arrived
            if not steady.all() or followers.size < self._confirm - 1:
                cls[pos] = _GLITCH  # not confirmed: drop it, judge the next samples afresh
                pos += 1
                continue
            if topic.newest != _NO_STAMP:
                self.count(signal, "reanchored", 1)
            topic.newest = int(keys[pos])
            topic.floor = max(topic.floor, topic.newest - window)
        return cls, behind, n

    def _accept(self, signal: str, topic: _Topic, final: bool) -> None:
        """Classify the queued samples of one topic and merge the good ones into its pending buffer."""
        if not topic.raw:
            return
        stamps = np.concatenate([r[0] for r in topic.raw]) if len(topic.raw) > 1 else topic.raw[0][0]
        values = np.concatenate([r[1] for r in topic.raw]) if len(topic.raw) > 1 else topic.raw[0][1]
        topic.raw.clear()
        ns, ok_stamp = stamps_to_ns(stamps)
        keys = np.where(ok_stamp, ns // self._quantum, _NO_STAMP)
        cls, behind, decided = self._order(signal, topic, keys, ok_stamp, final)
        if decided < keys.size:
            topic.raw.append((stamps[decided:], values[decided:]))
            ns, ok_stamp, keys, values = ns[:decided], ok_stamp[:decided], keys[:decided], values[:decided]
            cls, behind = cls[:decided], behind[:decided]
        lo, hi = self._bounds[signal]
        bad = ~ok_stamp
        self.count(signal, "bad_stamp", np.count_nonzero(bad))
        kind = ~bad & ~np.isfinite(values)
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
        for code, name in ((_GLITCH, "stamp_glitch"), (_BACKWARDS, "stamp_backwards"), (_LATE, "late")):
            kind = ~bad & (cls == code)
            self.count(signal, name, np.count_nonzero(kind))
            bad |= kind
        good = np.flatnonzero(~bad)
        merged = np.concatenate([topic.keys, keys[good]])
        _, first = np.unique(merged, return_index=True)
        is_first = np.zeros(merged.size, dtype=bool)
        is_first[first] = True
        new_first = is_first[topic.keys.size:]
        self.count(signal, "duplicate", np.count_nonzero(~new_first))
        good = good[new_first]
        self.count(signal, "out_of_order", np.count_nonzero(behind[good]))
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
    def _limit(self, signal: str, topic: _Topic) -> int:
        """Base keys below this have a final value (or a final 'missing') in ``topic``."""
        if signal == self._base:
            return topic.floor
        last = int(np.searchsorted(topic.keys, topic.floor, side="left")) - 1
        if last < 0 or topic.floor - int(topic.keys[last]) > self._bracket:
            return topic.floor
        return int(topic.keys[last]) + 1

    def release(self, final: bool = False) -> AlignedBatch:
        """Aligned samples whose values can no longer change with later arrivals (all if ``final``)."""
        for signal, topic in self._topics.items():
            self._accept(signal, topic, final)
        if final:
            limit = _MAX_KEY
        else:
            # a topic lagging the median topic by more than stale_after_s no longer holds the others
            # back (a dead sensor): its floor is raised to theirs
            newest = sorted(t.newest for t in self._topics.values())
            median = newest[len(newest) // 2]
            if median == _NO_STAMP:
                limit = _NO_STAMP
            else:
                live = {s for s, t in self._topics.items()
                        if t.newest != _NO_STAMP and median - t.newest <= self._stale}
                floor = min(self._topics[s].floor for s in live)
                for s, t in self._topics.items():
                    if s not in live:
                        t.floor = max(t.floor, floor)
                limit = min(self._limit(s, t) for s, t in self._topics.items())
        limit = max(limit, self._released)
        base = self._topics[self._base]
        cut = int(np.searchsorted(base.keys, limit, side="left"))
        t_keys, picked = base.keys[:cut], {self._base: base.values[:cut]}
        base.keys, base.values = base.keys[cut:], base.values[cut:]
        usable = np.ones(t_keys.size, bool)
        for signal, topic in self._topics.items():
            if signal == self._base:
                continue
            value, ok = self._interpolate(topic, t_keys)
            self.count(signal, "missing", np.count_nonzero(~ok))
            usable &= ok
            picked[signal] = value
            keep = max(int(np.searchsorted(topic.keys, limit, side="left")) - 1, 0)
            topic.keys, topic.values = topic.keys[keep:], topic.values[keep:]
        if final:
            for topic in self._topics.values():
                if topic.keys.size:
                    topic.floor = max(topic.floor, int(topic.keys[-1]) + 1)
                topic.keys, topic.values = topic.keys[:0], topic.values[:0]
            limit = max((t.floor for t in self._topics.values()), default=limit)
        self._released = limit
        common = t_keys[usable]
        gap_before = np.zeros(common.size, dtype=bool)
        if common.size:
            prev = np.empty_like(common)
            prev[0] = common[0] if self._last_released_key is None else self._last_released_key
            prev[1:] = common[:-1]
            gap_before = (common - prev) > self._gap
            self._last_released_key = int(common[-1])
            self.count("stream", "gap", gap_before.sum())
        return AlignedBatch(common * self._quantum, picked["angle"][usable], picked["velocity"][usable],
                            picked["axial_force"][usable], gap_before)

    def _interpolate(self, topic: _Topic, t_keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Values of ``topic`` at base keys ``t_keys`` (linear between its two samples around each, module
        docstring) and where that was possible."""
        keys, values = topic.keys, topic.values
        if keys.size == 0:
            return np.full(t_keys.size, np.nan), np.zeros(t_keys.size, bool)
        hi = np.searchsorted(keys, t_keys, side="left")
        hic = np.minimum(hi, keys.size - 1)
        exact = (hi < keys.size) & (keys[hic] == t_keys)
        loc = np.maximum(hi - 1, 0)
        width = keys[hic] - keys[loc]
        between = (hi > 0) & (hi < keys.size) & (width <= self._bracket)
        frac = (t_keys - keys[loc]) / np.where(width > 0, width, 1)
        value = np.where(exact, values[hic], values[loc] + (values[hic] - values[loc]) * frac)
        return value, exact | between

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
            first, last = t.first_ns, t.last_ns
            span = (last - first) * 1e-9 if first is not None and last is not None else 0.0
            out[signal] = (t.accepted - 1) / span if span > 0 else None
        return out

    def pending(self) -> int:
        """Samples waiting (queued, held for confirmation or in the reorder window), all topics."""
        return sum(t.keys.size + sum(r[0].size for r in t.raw) for t in self._topics.values())
