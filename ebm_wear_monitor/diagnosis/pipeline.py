"""The whole sim-to-real diagnosis of one recording: where, which, how far (interface.md section 4).

    result = diagnose_recording(recording, unit)

1. phases and cycles from the signals (:mod:`.phases`), the speed from the angle;
2. the recording's conventions, estimated from the data (:mod:`.conventions`): released
   rest angle and force tare per application, the recorded velocity's lag and gain;
3. block residuals of the nominal twin of 004 in the torque and force channels,
   re-anchored every block (:mod:`.residuals`), normalised by measured noise
   (:meth:`.ranking.Scorer.noise_scale`, measured twice: on the residual of the twin
   within its tolerance, then on that of the best single effect of a first pass, which
   holds less model error), with the acquisition nuisances fitted;
4. every catalog effect (:mod:`.catalog`) fitted on calibration cycles and judged
   on held-out cycles against the noise and against its detectability floor from
   the model-tolerance budget (:mod:`.tolerance`), a second effect by forward
   selection, and the verdict (:mod:`.ranking`);
5. ``where`` before and after the explaining model (:mod:`.where`), and a summary in
   plain words.
"""

from __future__ import annotations

import numpy as np
from threadpoolctl import threadpool_limits

from ebm_wear_monitor.diagnosis import tolerance
from ebm_wear_monitor.diagnosis.catalog import build_catalog, friction_refit
from ebm_wear_monitor.diagnosis.conventions import estimate_conventions
from ebm_wear_monitor.diagnosis.noise import signal_noise
from ebm_wear_monitor.diagnosis.phases import segment
from ebm_wear_monitor.diagnosis.ranking import (
    ALPHA,
    METRIC,
    SHRINK_NEEDED,
    EffectFit,
    OpenSet,
    Ranking,
    Scorer,
    evaluate,
    material_channels,
    nominal_sse,
    rank,
    ranked_fits,
    sampling_caution,
    separating_experiment,
)
from ebm_wear_monitor.diagnosis.recording import Resampled
from ebm_wear_monitor.diagnosis.residuals import NUISANCE_UNITS, ResidualModel, nuisances_of
from ebm_wear_monitor.diagnosis.where import where_table
from ebm_wear_monitor.domain.signals import SIGNALS
from ebm_wear_monitor.params import UnitParams
from ebm_wear_monitor.schema.diagnose import (
    Cycles,
    DiagnosisResult,
    Estimate,
    FrictionRefit,
    HysteresisTest,
    LostMotionTest,
    PositionTorque,
    RestTorqueTest,
    TorqueScaleTest,
)
from ebm_wear_monitor.twin.dynamics import ActuatorModel, actuator_model

RESIDUAL_METHOD = ("torque balance of 004 eq. 1 re-anchored to the recorded state every block "
                   "(integrated current vs the speed change of the angle) and force-travel law of 004 eq. 5 "
                   "from each application's released rest angle and force tare")


def shrink(gap_before: float, gap_after: float) -> float:
    """Share of the held-out gap an effect removes, 1 - gap_after / gap_before (0 when there is no gap)."""
    return float(1.0 - gap_after / gap_before) if gap_before > 0.0 else 0.0


def residual_model(rec: Resampled, nominal: ActuatorModel, block_s: float = 0.02) -> ResidualModel:
    """Steps 1-3 of the module docstring: phases, conventions, and the residual model of ``rec``."""
    seg = segment(rec)
    return ResidualModel(rec, seg, estimate_conventions(rec, seg), nominal, block_s=block_s)


def analyse(rec: Resampled, unit: UnitParams, block_s: float = 0.02) -> tuple[Scorer, Ranking]:
    """Segment, estimate conventions, build residuals and rank the catalog (:func:`diagnose_recording`)."""
    nominal = actuator_model(unit)
    model = residual_model(rec, nominal, block_s)
    moving = model.speed[model.moving]
    lo, hi = (np.percentile(moving, [5.0, 95.0]) if moving.size else (0.0, 1.0))
    catalog = build_catalog(nominal, max_speed=float(np.percentile(model.speed, 99.5)),
                            max_force=float(max(np.percentile(model.force, 99.5), 1.0)),
                            speed_range=(float(lo), float(hi)))
    # two passes: the noise is measured again on the residual of the first pass's best effect, of which
    # the first pass needs nothing else (no tests, no selection); the two scales practically never agree
    sensors = Scorer.sensors(model)
    first = sensors.scaled(sensors.noise_scale())
    sc = sensors.scaled(sensors.noise_scale(ranked_fits(first, catalog, tested=False)[0].model))
    return sc, rank(sc, catalog)


