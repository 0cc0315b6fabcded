"""``ebm-wear replay BAG... [--params P] [--json OUT] [--report DIR]``: the monitor core over recorded bags.

Reads the input topics of every bag (several units by namespace, several bags
per unit in time order), runs :class:`~ebm_wear_monitor.monitor.MonitorCore`
over each unit exactly as the node does, prints wear, clearance and remaining
life per unit, and writes the JSON of interface.md section 4 and an HTML
report. Bad input: one line on stderr, exit status 2, nothing written.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ebm_wear_monitor.cli.options import add_output_options, check_outputs, progress


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Arguments of ``ebm-wear replay``."""
    parser.add_argument("bags", nargs="+", metavar="BAG", help="rosbag2 bag directories (sqlite3 or mcap)")
    parser.add_argument("--params", metavar="P", default=None,
                        help="unit parameter YAML, or a reference name (default: embu_000)")
    parser.add_argument("--config", metavar="FILE",
                        help="monitor-core thresholds: the node's ROS parameter file (e.g. "
                             "config/wear_monitor.yaml) or a flat YAML mapping (default: the defaults)")
    add_output_options(parser)
    parser.add_argument("--stamps", choices=("header", "log"), default="header",
                        help="sample time of each message: its header.stamp (default; interface.md "
                             "section 2) or the bag's log (receive) time, when header stamps are unusable")
    parser.add_argument("--strict", action="store_true",
                        help="damaged storage (messages lost against metadata.yaml or the storage index, a "
                             "chunk failing its CRC) is an error (exit 2) instead of a counted 'lost' fault")


#: the alpha-lambda test in words (None: the record ends before its time t_lambda, replay.prognostics)
_PASS = {True: "passed", False: "failed", None: "not judged: the recording ends before lambda"}


def format_unit(entry: dict) -> str:
    """Human-readable lines of one unit's section 4 entry (µm, mm, counts, hours, days)."""
    from ebm_wear_monitor.reports.life import life_view

    w, c, r = entry["wear"], entry["clearance"], entry["remaining_life"]

    def mm(v: float | None) -> str:
        return "n/a" if v is None else f"{v * 1e3:.4f} mm"

    life = life_view(r, c).line()
    if r.get("growth_rate_m_per_cycle") is not None:
        life += (f"; clearance growth {r['growth_rate_m_per_cycle'] * 1e6:.3g} ± "
                 f"{r['growth_rate_std_m_per_cycle'] * 1e6:.2g} µm per application")
    if r.get("fatigue_remaining_cycles") is not None:
        life += (f"; fatigue (ISO 3408-5 L10): {r['fatigue_remaining_cycles']:.4g} applications; "
                 f"limiting: {r.get('limiting_mechanism', 'unknown')}")
    faults = ", ".join(f"{k} {v}" for k, v in sorted(entry["input_faults"].items())) or "none"
    lines = [f"{entry['unit']}: {entry['duty_cycles']} brake applications",
             f"  wear depth: screw raceway {w['screw_raceway_m'] * 1e6:.4g} µm, nut raceway "
             f"{w['nut_raceway_m'] * 1e6:.4g} µm, balls {w['ball_m'] * 1e6:.4g} µm",
             f"  clearance x_ag: model {mm(c['model_m'])}, estimate {mm(c['estimate_m'])} ± {mm(c['std_m'])}"
             f" (limit {mm(r['limit_m'])})",
             f"  remaining life: {life}",
             f"  input faults: {faults}"]
    p = entry.get("prognostics")
    if p and p["predictions"]:
        horizon = "—" if p["prognostic_horizon_cycles"] is None else f"{p['prognostic_horizon_cycles']:.4g}"
        lines.append(f"  vs ground truth (end of life at {p['eol_cycles']:.4g} applications): cumulative "
                     f"relative accuracy {p['cumulative_relative_accuracy']:.3g}, share in the alpha cone "
                     f"{p['alpha_lambda_fraction']:.2f}, prognostic horizon {horizon} applications, "
                     f"alpha-lambda {_PASS[p['alpha_lambda_pass']]}")
    elif p:
        lines.append(f"  vs ground truth (end of life at {p['eol_cycles']:.4g} applications): no prediction "
                     "to judge yet")
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    """Replay, print, write JSON and report."""
    from ebm_wear_monitor.outputs import write_json
    from ebm_wear_monitor.params import load_unit
    from ebm_wear_monitor.replay.config import load_monitor_config
    from ebm_wear_monitor.replay.run import replay_bags

    check_outputs(args)
    params = load_unit(args.params)
    config = load_monitor_config(args.config) if args.config else None
    with progress(args, None, "replay", "msg") as bar:
        def total(n: int) -> None:  # known once the bags are open: from their own indexes
            bar.total = n
            bar.refresh()

        result = replay_bags(args.bags, params, config=config, progress=bar.update, total=total,
                             stamps=args.stamps, strict=args.strict)
    for unit in result.units:
        print(format_unit(unit.to_json_dict()))
    for where, why in result.rejected.items():
        print(f"skipped {where}: {why}")
    for problem in result.problems:
        print(f"storage: {problem}")
    if args.json:
        write_json(args.json, result.to_json_dict())
    if args.report:
        from ebm_wear_monitor.replay.report import write_replay_report

        write_replay_report(args.report, result.units, result.rejected)
        print(f"report: {Path(args.report) / 'index.html'}")
    return 0
