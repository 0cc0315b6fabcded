"""One unit's recording: per input signal, the header stamps (int64 ns, exact) and the values (float64).

This is what a unit's recorder holds and what every reader of recorded data starts from: the bag
reader fills it (:func:`ebm_wear_monitor.bagio.read_bags`), the player publishes it, the replay
feeds it to the monitor core, the diagnosis screens and resamples it. Each signal keeps its own
stamps in the order the samples were recorded (late, duplicated and interleaved samples as they
came); nothing is aligned or resampled here. Signal names and units are those of
:mod:`.signals` (interface.md sections 2 and 4).

Stamps are ``header.stamp`` in int64 nanoseconds (``sec * 1e9 + nanosec``). Float seconds are a
view for plots and the diagnosis (:attr:`Signal.stamps`, :meth:`Recording.seconds`), never the
monitor core's time base.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ebm_wear_monitor.arrays import FloatArray, IntArray

#: seconds per nanosecond of a stamp
S_PER_NS = 1e-9


@dataclass(frozen=True)
class Signal:
    """One input signal of one unit: header stamps [ns] (int64) and values [SI unit of the topic]."""

    stamps_ns: IntArray
    values: FloatArray

    @property
    def stamps(self) -> FloatArray:
        """Header stamps [s] (float64: for plots and the diagnosis, not for the monitor core)."""
        return (self.stamps_ns * S_PER_NS).astype(np.float64, copy=False)


@dataclass
class Recording:
    """Everything recorded of one unit (namespace): its signals, where they came from, what was lost.

    ``signals``: signal name -> :class:`Signal`; ``bags``: the bags they were read from, in time
    order (empty for data that never was in a bag); ``faults``: per signal, records counted but not
    delivered (``undecodable``, ``lost``: ``{signal: {kind: n}}``).
    """

    unit: str
    signals: dict[str, Signal]
    bags: list[Path] = field(default_factory=list)
    faults: dict[str, dict[str, int]] = field(default_factory=dict)

    @property
    def messages(self) -> int:
        """Number of input messages of this unit."""
        return sum(int(s.stamps_ns.size) for s in self.signals.values())

    def seconds(self) -> dict[str, tuple[FloatArray, FloatArray]]:
        """The float-seconds view: ``{signal: (stamps [s], values)}`` (the diagnosis' input)."""
        return {name: (s.stamps, s.values) for name, s in self.signals.items()}
