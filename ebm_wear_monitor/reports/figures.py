"""Plotly figures as plain JSON dicts, shared by the replay report and the fleet dashboard.

Each function takes SI data (a unit's per-application table, ``replay.result.APPLICATION_COLUMNS``,
and its section 4 entries) and returns ``{"data": [...], "layout": {...}}`` in the units people read
(mm, µm, applications), or None when there is nothing to draw. Axes are linear unless the values
span at least a decade (:func:`axis_type`).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ebm_wear_monitor.outputs import jsonable
from ebm_wear_monitor.reports.humanize import count, known, mm, um

BLUE, ORANGE, GREY, RED, GREEN = "#1565c0", "#e65100", "#8d6e63", "#c62828", "#2e7d32"
#: the projection is drawn at most this many times the recorded span past the last application
PROJECTION_SPAN = 10.0


def axis_type(*arrays: object) -> str:
    """'log' if the positive finite values span at least a factor of ten, else 'linear'."""
    values = np.concatenate([np.asarray(a, dtype=float).ravel() for a in arrays] or [np.empty(0)])
    values = values[np.isfinite(values) & (values > 0)]
    return "log" if values.size and values.max() >= 10.0 * values.min() else "linear"


def value_axis(title: str, *arrays: object) -> dict:
    """A y axis for ``arrays``: linear, or logarithmic with one labelled tick per decade (no crowding)."""
    kind = axis_type(*arrays)
    axis = {"title": {"text": title}, "zeroline": False, "type": kind}
    return axis | {"dtick": 1} if kind == "log" else axis


def _layout(xtitle: str, ytitle: str, **extra: object) -> dict:
    return {"xaxis": {"title": {"text": xtitle}, "zeroline": False},
            "yaxis": {"title": {"text": ytitle}, "zeroline": False},
            "margin": {"l": 70, "r": 20, "t": 30, "b": 50}, "hovermode": "x unified",
            "legend": {"orientation": "h", "y": -0.22}, "template": "plotly_white", **extra}


def _figure(data: list[dict], layout: dict) -> dict:
    return jsonable({"data": data, "layout": layout})  # NaN -> null: a gap in the line


def clearance_figure(app: pd.DataFrame, remaining_life: dict) -> dict | None:
    """Observed clearance per application (on top), filter estimate with its ±2σ band, the wear
    model's line, the limit, and the projection to the limit at the learned rate with the p05-p95
    fan (the constant-rate paths reaching the limit after p05, p50 and p95 applications) [mm]."""
    if not len(app):
        return None
    k = app["index"].to_numpy(float)
    est, std = app["clearance_estimate_m"].to_numpy(float) * 1e3, app["clearance_std_m"].to_numpy(float) * 1e3
    observed = app["clearance_observed_m"].to_numpy(float) * 1e3
    data = [
        {"x": np.concatenate([k, k[::-1]]), "y": np.concatenate([est + 2 * std, (est - 2 * std)[::-1]]),
         "fill": "toself", "mode": "lines", "fillcolor": "rgba(21,101,192,0.18)", "line": {"width": 0},
         "hoverinfo": "skip", "name": "filter ±2σ", "type": "scatter"},
        {"x": k, "y": est, "mode": "lines", "line": {"color": BLUE, "width": 2}, "name": "filter estimate",
         "type": "scatter"},
        {"x": k, "y": app["clearance_model_m"].to_numpy(float) * 1e3, "mode": "lines",
         "line": {"color": GREY, "dash": "dash"}, "name": "wear model alone (from the nominal clearance)",
         "type": "scatter"},
    ]
    limit = remaining_life.get("limit_m")
    p05, p50, p95 = (remaining_life.get(f"cycles_{q}") for q in ("p05", "p50", "p95"))
    x_max = None
    if known(limit) and known(p05) and known(p50) and known(p95) and np.isfinite(est[-1]):
        k0, x0, lim = k[-1], est[-1], limit * 1e3
        data += [
            {"x": [k0, k0 + p05, k0 + p95, k0], "y": [x0, lim, lim, x0], "fill": "toself", "mode": "lines",
             "fillcolor": "rgba(198,40,40,0.12)", "line": {"width": 0}, "hoverinfo": "skip",
             "name": "projection p05–p95", "type": "scatter"},
            {"x": [k0, k0 + p50], "y": [x0, lim], "mode": "lines", "line": {"color": RED, "dash": "dot"},
             "name": f"projection p50: limit after {count(p50)} more", "type": "scatter"},
        ]
        span = max(k[-1] - k[0], 1.0)
        x_max = k0 + min(1.05 * p95, PROJECTION_SPAN * span)
    data.append({"x": k, "y": observed, "mode": "markers", "name": "observed in the application",
                 "marker": {"color": ORANGE, "size": 7, "line": {"color": "white", "width": 1}},
                 "type": "scatter"})
    layout = _layout("brake applications since the state began", "axial clearance x_ag [mm]")
    shown = np.concatenate([est + 2 * std, est - 2 * std, observed])
    shown = shown[np.isfinite(shown)]
    if known(limit) and shown.size:
        top, span = shown.max(), max(np.ptp(shown), 1e-3)  # [mm]
        label = {"showarrow": False, "font": {"color": RED}, "xref": "paper", "x": 0.01, "yanchor": "bottom"}
        if x_max is not None or limit * 1e3 <= top + 2.0 * span:
            layout["shapes"] = [{"type": "line", "xref": "paper", "x0": 0, "x1": 1, "y0": limit * 1e3,
                                 "y1": limit * 1e3, "line": {"color": RED, "width": 1.5}}]
            layout["annotations"] = [label | {"y": limit * 1e3, "text": f"limit {mm(limit)}"}]
        else:  # far above a flat history: drawn, it would squash the observations into one line
            layout["annotations"] = [label | {"yref": "paper", "y": 1.0,
                                              "text": f"limit {mm(limit)}: above the plotted range"}]
    if x_max is not None:
        layout["xaxis"]["range"] = [k[0] - 0.5, x_max]
    return _figure(data, layout)


def model_offset_text(app: pd.DataFrame) -> str:
    """Why the wear-model line sits where it does, in numbers of this record."""
    if not len(app):
        return ""
    est = app["clearance_estimate_m"].to_numpy(float)
    model = app["clearance_model_m"].to_numpy(float)
    n = len(app)
    gap = est[-1] - model[-1]
    return (f"The dashed line is the wear model alone: it starts from the nominal clearance of the unit "
            f"file at the first application this state saw and adds the model's wear. The filter fuses "
            f"it with the observations: after {n} applications the estimate is {um(abs(gap))} "
            f"{'above' if gap >= 0 else 'below'} the model line, clearance the unit had before this "
            f"record or that the model does not explain. Growth over these applications: model "
            f"{um(model[-1] - model[0])}, filter {um(est[-1] - est[0])}.")


def rul_figure(app: pd.DataFrame, truth: dict | None, alpha: float) -> dict | None:
    """Remaining applications after each application: median and p05-p95 band; the truth and its
    ±alpha cone when the simulator's ground truth is known."""
    if not len(app) or not np.isfinite(app["cycles_p50"].to_numpy(float)).any():
        return None
    k = app["index"].to_numpy(float)
    p05, p50, p95 = (app[c].to_numpy(float) for c in ("cycles_p05", "cycles_p50", "cycles_p95"))
    band = np.isfinite(p05) & np.isfinite(p95)  # a polygon with holes would not fill
    kb = k[band]
    data = [{"x": np.concatenate([kb, kb[::-1]]), "y": np.concatenate([p95[band], p05[band][::-1]]),
             "fill": "toself", "mode": "lines",
             "fillcolor": "rgba(21,101,192,0.18)", "line": {"width": 0}, "hoverinfo": "skip",
             "name": "p05–p95", "type": "scatter"},
            {"x": k, "y": p50, "mode": "lines+markers", "line": {"color": BLUE}, "marker": {"size": 4},
             "name": "median", "type": "scatter"}]
    arrays = [p05, p50, p95]
    if truth is not None and truth.get("eol_cycles") is not None:
        true_rul = truth["eol_cycles"] - (k + float(truth.get("cycles_at_start") or 0))
        data += [{"x": np.concatenate([k, k[::-1]]),
                  "y": np.concatenate([(1 + alpha) * true_rul, ((1 - alpha) * true_rul)[::-1]]),
                  "fill": "toself", "mode": "lines", "fillcolor": "rgba(0,0,0,0.07)", "line": {"width": 0},
                  "hoverinfo": "skip", "name": f"±{alpha:.0%} of the truth", "type": "scatter"},
                 {"x": k, "y": true_rul, "mode": "lines", "line": {"color": "black", "dash": "dash"},
                  "name": "true (simulator)", "type": "scatter"}]
        arrays.append(true_rul)
    layout = _layout("brake applications since the state began", "remaining brake applications")
    layout["yaxis"] = value_axis("remaining brake applications", *arrays)
    return _figure(data, layout)


