"""HTML report of a diagnosis: residuals by phase and signal before/after, ranking, recorded vs twin overlays.

``write_report(directory, states)`` writes ``index.html`` and PNG figures
(matplotlib, Agg backend, no display needed) for every unit; ``states`` are the
``(result, scorer, ranking)`` triples of :func:`.pipeline.diagnose_with_state`.
Files are built in a temporary directory and moved into ``directory`` at the end
(:func:`ebm_wear_monitor.outputs.publish_directory`), so a failed run leaves nothing half-written.
"""

from __future__ import annotations

import html
import json
from pathlib import Path

import numpy as np

from ebm_wear_monitor.diagnosis.phases import PHASES
from ebm_wear_monitor.diagnosis.ranking import Ranking, Scorer
from ebm_wear_monitor.diagnosis.recording import SIGNALS
from ebm_wear_monitor.diagnosis.residuals import NOMINAL, Augment
from ebm_wear_monitor.outputs import publish_directory


def needed_current(sc: Scorer, aug: Augment) -> np.ndarray:
    """Current the model needs for the recorded motion and force, (J_me dw/dt + T_L + T_f) / K_T [A].

    For display: the speed derivative is taken from the smoothed speed.
    """
    from scipy.ndimage import uniform_filter1d

    m, n = sc.model, sc.model.nominal
    T_f, T_L = m.friction(aug)
    w = uniform_filter1d(m.w_m, max(1, round(0.005 / m.rec.dt)), mode="nearest")
    accel = n.J_me * np.gradient(w, m.rec.t)
    # at rest the friction balances the drive exactly: show the recorded current there
    return np.where(m.moving, (accel + T_L + T_f) / n.K_T, m.rec.current)