def diagnose_recording(rec: Resampled, unit: UnitParams, block_s: float = 0.02) -> DiagnosisResult:
    """Diagnosis of one unit's recording (interface.md section 4, with extra keys; ``.to_json_dict()``)."""
    return diagnose_with_state(rec, unit, block_s)[0]


def _percent(f: float) -> str:
    return f"{100.0 * f:+.0f} %"


def describe(f: EffectFit) -> str:
    """One effect's fitted size in plain words with the units people read (µm, %, N m)."""
    e, mag = f.effect, f.effect.magnitude(f.theta, f.stderr)
    words = e.meaning.split(" (")[0]
    if e.name == "clearance_growth":
        m = mag["dx"]
        assert m.fraction is not None  # x_ag is its nominal quantity
        return (f"{words}: {m.value * 1e6:+.1f} µm ± {m.std * 1e6:.1f} µm "
                f"({_percent(m.fraction)} of the nominal clearance x_ag)")
    first = mag[e.params[0]]
    if first.fraction is not None and first.fraction_std is not None:
        return (f"{words}: {_percent(first.fraction)} ± {100.0 * first.fraction_std:.0f} % "
                f"of {first.nominal_name}")
    return f"{words}: {100.0 * f.size:.1f} % ± {100.0 * f.size_std:.1f} % ({e.size_meaning})"


def _material_closed(ranking: Ranking, joint: EffectFit) -> str:
    """What the verdict's rule judged (:func:`.ranking.rank`): the share of the material model error of the
    twin within its tolerance the effects close, per channel (the gap also counts the noise-level rows)."""
    w = ranking.unexplained_share
    closed = [f"{100.0 * (1.0 - joint.share[ch] / w[ch]):.0f} % of the {ch} model error"
              for ch in material_channels(w)]
    if not closed:
        return ("; the twin within its tolerance leaves no material model error, the effect is named for its "
                "significant size above its floor")
    return f" and {' and '.join(closed)} the twin within its tolerance leaves"


#: what each channel's unexplained share is a share of (:meth:`.ranking.Scorer.unexplained_share`)
SHARE_OF = {"torque": "the motor torque", "force": "the clamp force"}


def _material_words(ranking: Ranking) -> str:
    """The model error the twin within its tolerance leaves where it is material, against its bound: the
    numbers the ``unexplained`` rule judged (:func:`.ranking.rank`), so that a verdict at the bound reads
    as one."""
    w = ranking.unexplained_share
    return " and ".join(
        f"{100.0 * w[ch]:.2f} % of {SHARE_OF[ch]} beyond the noise where "
        f"{100.0 * tolerance.MATERIAL_SHARE[ch]:.0f} % is material"
        for ch in material_channels(w))


def _drift_words(f: EffectFit) -> str:
    """One friction effect that changes within the recording (test (d)): the magnitude of its size (a
    fraction of the nominal quantity) on the early and the late half of the applications."""
    d = f.drift
    assert d is not None  # drifting means tested
    return (f"the fitted {f.effect.name.replace('_', ' ')} changes within the recording: its magnitude is "
            f"{100.0 * d.early:.1f} % on the early half of the applications and {100.0 * d.late:.1f} % on "
            f"the late half (late - early ± {100.0 * d.std:.1f} %; {f.effect.size_meaning}; trend with "
            f"time p = {d.p_value:.2g})")


def _look_alike(ranking: Ranking, f: EffectFit) -> str:
    """What else an effect of the verdict can be (:attr:`.catalog.Effect.look_alike`), or, for a clearance
    growth the lost-motion test could ask (:mod:`.play`), what it found."""
    m = ranking.play
    if f.effect.name == "clearance_growth" and m is not None:
        return (f" In the release the extra clearance lacks {m.deficit:+.3f} ± {m.deficit_std:.3f} N m of "
                "friction against the travel right after it; a play between motor and screw, crossed "
                "without the screw's friction, would lack significantly more than "
                f"{max(m.budget, m.floor):.3f} N m there: read as a wider clearance.")
    return f" {f.effect.name.replace('_', ' ').capitalize()} reads the same as {f.effect.look_alike}."


