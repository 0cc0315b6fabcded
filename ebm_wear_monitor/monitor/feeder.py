"""The one way records enter the core: batches in, events (applications with snapshots) out.

The live node's timer (records drained from its subscriptions, decoded by
:mod:`.wire`) and the replay's reader (records sliced from storage chunks,
decoded by :mod:`.wire`) both hand :class:`~.wire.Batch` es to a
:class:`Feeder`; it queues every signal into the :class:`~.core.MonitorCore`,
counts what was lost before decoding, and lets the core release what alignment
allows. The core's decisions depend only on each topic's own arrival order and
values (see :mod:`.alignment`), and a snapshot is taken inside the core right
after each application, so node and replay produce the same events from the
same records however the batches are cut: by construction, not by a test of
two loops.
"""

from __future__ import annotations

from ebm_wear_monitor.monitor.core import Application, MonitorCore
from ebm_wear_monitor.monitor.wire import Batch


class Feeder:
    """Drives one :class:`MonitorCore` with batches of decoded records.

    ``feed(batch)`` returns the applications the batch completed (each with the
    snapshot right after it); ``finish()`` releases everything at the end of the
    data (replay; the node never finishes: what is pending at shutdown is simply
    not yet integrated, and a restart resumes from the saved state). ``messages``
    counts the records handed in (decoded or not).
    """

    def __init__(self, core: MonitorCore) -> None:
        self.core = core
        self.messages = 0

    def _queue(self, batch: Batch) -> None:
        for signal, (stamps_ns, values) in batch.signals.items():
            self.core.add(signal, stamps_ns, values)
            self.messages += int(stamps_ns.size)
        for signal, per in batch.faults.items():
            for kind, n in per.items():
                self.core.count(signal, kind, n)
                self.messages += int(n) if kind == "undecodable" else 0

    def feed(self, batch: Batch) -> list[Application]:
        """Queue ``batch`` and return the applications that alignment could complete now."""
        self._queue(batch)
        return self.core.process_events(final=False)

    def finish(self, batch: Batch | None = None) -> list[Application]:
        """Queue a last ``batch`` (if any) and release everything: the end of the data."""
        if batch is not None:
            self._queue(batch)
        return self.core.process_events(final=True)
