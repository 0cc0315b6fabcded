"""HTML report of a diagnosis: residuals by phase and signal before/after, ranking, recorded vs twin overlays.

``write_report(directory, states)`` writes ``index.html`` and PNG figures
(matplotlib, Agg backend, no display needed) for every unit; ``states`` are the
``(result, scorer, ranking)`` triples of :func:`.pipeline.diagnose_with_state`.
The page is a thin view over each unit's diagnosis result dict, rendered with the project's
shared templates and stylesheet (:mod:`ebm_wear_monitor.reports`, ``diagnose.html``). The
overlays show the recorded signal and the twin's on top and their difference below (the gap is
small against the signal, so only the difference makes it visible); the ranking shows the share
of the held-out gap each effect removes, so the best effects have the longest bars.
Files are built in a temporary directory and moved into ``directory`` at the end
(:func:`ebm_wear_monitor.outputs.publish_directory`), so a failed run leaves nothing half-written.
"""

from __future__ import annotations

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

    ranking = res["ranking"]
    names = [r["effect"] for r in ranking]
    before = res["gap_before"]
    removed = [100.0 * (1.0 - r["gap_after"] / before) if before > 0 else 0.0 for r in ranking]
    fig, ax = plt.subplots(figsize=(8, 0.35 * len(names) + 1.2))
    y = np.arange(len(names))[::-1]
    ax.barh(y, removed, color=["tab:green" if r > 0 else "tab:gray" for r in removed])
    for yi, r, rem in zip(y, ranking, removed, strict=True):
        ax.text(max(rem, 0.0) + 1.0, yi, f"gap after {r['gap_after']:.3g}", va="center", fontsize=7)
    ax.axvline(0.0, color="k", lw=0.8)
    ax.set_xlim(min(0.0, min(removed, default=0.0)) - 2.0, 125.0)
    ax.set_yticks(y, names, fontsize=8)
    ax.set_xlabel(f"share of the held-out gap removed [%] (gap before: {before:.3g} {res['metric']})")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def _fig_overlay(sc: Scorer, ranking: Ranking, found: bool, path: Path) -> None:
    """Per representative held-out cycle: current and force, recorded vs twin, and their differences."""
    import matplotlib.pyplot as plt

    m, b = sc.model, sc.model.blocks
    held = sc.split.heldout_cycles
    peak = np.array([b.force[b.cycle == c].max() for c in held])
    show = sorted({int(held[np.argmin(peak)]), int(held[np.argmax(peak)])})
    fig, axes = plt.subplots(4, len(show), figsize=(6 * len(show), 10), squeeze=False, sharex="col",
                             gridspec_kw={"height_ratios": [2, 1, 2, 1]})
    aug = ranking.top.augment if found else None
    label = ranking.top.effect.name if found else ""
    for j, c in enumerate(show):
        idx = np.flatnonzero(m.seg.cycle == c)
        t = m.rec.t[idx] - m.rec.t[idx[0]]
        for row, (recorded, nominal, augmented, what, unit) in enumerate((
                (m.rec.current[idx], needed_current(sc, sc.base.aug)[idx],
                 None if aug is None else needed_current(sc, aug)[idx], "current", "A"),
                (m.rec.axial_force[idx], m.force_model(NOMINAL)[idx],
                 None if aug is None else m.force_model(aug)[idx], "axial force", "N"))):
            ax, diff = axes[2 * row, j], axes[2 * row + 1, j]
            ax.plot(t, recorded, lw=1.4, color="0.35", label="recorded")
            ax.plot(t, nominal, lw=0.9, color="tab:red", label="nominal twin")
            diff.plot(t, recorded - nominal, lw=0.8, color="tab:red", label="recorded − nominal twin")
            if augmented is not None:
                ax.plot(t, augmented, lw=0.9, ls="--", color="tab:blue", label=f"twin with {label}")
                diff.plot(t, recorded - augmented, lw=0.8, color="tab:blue",
                          label=f"recorded − twin with {label}")
            diff.axhline(0.0, color="k", lw=0.6)
            ax.set_title(f"held-out cycle {c}: {what} [{unit}]", fontsize=9)
            diff.set_ylabel(f"difference [{unit}]", fontsize=8)
            ax.legend(fontsize=7)
            diff.legend(fontsize=7)
        axes[-1, j].set_xlabel("time in cycle [s]")
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def unit_context(res: dict, stem: str) -> dict:
    """What the template shows of one unit: the result dict, the figure files and table rows."""
    ranking = [{"effect": r["effect"], "score": f"{r['score']:+.3f}", "gap_after": f"{r['gap_after']:.3g}",
                "p_value": f"{r['p_value']:.2g}",
                "parameters": ", ".join(f"{k} = {v['value']:.4g} ± {v['stderr']:.2g} {v['unit']}"
                                        for k, v in r["parameters"].items())} for r in res["ranking"]]
    faults = [f"{sig}: {kind} {n}" for sig, kinds in sorted((res.get("input_faults_by_signal") or {}).items())
              for kind, n in sorted(kinds.items())]
    return {"res": res, "stem": stem, "ranking": ranking, "faults": faults,
            "json": json.dumps({k: v for k, v in res.items() if k != "ranking"}, indent=1, default=float)}


def write_report(directory: str | Path, states: list[tuple[dict, Scorer, Ranking]]) -> Path:
    """Write the HTML report of every unit into ``directory`` (created if needed; files replaced).

    Built in a temporary sibling and moved in by :func:`ebm_wear_monitor.outputs.publish_directory`
    (``index.html`` last), so a failed run leaves no half-written page.
    """
    import matplotlib

    matplotlib.use("Agg")

    from ebm_wear_monitor.reports import render_page

    def build(tmp: Path) -> None:
        units = []
        for i, (res, sc, ranking) in enumerate(states):
            stem = f"unit{i}"
            _fig_where(res, tmp / f"{stem}_where.png")
            _fig_ranking(res, tmp / f"{stem}_ranking.png")
            _fig_overlay(sc, ranking, res["verdict"] == "effect", tmp / f"{stem}_overlay.png")
            units.append(unit_context(res, stem))
        page = render_page("diagnose.html", "Sim-to-real gap diagnosis",
                           subtitle=", ".join(r["unit"] for r, _, _ in states), units=units,
                           method=states[0][0]["residual_method"])
        (tmp / "index.html").write_text(page, encoding="utf-8")

    return publish_directory(build, directory)
