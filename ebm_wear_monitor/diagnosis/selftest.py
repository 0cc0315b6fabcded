"""Blind self-test of the diagnosis on twin recordings with withheld effects (issue item 7).

Each case simulates a "real" unit with the twin's simulator
(:func:`ebm_wear_monitor.twin.simulate_unit`) with zero, one or two catalog
effects present, then runs the diagnosis against the *nominal* twin without
telling it what was injected.  The simulator's effect forms are its own
(:mod:`ebm_wear_monitor.twin.effects`): e.g. its Stribeck curve falls from
T_fs to T_fc (the catalog fits a free amplitude), its efficiency variation is
an exponential low-speed drop (the catalog fits a loss linear in speed and
force), its force-sensor gain is a separate effect (the catalog's
``force_sensor_bias`` fits offset and gain together).

Recordings: the plant is integrated at ``OVERSAMPLE`` x the recording rate and
every ``OVERSAMPLE``-th sample is kept, as a data logger samples a continuous
plant (the simulator's fixed-step integrator run at the recording rate itself
would put its own first-order discretisation error into the "real" data).

Case set: every effect at several magnitudes x noise seeds x demand sequences,
two-effect cases, and no-effect cases (18 in the full set).  ``relative_change`` of a case is the
relative change of the quantity the effect acts on (B, G, the screw
efficiency, the preload share of T_fc, the low-speed friction, the tangent
stiffness at 20 kN, x_ag, the force reading at 20 kN); the top-1 target
(>= 90 %) applies to cases with relative_change >= 0.1.

Scores: confusion matrix (true effect -> diagnosed effect or ``none``),
top-1 (the verdict names a true effect), top-2 (a true effect is among the
two best-ranked), false-positive rate (verdict ``effect`` on no-effect cases)
and the median held-out shrink 1 - gap_after / gap_before of effect cases.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from ebm_wear_monitor.diagnosis.pipeline import diagnose_recording
from ebm_wear_monitor.diagnosis.recording import Recording
from ebm_wear_monitor.params import UnitParams, load_unit

RATE_HZ = 500.0  # recording rate of the self-test [Hz]
OVERSAMPLE = 8  # plant integration steps per recorded sample
CYCLES = 20  # brake applications per recording
DEMANDS = ((8e3, 14e3, 20e3, 26e3), (12e3, 24e3, 6e3, 18e3))  # demand sequences [N]
HOLDS = ((0.3,), (0.2, 0.4))  # force-maintenance times [s], cycled
SEEDS = (11, 12, 13)
NULL_SEEDS = (21, 22, 23, 24, 25, 26)  # extra no-effect cases of the full set (false-positive rate)

#: twin effect name -> the catalog effect the diagnosis should name
EXPECTED = {"force_sensor_gain": "force_sensor_bias"}

#: effect -> [(magnitude, relative change of the affected quantity)]
MAGNITUDES: dict[str, list[tuple[float, float]]] = {
    "viscous_friction": [(0.3, 0.3), (1.0, 1.0)],
    "load_friction": [(0.1, 0.1), (0.3, 0.3), (1.0, 1.0)],
    "efficiency_variation": [(0.1, 0.1), (0.3, 0.3)],
    "preload_change": [(-0.5, 0.5), (0.5, 0.5)],
    "stribeck": [(5.0, 0.1), (15.0, 0.1)],  # hump (T_fs - T_fc) / T_fc = 0.107 at zero speed
    "stiffness_nonlinearity": [(0.1, 0.1), (0.3, 0.3)],
    "clearance_growth": [(2e-5, 0.1), (6e-5, 0.3)],
    "force_sensor_bias": [(200.0, 0.01), (2000.0, 0.1)],
    "force_sensor_gain": [(0.02, 0.02), (0.1, 0.1)],
}
QUICK = {"viscous_friction": [(1.0, 1.0)], "load_friction": [(0.3, 0.3)],
         "efficiency_variation": [(0.3, 0.3)],
         "preload_change": [(-0.5, 0.5)], "stribeck": [(15.0, 0.1)], "stiffness_nonlinearity": [(0.3, 0.3)],
         "clearance_growth": [(6e-5, 0.3)], "force_sensor_bias": [(2000.0, 0.1)],
         "force_sensor_gain": [(0.1, 0.1)]}
PAIRS = [({"viscous_friction": 1.0, "clearance_growth": 6e-5}, 0.3),
         ({"load_friction": 0.5, "force_sensor_bias": 2000.0}, 0.1),
         ({"preload_change": -0.5, "stiffness_nonlinearity": 0.3}, 0.3)]


@dataclass(frozen=True)
class Case:
    effects: dict[str, float]
    relative_change: float
    seed: int
    demands: int  # index into DEMANDS / HOLDS

    @property
    def label(self) -> str:
        return "+".join(sorted(self.effects)) or "none"

    @property
    def expected(self) -> set[str]:
        return {EXPECTED.get(e, e) for e in self.effects}


def case_set(quick: bool = False) -> list[Case]:
    """All cases (module docstring); ``quick``: one magnitude per effect, fewer seeds."""
    seeds = SEEDS[:1] if quick else SEEDS
    mags = QUICK if quick else MAGNITUDES
    cases = []
    for i, seed in enumerate(seeds):
        for d in range(len(DEMANDS)):
            if quick and d != i % len(DEMANDS):
                continue
            cases.append(Case({}, 0.0, seed, d))
            cases.extend(Case({e: m}, rel, seed, d) for e, ms in mags.items() for m, rel in ms)
            cases.extend(Case(dict(p), rel, seed, d) for p, rel in PAIRS)
    if quick:  # a second no-effect case with the other demands
        cases.append(Case({}, 0.0, SEEDS[1], 1))
    else:
        cases.extend(Case({}, 0.0, seed, d) for seed in NULL_SEEDS for d in range(len(DEMANDS)))
    return cases


def simulate_case(unit: UnitParams, case: Case) -> Recording:
    """The case's recording: the twin oversampled, then sampled at :data:`RATE_HZ`."""
    from ebm_wear_monitor.twin import simulate_unit

    sim = simulate_unit(unit, CYCLES, demands=DEMANDS[case.demands], effects=case.effects, seed=case.seed,
                        rate_hz=RATE_HZ * OVERSAMPLE, wear=False, hold_s=HOLDS[case.demands], rest_s=0.2)
    s = slice(None, None, OVERSAMPLE)
    return Recording(sim.t[s], sim.angle[s], sim.velocity[s], sim.axial_force[s], sim.current[s],
                     unit=case.label)


