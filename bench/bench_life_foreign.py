"""Benchmark: remaining life on the foreign world's life recordings, through replay, against the truth.

The foreign generator (``ebm_wear_monitor.validation.foreign``, written independently of the twin
and the monitor: its own plant, ECU, sensors and conventions) writes its ``life`` set: 12 healthy
units of 150-240 applications whose true clearance follows a schedule that is not the wear model
(linear 0.3-1.5 µm per application, exponential, a 30 µm step then flat, three flat units of
different usage, slow growth with about 5,800 applications to go, one unit with a 0.4 mm limit).
Each recording is replayed from disk (``replay_bags``, the CLI's path) with its own ``unit.yaml``;
after every application the monitor's p05/p50/p95 remaining life is compared with the truth
(``eol_cycles - n``, n the 0-based index of the application just completed, as the generator counts
them), next to the naive baseline measured in the same run: a least-squares line
through the clearance observed so far (``replay.prognostics.line_forecast``).

Printed per unit: the clearance estimate's bias over the last 20 applications [µm], the p50 error
at 50 % and 80 % of the history (target ±30 %), the unit's p05-p95 coverage of the truth, the
remaining-life status at the end; flat units:
alarms (p05 < 1,000 applications). Over the set: p05-p95 coverage of the truth (pooled over every
bounded prediction; target 80-98 %) for both predictors.

    .venv/bin/python bench/bench_life_foreign.py [--dir DIR] [--jobs 2]

``--dir`` keeps the recordings (about 1.3 GB; written only where missing).
"""

from __future__ import annotations

import argparse
import json
import math
import tempfile
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.replay.prognostics import line_forecast
from ebm_wear_monitor.replay.run import replay_bags
from ebm_wear_monitor.validation.foreign import case_set, write_case

ALARM_CYCLES = 1000  # an alarm: p05 below this many applications


def _write(case, out: str) -> Path:
    path = Path(out) / case.case_id
    return path if (path / "ground_truth.json").exists() else write_case(case, out)


def _p50_error(p50: np.ndarray, truth: np.ndarray, at: float, eol: float) -> float:
    """Relative p50 error at the fraction ``at`` of the history (or of the life, if shorter)."""
    i = int(at * min(p50.size, math.floor(eol) + 1)) - 1
    return float(p50[i] / truth[i] - 1.0)


def evaluate(bag: Path) -> dict:
    """Replay one life recording; its per-application predictions against the truth."""
    (entry,) = json.loads((bag / "ground_truth.json").read_text())["units"].values()
    unit = replay_bags([bag], load_unit(bag / "unit.yaml")).units[0]
    a = unit.applications
    k = a["index"].to_numpy(float)
    ours = np.column_stack([a[f"cycles_{q}"].to_numpy(float) for q in ("p05", "p50", "p95")])
    line = line_forecast(k, a["clearance_observed_m"].to_numpy(float), entry["clearance_limit_m"])
    true_c = np.asarray(entry["clearance_m"], float)[k.astype(int) - 1]
    bias = float(np.mean(a["clearance_estimate_m"].to_numpy(float)[-20:] - true_c[-20:]))
    row = {"unit": bag.name, "n": int(k.size), "bias_m": bias, "eol": entry["eol_cycles"],
           "status": unit.snapshot.life_status}
    if entry["eol_cycles"] is None:
        return row | {f"alarms_{name}": int(np.sum(p[:, 0][np.isfinite(p[:, 0])] < ALARM_CYCLES))
                      for name, p in (("ours", ours), ("line", line))}
    truth = entry["eol_cycles"] - (k - 1)  # applications counted from 0 (validation/foreign/life.py)
    for name, p in (("ours", ours), ("line", line)):
        bounded = np.isfinite(p[:, 0]) & np.isfinite(p[:, 2]) & (truth > 0)
        row[f"inside_{name}"] = ((p[:, 0] <= truth) & (truth <= p[:, 2]))[bounded].tolist()
        row[f"p50_{name}"] = [_p50_error(p[:, 1], truth, at, entry["eol_cycles"]) for at in (0.5, 0.8)]
    return row


def _share(flags: list[bool]) -> float:
    return float(np.mean(flags)) if flags else math.nan


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dir", help="where the recordings are kept (default: a temporary directory)")
    parser.add_argument("--jobs", type=int, default=2)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="bench_life_foreign_") as tmp:
        out = args.dir or tmp
        Path(out).mkdir(parents=True, exist_ok=True)
        cases = case_set("life")
        with ProcessPoolExecutor(args.jobs) as pool:
            bags = list(pool.map(_write, cases, [out] * len(cases)))
            rows = list(pool.map(evaluate, bags))
    print(f"{'unit':30s} {'apps':>4s} {'bias um':>8s} {'status':>17s}  p50 error at 50 % / 80 % "
          f"and coverage (ours | line), or alarms on a flat unit")
    inside = {"ours": [], "line": []}
    for r in rows:
        if r["eol"] is None:
            tail = f"flat: alarms ours {r['alarms_ours']}, line {r['alarms_line']}"
        else:
            tail = " | ".join(" ".join(f"{100 * e:+6.1f} %" for e in r[f"p50_{n}"])
                              + f", coverage {_share(r[f'inside_{n}']):.2f}" for n in ("ours", "line"))
            for n in inside:
                inside[n] += r[f"inside_{n}"]
        print(f"{r['unit']:30s} {r['n']:4d} {r['bias_m'] * 1e6:+8.2f} {r['status']:>17s}  {tail}")
    print("p05-p95 coverage of the true remaining life (target 0.80-0.98): "
          + ", ".join(f"{n} {np.mean(v):.3f} ({len(v)} predictions)" for n, v in inside.items()))


if __name__ == "__main__":
    main()
