"""Fleet outputs assembled from the per-unit result files: Parquet tables, ranked summary, JSON.

Written into OUT (each file atomically):

* ``units.parquet``: one row per unit (the section 4 entry flattened, SI units, plus
  ``status`` = the remaining-life status, or ``failed``; ``job`` = done | failed; ``error``;
  ``clearance_fraction`` = estimate / limit; bag count; prognostics metrics when ground truth is
  known), ranked by urgency (:func:`rank_units`): status (due, warn, then ok and
  insufficient_data), then p05 remaining life ascending, then, for units without a measurable
  trend, clearance fraction descending; failed units last;
* ``applications.parquet``: one row per unit and completed brake application
  (columns of ``replay.result.APPLICATION_COLUMNS`` plus ``unit``);
* ``fleet_summary.csv``: the ranking for people (rank, unit, p05/p50/p95, clearance, status, reason);
* ``fleet.json``: the replay layout of interface.md section 4 with ``unit`` the
  folder relative to DIR, plus ``failures`` (unit, bag, reason).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ebm_wear_monitor.fleet.manifest import Manifest
from ebm_wear_monitor.outputs import atomic_write, write_json
from ebm_wear_monitor.schema import json_row
from ebm_wear_monitor.schema.monitor import STATUS_INSUFFICIENT, MonitorSnapshot
from ebm_wear_monitor.schema.replay import Prognostics, ReplayEntry

SUMMARY_COLUMNS = ["rank", "unit", "status", "cycles_p05", "cycles_p50", "cycles_p95", "clearance_estimate_m",
                   "clearance_std_m", "limit_m", "clearance_fraction", "duty_cycles", "input_faults_total",
                   "bags", "error"]

#: columns that stay text even when every value is null
TEXT_COLUMNS = ["unit", "status", "job", "error", "input_faults", "input_faults_by_signal",
                "limiting_mechanism"]
#: urgency of a status (0 = most urgent); unknown statuses rank with ok
SEVERITY = {"due": 0, "limit_reached": 0, "warn": 1, "ok": 2, "insufficient_data": 2, "failed": 3}


@dataclass
class FleetTables:
    """The assembled fleet outputs in memory."""

    units: pd.DataFrame
    applications: pd.DataFrame
    document: dict


def flatten(entry: dict) -> dict:
    """One units-table row from a section 4 entry (columns declared in schema/: ``units``), plus the
    fleet's own: ``clearance_fraction``, the bag count."""
    row = json_row("units", ReplayEntry, entry) | json_row("units", MonitorSnapshot, entry)
    if row["status"] is None:
        row["status"] = STATUS_INSUFFICIENT
    est, limit = row["clearance_estimate_m"], row["limit_m"]
    row["clearance_fraction"] = None
    if isinstance(est, float | int) and isinstance(limit, float | int) and limit:
        row["clearance_fraction"] = est / limit
    row["bags"] = len(entry.get("bags", []))
    if entry.get("prognostics") is not None:
        row |= json_row("units", Prognostics, entry["prognostics"])
    return row


def _numeric(frame: pd.DataFrame) -> pd.DataFrame:
    """Columns holding only numbers and nulls (None from JSON) as float/int columns (NaN for null)."""
    for col in frame.columns.difference(TEXT_COLUMNS):
        values = frame[col]
        if values.map(lambda v: v is None or (isinstance(v, (int, float)) and not isinstance(v, bool))).all():
            frame[col] = pd.to_numeric(values, errors="coerce")
    return frame


def rank_units(units: pd.DataFrame) -> pd.DataFrame:
    """``units`` sorted most urgent first, with a ``rank`` column (module docstring)."""
    keys = pd.DataFrame({
        "severity": units["status"].map(SEVERITY).fillna(SEVERITY["ok"]),
        "p05": pd.to_numeric(units["cycles_p05"], errors="coerce"),
        "fraction": -pd.to_numeric(units["clearance_fraction"], errors="coerce"),
        "unit": units["unit"]}, index=units.index)
    units = units.loc[keys.sort_values(["severity", "p05", "fraction", "unit"], na_position="last").index]
    units.insert(0, "rank", np.arange(1, len(units) + 1))
    return units.reset_index(drop=True)


def assemble(out: Path, folders: list[str], manifest: Manifest) -> FleetTables:
    """Gather the result files of ``folders`` (the units found in DIR now) into the fleet outputs."""
    rows, apps, entries, failures = [], [], [], []
    for folder in folders:
        info = manifest.units.get(folder)
        if info is None:
            continue
        result = json.loads((out / info["file"]).read_text(encoding="utf-8"))
        failures += [{"unit": folder, "bag": bag, "reason": why}
                     for bag, why in result["failed_bags"].items()]
        if result["error"]:
            if not result["failed_bags"]:
                failures.append({"unit": folder, "bag": None, "reason": result["error"]})
            rows.append({"unit": folder, "status": "failed", "job": "failed", "error": result["error"]})
            continue
        for entry in result["entries"]:
            entries.append(entry)
            rows.append({**flatten(entry), "job": "done", "error": None})
        parquet = out / info["file"].replace(".json", ".parquet")
        if parquet.exists():
            apps.append(pd.read_parquet(parquet))
    columns = list(dict.fromkeys([*SUMMARY_COLUMNS[1:], *(k for r in rows for k in r)]))
    units = rank_units(_numeric(pd.DataFrame(rows, columns=columns)))
    applications = pd.concat(apps, ignore_index=True) if apps else pd.DataFrame()
    by_unit = {e["unit"]: e for e in entries}
    document = {"units": [by_unit[u] for u in units["unit"] if u in by_unit], "failures": failures}
    return FleetTables(units, applications, document)


def write_tables(out: Path, tables: FleetTables) -> None:
    """Write the Parquet tables, the ranked CSV summary and ``fleet.json`` into ``out``."""
    atomic_write(out / "units.parquet", lambda tmp: tables.units.to_parquet(tmp, index=False))
    atomic_write(out / "applications.parquet", lambda tmp: tables.applications.to_parquet(tmp, index=False))
    atomic_write(out / "fleet_summary.csv",
                 lambda tmp: tables.units[SUMMARY_COLUMNS].to_csv(tmp, index=False, float_format="%.6g"))
    write_json(out / "fleet.json", tables.document)
