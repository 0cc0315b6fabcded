"""CLI of the third world.

``python -m ebm_wear_monitor.validation.third list``
``python -m ebm_wear_monitor.validation.third write --out DIR [--jobs N] [--only ID,ID] [--seed S]``
"""

from __future__ import annotations

import argparse
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import NoReturn

from .cases import default_cases
from .plant import load_nominal


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> NoReturn:  # one line, exit 2
        sys.stderr.write(f"error: {message}\n")
        raise SystemExit(2)


def _one(args: tuple) -> str:
    from .generate import write_case

    case, out, nom = args
    sec, n = write_case(case, out, nom)
    return f"{case.case_id:28s} {case.kind:8s} {case.effect or '-':24s} {n:7d} msgs  {sec:5.1f} s"


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the exit status."""
    p = _Parser(prog="python -m ebm_wear_monitor.validation.third", description="third validation world")
    sub = p.add_subparsers(dest="cmd", required=True, parser_class=_Parser)
    ls = sub.add_parser("list", help="list the default cases")
    ls.add_argument("--seed", type=int, default=3)
    w = sub.add_parser("write", help="write cases as rosbag2 directories with truth.json")
    w.add_argument("--out", required=True, type=Path)
    w.add_argument("--jobs", type=int, default=1)
    w.add_argument("--only", default="")
    w.add_argument("--seed", type=int, default=3)
    a = p.parse_args(argv)
    nom = load_nominal()
    cases = default_cases(nom, a.seed)
    if a.cmd == "list":
        for c in cases:
            mag = "" if c.magnitude is None else f"{c.magnitude:+.3f}"
            print(
                f"{c.case_id:28s} {c.kind:8s} {c.effect or '-':24s} {mag:8s} {c.ctrl['name']:18s} "
                f"{c.storage:7s} {c.namespace}"
            )
        return 0
    if a.jobs < 1:
        p.error("--jobs must be >= 1")
    if a.only:
        want = [s.strip() for s in a.only.split(",") if s.strip()]
        known = {c.case_id for c in cases}
        bad = [s for s in want if s not in known]
        if bad:
            p.error(f"unknown case id(s): {', '.join(bad)} (see 'list')")
        cases = [c for c in cases if c.case_id in want]
    if a.out.exists() and not a.out.is_dir():
        p.error(f"--out {a.out} exists and is not a directory")
    for c in cases:
        tgt = a.out / c.case_id
        if tgt.exists() and not (tgt / "truth.json").exists():
            p.error(f"{tgt} exists and was not written by this generator")
    a.out.mkdir(parents=True, exist_ok=True)
    jobs = [(c, a.out, nom) for c in cases]
    if a.jobs == 1:
        for j in jobs:
            print(_one(j), flush=True)
    else:
        with ProcessPoolExecutor(a.jobs) as ex:
            for line in ex.map(_one, jobs):
                print(line, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
