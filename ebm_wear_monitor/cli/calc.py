"""``ebm-wear calc``: single-point calculators (interface.md sections 4-5).

    ebm-wear calc contact  --params P (--axial-force F | --normal-load Q) [--json OUT]
    ebm-wear calc wear     --params P --axial-force F --speed W [--json OUT]
    ebm-wear calc actuator --params P --clamp-force F [--json OUT]

``contact``: one ball on the screw and nut raceways (000 eq. 1-7, 003 eq. 1-17);
``wear``: instantaneous wear state at constant force and screw speed (000 eq. 5-23);
``actuator``: actuator torques at a held clamp force (004 eq. 1, 9, 42), from the twin.
Forces in N, speeds in rad/s, within the physical envelope of
:mod:`ebm_wear_monitor.physics.reports` (forces up to 80 kN, |speed| up to 200 rad/s).
Each calculator reads only the unit-file blocks it uses (interface.md section 3): contact
``ball_screw`` + ``materials``, wear also ``lubricant`` + ``wear``, actuator ``ball_screw`` +
``actuator``. Bad input: one line on stderr, exit status 2.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING, Any

from ebm_wear_monitor.outputs import check_destination, write_json
from ebm_wear_monitor.params import ACTUATOR_BLOCKS, CONTACT_BLOCKS, WEAR_BLOCKS, load_unit
from ebm_wear_monitor.physics.kinematics import KINEMATICS
from ebm_wear_monitor.physics.plasticity import KAPPA_READINGS, RADIUS_READINGS

if TYPE_CHECKING:
    from ebm_wear_monitor.schema.calc import ActuatorResult, ContactResult, WearResult


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
    parser.add_argument("--json", metavar="OUT", help="write the result as JSON to OUT ('-': stdout)")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest="calculator", metavar="CALCULATOR", required=True)
    p = sub.add_parser("contact", help="ball-raceway contact (000 eq. 1-7, 003 eq. 1-17)")
    _common(p)
    load = p.add_mutually_exclusive_group(required=True)
    load.add_argument("--axial-force", type=float, metavar="F", help="axial force [N], 0 < F <= 8e4")
    load.add_argument("--normal-load", type=float, metavar="Q",
                      help="normal load per ball [N], up to what 80 kN of axial force gives")
    _readings(p)
    p = sub.add_parser("wear", help="wear state at constant axial force and screw speed (000 eq. 5-23)")
    _common(p)
    p.add_argument("--axial-force", type=float, required=True, metavar="F",
                   help="axial force [N], 0 < F <= 8e4")
    p.add_argument("--speed", type=float, required=True, metavar="W", help="screw speed [rad/s], |W| <= 200")
    _readings(p)
    p = sub.add_parser("actuator", help="actuator torques at a held clamp force (004 eq. 1, 9, 42)")
    _common(p)
    p.add_argument("--clamp-force", type=float, required=True, metavar="F",
                   help="clamp force [N], 0 <= F <= 8e4")


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


BLOCKS = {"contact": CONTACT_BLOCKS, "wear": WEAR_BLOCKS, "actuator": ACTUATOR_BLOCKS}


def run(args: argparse.Namespace) -> int:
    check_destination(args.json, "--json")
    unit = load_unit(args.params, BLOCKS[args.calculator])
    result: ContactResult | WearResult | ActuatorResult
    if args.calculator == "contact":
        from ebm_wear_monitor.physics import contact_report
        result = contact_report(unit, axial_force=args.axial_force, normal_load_n=args.normal_load,
                                options=_options(args))
    elif args.calculator == "wear":
        from ebm_wear_monitor.physics import wear_report
        result = wear_report(unit, args.axial_force, args.speed, options=_options(args))
    else:
        from ebm_wear_monitor.physics.reports import check_axial_force
        from ebm_wear_monitor.twin import actuator_torques
        check_axial_force(args.clamp_force, "clamp force", allow_zero=True)
        result = actuator_torques(unit, args.clamp_force)
    doc = result.to_json_dict()
    if args.json:
        write_json(args.json, doc)
    _print(doc)
    return 0
