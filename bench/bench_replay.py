"""Benchmark of ``ebm-wear replay`` end to end against reading the same bag's raw messages, same run.

A bag of the three monitor topics at 1 kHz (brake applications of the digital
twin, tiled to ``--seconds`` of data) is written in sqlite3 and in mcap storage.
For each, on one core, in the same run:

* raw read: ``rosbags`` ``Reader.messages()`` over every message, bytes only, no
  decoding: the floor any replay must stand on (the baseline);
* raw read, GC paused: the same with Python's cyclic garbage collector paused, as
  the bulk reader does while records stream in (a stricter baseline, also printed);
* general decode: the same plus ``typestore.deserialize_cdr`` per message (one
  Python object per message, what a naive replay would do);
* bulk read: ``bagio.read_bags`` (raw records decoded in bulk with numpy);
* replay: ``replay.run.replay_bags`` = bulk read + the monitor core + per-application
  history, i.e. ``ebm-wear replay`` without printing.

Printed: messages per second of each and the ratios replay / raw read (issue 6
target: >= 0.25) and replay / raw read with GC paused. Best of ``--repeat`` runs each.

Run: ``.venv/bin/python bench/bench_replay.py [--seconds 300] [--repeat 3]``
"""

from __future__ import annotations

import argparse
import gc
import tempfile
import time
from pathlib import Path

import numpy as np
from rosbags.rosbag2 import Reader

from ebm_wear_monitor.bagio import FLOAT64_STAMPED, read_bags, typestore, write_unit_bag
from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.replay.run import replay_bags
from ebm_wear_monitor.twin import simulate_unit

SIGNALS = ("angle", "velocity", "axial_force")


def make_signals(seconds: float, unit) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Twin brake applications at 1 kHz, tiled (angle continued) to ``seconds`` of data."""
    sim = simulate_unit(unit, 16, rate_hz=1000.0, hold_s=(0.5, 1.0), rest_s=0.5)
    reps = int(np.ceil(seconds / (len(sim.t) * 1e-3)))
    n = len(sim.t) * reps
    t = 1.7e9 + np.arange(n) * 1e-3
    signals = {k: np.tile(getattr(sim, k), reps) for k in SIGNALS}
    return t[: int(seconds * 1000)], {k: v[: int(seconds * 1000)] for k, v in signals.items()}


def best(fn, repeat: int) -> tuple[float, object]:
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def raw_read(bag: Path) -> int:
    with Reader(bag) as reader:
        return sum(1 for _ in reader.messages())


def raw_read_gc_paused(bag: Path) -> int:
    gc.disable()
    try:
        return raw_read(bag)
    finally:
        gc.enable()


def general_decode(bag: Path) -> int:
    store = typestore()
    with Reader(bag) as reader:
        return sum(1 for _, _, raw in reader.messages() if store.deserialize_cdr(raw, FLOAT64_STAMPED))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=300.0, help="seconds of 1 kHz data (3 topics)")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    unit = load_unit()
    t, signals = make_signals(args.seconds, unit)
    print(f"bag: {len(t)} samples x {len(signals)} topics = {len(t) * len(signals)} messages, 1 kHz")
    with tempfile.TemporaryDirectory() as tmp:
        for storage in ("sqlite3", "mcap"):
            bag = Path(tmp) / storage
            write_unit_bag(bag, t, {"/embu": signals}, storage=storage)
            n_raw_s, n = best(lambda b=bag: raw_read(b), args.repeat)
            nogc_s, _ = best(lambda b=bag: raw_read_gc_paused(b), args.repeat)
            gen_s, _ = best(lambda b=bag: general_decode(b), 1)
            bulk_s, rec = best(lambda b=bag: read_bags([b]), args.repeat)
            replay_s, res = best(lambda b=bag: replay_bags([b], unit), args.repeat)
            assert rec.messages == n
            raw, nogc, gen, bulk, rep = n / n_raw_s, n / nogc_s, n / gen_s, n / bulk_s, n / replay_s
            cycles = res.units[0].summary["duty_cycles"]
            print(f"{storage}: raw read {raw / 1e3:.0f} k msg/s (GC paused {nogc / 1e3:.0f} k) | general "
                  f"decode {gen / 1e3:.0f} k ({gen / raw:.2f}) | bulk read {bulk / 1e3:.0f} k "
                  f"({bulk / raw:.2f}) | replay {rep / 1e3:.0f} k msg/s, {cycles} applications\n"
                  f"    replay / raw read = {rep / raw:.2f} (target >= 0.25); replay / raw read with GC "
                  f"paused = {rep / nogc:.2f}")


if __name__ == "__main__":
    main()
