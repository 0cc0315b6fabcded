"""The read-ahead worker: same items in the same order, errors where they happened, early stops clean up."""

from __future__ import annotations

import math
import os
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from ebm_wear_monitor.bagio import BagReader, write_unit_bag
from ebm_wear_monitor.bagio.ahead import _cgroup_cpus, read_ahead, spare_core
from ebm_wear_monitor.bagio.storage import SQLITE_BLOCK


def _workers() -> int:
    return sum(t.name == "bag-read-ahead" and t.is_alive() for t in threading.enumerate())


def test_items_arrive_in_order_and_nothing_is_lost() -> None:
    assert list(read_ahead(iter(range(1000)), depth=3)) == list(range(1000))
    assert list(read_ahead(iter([]))) == []


def test_an_error_while_reading_reaches_the_caller_after_the_items_before_it() -> None:
    def source() -> Iterator[int]:
        yield 1
        yield 2
        raise OSError("disk gone")

    before = _workers()
    got = []
    with pytest.raises(OSError, match="disk gone"):
        for item in read_ahead(source()):
            got.append(item)
    assert got == [1, 2]
    assert _workers() == before


def test_an_early_stop_stops_the_worker_and_closes_the_source() -> None:
    closed = threading.Event()
    produced = []

    def source() -> Iterator[int]:
        try:
            for i in range(10_000):
                produced.append(i)
                yield i
        finally:
            closed.set()

    before = _workers()
    stream = read_ahead(source(), depth=2)
    assert [next(stream) for _ in range(3)] == [0, 1, 2]
    stream.close()
    assert closed.is_set()
    assert _workers() == before
    assert len(produced) <= 3 + 2 + 1  # taken + queued + the one being put: memory stays bounded


def test_the_reading_overlaps_the_callers_work() -> None:
    """Reading that releases the interpreter lock (sleep stands for sqlite3) runs while the caller works:
    8 items of 50 ms reading and 50 ms work take about 0.45 s read ahead, 0.8 s in one thread."""

    def source() -> Iterator[int]:
        for i in range(8):
            time.sleep(0.05)
            yield i

    def took(depth: int) -> float:
        t0 = time.perf_counter()
        for _ in read_ahead(source(), depth):
            time.sleep(0.05)
        return time.perf_counter() - t0

    serial = took(0)
    assert serial >= 0.8
    assert took(2) < 0.75 * serial


def test_depth_zero_reads_in_the_callers_thread() -> None:
    seen = []

    def source() -> Iterator[int]:
        for i in range(5):
            seen.append(threading.current_thread().name)
            yield i

    assert list(read_ahead(source(), depth=0)) == list(range(5))
    assert set(seen) == {threading.current_thread().name}


@pytest.mark.skipif(not hasattr(os, "sched_setaffinity") or len(os.sched_getaffinity(0)) < 2,
                    reason="needs a process affinity of two cores or more to narrow")
def test_a_process_on_one_core_reads_sqlite3_in_its_own_thread(tmp_path: Path) -> None:
    """Read ahead, one core would pay the threads' contention for nothing: the reader reads in the
    caller's thread when the process is allowed one core only, and ahead when it has two."""
    n = SQLITE_BLOCK  # three storage chunks (blocks of row ids) of the three topics
    t = 1_700_000_000_000_000_000 + np.arange(n, dtype=np.int64) * 1_000_000
    values = {"angle": np.linspace(0.0, 1.0, n), "velocity": np.zeros(n), "axial_force": np.ones(n)}
    write_unit_bag(tmp_path / "bag", t, {"/embu": values}, storage="sqlite3")

    def most_workers() -> int:
        with BagReader([tmp_path / "bag"], signals=set(values)) as reader:
            return max(_workers() for _ in reader.batches())

    cores = os.sched_getaffinity(0)
    assert most_workers() >= 1
    os.sched_setaffinity(0, {min(cores)})
    try:
        assert not spare_core()
        assert most_workers() == 0
    finally:
        os.sched_setaffinity(0, cores)


def test_a_cgroup_cpu_quota_counts_as_the_cores_it_allows(tmp_path: Path) -> None:
    """A container limited to one CPU sees every core of its host in its affinity: the quota decides."""
    (tmp_path / "cpu.max").write_text("100000 100000\n")
    assert _cgroup_cpus(tmp_path) == 1.0
    (tmp_path / "cpu.max").write_text("max 100000\n")
    assert _cgroup_cpus(tmp_path) == math.inf
    (tmp_path / "cpu.max").unlink()
    (tmp_path / "cpu").mkdir()
    (tmp_path / "cpu" / "cpu.cfs_quota_us").write_text("250000\n")
    (tmp_path / "cpu" / "cpu.cfs_period_us").write_text("100000\n")
    assert _cgroup_cpus(tmp_path) == 2.5
    (tmp_path / "cpu" / "cpu.cfs_quota_us").write_text("-1\n")
    assert _cgroup_cpus(tmp_path) == math.inf
    assert _cgroup_cpus(tmp_path / "absent") == math.inf
