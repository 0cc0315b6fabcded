"""``python -m ebm_wear_monitor.schema [--check]``: rewrite the shipped JSON Schema files (or check them)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from ebm_wear_monitor.schema.documents import stale, write_all


def main(argv: Sequence[str] | None = None) -> int:
    """Write every file (exit 0), or with ``--check`` exit 1 naming the stale ones."""
    parser = argparse.ArgumentParser(prog="python -m ebm_wear_monitor.schema",
                                     description="write the JSON Schema files of every --json output")
    parser.add_argument("--check", action="store_true", help="only check that the files are up to date")
    args = parser.parse_args(argv)
    if args.check:
        names = stale()
        for name in names:
            print(f"stale: {name}.schema.json (run python -m ebm_wear_monitor.schema)", file=sys.stderr)
        return 1 if names else 0
    for p in write_all():
        print(p)
    return 0


if __name__ == "__main__":
    sys.exit(main())