def _model_words(ranking: Ranking) -> str:
    """The verdict's model in words: the twin with the selected effects, or within its tolerance."""
    if ranking.joint is None:
        return "within its tolerance"
    return "with " + " and ".join(f.effect.name.replace("_", " ") for f in ranking.selected)


def _ripple(o: OpenSet | None) -> str:
    """What else a motor-torque scale can be when the torque also depends on the screw's position."""
    if o is None or not o.significant:
        return ""
    return (f" The torque residual also depends on where the screw is ({1e3 * o.periodic.rms:.0f} mN m RMS, "
            f"p = {o.periodic.p_value:.1g}): a torque ripple in phase with the drive over the stroke reads "
            "the same.")


def summary(ranking: Ranking) -> str:
    """The verdict in plain words."""
    gap = f"held-out gap {ranking.gap_before:.2f} x noise"
    if ranking.verdict == "effect":
        parts = [describe(f) for f in sorted(ranking.selected, key=lambda f: -f.score)]
        joint = ranking.joint
        assert joint is not None  # an "effect" verdict rests on the selected effects fitted together
        alike = "".join(_look_alike(ranking, f) for f in ranking.selected if f.effect.look_alike)
        return (f"{'; '.join(parts)}. Adding {'them' if len(parts) > 1 else 'it'} to the twin closes "
                f"{100.0 * joint.shrink:.0f} % of the {gap}{_material_closed(ranking, joint)}.{alike}"
                f"{_sampling_words(ranking)}{_independence_words(ranking)}")
    o = ranking.open_set
    if o is not None and o.decided:
        torque = (f"a torque that depends on where the screw is ({1e3 * o.periodic.rms:.0f} ± "
                  f"{1e3 * o.periodic.rms_std:.0f} mN m RMS beyond force- and speed-shaped terms)")
        if not o.on_effects:
            return (f"The twin, even within its tolerance, misses {torque}, above 2 % of the motor torque "
                    f"({gap}); no known effect makes such a torque: an effect outside the catalog is likely.")
        named = " and ".join(f.effect.name.replace("_", " ") for f in ranking.selected)
        assert o.share is not None  # on the effects only the share rule decides (open_set_verdict)
        return (f"The best known effects ({named}) close only {100.0 * o.share:.0f} % of the "
                f"explainable error; the rest is {torque}, which no known effect makes: an effect outside "
                "the catalog is likely.")
    s = ranking.scale
    if s is not None and ranking.scale_decided:
        size = f"{100.0 * s.gain:+.1f} % ± {100.0 * s.gain_std:.1f} %"
        return (f"The recorded torque reads every term of the motor's torque balance (004 eq. 1: "
                f"acceleration, friction and load alike) at least {size} off the twin "
                f"{_model_words(ranking)}, beyond the ±{100.0 * s.bound:.0f} % tolerance of the torque "
                "constant times the current sensor's gain: a loss of torque constant (a weakened magnet) "
                "or a current sensor out of its class. No known effect scales the motor torque: an effect "
                "outside the catalog is likely."
                + _ripple(o))
    hy = ranking.hysteresis
    if hy is not None and ranking.hysteresis_decided:
        return (f"Below about {hy.split / 1e3:.1f} kN the release reaches each force "
                f"{1e6 * hy.step:.1f} ± {1e6 * hy.step_std:.1f} µm of nut travel closer to rest than the "
                f"apply did, beyond what the force reading's timing explains, in {hy.applications} held-out "
                "applications; above it the two agree. 004 eq. 5 has one force-travel path both ways, and no "
                "known effect makes a second: a play between motor and screw with the angle measured on the "
                "motor side, which the motor turns back through while the pads still press (the clamp force "
                "no longer back-drives the screw), makes such a step, up to the play's width; a hysteresis "
                "of the pads or the load cell growing with the force could make one too. An effect outside "
                "the catalog is likely.")
    r = ranking.rest
    if r is not None and ranking.rest_decided:
        model = _model_words(ranking)
        return (f"In {r.violated} of {r.cycles} held-out applications the recorded screw stays at rest while "
                f"the motor drives {r.excess:.2f} N m beyond the breakaway torque of the twin {model} "
                f"(004 eq. 9; {r.band:.2f} N m, plus 2 % for K_T): the motor turns where the angle sees no "
                "motion (a play between motor and screw with the angle measured on the screw side, a "
                "slipping coupling), or the screw sticks far harder than any known friction. No known "
                "effect does that: an effect outside the catalog is likely.")
    m = ranking.play
    if m is not None and ranking.play_decided:
        named = " and ".join(f.effect.name.replace("_", " ") for f in ranking.selected)
        size = f"{1e6 * m.travel:.0f} µm"
        return (f"The twin fits the recording with {named}, an extra clearance of {size}, but in "
                f"{m.crossings} held-out releases the motor crosses that extra travel with "
                f"{m.deficit:.3f} ± {m.deficit_std:.3f} N m less friction than the travel right after it: "
                "the motor turns there "
                f"without the screw. That is a play of up to {size} of nut travel between the motor and "
                "the screw (gear, coupling), not a wider brake clearance, which the screw crosses with its "
                "friction; or a friction that changes with the screw's position there. No known effect "
                "does that: an effect outside the catalog is likely.")
    if ranking.verdict == "unexplained":
        material = _material_words(ranking)
        within = f"held-out gap {ranking.gap_tolerance:.2f} x noise within its tolerance"
        drifting = [f for f in ranking.fits if f.drifting]
        if ranking.joint is None and drifting:  # test (d) decided (:func:`.ranking.rank`)
            left = f" The twin within its tolerance leaves {material} ({within})." if material else ""
            words = "; ".join(_drift_words(f) for f in drifting)
            # each is fitted alone: where the whole law drifts, each takes the others' part too (foreign
            # outside_i rising.0: eq. 9's friction +13 % from the early to the late half; load friction
            # alone +26 %, preload alone +20 %)
            alone = " (each fitted alone, so each also takes the others' part)" if len(drifting) > 1 else ""
            return (f"{words[0].upper()}{words[1:]}{alone}. A friction that drifts "
                    "within minutes (grease warming up, running-in) is no property of the unit the catalog "
                    f"describes: an effect outside the catalog is likely.{left}")
        assert material  # otherwise a material error no effect or pair closes half of decided
        return (f"The twin, even within its tolerance, leaves {material} ({within}), and no known effect or "
                f"pair closes half of it (best {100.0 * ranking.best_pair_shrink:.0f} %): an effect outside "
                "the catalog is likely.")
    return (f"The twin explains the recording within its tolerance ({gap}, {ranking.gap_tolerance:.2f} "
            f"within tolerance); no effect is both significant and above its detectability floor."
            f"{_nearest(ranking)}")


