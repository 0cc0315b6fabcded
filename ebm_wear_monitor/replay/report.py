"""The replay report: one HTML page with PNG plots per unit.

Plots per unit: cumulative wear depths against brake applications (000 eq.
20-23 accumulated by the monitor core); the observed axial clearance with the
filter's estimate and its +-2 sigma band, the model's clearance and the limit;
the remaining-life distribution (p05-p95 band and median after each
application, with the true remaining life and the alpha cone of
``replay.prognostics`` when the simulator's ground truth is known); the input
faults counted by kind. Figures use matplotlib's object API (``Figure``, Agg
canvas): no pyplot state, safe in worker processes.
"""

from __future__ import annotations

import html
import os
import re
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from ebm_wear_monitor.outputs import publish_directory
from ebm_wear_monitor.replay.prognostics import ALPHA
from ebm_wear_monitor.replay.result import UnitReplay

_UM = 1e6  # m -> µm for axis labels
_CSS = ("body{font-family:sans-serif;max-width:1100px;margin:auto;padding:1em}"
        "table{border-collapse:collapse;font-size:90%}td,th{border:1px solid #bbb;padding:2px 6px;"
        "text-align:right}img{max-width:49%}h2{border-bottom:1px solid #888}.bad{color:#b00}")


def slug(name: str) -> str:
    """File-name-safe form of a unit name ('/train7/car3/embu2' -> 'train7_car3_embu2')."""
    return re.sub(r"[^A-Za-z0-9._-]+", "_", name.strip("/")) or "root"


def save_png(fig: Figure, path: Path) -> str:
    """Write ``fig`` as PNG at ``path``; returns the file name for the page."""
    fig.savefig(path, format="png", dpi=90, bbox_inches="tight")
    return path.name


def _axes(title: str, xlabel: str, ylabel: str) -> tuple[Figure, object]:
    fig = Figure(figsize=(6.4, 3.8))
    ax = fig.add_subplot()
    ax.set(title=title, xlabel=xlabel, ylabel=ylabel)
    ax.grid(alpha=0.3)
    return fig, ax


def wear_figure(app: pd.DataFrame) -> Figure:
    """Cumulative wear depth of screw raceway, nut raceway and balls [µm] against applications."""
    fig, ax = _axes("Wear depth", "brake applications [-]", "wear depth [µm]")
    for col, label in (("screw_raceway_m", "screw raceway"), ("nut_raceway_m", "nut raceway"),
                       ("ball_m", "balls")):
        ax.plot(app["index"], app[col] * _UM, label=label)
    ax.legend()
    return fig


def clearance_figure(app: pd.DataFrame, limit_m: float | None) -> Figure:
    """Observed clearance x_ag, filter estimate with +-2 sigma band, model and limit [mm]."""
    fig, ax = _axes("Axial clearance x_ag", "brake applications [-]", "clearance [mm]")
    k, est, std = app["index"], app["clearance_estimate_m"] * 1e3, app["clearance_std_m"] * 1e3
    ax.plot(k, app["clearance_observed_m"] * 1e3, ".", ms=3, alpha=0.5, label="observed")
    ax.plot(k, app["clearance_model_m"] * 1e3, "--", label="wear model")
    ax.plot(k, est, label="filter estimate")
    ax.fill_between(k, est - 2 * std, est + 2 * std, alpha=0.25, label="±2σ")
    if limit_m is not None:
        ax.axhline(limit_m * 1e3, color="r", lw=1, label="limit")
    ax.legend(fontsize=8)
    return fig


def rul_figure(app: pd.DataFrame, truth: dict | None) -> Figure:
    """Remaining-life distribution after each application: p05-p95 band, median; truth and alpha cone."""
    fig, ax = _axes("Remaining life to the clearance limit", "brake applications [-]",
                    "remaining applications [-]")
    k = app["index"].to_numpy(float)
    ax.fill_between(k, app["cycles_p05"], app["cycles_p95"], alpha=0.3, label="p05-p95")
    ax.plot(k, app["cycles_p50"], label="median")
    if truth is not None and truth.get("eol_cycles") is not None:
        # k counts the applications of this replay; the truth counts since new
        true_rul = truth["eol_cycles"] - (k + float(truth.get("cycles_at_start") or 0))
        ax.plot(k, true_rul, "k--", label="true")
        ax.fill_between(k, (1 - ALPHA) * true_rul, (1 + ALPHA) * true_rul, color="k", alpha=0.08,
                        label=f"±{ALPHA:.0%} cone")
    if np.isfinite(app["cycles_p95"].to_numpy(float)).any():
        ax.set_yscale("log")
    ax.legend(fontsize=8)
    return fig