def _fig_where(res: dict, path: Path) -> None:
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 3.8), sharey=True)
    for ax, key, title in ((axes[0], "where", "nominal twin"), (axes[1], "where_after", "with top effect")):
        table = res.get(key)
        ax.set_title(title)
        if not table:
            ax.text(0.5, 0.5, "no effect added", ha="center", transform=ax.transAxes)
            continue
        x = np.arange(len(PHASES))
        for k, sig in enumerate(SIGNALS):
            vals = [table["table"][p][sig] or 0.0 for p in PHASES]
            ax.bar(x + (k - 1.5) * 0.2, vals, 0.2, label=sig)
        ax.axhline(1.0, color="k", lw=0.8, ls="--")
        ax.set_xticks(x, [p.replace("_", "\n") for p in PHASES], fontsize=8)
    axes[0].set_ylabel("RMS residual / noise")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def _fig_ranking(res: dict, path: Path) -> None:
    import matplotlib.pyplot as plt

    names = [r["effect"] for r in res["ranking"]]
    fig, ax = plt.subplots(figsize=(8, 3.5))
    y = np.arange(len(names))[::-1]
    ax.barh(y, [r["gap_after"] for r in res["ranking"]], color="tab:blue", label="held-out gap after")
    ax.axvline(res["gap_before"], color="tab:red", label="held-out gap before")
    ax.set_yticks(y, names, fontsize=8)
    ax.set_xlabel(res["metric"])
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def _fig_overlay(sc: Scorer, ranking: Ranking, found: bool, path: Path) -> None:
    import matplotlib.pyplot as plt

    m, b = sc.model, sc.model.blocks
    held = sc.split.heldout_cycles
    peak = np.array([b.force[b.cycle == c].max() for c in held])
    show = sorted({int(held[np.argmin(peak)]), int(held[np.argmax(peak)])})
    fig, axes = plt.subplots(2, len(show), figsize=(6 * len(show), 6), squeeze=False)
    aug = ranking.top.augment if found else None
    for j, c in enumerate(show):
        idx = np.flatnonzero(m.seg.cycle == c)
        t = m.rec.t[idx] - m.rec.t[idx[0]]
        ax = axes[0, j]
        ax.plot(t, m.rec.current[idx], lw=0.6, color="0.5", label="recorded")
        ax.plot(t, needed_current(sc, sc.base)[idx], lw=1.0, label="nominal twin needs")
        if aug is not None:
            ax.plot(t, needed_current(sc, aug)[idx], lw=1.0, label=f"with {ranking.top.effect.name}")
        ax.set_title(f"held-out cycle {c}: current [A]")
        ax.legend(fontsize=7)
        ax = axes[1, j]
        ax.plot(t, m.rec.axial_force[idx], lw=0.6, color="0.5", label="recorded")
        ax.plot(t, m.force_model(NOMINAL)[idx], lw=1.0, label="nominal twin from travel")
        if aug is not None:
            ax.plot(t, m.force_model(aug)[idx], lw=1.0, label=f"with {ranking.top.effect.name}")
        ax.set_title("axial force [N]")
        ax.set_xlabel("time in cycle [s]")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def _unit_html(res: dict, stem: str) -> str:
    e = html.escape
    rows = "".join(
        f"<tr><td>{e(r['effect'])}</td><td>{r['score']:+.3f}</td><td>{r['gap_after']:.3g}</td>"
        f"<td>{r['p_value']:.2g}</td><td>" + ", ".join(
            f"{e(k)} = {v['value']:.4g} &plusmn; {v['stderr']:.2g} {e(v['unit'])}"
            for k, v in r["parameters"].items()) + "</td></tr>" for r in res["ranking"])
    ties = "".join(f"<li>{e(t['between'][0])} ~ {e(t['between'][1])}: {e(t['experiment'])}</li>"
                   for t in res["near_ties"]) or "<li>none</li>"
    w = res["where"]
    return f"""
<h2>Unit {e(res['unit'])}</h2>
<p><b>Verdict: {e(res['verdict'])}</b>{' &mdash; ' + e(res['effect']) if res['effect'] else ''};
held-out gap ({e(res['metric'])}) {res['gap_before']:.3g} &rarr; {res['gap_after']:.3g}
(shrink {100 * res['shrink']:.0f} %). Where: {e(str(w['phase']))} / {e(str(w['signal']))}.</p>
<img src="{stem}_where.png"><br><img src="{stem}_ranking.png"><br><img src="{stem}_overlay.png">
<table border="1" cellpadding="3"><tr><th>effect</th><th>score</th><th>gap after</th><th>p</th>
<th>fitted parameters (cluster-robust s.e.)</th></tr>{rows}</table>
<p>Near-ties and the experiment that would separate them:</p><ul>{ties}</ul>
<details><summary>JSON</summary><pre>{e(json.dumps({k: v for k, v in res.items() if k != 'ranking'},
                                               indent=1, default=float))}</pre></details>
"""


def write_report(directory: str | Path, states: list[tuple[dict, Scorer, Ranking]]) -> Path:
    """Write the HTML report of every unit into ``directory`` (created if needed; files replaced).

    Built in a temporary sibling and moved in by :func:`ebm_wear_monitor.outputs.publish_directory`
    (``index.html`` last), so a failed run leaves no half-written page.
    """
    import matplotlib

    matplotlib.use("Agg")

    def build(tmp: Path) -> None:
        parts = []
        for i, (res, sc, ranking) in enumerate(states):
            stem = f"unit{i}"
            _fig_where(res, tmp / f"{stem}_where.png")
            _fig_ranking(res, tmp / f"{stem}_ranking.png")
            _fig_overlay(sc, ranking, res["verdict"] == "effect", tmp / f"{stem}_overlay.png")
            parts.append(_unit_html(res, stem))
        (tmp / "index.html").write_text(
            "<!doctype html><html><head><meta charset='utf-8'><title>ebm-wear diagnose</title></head>"
            "<body><h1>Sim-to-real gap diagnosis</h1>"
            f"<p>Residuals: {html.escape(states[0][0]['residual_method'])}.</p>"
            + "".join(parts) + "</body></html>", encoding="utf-8")

    return publish_directory(build, directory)
