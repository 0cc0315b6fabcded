"""Benchmark of ``ebm-wear replay`` end to end against rosbags' raw iteration of the same bag, same run.

A bag of the three monitor topics at 1 kHz (brake applications of the digital
twin, tiled) is written in sqlite3 and in mcap storage (by rosbags' writer), in
two shapes (``--shape``):

* ``issue``: the recording issue 12 measured, 2.2 M messages holding 200 brake
  applications (about 11 k messages per application: 1 s of motion and hold,
  2.7 s of rest);
* ``dense``: a stress case, 1.2 M messages holding 263 applications (4.5 k
  messages per application: 0.5 s of rest), where the monitor core's work per
  application (filter bank, remaining-life quantiles, clearance observation)
  weighs 2.4x more per message.

For each, in one process, in the same run, best of ``--repeat``:

* raw read (the baseline): ``rosbags`` ``Reader.messages()`` over every message,
  bytes only, no decoding: what any replay built on rosbags stands on;
* bulk read: ``bagio.BagReader`` alone (storage chunks decoded by ``monitor.wire``);
* replay: ``replay.run.replay_bags`` = streaming read + the monitor core through
  its Feeder + per-application history, i.e. ``ebm-wear replay`` without printing
  (warm: the wear model's table is built once before timing); and the same with
  ``read_ahead=0`` (everything in one thread, as a fleet worker reads).

Printed: messages per second of each and the ratio replay / raw read (issue 12
target: >= 1.5 on both storages), from wall time and from the process's CPU time.
rosbags' raw read runs on one core. The replay (and the bulk read) read sqlite3
storage a few chunks ahead in a worker thread (``bagio.ahead``) that overlaps
sqlite3's work, which releases the interpreter lock, with the monitor core: on
two or more cores its wall time is what a user waits; its CPU time (both
threads) is what it costs a machine shared with other jobs. A process allowed
one core only reads in one thread (``bagio.ahead.spare_core``), so the
one-thread figure is the one-core figure. mcap is read in one thread either way.

``--memory`` instead measures peak RSS of ``ebm-wear replay`` (a fresh process
each) on recordings of two lengths written block by block (``--memory-messages``,
default 2 M and 20 M messages): issue 12 target < 400 MB for any length, the same
at both lengths.

Run: ``.venv/bin/python bench/bench_replay.py [--shape issue dense] [--repeat 3]``
     ``.venv/bin/python bench/bench_replay.py --memory [--storage sqlite3]``
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from rosbags.rosbag2 import Reader

from ebm_wear_monitor.bagio import BagReader, BagWriter, Series, write_unit_bag
from ebm_wear_monitor.domain.signals import MONITOR_SIGNALS as SIGNALS
from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.replay.run import replay_bags
from ebm_wear_monitor.twin import simulate_unit

T0_NS = 1_700_000_000_000_000_000
#: bag shapes: (seconds of 1 kHz data, rest after each application [s])
SHAPES = {"issue": (733.0, 2.7), "dense": (400.0, 0.5)}


def twin_period(unit, rest_s: float = 0.5) -> dict[str, np.ndarray]:
    """16 twin brake applications at 1 kHz (angle, velocity, force), ``rest_s`` [s] of rest after each."""
    sim = simulate_unit(unit, 16, rate_hz=1000.0, hold_s=(0.5, 1.0), rest_s=rest_s)
    return {k: getattr(sim, k) for k in SIGNALS}


def tiled(period: dict[str, np.ndarray], start: int, n: int) -> dict[str, np.ndarray]:
    """Samples ``start .. start + n`` of the period repeated for ever (angle continued per period)."""
    size = len(period["angle"])
    idx = np.arange(start, start + n)
    return {k: v[idx % size] for k, v in period.items()}


def best(fn, repeat: int) -> tuple[float, float, object]:
    """(best wall time [s], best CPU time of this process [s], result) of ``repeat`` runs."""
    walls, cpus, out = [], [], None
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        out = fn()
        walls.append(time.perf_counter() - t0)
        cpus.append(time.process_time() - c0)
    return min(walls), min(cpus), out


def raw_read(bag: Path) -> int:
    with Reader(bag) as reader:
        return sum(1 for _ in reader.messages())


def bulk_read(bag: Path) -> int:
    with BagReader([bag], signals=SIGNALS) as reader:
        return sum(s.size for batches in reader.batches() for b in batches.values()
                   for s, _ in b.signals.values())


def ratios(args) -> None:
    unit = load_unit()
    for shape in args.shape:
        seconds, rest_s = SHAPES[shape]
        n = int(seconds * 1000)
        signals = tiled(twin_period(unit, rest_s), 0, n)
        t = T0_NS + np.arange(n, dtype=np.int64) * 1_000_000
        print(f"{shape} bag: {n} samples x {len(signals)} topics = {n * len(signals)} messages, 1 kHz, "
              f"{rest_s} s rest after each application")
        one_shape(unit, t, signals, args.repeat)


def one_shape(unit, t: np.ndarray, signals: dict[str, np.ndarray], repeat: int) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        for storage in ("sqlite3", "mcap"):
            bag = Path(tmp) / storage
            write_unit_bag(bag, t, {"/embu": signals}, storage=storage)
            replay_bags([bag], unit)  # warm: wear-model table, imports
            raw_s, raw_cpu, count = best(lambda b=bag: raw_read(b), repeat)
            bulk_s, _, got = best(lambda b=bag: bulk_read(b), repeat)
            rep_s, rep_cpu, res = best(lambda b=bag: replay_bags([b], unit), repeat)
            one_s, one_cpu, _ = best(lambda b=bag: replay_bags([b], unit, read_ahead=0), repeat)
            assert got == count, (got, count)
            raw, bulk, rep, one = count / raw_s, count / bulk_s, count / rep_s, count / one_s
            print(f"{storage}: raw read (rosbags) {raw / 1e3:.0f} k msg/s | bulk read {bulk / 1e3:.0f} k "
                  f"msg/s ({bulk / raw:.2f}x) | replay {rep / 1e3:.0f} k msg/s, "
                  f"{res.units[0].snapshot.duty_cycles} applications\n"
                  f"    replay / raw read = {rep / raw:.2f} wall time, {raw_cpu / rep_cpu:.2f} CPU time "
                  "(target >= 1.5)\n"
                  f"    without read-ahead (one thread, as on one core): {one / raw:.2f} wall, "
                  f"{raw_cpu / one_cpu:.2f} CPU")


def write_long(path: Path, messages: int, storage: str, unit) -> int:
    """A recording of ``messages`` messages (3 topics at 1 kHz), written block by block."""
    period = twin_period(unit)
    n = messages // 3
    topics = [("/embu", s) for s in SIGNALS]
    writer = BagWriter(path, topics, storage=storage)
    block = 600_000
    for start in range(0, n, block):
        m = min(block, n - start)
        t = T0_NS + (start + np.arange(m, dtype=np.int64)) * 1_000_000
        writer.write({("/embu", s): Series(t, v) for s, v in tiled(period, start, m).items()})
    return writer.close()


def peak_rss_mb(bag: Path) -> tuple[float, float]:
    """(peak RSS [MB], wall time [s]) of ``ebm-wear replay BAG --no-progress`` in a fresh process.

    The peak is the child's own ``VmHWM`` (high-water mark of its address space): ``ru_maxrss`` would
    carry this (large) benchmark process's mark over into the child across fork and exec.
    """
    script = ("import sys; from ebm_wear_monitor.cli.main import main; rc = main(sys.argv[1:]); "
              "print(next(l for l in open('/proc/self/status') if l.startswith('VmHWM')), file=sys.stderr); "
              "sys.exit(rc)")
    t0 = time.perf_counter()
    done = subprocess.run([sys.executable, "-c", script, "replay", str(bag), "--no-progress"],
                          capture_output=True, text=True, check=True)
    wall = time.perf_counter() - t0
    peak = next(line for line in done.stderr.splitlines() if line.startswith("VmHWM"))
    return int(peak.split()[1]) / 1024.0, wall


def memory(args) -> None:
    unit = load_unit()
    with tempfile.TemporaryDirectory(dir=args.tmp) as tmp:
        for storage in args.storage:
            peaks = []
            for messages in args.memory_messages:
                bag = Path(tmp) / f"{storage}_{messages}"
                t0 = time.perf_counter()
                written = write_long(bag, messages, storage, unit)
                size = sum(f.stat().st_size for f in bag.iterdir()) / 1e9
                rss, wall = peak_rss_mb(bag)
                peaks.append(rss)
                took = time.perf_counter() - t0
                print(f"{storage}: {written} messages ({size:.2f} GB, written in {took:.0f} s):"
                      f" replay peak RSS {rss:.0f} MB, {wall:.1f} s ({written / wall / 1e6:.2f} M msg/s)")
                shutil.rmtree(bag)
            print(f"{storage}: peak RSS {peaks[-1]:.0f} MB at {args.memory_messages[-1]} messages vs "
                  f"{peaks[0]:.0f} MB at {args.memory_messages[0]}: ratio {peaks[-1] / peaks[0]:.2f} "
                  "(target: < 400 MB, not growing with length)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--shape", nargs="+", default=list(SHAPES), choices=list(SHAPES),
                        help="bag shapes (module docstring)")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--memory", action="store_true", help="peak RSS at two lengths instead of speed")
    parser.add_argument("--memory-messages", type=int, nargs=2, default=[2_000_000, 20_000_000])
    parser.add_argument("--storage", nargs="+", default=["sqlite3", "mcap"], choices=["sqlite3", "mcap"])
    parser.add_argument("--tmp", default=None, help="directory for the long recordings (default: system tmp)")
    args = parser.parse_args()
    memory(args) if args.memory else ratios(args)


if __name__ == "__main__":
    main()