def faults_figure(faults: dict[str, int], title: str = "Input faults") -> Figure:
    """Bar chart of input-fault counts by kind."""
    fig, ax = _axes(title, "", "count [-]")
    names = sorted(faults)
    ax.bar(range(len(names)), [faults[n] for n in names])
    ax.set_xticks(range(len(names)), names, rotation=30, ha="right", fontsize=8)
    if not names:
        ax.text(0.5, 0.5, "none", ha="center", va="center", transform=ax.transAxes)
    return fig


def _num(value: object, scale: float = 1.0, fmt: str = "{:.4g}") -> str:
    if value is None or (isinstance(value, float) and not np.isfinite(value)):
        return "—"
    return fmt.format(value * scale) if isinstance(value, (int, float)) else html.escape(str(value))


def summary_table(entry: dict) -> str:
    """HTML table of one unit's section 4 entry (lengths in µm/mm, cycles as counts)."""
    w, c, r = entry["wear"], entry["clearance"], entry["remaining_life"]
    rows = [("brake applications", _num(entry["duty_cycles"], fmt="{:.0f}")),
            ("wear screw / nut / ball [µm]", " / ".join(_num(w[k], _UM) for k in
                                                      ("screw_raceway_m", "nut_raceway_m", "ball_m"))),
            ("clearance model / estimate ± std [mm]",
             f"{_num(c['model_m'], 1e3)} / {_num(c['estimate_m'], 1e3)} ± {_num(c['std_m'], 1e3)}"),
            ("clearance limit [mm]", _num(r.get("limit_m"), 1e3)),
            ("remaining applications p05 / p50 / p95",
             " / ".join(_num(r.get(k), fmt="{:.3g}") for k in ("cycles_p05", "cycles_p50", "cycles_p95")))]
    cells = "".join(f"<tr><th>{html.escape(a)}</th><td>{b}</td></tr>" for a, b in rows)
    return f"<table>{cells}</table>"


def dict_table(data: dict, title: str) -> str:
    """Two-column HTML table of a flat dict."""
    cells = "".join(f"<tr><th>{html.escape(str(k))}</th><td>{_num(v)}</td></tr>" for k, v in data.items())
    return f"<h3>{html.escape(title)}</h3><table>{cells}</table>"


def page(title: str, body: str) -> str:
    """A complete HTML page."""
    return (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>"
            f"<style>{_CSS}</style></head><body><h1>{html.escape(title)}</h1>{body}</body></html>\n")


def unit_section(unit: UnitReplay, out: Path, prefix: str = "") -> str:
    """Plots (PNG files in ``out``) and tables of one unit as an HTML fragment."""
    name = prefix + slug(unit.unit)
    app = unit.applications
    figures = {"faults": faults_figure(unit.summary.get("input_faults", {}))}
    if len(app):
        figures = {"wear": wear_figure(app),
                   "clearance": clearance_figure(app, unit.summary["remaining_life"].get("limit_m")),
                   "rul": rul_figure(app, unit.truth), **figures}
    images = "".join(f"<img src='{save_png(f, out / f'{name}_{k}.png')}' alt='{k}'>"
                     for k, f in figures.items())
    parts = [f"<h2>{html.escape(unit.unit)}</h2>", summary_table(unit.summary), images]
    if unit.prognostics is not None:
        parts.append(dict_table(unit.prognostics, "Prognostics metrics against the simulator's ground truth"))
    parts.append(f"<p>bags: {html.escape(', '.join(unit.bags))}; messages: {unit.messages}</p>")
    return "".join(parts)


def write_replay_report(report_dir: str | os.PathLike, units: Sequence[UnitReplay],
                        rejected: dict[str, str] | None = None) -> Path:
    """Write ``index.html`` and its PNG plots into ``report_dir`` (atomically per file)."""
    def build(tmp: Path) -> None:
        body = "".join(unit_section(u, tmp) for u in units)
        if rejected:
            body += dict_table(rejected, "Skipped topics (wrong message type)")
        (tmp / "index.html").write_text(page("ebm_wear_monitor replay", body), encoding="utf-8")
    return publish_directory(build, report_dir)