def _cautioned_fits(ranking: Ranking) -> list[EffectFit]:
    """The named effects, each as fitted alone, whose size the transients the sampling does not resolve
    could take under its floor at the worst (:func:`.ranking.sampling_caution`), in the order named."""
    if ranking.verdict != "effect":
        return []
    alone = {f.effect.name: f for f in ranking.fits}
    return [alone[f.effect.name] for f in ranking.selected
            if f.effect.name in alone and sampling_caution(alone[f.effect.name])]


def cautioned(ranking: Ranking) -> list[str]:
    """The names of :func:`_cautioned_fits` (JSON ``sampling_caution``)."""
    return [f.effect.name for f in _cautioned_fits(ranking)]


def _sampling_words(ranking: Ranking) -> str:
    """The caution of :func:`_cautioned_fits` in plain words, with each effect's worst-case change (empty
    when there is none)."""
    words = [f"the {f.effect.name.replace('_', ' ')} by up to {size_words(f, f.sampling or 0.0)}"
             for f in _cautioned_fits(ranking)]
    if not words:
        return ""
    it, its = ("them", "their") if len(words) > 1 else ("it", "its")
    return (" Caution: at the worst, transients the sampling does not resolve (current steps, speed changes "
            f"between samples) could move {' and '.join(words)}, enough to take {it} under {its} "
            "detectability floor (README, \"The sampling's share of a size\").")