def run_selftest(quick: bool = False, max_cases: int | None = None, seed: int = 0,
                 unit: UnitParams | None = None) -> dict:
    """Run the blind self-test; returns the JSON object of interface.md section 4 (plus details).

    ``seed`` shifts every case's noise seed (a different draw of the same case set).
    """
    unit = load_unit() if unit is None else unit
    cases = case_set(quick)[:max_cases]
    rows = []
    t0 = time.perf_counter()
    for case in cases:
        case = Case(case.effects, case.relative_change, case.seed + seed, case.demands)
        res = diagnose_recording(simulate_case(unit, case), unit)
        ranked = [r["effect"] for r in res["ranking"]]
        top_gap = res["ranking"][0]["gap_after"]
        rows.append({
            "true": case.label, "effects": case.effects, "relative_change": case.relative_change,
            "seed": case.seed, "demands": list(DEMANDS[case.demands]),
            "verdict": res["verdict"], "diagnosed": res["effect"] or "none", "top2": ranked[:2],
            "gap_before": res["gap_before"], "gap_after": res["gap_after"],
            "gap_after_top": top_gap,
            "top1_ok": bool(case.effects) and res["effect"] in case.expected,
            "top2_ok": bool(case.effects) and bool(case.expected & set(ranked[:2])),
            "where": [res["where"]["phase"], res["where"]["signal"]],
        })
    return summarise(rows, time.perf_counter() - t0)


def summarise(rows: list[dict], seconds: float) -> dict:
    """Scores of the self-test rows (module docstring)."""
    effect_rows = [r for r in rows if r["true"] != "none"]
    big = [r for r in effect_rows if r["relative_change"] >= 0.1]
    null = [r for r in rows if r["true"] == "none"]
    confusion: dict[str, dict[str, int]] = {}
    for r in rows:
        row = confusion.setdefault(r["true"], {})
        row[r["diagnosed"]] = row.get(r["diagnosed"], 0) + 1

    def share(sel: list[dict], key: str) -> float | None:
        return float(np.mean([r[key] for r in sel])) if sel else None

    shrink = [1.0 - r["gap_after"] / r["gap_before"] if r["gap_before"] > 0 else 0.0 for r in effect_rows]
    return {
        "cases": len(rows),
        "top1_accuracy": share(big, "top1_ok"),
        "top2_accuracy": share(big, "top2_ok"),
        "top1_accuracy_all_magnitudes": share(effect_rows, "top1_ok"),
        "false_positive_rate": float(np.mean([r["verdict"] == "effect" for r in null])) if null else None,
        "median_shrink": float(np.median(shrink)) if shrink else None,
        "confusion": confusion,
        "rate_hz": RATE_HZ, "cycles_per_case": CYCLES, "seconds": seconds,
        "case_results": rows,
    }


def format_summary(result: dict) -> str:
    """Human-readable confusion matrix and scores."""
    lines = [f"self-test: {result['cases']} cases in {result['seconds']:.1f} s "
             f"({result['cycles_per_case']} cycles at {result['rate_hz']:g} Hz each)"]
    diag = sorted({d for row in result["confusion"].values() for d in row})
    width = max(len(t) for t in result["confusion"]) + 2
    lines.append(" " * width + " ".join(f"{d[:10]:>10s}" for d in diag))
    for t, row in sorted(result["confusion"].items()):
        lines.append(f"{t:<{width}s}" + " ".join(f"{row.get(d, 0):>10d}" for d in diag))

    def pct(v: float | None) -> str:
        return "n/a" if v is None else f"{100 * v:.1f} %"

    lines.append(f"top-1 accuracy (effects >= 10 %): {pct(result['top1_accuracy'])}   "
                 f"top-2: {pct(result['top2_accuracy'])}   all magnitudes top-1: "
                 f"{pct(result['top1_accuracy_all_magnitudes'])}")
    lines.append(f"false-positive rate (no-effect cases): {pct(result['false_positive_rate'])}   "
                 f"median held-out shrink: {pct(result['median_shrink'])}")
    return "\n".join(lines)
