"""HTML report of a diagnosis for people: the verdict in words, where the twin misses, what closes it.

``write_report(directory, states)`` writes one self-contained ``index.html`` (the project's shared
templates and stylesheet, :mod:`ebm_wear_monitor.reports`, ``diagnose.html``; Plotly inlined, so it
opens without network access); ``states`` are ``(unit diagnosis, scorer, ranking)``: the typed result
(:class:`~ebm_wear_monitor.schema.diagnose.UnitDiagnosis`) with the scorer and ranking behind it
(:func:`.pipeline.diagnose_with_state`).  Per unit:

* the verdict in plain words with each effect's size relative to nominal (the result's ``summary``);
* the residuals, recorded minus twin, per phase, on the held-out cycles, for the twin as given and
  for the twin with the explaining effects: the torque channel as the current the difference is
  worth [A] (R_T / K_T, 004 eq. 7) and the force channel [N] (:mod:`.residuals`), one point per
  block against the time since the start of its phase; the residual, not an overlay of two signals
  that hides the gap under the signal;
* the torque residual of the verdict's model against the screw angle with the fitted harmonic of the
  open-set test (:mod:`.openset`): a torque that depends on where the screw is, which no catalog
  effect makes;
* the share of the held-out gap each catalog effect closes alone, with its size against its
  detectability floor (:mod:`.tolerance`);
* the acquisition conventions estimated from the data (``nuisances``) in the units people read.

Files are built in a temporary directory and moved into ``directory`` at the end
(:func:`ebm_wear_monitor.outputs.publish_directory`), so a failed run leaves nothing half-written.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from ebm_wear_monitor.diagnosis.pipeline import describe, size_words
from ebm_wear_monitor.diagnosis.ranking import EffectFit, Model, Ranking, Scorer
from ebm_wear_monitor.domain.phases import PHASES
from ebm_wear_monitor.outputs import jsonable, publish_directory
from ebm_wear_monitor.schema.diagnose import UnitDiagnosis

VERDICT_CLASS = {"none": "ok", "effect": "warn", "unexplained": "due"}
VERDICT_WORDS = {"none": "twin explains the data", "effect": "unmodelled effect found",
                 "unexplained": "gap no known effect explains"}
BLUE, RED, GREY = "#1565c0", "#c62828", "#8d6e63"


def _residuals(sc: Scorer, m: Model) -> tuple[np.ndarray, np.ndarray]:
    """Per block, recorded minus model: torque channel as a current [A], force channel [N]."""
    n = sc.model.blocks.size
    z = sc.z_all(m.aug) + sc.D @ m.t
    return z[:n] * sc.sigma_torque / sc.model.nominal.torque_constant, z[n:] * sc.sigma_force


def residual_figure(sc: Scorer, ranking: Ranking) -> dict[str, Any]:
    """Recorded minus twin per phase on the held-out cycles (module docstring), as a Plotly figure dict."""
    mdl, b = sc.model, sc.model.blocks
    t = mdl.rec.t
    run_start = np.concatenate(([True], b.run[1:] != b.run[:-1]))
    start_t = t[b.start][np.maximum.accumulate(np.where(run_start, np.arange(b.size), 0))]
    since = t[b.start] - start_t  # time since the start of the block's phase run [s]
    held = sc.split.heldout
    models = [("twin as given", Model(sc.base.aug), RED)]
    if ranking.explained is not None:
        names = " + ".join(f.effect.name for f in ranking.selected)
        models.append((f"twin with {names}", ranking.explained.model, BLUE))
    data: list[dict[str, Any]] = []
    layout: dict[str, Any] = {"template": "plotly_white", "margin": {"l": 70, "r": 20, "t": 40, "b": 50},
                              "legend": {"orientation": "h", "y": -0.15}, "height": 520}
    for i, phase in enumerate(PHASES):
        for row, what in enumerate(("current", "force")):
            axis = 2 * len(PHASES) * 0 + row * len(PHASES) + i + 1
            sfx = "" if axis == 1 else str(axis)
            layout[f"xaxis{sfx}"] = {"domain": [i / len(PHASES) + 0.02, (i + 1) / len(PHASES) - 0.02],
                                     "anchor": f"y{sfx}", "title": {"text": "s into phase"} if row else {}}
            layout[f"yaxis{sfx}"] = {"domain": [0.0, 0.44] if row else [0.56, 1.0], "anchor": f"x{sfx}",
                                     "zeroline": True,
                                     "title": {"text": ("recorded − twin [A]" if what == "current"
                                                        else "recorded − twin [N]")} if i == 0 else {}}
            rows = held & (b.phase == i) & (b.moving if what == "current" else np.ones(b.size, bool))
            if what == "force":
                rows &= sc.valid(np.ones(b.size, bool), "force")
            for label, m, colour in models:
                cur, force = _residuals(sc, m)
                y = cur if what == "current" else force
                data.append({"type": "scattergl", "mode": "markers", "x": since[rows].tolist(),
                             "y": y[rows].tolist(), "name": label, "legendgroup": label,
                             "showlegend": i == 0 and row == 0, "xaxis": f"x{sfx}", "yaxis": f"y{sfx}",
                             "marker": {"size": 4, "color": colour, "opacity": 0.6}})
        layout.setdefault("annotations", []).append(
            {"text": phase.replace("_", " "), "xref": "paper", "yref": "paper", "showarrow": False,
             "x": (i + 0.5) / len(PHASES), "y": 1.06})
    return jsonable({"data": data, "layout": layout})


def position_figure(sc: Scorer, ranking: Ranking) -> dict[str, Any] | None:
    """The torque residual of the model the open-set test ran on (the selected effects, or the twin within
    its tolerance) against the screw angle on the held-out moving blocks, with the fitted harmonic of
    :mod:`.openset` (None when it was not tested)."""
    o = ranking.open_set
    if o is None:
        return None
    p, mdl, b = o.periodic, sc.model, sc.model.blocks
    rows = sc.split.heldout & b.moving
    angle = b.mean(mdl.rec.angle)  # block mean screw angle [rad]
    grid = np.linspace(angle[rows].min(), angle[rows].max(), 400) if rows.any() else np.zeros(0)
    label = ("twin with " + " + ".join(f.effect.name.replace("_", " ") for f in ranking.selected)
             if o.on_effects else "twin within its tolerance")
    colour = RED if o.decided else GREY
    return jsonable({"data": [
        {"type": "scattergl", "mode": "markers", "x": angle[rows].tolist(),
         "y": p.beyond[rows].tolist(), "name": f"residual of the {label} beyond force and speed terms",
         "marker": {"size": 4, "color": BLUE, "opacity": 0.5}},
        {"type": "scatter", "mode": "lines", "x": grid.tolist(), "y": p.torque(grid).tolist(),
         "name": f"harmonic {p.harmonic} of the screw angle (p = {p.p_value:.2g})",
         "line": {"color": colour, "width": 3}}],
        "layout": {"template": "plotly_white", "height": 340, "margin": {"l": 70, "r": 20, "t": 10, "b": 50},
                   "legend": {"orientation": "h", "y": -0.25},
                   "xaxis": {"title": {"text": "screw angle as recorded [rad]"}},
                   "yaxis": {"title": {"text": "recorded − model torque [N m]"}, "zeroline": True}}})


def shrink_figure(fits: list[EffectFit]) -> dict:
    """The share of the held-out gap each effect closes alone, bars coloured by materiality."""
    names = [f.effect.name.replace("_", " ") for f in fits][::-1]
    shrink = [100.0 * max(f.shrink, 0.0) for f in fits][::-1]
    colours = [BLUE if f.material else GREY for f in fits][::-1]
    return {"data": [{"type": "bar", "orientation": "h", "y": names, "x": shrink,
                      "marker": {"color": colours},
                      "hovertemplate": "%{y}: %{x:.0f} % of the gap<extra></extra>"}],
            "layout": {"template": "plotly_white", "height": 60 + 28 * len(fits),
                       "margin": {"l": 170, "r": 20, "t": 10, "b": 40},
                       "xaxis": {"title": {"text": "share of the held-out gap closed alone [%]"},
                                 "range": [0, 105]}}}


def _quantity(value: float, std: float, unit: str) -> str:
    """A nuisance in the units people read (ms, µm, mrad, N, A); an angle beyond 10 rad (an encoder's
    zero, many turns away) in rad with its std in mrad."""
    if unit == "rad" and abs(value) >= 10.0:
        return f"{value:.6g} rad" + (f" ± {std * 1e3:.2g} mrad" if np.isfinite(std) and std > 0.0 else "")
    scale, shown = {"s": (1e3, "ms"), "rad": (1e3, "mrad"), "m": (1e6, "µm")}.get(unit, (1.0, unit))
    if not np.isfinite(std) or std == 0.0:
        return f"{value * scale:.4g} {shown}"
    return f"{value * scale:.4g} ± {std * scale:.2g} {shown}"


NUISANCE_WORDS = {
    "rest_angle_rad": "released rest angle (encoder zero), mean",
    "rest_angle_spread_rad": "… spread between applications",
    "park_half_band_rad": "… half the band the ECU parks in (interquartile range)",
    "force_tare_N": "force reading with the pads open (tare), mean",
    "force_tare_spread_N": "… spread between applications",
    "applications_not_released": "applications starting with the pads closed (left out of the force channel)",
    "angle_noise_rad": "angle noise while moving (at least the count's, count / sqrt(12))",
    "angle_count_rad": "encoder count (smallest step of the angle)",
    "velocity_lag_s": "recorded velocity lags the angle's speed by",
    "velocity_gain": "recorded velocity / the angle's speed",
    "current_shift": "current timing (read later by)",
    "current_offset": "current-sensor zero", "force_skew": "force stamped late by",
    "force_lag": "force-sensor lag",
    "load_shift": "load torque quadrature shift", "angle_rate_Hz": "angle sample rate",
    "velocity_rate_Hz": "velocity sample rate", "axial_force_rate_Hz": "force sample rate",
    "current_rate_Hz": "current sample rate",
}


def effect_note(f: EffectFit, *, alpha: float) -> str:
    """What to know about a fit beyond its numbers, in words: it drifts, or it ended on a limit (a physical
    one, or zero for an effect that only grows: the data want the opposite of what it names), or its
    held-out test passes at ``alpha`` only with independent rows
    (:meth:`.ranking.effect_fit.EffectFit.rests_on_independent_rows`)."""
    notes = ["drifts within the recording"] if f.drifting else []
    if f.rests_on_independent_rows(alpha):
        notes.append(f"significant only if the held-out samples are independent: with the brake "
                     f"applications' own scatter p = {f.p_cycles:.2g}")
    if f.at_limit:
        notes.append("fit ended at zero: the data want the opposite of this effect (never named)"
                     if f.effect.one_sided else "fit ended on a physical limit (never named)")
    return "; ".join(notes)


def unit_context(u: UnitDiagnosis, sc: Scorer, ranking: Ranking) -> dict:
    """What the template shows of one unit (``res``: its diagnosis, a
    :class:`~ebm_wear_monitor.schema.diagnose.DiagnosisResult`)."""
    res = u.diagnosis
    effects = [{"effect": f.effect.name.replace("_", " "), "size": describe(f),
                "floor": size_words(f, f.floor, meaning=False),
                "material": "yes" if f.material else "no",
                "sampling": "—" if f.sampling is None else f"± {size_words(f, f.sampling, meaning=False)}",
                "p": f"{f.p_value:.2g}", "shrink": f"{100 * f.shrink:.0f} %",
                "note": effect_note(f, alpha=ranking.alpha)}
               for f in ranking.fits]
    nuisances = [(NUISANCE_WORDS.get(k, k), _quantity(v.value, v.std, v.unit))
                 for k, v in res.nuisances.items()]
    faults = [f"{sig}: {kind} {n}" for sig, kinds in sorted(u.input_faults_by_signal.items())
              for kind, n in sorted(kinds.items())]
    return {"res": res, "light": VERDICT_CLASS[res.verdict], "words": VERDICT_WORDS[res.verdict],
            "residuals": residual_figure(sc, ranking), "shrink": shrink_figure(ranking.fits),
            "position": position_figure(sc, ranking),
            "effects": effects, "nuisances": nuisances, "faults": faults,
            "json": json.dumps({k: v for k, v in u.to_json_dict().items()
                                if k not in ("ranking", "where", "where_after")}, indent=1)}


def write_report(directory: str | Path, states: list[tuple[UnitDiagnosis, Scorer, Ranking]]) -> Path:
    """Write the HTML report of every unit into ``directory`` (created if needed; files replaced).

    Built in a temporary sibling and moved in by :func:`ebm_wear_monitor.outputs.publish_directory`
    (``index.html`` last), so a failed run leaves no half-written page.
    """
    from ebm_wear_monitor.reports import render_page

    def build(tmp: Path) -> None:
        units = [unit_context(u, sc, ranking) for u, sc, ranking in states]
        page = render_page("diagnose.html", "Sim-to-real gap diagnosis", plotly=True,
                           subtitle=", ".join(u.diagnosis.unit for u, _, _ in states), units=units,
                           method=states[0][0].diagnosis.residual_method)
        (tmp / "index.html").write_text(page, encoding="utf-8")

    return publish_directory(build, directory)
