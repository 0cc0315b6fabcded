"""Read-ahead: a storage's chunks read by a worker thread while the caller works on the previous ones.

Reading a chunk of a storage whose reads run outside Python's global
interpreter lock (sqlite3 stepping through rows and concatenating their blobs:
``Storage.reads_outside_lock``) overlaps, on a machine with a second core, with
the monitor core that consumes the chunks: the replay's wall time tends to
max(read, core) instead of read + core. The price is CPU time: the two threads
contend for the lock (about 10 % more on sqlite3; on mcap, whose chunks are
parsed in Python, 30 % more for no gain, so it is not read ahead). (rosbag2's
own player reads ahead into a queue the same way.) A process allowed less than two
cores (its affinity or its cgroup's CPU quota: :func:`spare_core`) would pay the
contention and gain nothing: the reader then reads in the caller's thread.

Memory stays bounded: at most ``depth`` chunks wait in the queue, plus the one
being read. Order is the storage's order (one producer, a FIFO queue). An
exception raised while reading reaches the caller at the point of the chunk
that failed; a caller that stops early (``close``, ``break``, an exception of
its own) stops the worker and the storage's generator before it returns.
"""

from __future__ import annotations

import math
import os
import queue
import threading
from collections.abc import Generator, Iterator
from pathlib import Path
from typing import TypeVar

T = TypeVar("T")

_END = object()  # the worker's last item: the storage is exhausted (or failed: the exception follows)
_POLL_S = 0.05  # how often a worker blocked on a full queue checks whether the caller stopped [s]


def spare_core() -> bool:
    """Whether this thread may use two cores or more: its CPU affinity (else the CPU count) and the CPU
    quota of its cgroup (a container limited to ``--cpus=1`` sees every core of the host)."""
    cores = float(len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1)
    return min(cores, _cgroup_cpus()) >= 2.0


def _cgroup_cpus(root: Path = Path("/sys/fs/cgroup")) -> float:
    """CPUs the cgroup quota allows (v2 ``cpu.max``: ``quota period``; v1 ``cpu/cpu.cfs_quota_us`` and
    ``cpu/cpu.cfs_period_us``); infinite when there is none or it cannot be read."""
    v1 = root / "cpu"
    for files in ((root / "cpu.max",), (v1 / "cpu.cfs_quota_us", v1 / "cpu.cfs_period_us")):
        try:
            quota, period = (" ".join(f.read_text() for f in files)).split()[:2]
            allowed = math.inf if quota in ("max", "-1") else float(quota) / float(period)
        except (OSError, ValueError, ZeroDivisionError):
            continue
        return allowed if allowed > 0.0 else math.inf
    return math.inf


def read_ahead(items: Iterator[T], depth: int = 2) -> Generator[T, None, None]:
    """Yield ``items`` in order, produced by a worker thread up to ``depth`` items ahead (module doc);
    ``depth`` 0: read in the caller's thread."""
    if depth <= 0:
        yield from items
        return
    box: queue.Queue[tuple[object, BaseException | None]] = queue.Queue(maxsize=depth)
    stop = threading.Event()

    def put(entry: tuple[object, BaseException | None]) -> bool:
        while not stop.is_set():
            try:
                box.put(entry, timeout=_POLL_S)
                return True
            except queue.Full:
                continue
        return False

    def work() -> None:
        try:
            for item in items:
                if not put((item, None)):
                    return
            put((_END, None))
        except BaseException as exc:  # handed to the caller, who raises it where the chunk was due
            put((_END, exc))
        finally:
            close = getattr(items, "close", None)
            if close is not None:
                close()

    worker = threading.Thread(target=work, name="bag-read-ahead", daemon=True)
    try:
        worker.start()
        while True:
            item, exc = box.get()
            if item is _END:
                if exc is not None:
                    raise exc
                return
            yield item  # type: ignore[misc]  # every other entry is an item of ``items``
    finally:
        stop.set()
        if worker.is_alive():
            worker.join()
