"""``ebm-wear diagnose``: sim-to-real gap diagnosis of recorded bags against the twin (interface.md sec. 4).

    ebm-wear diagnose BAG... --params P [--json OUT] [--report DIR] [--life]
    ebm-wear diagnose --selftest [--quick | --cases N] [--seed S] [--json OUT]

One result per unit (namespace) found in the bags (a unit's topics may be spread
over several bags).  The JSON holds ``units`` (one diagnosis object each) and,
at the top level, the keys of the first unit's diagnosis, so a single-unit
recording reads exactly as the spec's object.  ``--life`` adds the key ``life`` to each unit: the
monitor core (:func:`ebm_wear_monitor.replay.run.replay_unit`) over the same signals gives the
duty-cycle summaries, whose observed clearance growth :mod:`ebm_wear_monitor.diagnosis.life` compares
with the wear model's (issue 7 item 5).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.outputs import check_destination, write_json


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("bags", nargs="*", metavar="BAG", help="rosbag2 directories (sqlite3 or mcap)")
    parser.add_argument("--params", metavar="P", help="unit parameter file (YAML) or reference name")
    parser.add_argument("--json", metavar="OUT", help="write the result as JSON to OUT")
    parser.add_argument("--report", metavar="DIR", help="write an HTML report with plots into DIR")
    parser.add_argument("--life", action="store_true",
                        help="also the life level: the monitor core's duty-cycle summaries of the bags "
                             "(observed clearance growth) against the wear model (key 'life')")
    parser.add_argument("--selftest", action="store_true",
                        help="blind self-test on twin recordings with withheld effects")
    parser.add_argument("--quick", action="store_true", help="self-test: reduced case set (CI)")
    parser.add_argument("--cases", type=int, metavar="N", help="self-test: at most N cases")
    parser.add_argument("--seed", type=int, default=0, help="self-test: base random seed")


def _print_diagnosis(res: dict) -> None:
    print(f"{res['unit']}: verdict {res['verdict']}"
          + (f", effect {res['effect']}" if res["effect"] else "")
          + f"; held-out gap ({res['metric']}) {res['gap_before']:.3g} -> {res['gap_after']:.3g}")
    w = res["where"]
    if w["phase"]:
        print(f"  where: {w['phase']} / {w['signal']} (RMS {w['normalised_rms']:.3g} x noise)")
    for r in res["ranking"]:
        pars = ", ".join(f"{k}={v['value']:.4g}±{v['stderr']:.2g} {v['unit']}"
                         for k, v in r["parameters"].items())
        print(f"  {r['effect']:<24s} score {r['score']:+.3f}  gap_after {r['gap_after']:.3g}  "
              f"p {r['p_value']:.2g}  {pars}")
    for t in res["near_ties"]:
        print(f"  near-tie {t['between'][0]} ~ {t['between'][1]}: {t['experiment']}")
    life = res.get("life")
    if life is not None:
        top = life["ranking"][0]
        print(f"  life ({life['summaries']} duty-cycle summaries): verdict {life['verdict']}"
              + (f", effect {life['effect']}" if life["effect"] else "")
              + f"; best {top['effect']} {', '.join(f'{v:.4g}' for v in top['parameters'])}"
              + (f"; near-ties {', '.join(life['near_ties'])}" if life["near_ties"] else ""))


def _life(data, unit) -> dict:
    """Life-level diagnosis of one unit's signals: the monitor core over them, then :mod:`.life`."""
    from ebm_wear_monitor.diagnosis.life import diagnose_life, life_data_from_applications
    from ebm_wear_monitor.replay.run import replay_unit

    d = life_data_from_applications(replay_unit(data, unit).applications)
    return diagnose_life(d) | {"summaries": int(d.n.size),
                               "source": "monitor core duty-cycle summaries (clearance observed per "
                                         "application vs the wear model's growth)"}


def _run_selftest(args: argparse.Namespace) -> int:
    from ebm_wear_monitor.diagnosis.selftest import format_summary, run_selftest

    if args.cases is not None and args.cases < 1:
        raise InputError("--cases must be at least 1")
    result = run_selftest(quick=args.quick, max_cases=args.cases, seed=args.seed)
    print(format_summary(result))
    if args.json:
        write_json(args.json, result)
    return 0


def run(args: argparse.Namespace) -> int:
    check_destination(args.json, "--json")  # before minutes of work, not after
    check_destination(args.report, "--report", directory=True)
    if args.selftest:
        if args.bags:
            raise InputError("--selftest takes no BAG arguments")
        return _run_selftest(args)
    if not args.bags:
        raise InputError("no BAG given (or use --selftest)")
    if not args.params:
        raise InputError("--params P is required to build the twin")
    from ebm_wear_monitor.bagio import read_bags
    from ebm_wear_monitor.diagnosis import recording_from_signals
    from ebm_wear_monitor.diagnosis.pipeline import diagnose_with_state
    from ebm_wear_monitor.params import load_unit

    unit = load_unit(args.params)
    data = read_bags([Path(b) for b in args.bags])
    if not data.units:
        raise InputError("no unit with input topics found in the bags")
    results, states = [], []
    for name, ud in sorted(data.units.items()):
        rec = recording_from_signals({k: (s.stamps, s.values) for k, s in ud.signals.items()}, unit=name)
        res, sc, ranking = diagnose_with_state(rec, unit)
        if args.life:
            res["life"] = _life(ud, unit)
        results.append(res)
        states.append((res, sc, ranking))
    for res in results:
        _print_diagnosis(res)
    out = dict(results[0]) | {"units": results}
    if args.report:
        from ebm_wear_monitor.diagnosis.report import write_report

        write_report(args.report, states)
    if args.json:
        write_json(args.json, out)
    return 0
