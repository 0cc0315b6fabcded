"""Input buffering of the node: raw CDR records in, numpy arrays of (stamp [s], value) out.

At 3 x 1 kHz the Python cost per message decides whether the node keeps up
(``shared/notes/environment.md``: 11-13 us per callback with the EventsExecutor,
80 us with the SingleThreadedExecutor). So the subscriptions are ``raw=True``
and their callback is ``list.append`` of the serialised record (no message
object is built); a timer drains the lists at ``process_rate_hz`` and decodes
each batch at once with ``bagio.cdr.decode_float64_stamped``, the decoder the
offline replay uses, so both hand the monitor core bit-identical floats.

A record that cannot be decoded (corrupt, or written by a foreign definition
of the type) is dropped and counted as ``undecodable``; the rest of its batch
is kept.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ebm_wear_monitor.bagio.cdr import decode_float64_stamped


@dataclass
class InputBuffer:
    """One input topic: pending raw records and arrival statistics."""

    signal: str  # signal name of interface.md section 4 (angle, velocity, axial_force)
    pending: list[bytes] = field(default_factory=list)
    received: int = 0  # messages drained so far [-]
    undecodable: int = 0  # records that failed to decode [-]
    last_arrival: float = -np.inf  # time.monotonic() of the last drain that found messages [s]
    _rate_count: int = 0
    _rate_since: float = field(default_factory=time.monotonic)

    def drain(self) -> tuple[np.ndarray, np.ndarray]:
        """Take every pending record; returns (header stamps [s], values), in arrival order."""
        if not self.pending:
            return np.empty(0), np.empty(0)
        batch = self.pending.copy()  # the subscription's callback is this list's bound ``append``
        self.pending.clear()
        self.received += len(batch)
        self._rate_count += len(batch)
        self.last_arrival = time.monotonic()
        try:
            return decode_float64_stamped(batch)
        except Exception:  # a corrupt record spoils the bulk decode: decode one by one, drop the bad
            good = []
            for raw in batch:
                try:
                    good.append(decode_float64_stamped([raw]))
                except Exception:
                    self.undecodable += 1
            if not good:
                return np.empty(0), np.empty(0)
            return np.concatenate([g[0] for g in good]), np.concatenate([g[1] for g in good])

    def rate_hz(self) -> float:
        """Mean arrival rate since the previous call [Hz] (resets the window)."""
        now = time.monotonic()
        rate = self._rate_count / max(now - self._rate_since, 1e-9)
        self._rate_count, self._rate_since = 0, now
        return rate

    def age_s(self) -> float:
        """Time since messages last arrived [s]; inf before the first."""
        return time.monotonic() - self.last_arrival
