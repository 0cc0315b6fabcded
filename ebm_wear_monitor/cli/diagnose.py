"""``ebm-wear diagnose``: sim-to-real gap diagnosis of recorded bags against the twin (interface.md sec. 4).

    ebm-wear diagnose BAG... --params P [--json OUT] [--report DIR] [--life] [--no-progress]
    ebm-wear diagnose --selftest [--quick | --cases N] [--seed S] [--jobs N] [--in-world-only] [--json OUT]
                      [--no-progress]

One result per unit (namespace) found in the bags (a unit's topics may be spread
over several bags).  The JSON holds ``units`` (one diagnosis object each) and,
at the top level, the keys of the first unit's diagnosis, so a single-unit
recording reads exactly as the spec's object.  ``--life`` adds the key ``life`` to each unit: the
monitor core (:func:`ebm_wear_monitor.replay.run.replay_unit`) over the same signals gives the
duty-cycle summaries, whose observed clearance growth :mod:`ebm_wear_monitor.diagnosis.life` compares
with the wear model's (issue 7 item 5).

Input screening, as the monitor does it (:mod:`ebm_wear_monitor.diagnosis.bags`): a topic sampled
below the contract's 100 Hz is refused; non-finite or absurd samples are dropped and counted in
``input_faults`` / ``input_faults_by_signal`` (the replay's keys), never fitted. The unit file needs
``ball_screw`` and ``actuator`` (and the wear model's blocks with ``--life``).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ebm_wear_monitor.cli.options import add_output_options, check_outputs, progress
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.outputs import write_json
from ebm_wear_monitor.schema.diagnose import DiagnoseDocument, LifeDiagnosis, UnitDiagnosis


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("bags", nargs="*", metavar="BAG", help="rosbag2 directories (sqlite3 or mcap)")
    parser.add_argument("--params", metavar="P", help="unit parameter file (YAML) or reference name")
    add_output_options(parser)
    parser.add_argument("--life", action="store_true",
                        help="also the life level: the monitor core's duty-cycle summaries of the bags "
                             "(observed clearance growth) against the wear model (key 'life')")
    parser.add_argument("--selftest", action="store_true",
                        help="blind self-test with withheld effects: the twin's own recordings and an "
                             "independently written generator's bags (the 'foreign' key)")
    parser.add_argument("--in-world-only", action="store_true",
                        help="self-test: only the twin's own recordings (no foreign world)")
    parser.add_argument("--jobs", type=int, default=1, metavar="N",
                        help="self-test: diagnose the foreign cases on N processes (default 1)")
    parser.add_argument("--quick", action="store_true", help="self-test: reduced case set (CI)")
    parser.add_argument("--cases", type=int, metavar="N", help="self-test: at most N cases")
    parser.add_argument("--seed", type=int, default=0, help="self-test: base random seed")


def _print_diagnosis(u: UnitDiagnosis) -> None:
    res = u.diagnosis
    print(f"{res.unit}: verdict {res.verdict}"
          + (f", effect {res.effect}" if res.effect else "")
          + f"; held-out gap ({res.metric}) {res.gap_before:.3g} -> {res.gap_after:.3g}")
    w = res.where
    if w.phase:
        print(f"  where: {w.phase} / {w.signal} (RMS {w.normalised_rms:.3g} x noise)")
    for r in res.ranking:
        pars = ", ".join(f"{k}={v.value:.4g}±{v.stderr:.2g} {v.unit}" for k, v in r.parameters.items())
        print(f"  {r.effect:<24s} score {r.score:+.3f}  gap_after {r.gap_after:.3g}  "
              f"p {r.p_value:.2g}  {pars}")
    for t in res.near_ties:
        print(f"  near-tie {t.between[0]} ~ {t.between[1]}: {t.experiment}")
    if u.input_faults:
        print("  input faults (samples dropped): " + ", ".join(
            f"{sig} {kind} {n}" for sig, kinds in sorted(u.input_faults_by_signal.items())
            for kind, n in sorted(kinds.items())))
    life = u.life
    if life is not None:
        top = life.ranking[0]
        print(f"  life ({life.summaries} duty-cycle summaries): verdict {life.verdict}"
              + (f", effect {life.effect}" if life.effect else "")
              + f"; best {top.effect} {', '.join(f'{v:.4g}' for v in top.parameters)}"
              + (f"; near-ties {', '.join(life.near_ties)}" if life.near_ties else ""))


def _life(data, unit) -> LifeDiagnosis:
    """Life-level diagnosis of one unit's signals: the monitor core over them, then
    :mod:`ebm_wear_monitor.diagnosis.life`."""
    from ebm_wear_monitor.diagnosis.life import diagnose_life, life_data_from_applications
    from ebm_wear_monitor.replay.run import replay_unit

    return diagnose_life(life_data_from_applications(replay_unit(data, unit).applications))


def _run_selftest(args: argparse.Namespace) -> int:
    from ebm_wear_monitor.diagnosis.selftest import format_summary, run_selftest

    if args.cases is not None and args.cases < 1:
        raise InputError("--cases must be at least 1")
    if args.jobs < 1:
        raise InputError("--jobs must be at least 1")
    with progress(args, None, "self-test", "case") as bar:
        def on_case(done: int, total: int) -> None:
            bar.total = total
            bar.update(done - bar.n)
        result = run_selftest(quick=args.quick, max_cases=args.cases, seed=args.seed, on_case=on_case,
                              foreign=not args.in_world_only, jobs=args.jobs)
    print(format_summary(result))
    if args.json:
        write_json(args.json, result.to_json_dict())
    return 0


def run(args: argparse.Namespace) -> int:
    check_outputs(args)  # before minutes of work, not after
    if args.selftest:
        if args.bags:
            raise InputError("--selftest takes no BAG arguments")
        return _run_selftest(args)
    if not args.bags:
        raise InputError("no BAG given (or use --selftest)")
    if not args.params:
        raise InputError("--params P is required to build the twin")
    from ebm_wear_monitor.bagio import bag_message_count
    from ebm_wear_monitor.diagnosis.bags import recordings_from_bags
    from ebm_wear_monitor.diagnosis.pipeline import diagnose_with_state
    from ebm_wear_monitor.params import ACTUATOR_BLOCKS, WEAR_BLOCKS, load_unit

    unit = load_unit(args.params, ACTUATOR_BLOCKS + (WEAR_BLOCKS if args.life else ()))
    with progress(args, bag_message_count(args.bags), "read", "msg") as bar:
        units = recordings_from_bags(args.bags, progress=bar.update)
    results, states = [], []
    with progress(args, len(units), "diagnose", "unit") as bar:
        for ur in units.values():
            res, sc, ranking = diagnose_with_state(ur.recording, unit)
            u = UnitDiagnosis(res, ur.faults, ur.fault_totals, _life(ur.data, unit) if args.life else None)
            results.append(u)
            states.append((u, sc, ranking))
            bar.update()
    for u in results:
        _print_diagnosis(u)
    if args.report:
        from ebm_wear_monitor.diagnosis.report import write_report

        write_report(args.report, states)
        print(f"report: {Path(args.report) / 'index.html'}")
    if args.json:
        write_json(args.json, DiagnoseDocument(results[0], results).to_json_dict())
    return 0
