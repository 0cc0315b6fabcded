"""The whole sim-to-real diagnosis of one recording: where, which, how far (interface.md section 4).

    result = diagnose_recording(recording, unit)

1. phases and cycles from the signals (:mod:`.phases`);
2. block residuals of the nominal twin of 004 in the torque and force channels,
   re-anchored every block (:mod:`.residuals`), normalised by measured noise
   (measured twice: on the nominal residual, then on the residual of the best
   effect of a first ranking, which holds less model error);
3. every catalog effect (:mod:`.catalog`) fitted on calibration cycles and
   judged on held-out cycles (:mod:`.ranking`);
4. ``where`` before and after the top effect (:mod:`.where`).
"""

from __future__ import annotations

import numpy as np

from ebm_wear_monitor.diagnosis.catalog import build_catalog, friction_refit
from ebm_wear_monitor.diagnosis.noise import signal_noise
from ebm_wear_monitor.diagnosis.phases import segment
from ebm_wear_monitor.diagnosis.ranking import (
    METRIC,
    Ranking,
    Scorer,
    evaluate,
    nominal_sse,
    rank,
    separating_experiment,
)
from ebm_wear_monitor.diagnosis.recording import SIGNALS, Recording
from ebm_wear_monitor.diagnosis.residuals import Nominal, ResidualModel
from ebm_wear_monitor.diagnosis.where import where_table
from ebm_wear_monitor.params import UnitParams

RESIDUAL_METHOD = ("torque balance of 004 eq. 1 re-anchored to the recorded state every block "
                   "(integrated current vs recorded speed change) and force-travel law of 004 eq. 5")


def shrink(gap_before: float, gap_after: float) -> float:
    """Share of the held-out gap an effect removes, 1 - gap_after / gap_before (0 when there is no gap)."""
    return float(1.0 - gap_after / gap_before) if gap_before > 0.0 else 0.0


def analyse(rec: Recording, unit: UnitParams, block_s: float = 0.02) -> tuple[Scorer, Ranking]:
    """Segment, build residuals and rank the catalog; the pieces behind :func:`diagnose_recording`."""
    seg = segment(rec)
    nominal = Nominal.from_unit(unit)
    model = ResidualModel(rec, seg, nominal, block_s=block_s)
    catalog = build_catalog(nominal, max_speed=float(np.percentile(np.abs(model.w_m), 99.5)),
                            max_force=float(max(np.percentile(rec.axial_force, 99.5), 1.0)))
    # two passes: the noise is measured again on the residual of the first pass's best effect
    first = rank(Scorer.build(model), catalog)
    sc = Scorer.build(model, reference=first.top.augment)
    return sc, rank(sc, catalog)


def diagnose_recording(rec: Recording, unit: UnitParams, block_s: float = 0.02) -> dict:
    """Diagnosis JSON object of one unit's recording (interface.md section 4, with extra keys)."""
    return diagnose_with_state(rec, unit, block_s)[0]


def diagnose_with_state(rec: Recording, unit: UnitParams, block_s: float = 0.02
                        ) -> tuple[dict, Scorer, Ranking]:
    """:func:`diagnose_recording` plus the residual model and ranking behind it (for the report)."""
    sc, ranking = analyse(rec, unit, block_s)
    top = ranking.top
    found = ranking.verdict == "effect"
    nominal = sc.model.nominal
    b = sc.model.blocks
    ties = [f for f in ranking.fits[1:] if f.effect.name in top.ties]
    experiments = [separating_experiment(
        nominal, top, f, max_speed=float(np.abs(sc.model.w_m).max()), max_force=float(rec.axial_force.max()),
        sigma_torque=float(np.median(sc.sigma_torque)), sigma_force=float(np.median(sc.sigma_force)))
        for f in ties]
    gap_after = top.gap_after if found else ranking.gap_before
    refit = evaluate(sc, friction_refit(nominal), nominal_sse(sc))
    base = {"dT_fc": nominal.T_fc, "dB": nominal.B, "dG": nominal.G}
    return ({
        "unit": rec.unit,
        "verdict": ranking.verdict,
        "effect": top.effect.name if found else None,
        "ranking": [f.as_dict() for f in ranking.fits],
        "where": where_table(sc, sc.base),
        "where_after": where_table(sc, top.augment) if found else None,
        "gap_before": ranking.gap_before,
        "gap_after": gap_after,
        "shrink": shrink(ranking.gap_before, gap_after),
        "metric": METRIC,
        "significance_level": ranking.alpha,
        "near_ties": experiments,
        "friction_refit": refit.as_dict() | {
            "nominal": {"T_fc": nominal.T_fc, "B": nominal.B, "G": nominal.G},
            "refitted": {k[1:]: base[k] + float(v) for k, v in zip(refit.effect.params, refit.theta,
                                                                       strict=True)}},
        "cycles": {"total": int(np.unique(b.cycle).size),
                   "heldout": [int(c) for c in sc.split.heldout_cycles]},
        "noise": {s: signal_noise(getattr(rec, s)) for s in SIGNALS},
        "residual_method": RESIDUAL_METHOD,
        "current_time_shift_s": sc.base.current_shift,
        "load_quadrature_shift_s": sc.base.load_shift,
    }, sc, ranking)
