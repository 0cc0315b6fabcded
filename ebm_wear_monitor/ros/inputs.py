"""Input buffering of the node: raw CDR records in, a :class:`~ebm_wear_monitor.monitor.wire.Batch` out.

At 3 x 1 kHz the Python cost per message decides whether the node keeps up
(measured with rclpy Kilted: 11-13 us per callback with the EventsExecutor,
80 us with the SingleThreadedExecutor). So the subscriptions are ``raw=True``
and their callback is ``list.append`` of the serialised record (no message
object is built); a timer drains the lists at ``process_rate_hz`` and decodes
each batch at once with :func:`ebm_wear_monitor.monitor.wire.decode_records`,
the decoder the replay uses on storage records, so both hand the core the same
int64 ns stamps and float64 values.

A record the bulk decoder does not recognise goes through rclpy's own
deserializer (the replay uses rosbags' there); one that neither decodes is
dropped and counted ``undecodable`` in the batch (the core counts it), the rest
of its batch is kept.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ebm_wear_monitor.monitor.wire import Batch, Decoded, decode_records, stamp_ns


def _general(decoded: Decoded, raws: list[bytes]) -> None:
    """Records the bulk decoder did not recognise, through rclpy's deserializer (in place)."""
    if decoded.ok.all():
        return
    from ebm_wear_msgs.msg import Float64Stamped
    from rclpy.serialization import deserialize_message

    for i in np.flatnonzero(~decoded.ok).tolist():
        try:
            msg = deserialize_message(raws[i], Float64Stamped)
        except Exception:  # any deserializer failure means an undecodable record
            continue
        decoded.stamps_ns[i] = int(stamp_ns(msg.header.stamp.sec, msg.header.stamp.nanosec))
        decoded.values[i] = msg.data
        decoded.ok[i] = True


@dataclass
class InputBuffer:
    """One input topic: pending raw records and arrival statistics."""

    signal: str  # signal name of interface.md section 4 (angle, velocity, axial_force)
    pending: list[bytes] = field(default_factory=list)
    received: int = 0  # messages drained so far [-]
    last_arrival: float = -np.inf  # time.monotonic() of the last drain that found messages [s]
    _rate_count: int = 0
    _rate_since: float = field(default_factory=time.monotonic)

    def drain(self, into: Batch) -> None:
        """Take every pending record, decoded, into ``into`` (arrival order; undecodable ones counted)."""
        if not self.pending:
            return
        raws = self.pending.copy()  # the subscription's callback is this list's bound ``append``
        self.pending.clear()
        self.received += len(raws)
        self._rate_count += len(raws)
        self.last_arrival = time.monotonic()
        decoded = decode_records(raws)
        _general(decoded, raws)
        into.add(self.signal, decoded.stamps_ns[decoded.ok], decoded.values[decoded.ok])
        into.count(self.signal, "undecodable", int(decoded.ok.size - np.count_nonzero(decoded.ok)))

    def rate_hz(self) -> float:
        """Mean arrival rate since the previous call [Hz] (resets the window)."""
        now = time.monotonic()
        rate = self._rate_count / max(now - self._rate_since, 1e-9)
        self._rate_count, self._rate_since = 0, now
        return rate

    def age_s(self) -> float:
        """Time since messages last arrived [s]; inf before the first."""
        return time.monotonic() - self.last_arrival
