"""Benchmark: the monitor core over a 1 kHz twin recording, whole at once and in node-like chunks.

Prints messages per second (3 input topics) and the cost of one ``process`` call,
as ratios against a floor measured in the same run: sorting every topic's stamps
and gathering the three values at common stamps with numpy (the least any
by-stamp merge of the same messages must do).

    .venv/bin/python bench/bench_monitor_core.py [applications]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from ebm_wear_monitor.domain.signals import MONITOR_SIGNALS as SIGNALS
from ebm_wear_monitor.monitor import MonitorCore
from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.twin import simulate_unit


def _floor(data: dict[str, np.ndarray]) -> float:
    t0 = time.perf_counter()
    keys = {}
    for s in SIGNALS:
        order = np.argsort(data["t"], kind="stable")
        keys[s] = (np.rint(data["t"][order] * 1e9).astype(np.int64), data[s][order])
    common = keys["angle"][0]
    for s in SIGNALS[1:]:
        common = np.intersect1d(common, keys[s][0], assume_unique=True)
    for s in SIGNALS:
        keys[s][1][np.searchsorted(keys[s][0], common)].sum()
    return time.perf_counter() - t0


def _run(unit, data: dict[str, np.ndarray], chunk: int) -> tuple[float, int, int]:
    core = MonitorCore(unit)
    n, calls = data["t"].size, 0
    t0 = time.perf_counter()
    for a in range(0, n, chunk):
        for s in SIGNALS:
            core.add(s, data["t"][a:a + chunk], data[s][a:a + chunk])
        core.process()
        calls += 1
    core.process(final=True)
    return time.perf_counter() - t0, calls, core.snapshot().duty_cycles


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("applications", type=int, nargs="?", default=100, help="brake applications simulated")
    applications = parser.parse_args().applications
    unit = load_unit()
    sim = simulate_unit(unit, applications, seed=1)
    data = {"t": sim.t, "angle": sim.angle, "velocity": sim.velocity, "axial_force": sim.axial_force}
    n = sim.t.size
    _run(unit, {k: v[:5000] for k, v in data.items()}, 5000)  # warm-up: physics surrogate table, imports
    floor = min(_floor(data) for _ in range(3))
    print(f"recording: {applications} applications, {n} samples x 3 topics at 1 kHz")
    print(f"floor (sort + merge by stamp): {3 * n / floor:,.0f} msg/s")
    for label, chunk in (("whole recording", n), ("node-like, 40 samples/topic per call", 40)):
        wall, calls, cycles = _run(unit, data, chunk)
        print(f"{label}: {3 * n / wall:,.0f} msg/s = {floor / wall:.2f} x floor; "
              f"{wall / calls * 1e3:.3f} ms per process call; {cycles} applications")


if __name__ == "__main__":
    main()
