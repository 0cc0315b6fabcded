"""Command line: ``python -m ebm_wear_monitor.validation.foreign write --set NAME --out DIR``.

Writes every case of a set (one rosbag2 directory with ``ground_truth.json`` each), printing one
progress line per recording with its generation time; ``list`` prints the cases. Exit status 2
with a one-line reason on bad input, or when rosbags (the ``tools`` extra) is not installed.
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

from .cases import SETS, case_set
from .recording import write_case

PROG = "python -m ebm_wear_monitor.validation.foreign"


def _write_one(case, out: str) -> tuple[str, float]:
    t0 = time.perf_counter()
    write_case(case, out)
    return case.case_id, time.perf_counter() - t0


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the exit status."""
    parser = argparse.ArgumentParser(prog=PROG, description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    w = sub.add_parser("write", help="generate every recording of a case set")
    w.add_argument("--set", required=True, choices=SETS, dest="set_name")
    w.add_argument("--out", required=True, type=Path)
    w.add_argument("--jobs", type=int, default=1, help="worker processes (default 1)")
    w.add_argument("--only", default=None, help="comma-separated case ids to write")
    lst = sub.add_parser("list", help="print the cases of a set")
    lst.add_argument("--set", required=True, choices=SETS, dest="set_name")
    args = parser.parse_args(argv)
    if args.command == "write" and importlib.util.find_spec("rosbags") is None:
        print(f"{PROG}: error: needs the 'tools' extra (not installed: rosbags): "
              "pip install 'ebm_wear_monitor[tools]'", file=sys.stderr)
        return 2
    cases = case_set(args.set_name)
    if args.command == "list":
        for c in cases:
            print(f"{c.case_id}\t{c.kind}\t{','.join(c.effects) or '-'}\tseed={c.seed}")
        return 0
    if args.only:
        wanted = set(args.only.split(","))
        unknown = wanted - {c.case_id for c in cases}
        if unknown:
            print(f"{PROG}: error: unknown case ids: {', '.join(sorted(unknown))}", file=sys.stderr)
            return 2
        cases = [c for c in cases if c.case_id in wanted]
    if args.jobs < 1:
        print(f"{PROG}: error: --jobs must be at least 1", file=sys.stderr)
        return 2
    try:
        args.out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        print(f"{PROG}: error: cannot create {args.out}: {exc.strerror}", file=sys.stderr)
        return 2
    t0 = time.perf_counter()
    times = []
    with ProcessPoolExecutor(max_workers=args.jobs) as pool:
        futures = [pool.submit(_write_one, c, str(args.out)) for c in cases]
        for done, fut in enumerate(as_completed(futures), 1):
            case_id, dt = fut.result()
            times.append(dt)
            print(f"[{done}/{len(cases)}] {case_id}  {dt:.2f} s", flush=True)
    print(f"wrote {len(cases)} recordings to {args.out} in {time.perf_counter() - t0:.1f} s "
          f"({sum(times) / max(1, len(times)):.2f} s per recording)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