def wear_figure(app: pd.DataFrame) -> dict | None:
    """Cumulative wear depth of screw raceway, nut raceway and balls [µm] against applications."""
    if not len(app):
        return None
    k = app["index"].to_numpy(float)
    data = [{"x": k, "y": app[col].to_numpy(float) * 1e6, "mode": "lines", "name": name, "type": "scatter",
             "line": {"color": color}}
            for col, name, color in (("screw_raceway_m", "screw raceway", BLUE),
                                     ("nut_raceway_m", "nut raceway", ORANGE), ("ball_m", "balls", GREEN))]
    layout = _layout("brake applications since the state began", "wear depth [µm]")
    layout["yaxis"]["exponentformat"] = "e"  # a real unit wears 1e-4 µm per application: no "40μ" of µm
    return _figure(data, layout)


def faults_figure(by_signal: dict[str, dict[str, int]]) -> dict | None:
    """Input faults by kind, one bar group per signal (topic); None when there are none."""
    by_signal = {s: {k: n for k, n in kinds.items() if n} for s, kinds in (by_signal or {}).items()}
    by_signal = {s: kinds for s, kinds in by_signal.items() if kinds}
    if not by_signal:
        return None
    kinds = sorted({k for v in by_signal.values() for k in v})
    data = [{"x": kinds, "y": [by_signal[s].get(k, 0) for k in kinds], "name": s, "type": "bar"}
            for s in sorted(by_signal)]
    layout = _layout("fault kind", "samples or events", barmode="group")
    layout["hovermode"] = "closest"
    layout["yaxis"] = value_axis("samples or events", *[d["y"] for d in data])
    return _figure(data, layout)
