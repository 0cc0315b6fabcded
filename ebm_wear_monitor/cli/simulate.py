"""``ebm-wear simulate``: the digital twin writing a rosbag2 bag of the input topics (interface.md 2, 5).

Brake applications of one unit (004's actuator under the twin's brake
controller, coupled to the wear core of 000) are written as the four input
topics under a namespace, header stamps at the sample times, with realistic
sensor noise (``ebm_wear_monitor.twin.sensors``), plus a ground-truth sidecar
``<bag>/ground_truth.json`` (wear, clearance, effects, wear-acceleration
factor). The bag is written to a temporary directory and renamed, so a failed
run leaves nothing behind.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ebm_wear_monitor.domain.signals import DEFAULT_NAMESPACE
from ebm_wear_monitor.errors import InputError


def _effect(text: str) -> tuple[str, float]:
    name, sep, value = text.partition("=")
    if not sep:
        raise argparse.ArgumentTypeError(f"expected NAME=MAGNITUDE, got {text!r}")
    try:
        return name.strip(), float(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"magnitude of {name!r} is not a number: {value!r}") from None


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from ebm_wear_monitor.twin.effects import CATALOG

    parser.add_argument("--params", default=None, metavar="P",
                        help="unit parameter file or reference name (default: embu_000)")
    parser.add_argument("--cycles", type=int, required=True, metavar="N", help="brake applications")
    parser.add_argument("--demand", type=float, nargs="+", default=None, metavar="F",
                        help="demanded clamp force(s) [N], cycled (default: 10000 15000 20000)")
    parser.add_argument("--effect", type=_effect, action="append", default=[], metavar="NAME=MAGNITUDE",
                        help="inject a catalog effect (repeatable): " + "; ".join(
                            f"{k}: {v[1]}" for k, v in CATALOG.items()))
    parser.add_argument("--seed", type=int, default=0, help="sensor-noise seed (default 0)")
    parser.add_argument("--storage", choices=("mcap", "sqlite3"), default="mcap")
    parser.add_argument("--rate", type=float, default=1000.0, metavar="HZ", help="sample rate (default 1000)")
    parser.add_argument("--namespace", default=DEFAULT_NAMESPACE, metavar="NS",
                        help=f"unit namespace (default {DEFAULT_NAMESPACE})")
    parser.add_argument("--hold", type=float, nargs="+", default=[1.0], metavar="S",
                        help="force-maintenance time(s) [s], cycled (default 1.0)")
    parser.add_argument("--rest", type=float, default=0.5, metavar="S",
                        help="idle time after each release [s] (default 0.5)")
    parser.add_argument("--wear-acceleration", type=float, default=1.0, metavar="X",
                        help="ACCELERATED-LIFE factor on every wear increment (default 1 = real wear)")
    parser.add_argument("--prior-cycles", type=int, default=0, metavar="N",
                        help="applications the unit made before this recording (its initial wear)")
    parser.add_argument("--no-noise", action="store_true", help="record the noise-free truth")
    parser.add_argument("--out", required=True, metavar="BAG", help="bag directory to create")


def run(args: argparse.Namespace) -> int:
    from ebm_wear_monitor.bagio import write_unit_bag
    from ebm_wear_monitor.domain.signals import check_namespace
    from ebm_wear_monitor.outputs import check_destination
    from ebm_wear_monitor.params import load_unit
    from ebm_wear_monitor.twin import NOISELESS, SensorNoise, simulate_unit

    if Path(args.out).exists():
        raise InputError(f"{args.out} exists already; not overwriting a bag")
    check_destination(args.out, "--out", directory=True)  # before simulating, not after
    # normalised ('embu' -> '/embu'), so the ground-truth key is the unit name readers derive from topics
    namespace = check_namespace(args.namespace)
    unit = load_unit(args.params)
    effects: dict[str, float] = {}
    for name, magnitude in args.effect:
        if name in effects:
            raise InputError(f"effect {name} given twice")
        effects[name] = magnitude
    result = simulate_unit(
        unit, args.cycles, demands=args.demand, effects=effects, seed=args.seed, rate_hz=args.rate,
        wear_acceleration=args.wear_acceleration, hold_s=args.hold, rest_s=args.rest,
        noise=NOISELESS if args.no_noise else SensorNoise(), prior_cycles=args.prior_cycles,
        progress=sys.stderr.isatty() and args.cycles >= 20)
    truth = {"units": {namespace: result.ground_truth()},
             "simulator": {"unit": unit.name, "params_digest": unit.digest(),
                           "wear_acceleration_note": "wear increments multiplied by wear_acceleration"}}
    count = write_unit_bag(args.out, result.t, {namespace: result.signals()}, storage=args.storage,
                           ground_truth=truth)
    tr = result.truth
    seconds = result.t[-1] + 1.0 / args.rate
    print(f"{args.out}: {args.cycles} applications, {seconds:.2f} s at {args.rate:g} Hz, "
          f"{count} messages under {namespace}; clearance {tr['clearance_m'][0] * 1e3:.4f} -> "
          f"{tr['clearance_after_m'][-1] * 1e3:.4f} mm (wear acceleration x{args.wear_acceleration:g})")
    return 0
