"""``ebm-wear``: the command-line front door.

Each subcommand lives in its own module ``ebm_wear_monitor.cli.<name>`` with
``add_arguments(parser)`` and ``run(args) -> int``; modules are imported only
when their subcommand runs, so ``ebm-wear calc`` never pays for Dask or rclpy.
Bad input (:class:`~ebm_wear_monitor.errors.InputError`) becomes one line on
stderr and exit status 2 (interface.md section 5); an interruption (Ctrl-C) exits with 130.
``calc`` runs on the onboard install (``pip install .``); every other subcommand needs the
``tools`` extra and says so in one line (exit 2) when it is missing (:mod:`ebm_wear_monitor.extras`).
With ``--json -`` the JSON is the only thing on standard output: every line for people goes
to standard error (:func:`ebm_wear_monitor.outputs.human_output_to_stderr`).
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
from collections.abc import Sequence
from types import ModuleType

from ebm_wear_monitor import __version__
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.extras import MissingExtraError, missing_message, provider, require

#: subcommand (= module under ebm_wear_monitor.cli) -> one-line help
SUBCOMMANDS: dict[str, str] = {
    "replay": "run the monitor core over recorded rosbag2 bags, offline",
    "fleet": "the fleet pipeline over many units' bags, on Dask",
    "diagnose": "sim-to-real gap diagnosis of recorded data against the digital twin",
    "simulate": "the digital twin of the actuator writing a rosbag2 bag",
    "calc": "calculators: ball contact, wear rate, actuator torques",
}
#: subcommands that run on the onboard install; the others need the ``tools`` extra
ONBOARD_COMMANDS = frozenset({"calc"})


def _load(name: str) -> ModuleType:
    return importlib.import_module(f"ebm_wear_monitor.cli.{name}")


def build_parser(argv: Sequence[str]) -> argparse.ArgumentParser:
    """Parser with every subcommand; only the one named in ``argv`` gets its full arguments."""
    parser = argparse.ArgumentParser(
        prog="ebm-wear", description="Ball-screw wear monitor for railway EMB units (SI units throughout).")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    chosen = next((a for a in argv if not a.startswith("-")), None)
    for name, help_text in SUBCOMMANDS.items():
        p = sub.add_parser(name, help=help_text, description=help_text)
        if name == chosen:
            _load(name).add_arguments(p)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``ebm-wear``; returns the exit status."""
    argv = list(sys.argv[1:] if argv is None else argv)
    args = build_parser(argv).parse_args(argv)
    try:
        if args.command not in ONBOARD_COMMANDS:
            require("tools")
        from ebm_wear_monitor.outputs import human_output_to_stderr  # (numpy: not for --help)

        with human_output_to_stderr(getattr(args, "json", None)):
            status = int(_load(args.command).run(args) or 0)
        sys.stdout.flush()  # inside the try: a closed pipe surfaces here, not at interpreter exit
        return status
    except (InputError, MissingExtraError) as exc:
        print(f"ebm-wear {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except ModuleNotFoundError as exc:  # a lazy import of an extra's module the check above did not cover
        found = provider(exc.name)
        if found is None:
            raise
        print(f"ebm-wear {args.command}: error: {missing_message(found[0], [found[1]])}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"ebm-wear {args.command}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader went away (`ebm-wear ... | head`): stop quietly, like cat
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141


if __name__ == "__main__":
    sys.exit(main())
