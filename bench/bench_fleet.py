"""Benchmark of the fleet pipeline: throughput with 1 and 2 Dask worker processes, scaling efficiency.

A synthetic fleet (``fleet.synthetic``, the twin's brake applications) is written
once; then ``run_fleet`` processes it from scratch on a LocalCluster (loopback)
with 1 worker and with 2 workers, in the same run, after a serial baseline
(every unit's task function called in this process, no Dask). Cluster start-up
and the workers' one-time imports (the physics surrogate table) are excluded:
every worker is warmed up with one MonitorCore before the clock starts.
Printed: wall time, units/s and messages/s for each, the Dask overhead
T1 / T_serial, the scaling efficiency T1 / (2 T2), and the per-core cost figure
the fleet cost estimate uses (core-seconds per million input messages). The
machine's load average is printed too: other processes on the cores make the
2-worker figure meaningless.

Run: ``.venv/bin/python bench/bench_fleet.py [--units 16] [--cycles 6] [--rate 500]``
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

from ebm_wear_monitor.bagio import BagReader
from ebm_wear_monitor.fleet.cluster import dask_client
from ebm_wear_monitor.fleet.discover import discover
from ebm_wear_monitor.fleet.pipeline import process_unit, run_fleet
from ebm_wear_monitor.fleet.synthetic import generate_fleet, scenarios
from ebm_wear_monitor.params import load_unit


def warm_up(params) -> None:
    """One MonitorCore per worker: imports and the physics surrogate table of the fleet's unit file
    (cached per parameter set), outside the timing."""
    from ebm_wear_monitor.monitor import MonitorCore

    MonitorCore(params)


def cpu_seconds() -> float:
    """CPU time of this process so far [s] (user + system)."""
    return time.process_time()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--units", type=int, default=16)
    parser.add_argument("--cycles", type=int, default=6, help="brake applications per bag (2 bags per unit)")
    parser.add_argument("--rate", type=float, default=500.0, help="sample rate [Hz]")
    args = parser.parse_args()
    params = load_unit()
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp) / "fleet"
        with dask_client(n_workers=2) as client:
            units = scenarios(args.units, 7, cycles_per_bag=args.cycles, rate_hz=args.rate)
            params, bags = generate_fleet(root, units, params, client=client)
        with BagReader(bags) as reader:
            messages = reader.total
        print(f"fleet: {args.units} units, {len(bags)} bags, {messages} messages at {args.rate:g} Hz")
        warm_up(params)
        units = discover(root)
        t0 = time.perf_counter()
        for folder, bag_files in units.items():
            process_unit(str(root), folder, [b.relpath for b in bag_files], params)
        serial = time.perf_counter() - t0
        print(f"serial   : {serial:6.2f} s, {messages / serial / 1e3:7.1f} k msg/s, "
              f"{serial / messages * 1e6:5.2f} core-s per million messages "
              f"(load average {os.getloadavg()[0]:.1f})")
        times = {}
        for workers in (1, 2):
            with dask_client(n_workers=workers) as client:
                client.run(warm_up, params)
                cpu0 = sum(client.run(cpu_seconds).values())
                t0 = time.perf_counter()
                run = run_fleet(client, root, Path(tmp) / f"out{workers}", params)
                times[workers] = time.perf_counter() - t0
                cpu = sum(client.run(cpu_seconds).values()) - cpu0
            assert len(run.processed) == len(discover(root))
            wall = times[workers]
            print(f"{workers} worker(s): {wall:6.2f} s, {args.units / wall:6.2f} units/s, "
                  f"{messages / wall / 1e3:7.1f} k msg/s, "
                  f"{workers * times[workers] / messages * 1e6:5.2f} core-s per million messages; worker CPU "
                  f"{cpu:.2f} s ({cpu / serial:.2f} of the serial wall time)")
        print(f"Dask overhead T1 / T_serial = {times[1] / serial:.2f}; scaling efficiency 1 -> 2 workers: "
              f"T1 / (2 T2) = {times[1] / (2 * times[2]):.2f} (load average {os.getloadavg()[0]:.1f})")


if __name__ == "__main__":
    main()
