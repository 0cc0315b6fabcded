"""The fleet dashboard: one self-contained HTML file (``OUT/report/index.html`` or ``--report DIR``).

Opens without network access (stylesheet and Plotly inlined, :mod:`ebm_wear_monitor.reports`).
Content: the count of units per status (lights); an overview of clearance (% of its limit)
against p05 remaining life; a sortable, filterable table of every unit (train, car, unit, status,
clearance and % of limit, remaining life p05/p50 in applications, p50 in calendar time at the
observed usage, input faults), ranked by urgency as in ``units.parquet``
(:func:`ebm_wear_monitor.fleet.tables.rank_units`: units without a measurable trend by clearance
fraction); a drill-down per unit (click a row): its remaining life in words, its clearance
history with the projection to the limit (the replay report's figure) and its input faults per
signal; the failures with their reasons; prognostics metrics when the bags carry ground truth.
Per-unit histories are thinned to at most :data:`MAX_POINTS` applications in the page.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pandas as pd

from ebm_wear_monitor.fleet.tables import SEVERITY, FleetTables
from ebm_wear_monitor.outputs import jsonable, publish_directory
from ebm_wear_monitor.reports import figures, render_page
from ebm_wear_monitor.reports.humanize import NA, count, known, percent
from ebm_wear_monitor.reports.life import life_view

#: applications per unit kept in the page (evenly thinned, first and last kept)
MAX_POINTS = 400
_COLORS = {"ok": "#2e7d32", "warn": "#ef6c00", "due": "#c62828", "nodata": "#757575", "failed": "#6a1b9a"}


def _num(value: object) -> float | None:
    return float(value) if known(value) else None


def _thin(app: pd.DataFrame) -> pd.DataFrame:
    if len(app) <= MAX_POINTS:
        return app
    return app.iloc[np.unique(np.linspace(0, len(app) - 1, MAX_POINTS).round().astype(int))]


def _parts(unit: str) -> tuple[str, str, str]:
    """(train, car, unit) of a fleet folder ``train/car/embu[...]``; fewer levels leave blanks."""
    parts = unit.split("/")
    return (parts[0], parts[1], "/".join(parts[2:])) if len(parts) >= 3 else ("", "", unit)


def unit_entries(row: pd.Series) -> tuple[dict, dict]:
    """(remaining_life, clearance) entries of a units-table row (SI, None for missing)."""
    rl = {k: _num(row.get(k)) for k in ("limit_m", "cycles_p05", "cycles_p50", "cycles_p95", "seconds_p05",
                                       "seconds_p50", "seconds_p95", "usage_span_s", "applications_per_hour",
                                       "hours_p50")}
    rl["status"] = row.get("status")
    return rl, {k: _num(row.get(f"clearance_{k}")) for k in ("estimate_m", "std_m")}


def unit_rows(tables: FleetTables) -> tuple[list[dict], dict[str, dict]]:
    """Table rows (display text and sort keys) and drill-down data per unit."""
    units, apps = tables.units, tables.applications
    by_unit = dict(iter(apps.groupby("unit"))) if len(apps) else {}
    rows, drill = [], {}
    for _, row in units.iterrows():
        name = str(row["unit"])
        rl, clearance = unit_entries(row)
        view = life_view(rl, clearance, "failed" if row["status"] == "failed" else None)
        seconds = rl["seconds_p50"] if rl["seconds_p50"] is not None else (
            rl["hours_p50"] * 3600.0 if rl["hours_p50"] is not None else None)
        train, car, embu = _parts(name)
        faults = json.loads(row["input_faults"]) if isinstance(row.get("input_faults"), str) else {}
        rows.append({"rank": int(row["rank"]), "unit": name, "train": train, "car": car, "embu": embu,
                     "status": view.status, "status_words": view.status_words,
                     "status_class": view.status_class,
                     "clearance": _num(row.get("clearance_estimate_m")), "fraction": view.fraction,
                     "p05": rl["cycles_p05"], "p50": rl["cycles_p50"], "seconds": seconds,
                     "faults": _num(row.get("input_faults_total")), "error": row.get("error")})
        app = _thin(by_unit[name]) if name in by_unit else pd.DataFrame()
        by_signal = row.get("input_faults_by_signal")
        by_signal = json.loads(by_signal) if isinstance(by_signal, str) else {"all signals": faults}
        drill[name] = {"view": view.__dict__,
                       "error": row.get("error") if row["status"] == "failed" else None,
                       "clearance": figures.clearance_figure(app, rl) if len(app) else None,
                       "faults": figures.faults_figure(by_signal),
                       "model_text": figures.model_offset_text(app) if len(app) else ""}
    return rows, jsonable(drill)


def overview_figure(rows: list[dict]) -> dict | None:
    """Clearance (% of its limit) against p05 remaining applications, one colour per status."""
    with_life = [r for r in rows if r["p05"] is not None and r["fraction"] is not None]
    if not with_life:
        return None
    data = []
    for css, color in _COLORS.items():
        sel = [r for r in with_life if r["status_class"] == css]
        if sel:
            data.append({"x": [100 * r["fraction"] for r in sel], "y": [r["p05"] for r in sel],
                         "text": [r["unit"] for r in sel], "mode": "markers", "type": "scatter",
                         "name": sel[0]["status_words"], "marker": {"color": color, "size": 9},
                         "hovertemplate": "%{text}<br>%{x:.0f} % of limit<br>p05 %{y:,.0f}<extra></extra>"})
    layout = {"xaxis": {"title": {"text": "axial clearance [% of its limit]"}},
              "yaxis": figures.value_axis("remaining brake applications, p05", [r["p05"] for r in with_life]),
              "margin": {"l": 80, "r": 20, "t": 20, "b": 50}, "template": "plotly_white",
              "legend": {"orientation": "h", "y": -0.25}, "hovermode": "closest"}
    return {"data": data, "layout": layout}


def prognostics_rows(units: pd.DataFrame) -> list[tuple[str, str]]:
    """Fleet-level prognostics metrics in words (only units whose bags carry ground truth)."""
    if "prognostics_predictions" not in units.columns:
        return []
    judged = units[pd.to_numeric(units["prognostics_predictions"], errors="coerce").fillna(0) > 0]
    rows = [("units with ground truth", count(int(units["prognostics_eol_cycles"].notna().sum()))),
            ("units judged (with predictions)", count(len(judged)))]
    for key, label, fmt in (
            ("cumulative_relative_accuracy", "median cumulative relative accuracy (1 = perfect)",
             lambda v: f"{v:.3f}"),
            ("alpha_lambda_fraction", "median share of predictions within ±20 % of the truth", percent),
            ("prognostic_horizon_cycles", "median prognostic horizon", lambda v: f"{count(v)} applications")):
        col = pd.to_numeric(judged.get(f"prognostics_{key}"), errors="coerce")
        rows.append((label, fmt(float(col.median())) if col is not None and col.notna().any() else NA))
    passes = judged.get("prognostics_alpha_lambda_pass")
    judged_passes = passes.dropna() if passes is not None else pd.Series(dtype=object)
    passed = int(judged_passes.astype(bool).sum())
    rows.append(("α-λ test passed", f"{passed} of {len(judged_passes)} units judged" if len(judged_passes)
                 else "no unit judged: the recordings end before λ"))
    return rows


def write_fleet_report(report_dir: str | os.PathLike, tables: FleetTables, title: str) -> Path:
    """Write the dashboard ``index.html`` into ``report_dir`` (atomically)."""
    rows, drill = unit_rows(tables)
    counts: dict[str, int] = {}
    for r in rows:
        counts[r["status"]] = counts.get(r["status"], 0) + 1
    order = sorted(counts, key=lambda s: (SEVERITY.get(s, SEVERITY["ok"]), s))
    html = render_page(
        "fleet.html", "Ball-screw wear: fleet dashboard", subtitle=title, plotly=True, rows=rows,
        drill=drill, counts=[(s, counts[s]) for s in order], overview=overview_figure(rows),
        failures=tables.document["failures"], prognostics=prognostics_rows(tables.units),
        trendless=sum(r["p05"] is None and r["status"] != "failed" for r in rows))

    def build(tmp: Path) -> None:
        (tmp / "index.html").write_text(html, encoding="utf-8")
    return publish_directory(build, report_dir)
