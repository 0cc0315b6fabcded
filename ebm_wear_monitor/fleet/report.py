"""The fleet report: one HTML page with PNG plots over all units (``OUT/report/index.html``).

Plots: distribution of the p05 remaining life across the fleet; the most
urgent units with their p05-p95 interval; estimated clearance against brake
applications per unit, with the limit; input faults summed over the fleet.
Tables: the ranking (most urgent first), failures with their reasons, and the
prognostics metrics when the bags carry the simulator's ground truth.
"""

from __future__ import annotations

import html
import json
import os
from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from ebm_wear_monitor.fleet.tables import SUMMARY_COLUMNS, FleetTables
from ebm_wear_monitor.outputs import publish_directory
from ebm_wear_monitor.replay.report import faults_figure, page, save_png

TOP = 30  # units shown in the urgent-units plot and table


def p05_histogram(units: pd.DataFrame) -> Figure:
    """Histogram of p05 remaining applications over the units that have one (log bins)."""
    fig = Figure(figsize=(6.4, 3.8))
    ax = fig.add_subplot()
    p05 = pd.to_numeric(units["cycles_p05"], errors="coerce").dropna().to_numpy(float)
    p05 = p05[p05 > 0]
    if len(p05):
        ax.hist(p05, bins=np.geomspace(p05.min(), p05.max() * 1.0001 + 1e-9, 30))
        ax.set_xscale("log")
    ax.set(title=f"p05 remaining life ({len(p05)} of {len(units)} units)",
           xlabel="remaining brake applications, p05 [-]", ylabel="units [-]")
    return fig


def urgent_figure(units: pd.DataFrame) -> Figure:
    """The TOP most urgent units: p50 with the p05-p95 interval."""
    top = units[pd.to_numeric(units["cycles_p05"], errors="coerce").notna()].head(TOP)
    fig = Figure(figsize=(6.4, max(2.5, 0.22 * len(top) + 1)))
    ax = fig.add_subplot()
    y = np.arange(len(top))[::-1]
    p05, p50, p95 = (top[c].to_numpy(float) for c in ("cycles_p05", "cycles_p50", "cycles_p95"))
    ax.errorbar(p50, y, xerr=[p50 - p05, p95 - p50], fmt="o", ms=3, capsize=2)
    ax.set_yticks(y, top["unit"], fontsize=7)
    if len(top):
        ax.set_xscale("log")
    ax.set(title="Most urgent units (p05-p95, median)", xlabel="remaining brake applications [-]")
    return fig


def clearance_figure(units: pd.DataFrame, applications: pd.DataFrame) -> Figure:
    """Estimated clearance against applications for every unit (thin lines) and the limit."""
    fig = Figure(figsize=(6.4, 3.8))
    ax = fig.add_subplot()
    if len(applications):
        for _, app in applications.groupby("unit"):
            ax.plot(app["index"], app["clearance_estimate_m"] * 1e3, lw=0.6, alpha=0.6)
    limits = pd.to_numeric(units.get("limit_m"), errors="coerce").dropna().unique()
    for limit in limits:
        ax.axhline(limit * 1e3, color="r", lw=1)
    ax.set(title="Estimated axial clearance per unit", xlabel="brake applications [-]",
           ylabel="clearance [mm]")
    ax.grid(alpha=0.3)
    return fig


def _fault_totals(units: pd.DataFrame) -> dict[str, int]:
    totals: dict[str, int] = {}
    for text in units.get("input_faults", pd.Series(dtype=object)).dropna():
        for kind, count in json.loads(text).items():
            totals[kind] = totals.get(kind, 0) + int(count)
    return totals


def _table(frame: pd.DataFrame) -> str:
    return frame.to_html(index=False, float_format=lambda v: f"{v:.4g}", na_rep="—", escape=True)


def prognostics_table(units: pd.DataFrame) -> str:
    """Fleet-level prognostics metrics (only units whose bags carry ground truth)."""
    cols = [c for c in units.columns if c.startswith("prognostics_")]
    if "prognostics_predictions" not in cols:
        return ""
    judged = units[pd.to_numeric(units["prognostics_predictions"], errors="coerce").fillna(0) > 0]
    rows = {"units with ground truth": len(units[units[cols[0]].notna()]), "units judged": len(judged)}
    for key in ("relative_accuracy", "cumulative_relative_accuracy", "alpha_lambda_fraction",
                "prognostic_horizon_cycles"):
        col = pd.to_numeric(judged.get(f"prognostics_{key}"), errors="coerce")
        rows[f"median {key}"] = float(col.median()) if col is not None and col.notna().any() else None
    passes = judged.get("prognostics_alpha_lambda_pass")
    if passes is not None and passes.notna().any():
        rows["alpha-lambda pass rate"] = float(passes.dropna().astype(bool).mean())
    body = "".join(f"<tr><th>{html.escape(k)}</th><td>{'—' if v is None else f'{v:.4g}'}</td></tr>"
                   for k, v in rows.items())
    return f"<h2>Prognostics against ground truth</h2><table>{body}</table>"


def write_fleet_report(report_dir: str | os.PathLike, tables: FleetTables, title: str) -> Path:
    """Write the fleet page and its plots into ``report_dir``."""
    units, apps, failures = tables.units, tables.applications, tables.document["failures"]

    def build(tmp: Path) -> None:
        figures = {"p05": p05_histogram(units), "urgent": urgent_figure(units),
                   "clearance": clearance_figure(units, apps),
                   "faults": faults_figure(_fault_totals(units), "Input faults, whole fleet")}
        images = "".join(f"<img src='{save_png(f, tmp / f'fleet_{k}.png')}' alt='{k}'>"
                         for k, f in figures.items())
        ok = int((units["status"] == "ok").sum())
        body = [f"<p>{ok} units processed, {len(units) - ok} failed, {len(failures)} failure reports.</p>",
                images, f"<h2>Ranking by p05 remaining life (first {TOP})</h2>",
                _table(units[SUMMARY_COLUMNS].head(TOP)), prognostics_table(units)]
        if failures:
            body += ["<h2 class='bad'>Failures</h2>", _table(pd.DataFrame(failures))]
        (tmp / "index.html").write_text(page(title, "".join(body)), encoding="utf-8")
    return publish_directory(build, report_dir)
