"""Benchmark of the foreign-world generator: where the time of one recording goes.

For a few cases of a set, ``write_case`` reports the seconds of each stage: simulation (plant and
ECU at 10 kHz, every application of the recording in one batch), acquisition (clocks, sensors,
estimators, truth) and bag writing (CDR records in bulk, rosbags' Writer). The baseline, measured
in the same run, is rosbags' Writer alone writing the same number of ready-made records to the
same storage: the floor of any generator that writes through rosbags. Printed per case: messages,
seconds per stage (wall), total, the process CPU time, and total / baseline. The load average is
printed too: other processes on the cores inflate every wall figure (the CPU column less so).

Run: ``.venv/bin/python bench/bench_foreign.py [--set quick] [--cases 6]``
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import time
from pathlib import Path

from rosbags.rosbag2 import Writer

from ebm_wear_monitor.validation.foreign import case_set, write_case
from ebm_wear_monitor.validation.foreign.bag import MSGTYPE, storage_plugin, typestore


def _baseline(path: Path, storage: str, count: int) -> float:
    """rosbags' Writer alone: ``count`` 40-byte records round-robin on four connections."""
    ts = typestore()
    record = bytes(40)
    t0 = time.perf_counter()
    with Writer(path, version=9, storage_plugin=storage_plugin(storage)) as writer:
        conns = [writer.add_connection(f"/b/t{k}", MSGTYPE, typestore=ts) for k in range(4)]
        for j in range(count):
            writer.write(conns[j % 4], 1000 * j, record)
    return time.perf_counter() - t0


def main() -> None:
    """Time the stages of a few recordings against the writer-only baseline."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--set", default="quick", dest="set_name")
    parser.add_argument("--cases", type=int, default=6)
    args = parser.parse_args()
    print(f"load average {os.getloadavg()[0]:.2f}")
    print(f"{'case':44s} {'apps':>4s} {'msgs':>8s} {'sim':>6s} {'acq':>6s} {'write':>6s} "
          f"{'total':>6s} {'cpu':>6s} {'floor':>6s} {'ratio':>6s}")
    totals = []
    with tempfile.TemporaryDirectory() as tmp:
        for case in case_set(args.set_name)[:args.cases]:
            t = {}
            cpu = time.process_time()
            path = write_case(case, tmp, timings=t)
            cpu = time.process_time() - cpu
            (unit,) = json.loads((path / "ground_truth.json").read_text())["units"].values()
            floor = _baseline(Path(tmp) / f"{case.case_id}.floor", unit["foreign"]["storage"],
                              int(t["messages"]))
            total = t["simulate"] + t["acquire"] + t["write"]
            totals.append((total, cpu))
            print(f"{case.case_id:44s} {case.n_apps:4d} {int(t['messages']):8d} {t['simulate']:6.2f} "
                  f"{t['acquire']:6.2f} {t['write']:6.2f} {total:6.2f} {cpu:6.2f} {floor:6.2f} "
                  f"{total / floor:6.2f}")
    wall, cpu = (sum(x) / len(totals) for x in zip(*totals, strict=True))
    print(f"mean {wall:.2f} s wall, {cpu:.2f} s CPU per recording")


if __name__ == "__main__":
    main()
