"""Replay vs rosbags' raw iteration on recordings of the independent foreign generator, same run.

``bench_replay.py`` writes its bags with the project's own twin and writer. This bench times the
same two things on bags of :mod:`ebm_wear_monitor.validation.foreign` (its own plant, controller
and sensors; topics at different rates with their own stamps, non-empty frame_ids, namespaces,
sqlite3 and mcap): every ``--every``-th case directory under ``DIR``, laid out as the foreign
self-test writes them (``DIR/<case>/<case>/metadata.yaml``), best of ``--repeat``. Printed per
bag and as medians per storage: replay / raw read with read-ahead (the default) and in one thread.

Run: ``.venv/bin/python bench/bench_replay_foreign.py DIR [--every 4] [--repeat 3]``
"""

from __future__ import annotations

import argparse
import statistics
from pathlib import Path

import yaml

# the same timing and baseline as the twin-bag bench (bench/ is sys.path[0] when run as a script)
from bench_replay import best, raw_read

from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.replay.run import replay_bags


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dir", type=Path)
    parser.add_argument("--every", type=int, default=4)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    unit = load_unit()
    ratios: dict[str, list[tuple[float, float]]] = {}
    for meta in sorted(args.dir.glob("*/*/metadata.yaml"))[::args.every]:
        bag = meta.parent
        info = yaml.safe_load(meta.read_text())["rosbag2_bagfile_information"]
        storage, count = info["storage_identifier"], info["message_count"]
        replay_bags([bag], unit)  # warm
        raw = best(lambda b=bag: raw_read(b), args.repeat)[0]
        ahead = best(lambda b=bag: replay_bags([b], unit), args.repeat)[0]
        one = best(lambda b=bag: replay_bags([b], unit, read_ahead=0), args.repeat)[0]
        ratios.setdefault(storage, []).append((raw / ahead, raw / one))
        print(f"{bag.name:48s} {storage:7s} {count:8d} msgs  raw {raw:.3f} s  replay {ahead:.3f} s "
              f"({raw / ahead:.2f}x)  one thread {one:.3f} s ({raw / one:.2f}x)")
    for storage, pairs in ratios.items():
        ahead_r, one_r = [a for a, _ in pairs], [o for _, o in pairs]
        print(f"{storage}: {len(pairs)} bags, replay / raw read median {statistics.median(ahead_r):.2f} "
              f"({min(ahead_r):.2f}-{max(ahead_r):.2f}), one thread {statistics.median(one_r):.2f} "
              f"({min(one_r):.2f}-{max(one_r):.2f})  (target >= 1.5)")


if __name__ == "__main__":
    main()