def _independence_words(ranking: Ranking) -> str:
    """For the named effect that its own test (a) named at the ranking's level (the first of the forward
    selection, as fitted alone: the same object in ``ranking.fits``) and that passes it only with
    independent held-out rows (:meth:`.ranking.effect_fit.EffectFit.rests_on_independent_rows`), that
    caution in plain words.  An effect added to others, or named in a pair, or chosen again given the
    second, was named by the additions' or the pair's test, which is not computed over the applications'
    scatter: no caution (README, "The cycles' scale of the held-out test")."""
    words = [f"the {f.effect.name.replace('_', ' ')} (p = {f.p_cycles:.2g})" for f in ranking.selected
             if any(f is g for g in ranking.fits) and f.rests_on_independent_rows(ranking.alpha)]
    if not words:
        return ""
    return (f" Caution: with the scatter of the brake applications themselves rather than of independent "
            f"samples, the held-out test of {' and '.join(words)} is not significant at the level "
            f"{ranking.alpha:.2g} (README, \"The cycles' scale of the held-out test\").")


def size_words(f: EffectFit, size: float, *, meaning: bool = True) -> str:
    """A size of effect ``f`` in the unit people read: µm of clearance, else % of the quantity it is a
    fraction of (followed by what that quantity is, unless ``meaning`` is False)."""
    if f.effect.size_unit == "m":
        return f"{1e6 * size:.1f} µm"
    percent = f"{100.0 * size:.{0 if size >= 0.01 else 1}f} %"
    return f"{percent} ({f.effect.size_meaning})" if meaning else percent


def _nearest(ranking: Ranking) -> str:
    """For a ``none`` verdict: the best-ranked effect off its physical limits that passed one of the two
    tests an effect needs, significance (a) and materiality (b) of :mod:`.ranking`, or both and was still
    not named, in plain words; empty when none did.  A material effect counts here only when it would be
    significant were it the only effect tried (p below ``ALPHA``, not ``ALPHA`` / K): what a longer
    recording may name, not a finding."""
    for f in ranking.fits:
        if f.at_limit:
            continue
        significant = f.significant(ranking.alpha)
        test = f"p = {f.p_value:.2g} against the level {ranking.alpha:.2g}"
        if f.material and not significant and f.significant(ALPHA):
            return (f" Nearest, not named: {describe(f)}, above its floor but its held-out test is "
                    f"not significant once {len(ranking.fits)} effects are tried ({test}); more "
                    "applications, over more speeds and forces, would decide it.")
        if significant and not f.material:
            return (f" Nearest, not named: {describe(f)}, significant ({test}) but not above its "
                    f"detectability floor of {size_words(f, f.floor)} with 95 % confidence: within what the "
                    "twin's tolerance allows.")
        if significant:
            return (f" Nearest, not named: {describe(f)}, significant ({test}) and above its floor, but it "
                    "does not explain the recording (it leaves the held-out gap where the twin has it, or "
                    "makes another channel materially wrong).")
    return ""


def nuisance_report(sc: Scorer) -> dict[str, Estimate]:
    """Every acquisition convention estimated from the data: value, std, unit (interface.md section 4)."""
    out = dict(sc.model.conv.estimates)
    for name, value in nuisances_of(sc.base.aug).items():
        out[name] = Estimate(value, sc.base_std.get(name, float("nan")), NUISANCE_UNITS[name])
    return out


def diagnose_with_state(rec: Resampled, unit: UnitParams, block_s: float = 0.02
                        ) -> tuple[DiagnosisResult, Scorer, Ranking]:
    """:func:`diagnose_recording` plus the residual model and ranking behind it (for the report).

    BLAS runs on one thread: the fits solve hundreds of small least-squares problems, for which
    a multithreaded BLAS on a busy machine is tens of times slower than one thread.
    """
    with threadpool_limits(1, user_api="blas"):
        return _diagnose(rec, unit, block_s)


