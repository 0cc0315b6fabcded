"""The replay report: one self-contained HTML page (``index.html``) with interactive figures per unit.

It answers "how worn, when due, how sure" (:mod:`ebm_wear_monitor.reports.life`): a status light,
the clearance against its limit, the remaining life in brake applications and in calendar time at
the observed usage (with a caveat when that usage was observed for less than a day); the clearance
figure shows every observation on top of the filter's estimate and ±2σ band, the wear model's line
with the reason for its offset, and the projection to the limit with its p05-p95 fan; then the
remaining life after each application (with the truth and the alpha cone of
:mod:`ebm_wear_monitor.replay.prognostics` when the simulator's ground truth is known), the wear
depths, the input faults per topic and kind, and the prognostics metrics in words. Templates and
stylesheet: :mod:`ebm_wear_monitor.reports`.
"""

from __future__ import annotations

import os
import re
from collections.abc import Sequence
from pathlib import Path

from ebm_wear_monitor.outputs import publish_directory
from ebm_wear_monitor.replay.prognostics import ALPHA
from ebm_wear_monitor.replay.result import UnitReplay
from ebm_wear_monitor.reports import figures, render_page
from ebm_wear_monitor.reports.humanize import NA, count, known, percent, um
from ebm_wear_monitor.reports.life import life_view


def slug(name: str) -> str:
    """File-name-safe form of a unit name ('/train7/car3/embu2' -> 'train7_car3_embu2')."""
    return re.sub(r"[^A-Za-z0-9._-]+", "_", name.strip("/")) or "root"


def _yes_no(value: object, missing: str) -> str:
    return missing if value is None else ("passed" if value else "failed")


def prognostics_rows(p: dict) -> list[tuple[str, str]]:
    """The prognostics metrics (``replay.prognostics``) as (label, words) rows."""
    ph = p.get("prognostic_horizon_cycles")
    return [
        ("true end of life (simulator)", f"after {count(p.get('eol_cycles'))} applications since new"),
        ("predictions judged", count(p.get("predictions"))),
        ("first prediction", f"after {count(p.get('first_prediction_cycles'))} applications since new"
         if known(p.get("first_prediction_cycles")) else NA),
        (f"prognostic horizon (band ±{percent(p.get('alpha_ph'))} of end of life)",
         f"{count(ph)} applications before end of life" if known(ph)
         else "not reached: the last prediction is still outside the band"),
        (f"α-λ accuracy (±{percent(p.get('alpha'))} at λ = {p.get('lambda')})",
         _yes_no(p.get("alpha_lambda_pass"), "not judged: the recording ends before λ")),
        (f"share of predictions within ±{percent(p.get('alpha'))} of the truth",
         percent(p.get("alpha_lambda_fraction"))),
        ("relative accuracy at λ", f"{p['relative_accuracy']:.3f}" if known(p.get("relative_accuracy"))
         else "not judged: the recording ends before λ"),
        ("cumulative relative accuracy (1 = perfect)", f"{p['cumulative_relative_accuracy']:.3f}"
         if known(p.get("cumulative_relative_accuracy")) else NA),
    ]


def detail_rows(entry: dict) -> list[tuple[str, str]]:
    """Wear depths, filter factor, fatigue life and the mechanism that limits the unit, in words."""
    w, c, r = entry["wear"], entry["clearance"], entry["remaining_life"]
    f, f_std = c.get("wear_rate_factor"), c.get("wear_rate_factor_std")
    g, g_std = r.get("growth_rate_m_per_cycle"), r.get("growth_rate_std_m_per_cycle")
    return [
        ("brake applications", count(entry["duty_cycles"])),
        ("wear depth: screw raceway / nut raceway / balls",
         f"{um(w['screw_raceway_m'])} / {um(w['nut_raceway_m'])} / {um(w['ball_m'])}"),
        ("clearance growth per 1,000 applications (learned)",
         f"{um(g * 1e3)} ± {um(g_std * 1e3)}" if known(g) and known(g_std) else NA),
        ("wear-rate correction of the model (filter)",
         f"× {f:.3f} ± {f_std:.3f}" if known(f) and known(f_std) else NA),
        ("fatigue life left (ISO 3408-5 L10)", f"{count(r.get('fatigue_remaining_cycles'))} applications"
         if known(r.get("fatigue_remaining_cycles")) else NA),
        ("limiting mechanism", str(r.get("limiting_mechanism") or NA)),
        ("input messages", count(entry.get("messages"))),
        ("bags", ", ".join(entry.get("bags", [])) or NA),
    ]


def unit_context(unit: UnitReplay) -> dict:
    """Everything the template shows of one unit."""
    entry = unit.to_json_dict()
    rl, app = entry["remaining_life"], unit.applications
    return {
        "name": unit.unit,
        "view": life_view(rl, entry["clearance"]),
        "figures": {"clearance": figures.clearance_figure(app, rl),
                    "rul": figures.rul_figure(app, unit.truth, ALPHA), "wear": figures.wear_figure(app),
                    "faults": figures.faults_figure(entry.get("input_faults_by_signal") or {})},
        "projected": known(rl.get("cycles_p50")),
        "model_text": figures.model_offset_text(app),
        "has_truth": bool(unit.truth and unit.truth.get("eol_cycles") is not None),
        "alpha_pct": percent(ALPHA),
        "details": detail_rows(entry),
        "prognostics": prognostics_rows(entry["prognostics"]) if "prognostics" in entry else [],
    }


def write_replay_report(report_dir: str | os.PathLike, units: Sequence[UnitReplay],
                        rejected: dict[str, str] | None = None) -> Path:
    """Write ``index.html`` (self-contained) into ``report_dir`` (atomically)."""
    bags = sorted({b for u in units for b in u.bags})
    html = render_page("replay.html", "Ball-screw wear: replay", subtitle=", ".join(bags), plotly=True,
                       units=[unit_context(u) for u in units], bags=", ".join(bags) or "no bag",
                       rejected=sorted((rejected or {}).items()))

    def build(tmp: Path) -> None:
        (tmp / "index.html").write_text(html, encoding="utf-8")
    return publish_directory(build, report_dir)
