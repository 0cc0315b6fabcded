"""``ebm-wear calc``: single-point calculators (interface.md sections 4-5).

    ebm-wear calc contact  --params P (--axial-force F | --normal-load Q) [--json OUT]
    ebm-wear calc wear     --params P --axial-force F --speed W [--json OUT]
    ebm-wear calc actuator --params P --clamp-force F [--json OUT]

``contact``: one ball on the screw and nut raceways (000 eq. 1-7, 003 eq. 1-17);
``wear``: instantaneous wear state at constant force and screw speed (000 eq. 5-23);
``actuator``: actuator torques at a held clamp force (004 eq. 1, 9, 42), from the twin.
Forces in N, speeds in rad/s. Bad input: one line on stderr, exit status 2.
"""

from __future__ import annotations

import argparse
import math
from typing import Any

from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.outputs import write_json
from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.physics.kinematics import KINEMATICS
from ebm_wear_monitor.physics.plasticity import KAPPA_READINGS, RADIUS_READINGS


def _readings(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--kinematics", choices=KINEMATICS, default="literal",
                        help="reading of 000 eq. 10-11, 19 (default: literal)")
    parser.add_argument("--radius", choices=RADIUS_READINGS, default="hertz",
                        help="R of 000 eq. 6-7 (default: hertz = 2/sum_rho)")
    parser.add_argument("--kappa", choices=KAPPA_READINGS, default="b/a",
                        help="kappa in Horng's functions of 000 eq. 7 (default: b/a)")


def _common(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--params", required=True, metavar="P",
                        help="unit parameter file (YAML) or reference name (embu_000, screw_003)")
    parser.add_argument("--json", metavar="OUT", help="write the result as JSON to OUT")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest="calculator", metavar="CALCULATOR", required=True)
    p = sub.add_parser("contact", help="ball-raceway contact (000 eq. 1-7, 003 eq. 1-17)")
    _common(p)
    load = p.add_mutually_exclusive_group(required=True)
    load.add_argument("--axial-force", type=float, metavar="F", help="axial force on the screw [N]")
    load.add_argument("--normal-load", type=float, metavar="Q", help="normal load per ball [N]")
    _readings(p)
    p = sub.add_parser("wear", help="wear state at constant axial force and screw speed (000 eq. 5-23)")
    _common(p)
    p.add_argument("--axial-force", type=float, required=True, metavar="F", help="axial force [N], > 0")
    p.add_argument("--speed", type=float, required=True, metavar="W", help="screw speed [rad/s]")
    _readings(p)
    p = sub.add_parser("actuator", help="actuator torques at a held clamp force (004 eq. 1, 9, 42)")
    _common(p)
    p.add_argument("--clamp-force", type=float, required=True, metavar="F", help="clamp force [N], >= 0")


def _options(args: argparse.Namespace) -> Any:
    from ebm_wear_monitor.physics import ModelOptions
    return ModelOptions(kinematics=args.kinematics, radius=args.radius, kappa=args.kappa)


def _print(result: dict[str, Any], indent: str = "") -> None:
    for key, value in result.items():
        if isinstance(value, dict):
            print(f"{indent}{key}:")
            _print(value, indent + "  ")
        elif isinstance(value, float):
            print(f"{indent}{key:28s} {value:.6g}")
        else:
            print(f"{indent}{key:28s} {value}")


def run(args: argparse.Namespace) -> int:
    unit = load_unit(args.params)
    if args.calculator == "contact":
        from ebm_wear_monitor.physics import contact_report
        result = contact_report(unit, axial_force=args.axial_force, normal_load_n=args.normal_load,
                                options=_options(args))
    elif args.calculator == "wear":
        from ebm_wear_monitor.physics import wear_report
        result = wear_report(unit, args.axial_force, args.speed, options=_options(args))
    else:
        if unit.actuator is None:
            raise InputError(f"{args.params}: the unit file has no 'actuator' section")
        if not (math.isfinite(args.clamp_force) and args.clamp_force >= 0.0):
            raise InputError(f"clamp force must be a finite number >= 0, got {args.clamp_force!r}")
        from ebm_wear_monitor.twin import actuator_torques
        result = actuator_torques(unit, args.clamp_force)
    if args.json:
        write_json(args.json, result)
    _print(result)
    return 0