def _diagnose(rec: Resampled, unit: UnitParams, block_s: float) -> tuple[DiagnosisResult, Scorer, Ranking]:
    sc, ranking = analyse(rec, unit, block_s)
    top = ranking.top
    explained = ranking.explained
    nominal = sc.model.nominal
    b = sc.model.blocks
    ties = [f for f in ranking.fits[1:] if f.effect.name in top.ties]
    experiments = [separating_experiment(
        nominal, top, f, max_speed=float(sc.model.speed.max()), max_force=float(sc.model.force.max()),
        sigma_torque=float(np.median(sc.sigma_torque)), sigma_force=float(np.median(sc.sigma_force)))
        for f in ties]
    gap_after = explained.gap_after if explained is not None else ranking.gap_before
    refit = evaluate(sc, friction_refit(nominal), nominal_sse(sc), ranking.gap_before)
    law = nominal.friction
    base = {"dT_fc": law.coulomb, "dB": law.viscous, "dG": law.load_coefficient}
    effect = ranking.effect
    return (DiagnosisResult(
        unit=rec.unit,
        verdict=ranking.verdict,
        effect=effect.effect.name if effect is not None else None,
        effects=[f.effect.name for f in ranking.selected] if explained is not None else [],
        summary=summary(ranking),
        ranking=[f.entry() for f in ranking.fits],
        where=where_table(sc, sc.base),
        where_after=where_table(sc, explained.model) if explained is not None else None,
        gap_before=ranking.gap_before,
        gap_tolerance=ranking.gap_tolerance,
        gap_after=gap_after,
        shrink=shrink(ranking.gap_before, gap_after),
        shrink_needed=SHRINK_NEEDED,
        unexplained_share=ranking.unexplained_share,
        metric=METRIC,
        significance_level=ranking.alpha,
        nuisances=nuisance_report(sc),
        near_ties=experiments,
        friction_refit=FrictionRefit(
            refit.entry(), {"T_fc": law.coulomb, "B": law.viscous, "G": law.load_coefficient},
            {k[1:]: base[k] + float(v) for k, v in zip(refit.effect.params, refit.theta, strict=True)}),
        cycles=Cycles(int(np.unique(b.cycle).size), [int(c) for c in sc.split.heldout_cycles]),
        noise={s: signal_noise(getattr(rec, s)) for s in SIGNALS},
        residual_method=RESIDUAL_METHOD,
        position_torque=position_torque(ranking),
        torque_scale=scale_report(ranking),
        rest_torque=rest_report(ranking),
        lost_motion=play_report(ranking),
        hysteresis=hysteresis_report(ranking),
        sampling_caution=tuple(cautioned(ranking)),
    ), sc, ranking)


def position_torque(ranking: Ranking) -> PositionTorque | None:
    """The screw-position harmonic the verdict's model leaves (:mod:`.openset`), as reported."""
    o = ranking.open_set
    if o is None:
        return None
    p = o.periodic
    return PositionTorque(p.harmonic, p.amplitude, p.rms, p.rms_std, p.floor, p.p_value, o.share, o.decided)


def scale_report(ranking: Ranking) -> TorqueScaleTest | None:
    """The motor torque's scale test of the verdict's model (:mod:`.scale`), as reported."""
    s = ranking.scale
    if s is None:
        return None
    return TorqueScaleTest(s.gain, s.gain_std, s.fitted, s.bound, s.p_value, ranking.scale_decided)


def rest_report(ranking: Ranking) -> RestTorqueTest | None:
    """The breakaway-band test of the verdict's model at rest (:mod:`.stick`), as reported."""
    r = ranking.rest
    if r is None:
        return None
    return RestTorqueTest(r.cycles, r.violated, r.excess, r.band, r.floor, r.p_value, ranking.rest_decided)


def play_report(ranking: Ranking) -> LostMotionTest | None:
    """The lost-motion test of the verdict's model (:mod:`.play`), as reported."""
    m = ranking.play
    if m is None:
        return None
    return LostMotionTest(m.crossings, m.travel, m.deficit, m.deficit_std, m.budget, m.floor, m.p_value,
                          ranking.play_decided)


def hysteresis_report(ranking: Ranking) -> HysteresisTest | None:
    """The two-path test of the recording (:mod:`.hysteresis`), as reported."""
    h = ranking.hysteresis
    if h is None:
        return None
    return HysteresisTest(h.applications, h.split, h.step, h.step_std, h.lag, h.floor, h.p_value,
                          ranking.hysteresis_decided)
