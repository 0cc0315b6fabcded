"""Benchmark: remaining life on life histories that are not the wear model, against a naive baseline.

The validation set of issue 11 (test/monitor/life_histories.py: 20 linear units 0.1-2 um per
application, exponential and climbing-rate growth, slow growth with a true remaining life beyond
10,000 applications, clearance steps, flat units of different usage; observation noise from twin
recordings through the bag writer and the core). After every application the monitor's filter bank
(monitor/tracker.py, monitor/life.py) and, in the same run, the naive baseline (a least-squares line
through every observation so far, replay/prognostics.py ``line_forecast``) predict the remaining
life. Printed: the prognostics metrics of Saxena et al. 2010 (replay/prognostics.py) per family and
over the set, the issue's targets, the cost per application, and one HTML page (Plotly) with the
remaining life against the truth for every unit.

    .venv/bin/python bench/bench_life.py [--out life_vs_truth.html] [--every 1]
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from ebm_wear_monitor.replay.prognostics import prognostics_metrics

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "test" / "monitor"))
from life_histories import baseline, calibrate, checkpoints, histories, observe, resolvable_at, track

FAMILIES = ("linear", "exponential", "climbing", "slow")
ALARM_CYCLES = 1000.0


def _metrics(h, f) -> dict:
    """Metrics of one unit; a prediction counts once it has a bounded band (p95 finite), for both
    predictors: before that a median is a bound (ours: the model's life; the line: an unresolved slope)."""
    issued = np.where(np.isfinite(f.p95), f.p50, np.nan)
    m = prognostics_metrics(f.k, issued, h.eol, rul_p05=f.p05, rul_p95=f.p95)
    true_rul = h.eol - f.k
    n = h.truth_m.size
    m["p50_error"] = [f.p50[int(q * n) - 1] / true_rul[int(q * n) - 1] - 1.0 for q in (0.5, 0.8)]
    banded = np.isfinite(f.p05) & np.isfinite(f.p95) & (true_rul > 0)
    m["inside"] = ((f.p05 <= true_rul) & (true_rul <= f.p95))[banded]
    return m


def _row(label: str, ms: list[dict]) -> str:
    def mean(key: str) -> str:
        v = [m[key] for m in ms if m[key] is not None]
        return f"{np.mean(v):.3f}" if v else "—"

    ph = [m["prognostic_horizon_cycles"] / m["eol_cycles"] if m["prognostic_horizon_cycles"] else 0.0
          for m in ms]
    passed = [m["alpha_lambda_pass"] for m in ms if m["alpha_lambda_pass"] is not None]
    inside = np.concatenate([m["inside"] for m in ms]) if ms else np.empty(0)
    within = np.mean([abs(e) <= 0.3 for m in ms for e in m["p50_error"]])
    cra = [m["cumulative_relative_accuracy"] for m in ms if m["cumulative_relative_accuracy"] is not None]
    return (f"  {label:<22s} {np.mean(ph):>8.3f} {np.mean(passed) if passed else math.nan:>9.2f} "
            f"{mean('alpha_lambda_fraction'):>9s} {mean('relative_accuracy'):>8s} "
            f"{np.median(cra) if cra else math.nan:>8.3f} "
            f"{np.mean(inside) if inside.size else math.nan:>9.3f} "
            f"{within:>10.2f}")


def _figure(path: Path, runs: list) -> None:
    """One self-contained HTML page: a panel per unit, remaining life against the truth (log axis)."""
    from plotly.io import write_html
    from plotly.subplots import make_subplots

    cols = 7
    rows = math.ceil(len(runs) / cols)
    fig = make_subplots(rows=rows, cols=cols, subplot_titles=[h.name for h, *_ in runs],
                        horizontal_spacing=0.02, vertical_spacing=0.06)
    shown: set[str] = set()
    for i, (h, ours, base, _res) in enumerate(runs):
        k, row, col = ours.k, i // cols + 1, i % cols + 1
        p95 = np.where(np.isfinite(ours.p95), ours.p95, 1e9)
        band = np.concatenate([k, k[::-1]]), np.concatenate([ours.p05, p95[::-1]])
        traces = [dict(x=band[0], y=band[1], fill="toself", line=dict(width=0),
                       fillcolor="rgba(31,119,180,0.25)", name="ours p05-p95", legendgroup="band"),
                  dict(x=k, y=ours.p50, line=dict(color="#1f77b4", width=1), name="ours p50",
                       legendgroup="p50"),
                  dict(x=k, y=base.p50, line=dict(color="#ff7f0e", width=1, dash="dash"),
                       name="least-squares line p50", legendgroup="base")]
        if h.grows:
            traces.insert(0, dict(x=k, y=h.eol - k, line=dict(color="black", width=1.5), name="truth",
                                  legendgroup="truth"))
        else:
            traces.append(dict(x=k, y=np.full(k.shape, ALARM_CYCLES), name="alarm (p05 < 1000)",
                               line=dict(color="red", width=1, dash="dot"), legendgroup="alarm"))
        for t in traces:
            fig.add_scatter(**t, mode="lines", showlegend=t["legendgroup"] not in shown, row=row, col=col)
            shown.add(t["legendgroup"])
        top = 3 * (h.eol if h.grows else 1e7)
        fig.update_yaxes(type="log", range=[0, math.log10(top)], row=row, col=col)
    fig.update_layout(height=260 * rows, width=1800, template="plotly_white", font=dict(size=9),
                      title="Remaining life (brake applications to the clearance limit) against the truth, "
                            "every unit of the validation set (issue 11); x: brake application")
    write_html(fig, str(path), include_plotlyjs=True, full_html=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="life_vs_truth.html",
                        help="HTML page (Plotly) of remaining life against the truth")
    parser.add_argument("--every", type=int, default=1,
                        help="evaluate the remaining life every N applications")
    args = parser.parse_args()

    with tempfile.TemporaryDirectory(prefix="bench_life_") as tmp:
        pools = calibrate(Path(tmp))
    print("observation noise, twin recordings -> bag -> core (error sd / median budget / model growth):")
    for rate, p in pools.items():
        print(f"  {rate:6.0f} Hz: {p.sigma_m * 1e6:.2f} um / {np.median(p.budget_std_m) * 1e6:.2f} um / "
              f"{p.model_growth_m:.3g} m per application")

    runs, t_ours, t_base, applications = [], 0.0, 0.0, 0
    for j, h in enumerate(histories()):
        pool = pools[h.rate_hz]
        z, var = observe(h, pools, seed=100 + j)
        at = checkpoints(h, pool.sigma_m, args.every)
        t0 = time.perf_counter()
        ours = track(h, z, var, pool.model_growth_m, at=at)
        t1 = time.perf_counter()
        base = baseline(z)
        t2 = time.perf_counter()
        t_ours, t_base, applications = t_ours + t1 - t0, t_base + t2 - t1, applications + z.size
        runs.append((h, ours, base, resolvable_at(h, pool.sigma_m)))

    header = (f"  {'family (units)':<22s} {'PH/EOL':>8s} {'a-l pass':>9s} {'in cone':>9s} {'RA':>8s} "
              f"{'CRA':>8s} {'coverage':>9s} {'p50 +-30%':>10s}")
    for who, pick in (("ours (filter bank)", 1), ("naive least-squares line", 2)):
        print(f"\n{who}: prognostic horizon over EOL (alpha 0.1, mean) / alpha-lambda pass rate (alpha 0.2, "
              "lambda 0.5) / share in the cone / relative accuracy at lambda (mean) / CRA (median) / "
              "p05-p95 coverage (pooled) / share of p50 within 30 % at 50 % and 80 % of the record")
        print(header)
        everything = []
        for family in FAMILIES:
            ms = [_metrics(r[0], r[pick]) for r in runs if r[0].kind == family]
            everything += ms
            print(_row(f"{family} ({len(ms)})", ms))
        print(_row(f"all growing ({len(everything)})", everything))
        quiet = [r for r in runs if not r[0].grows]
        alarms = sum(int(np.sum(r[pick].p05[np.isfinite(r[pick].p05)] < ALARM_CYCLES)) for r in quiet)
        delays = [int(r[pick].k[np.flatnonzero(r[pick].finite())[0]]) - r[3] if r[pick].finite().any()
                  else math.inf for r in runs if r[0].grows]
        print(f"  alarms (p05 < 1000) on {len(quiet)} flat/step units over 2,000 applications: {alarms}; "
              f"finite numbers after growth is resolvable: max {max(delays):+.0f}, median "
              f"{np.median(delays):+.0f} applications")

    print(f"\ncost per application: filter bank + remaining life {t_ours / applications * 1e3:.2f} ms, "
          f"least-squares line {t_base / applications * 1e3:.4f} ms (ratio {t_ours / t_base:.0f}x) "
          f"over {applications} applications")
    _figure(Path(args.out), runs)
    print(f"figure: {args.out}")


if __name__ == "__main__":
    main()
