"""``ebm-wear fleet DIR [--params P] [--scheduler ADDRESS] [--out DIR] [--json OUT] [--report DIR]``.

Every unit folder under DIR (``<train>/<car>/<embu>/<date>.bag``) runs through
the monitor core as one Dask task, on an embedded local cluster sized to the
machine or on an existing scheduler (``--scheduler``: any address form Dask accepts,
:func:`ebm_wear_monitor.fleet.cluster.scheduler_address`).
Incremental and resumable: units whose bags (by content hash) and parameters
are unchanged since the last run into the same ``--out`` are skipped; an
interrupted run continues where it stopped. A failing bag is reported with its
reason and the fleet continues. ``--generate N`` first writes a synthetic
fleet of N units into DIR through the digital twin (demos and tests), with its
accelerated-life unit file ``DIR/params.yaml`` (used by default for DIR).
Outputs in ``--out``: ``units.parquet``, ``applications.parquet``,
``fleet_summary.csv`` (ranked by urgency), ``fleet.json``, ``manifest.json``, ``units/``
(per-unit results); the dashboard ``report/index.html`` (or ``--report DIR``). Every destination
is checked (exists or can be created, writable) before the cluster starts; DIR must be readable
throughout (an unreadable folder is an error, never silently skipped).
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from ebm_wear_monitor.cli.options import add_output_options, check_outputs, progress
from ebm_wear_monitor.errors import InputError


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Arguments of ``ebm-wear fleet``."""
    parser.add_argument("dir", metavar="DIR", help="fleet directory tree of units' bags")
    parser.add_argument("--params", metavar="P", default=None,
                        help="unit parameter YAML, or a reference name (default: DIR/params.yaml if "
                             "present, as --generate writes it, else embu_000)")
    parser.add_argument("--config", metavar="FILE",
                        help="monitor-core thresholds: the node's ROS parameter file or a flat mapping")
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help="existing Dask scheduler (host:port, tcp://host:port); default: a local cluster")
    parser.add_argument("--workers", type=int, default=None, metavar="N",
                        help="worker processes of the local cluster (default: one per CPU core)")
    parser.add_argument("--out", metavar="DIR", default="fleet_out",
                        help="output directory of tables and per-unit results (default: fleet_out)")
    add_output_options(parser, report_default="OUT/report")
    parser.add_argument("--generate", type=int, metavar="N",
                        help="first write a synthetic fleet of N units into DIR (DIR must not exist)")
    parser.add_argument("--seed", type=int, default=0, help="seed of --generate (default 0)")
    parser.add_argument("--cycles-per-bag", type=int, default=12, help="--generate: applications per bag")
    parser.add_argument("--bags-per-unit", type=int, default=2, help="--generate: bags (days) per unit")
    parser.add_argument("--rate", type=float, default=200.0, help="--generate: sample rate [Hz], 100..20000")


def _check(args: argparse.Namespace) -> None:
    """Every argument and destination, before the cluster starts (InputError, one line)."""
    from ebm_wear_monitor.fleet.cluster import scheduler_address
    from ebm_wear_monitor.outputs import check_destination

    check_outputs(args)
    check_destination(args.out, "--out", directory=True)
    if args.workers is not None and args.workers < 1:
        raise InputError(f"--workers must be >= 1, got {args.workers}")
    if args.scheduler:
        scheduler_address(args.scheduler)
    if args.generate is not None:
        if (args.generate < 1 or args.cycles_per_bag < 2 or args.bags_per_unit < 1
                or not 100 <= args.rate <= 20e3):
            raise InputError("--generate needs N >= 1, --cycles-per-bag >= 2, --bags-per-unit >= 1, "
                             "--rate 100..20000 Hz")
        if Path(args.dir).exists():
            raise InputError(f"{args.dir}: exists already; --generate writes a new fleet directory")
        check_destination(args.dir, "DIR", directory=True)
        return
    if not Path(args.dir).is_dir():
        raise InputError(f"{args.dir}: not a directory")
    try:
        os.listdir(args.dir)
    except OSError as exc:
        raise InputError(f"{args.dir}: cannot read the fleet directory ({exc.strerror or exc})") from None


def run(args: argparse.Namespace) -> int:
    """Run the fleet pipeline and print the ranking and failures."""
    from ebm_wear_monitor.fleet.cluster import dask_client
    from ebm_wear_monitor.fleet.manifest import Manifest
    from ebm_wear_monitor.fleet.pipeline import run_fleet
    from ebm_wear_monitor.fleet.report import unit_entries, write_fleet_report
    from ebm_wear_monitor.fleet.synthetic import generate_fleet, scenarios
    from ebm_wear_monitor.fleet.tables import assemble, write_tables
    from ebm_wear_monitor.outputs import write_json
    from ebm_wear_monitor.params import load_unit
    from ebm_wear_monitor.replay.config import load_monitor_config
    from ebm_wear_monitor.reports.life import life_view

    _check(args)
    fleet_params = Path(args.dir) / "params.yaml"
    params = load_unit(args.params if args.params or not fleet_params.is_file() else fleet_params)
    config = load_monitor_config(args.config) if args.config else None
    out = Path(args.out)
    report = Path(args.report) if args.report else out / "report"
    with dask_client(args.scheduler, args.workers) as client:
        if args.generate is not None:
            units = scenarios(args.generate, args.seed, cycles_per_bag=args.cycles_per_bag,
                              bags_per_unit=args.bags_per_unit, rate_hz=args.rate)
            with progress(args, len(units), "generate", "unit") as bar:
                params, bags = generate_fleet(args.dir, units, params, client=client, on_unit=bar.update)
            print(f"generated {len(units)} units, {len(bags)} bags in {args.dir} (unit file: {fleet_params})")
        with progress(args, None, "fleet", "unit") as bar:
            fleet = run_fleet(client, args.dir, out, params, config=config,
                              on_unit=lambda _: bar.update(), on_start=bar.reset)
    tables = assemble(out, list(fleet.units), Manifest.load(out))
    write_tables(out, tables)
    write_fleet_report(report, tables, f"ebm_wear_monitor fleet: {args.dir}")
    if args.json:
        write_json(args.json, tables.document)
    print(f"{len(fleet.units)} units: {len(fleet.processed)} processed, "
          f"{len(fleet.skipped)} unchanged (skipped)")
    for _, row in tables.units.head(10).iterrows():
        view = life_view(*unit_entries(row), "failed" if row["status"] == "failed" else None)
        print(f"{row['rank']:>5d}  {row['unit']:<28s} clearance {view.clearance} "
              f"({view.fraction_text} of limit); life {view.line()}")
    for failure in tables.document["failures"]:
        print(f"failed: {failure['unit']} {failure['bag'] or ''}: {failure['reason']}")
    print(f"outputs in {out}: units.parquet, applications.parquet, fleet_summary.csv, fleet.json; "
          f"dashboard: {report / 'index.html'}")
    return 0
