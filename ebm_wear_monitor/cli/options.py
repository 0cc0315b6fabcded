"""The options every analysing subcommand (replay, diagnose, fleet) shares, with one meaning each.

``--json OUT`` (``-``: standard output, and then nothing else goes there), ``--report DIR`` (an
HTML report, DIR created if missing, its parent must exist) and ``--no-progress``; progress bars
(tqdm, on stderr, with total and ETA) on every step that can last more than a second.
"""

from __future__ import annotations

import argparse
import sys
from typing import Any


def add_output_options(parser: argparse.ArgumentParser, report_default: str = "") -> None:
    """Add ``--json``, ``--report`` and ``--no-progress`` to ``parser``."""
    parser.add_argument("--json", metavar="OUT", help="write the result as JSON to OUT ('-': stdout)")
    parser.add_argument("--report", metavar="DIR",
                        help="write an HTML report into DIR" + (f" (default: {report_default})"
                                                                if report_default else ""))
    parser.add_argument("--no-progress", action="store_true", help="no progress bars on stderr")


def check_outputs(args: argparse.Namespace) -> None:
    """Before any work: ``--json`` and ``--report`` destinations usable (InputError otherwise).

    ``--json`` may go into the ``--report`` directory about to be created (``--report report
    --json report/replay.json``, the README's first command).
    """
    from pathlib import Path

    from ebm_wear_monitor.outputs import check_destination

    check_destination(args.report, "--report", directory=True)
    into_new_report = (args.json is not None and args.report is not None and not Path(args.report).exists()
                       and Path(args.json).parent == Path(args.report))
    if not into_new_report:
        check_destination(args.json, "--json")


def progress(args: argparse.Namespace, total: int | None, desc: str, unit: str) -> Any:
    """A tqdm bar on stderr with ``total`` (so it shows the ETA); off with ``--no-progress`` or no tty."""
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit=unit, disable=args.no_progress or None, file=sys.stderr,
                dynamic_ncols=True)
