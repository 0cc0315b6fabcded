"""The diagnosis results (``ebm-wear diagnose --json`` and ``--selftest --json``), declared once.

A diagnosis of one unit's recording is :class:`DiagnosisResult` (interface.md section 4 and the
diagnosis contract: verdict, effect(s), the ranking of the catalog with each effect's fitted
:class:`Magnitude` and :class:`Size`, where the twin misses, the held-out gaps, the acquisition
conventions estimated from the data as :class:`Estimate`), built by
:func:`ebm_wear_monitor.diagnosis.pipeline.diagnose_recording`. The CLI adds the input screening
and, with ``--life``, the wear-level diagnosis (:class:`UnitDiagnosis`); its document
(:class:`DiagnoseDocument`) holds the first unit's keys at the top level and every unit under
``units``. The self-test's is :class:`SelftestResult` (in-world scores, one :class:`CaseResult` per
case, and the foreign world's :class:`ForeignSelftest`).

Sizes whose unit depends on the entry (a fitted parameter, a nuisance) carry it in their own ``unit``
key; their quantities are declared in :data:`GIVEN` (the unit named by that key, SI).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

from ebm_wear_monitor.domain.phases import PHASES
from ebm_wear_monitor.domain.signals import SIGNALS
from ebm_wear_monitor.schema.fields import Record, quantity

#: the unit of a value whose entry names it in its ``unit`` key (SI: "m", "N m", "rad/s", "-", ...)
GIVEN = "unit key"
#: the verdicts of interface.md section 4
VERDICTS = ("effect", "none", "unexplained")


@dataclass(frozen=True)
class Estimate(Record):
    """A quantity estimated from the data: value, standard deviation and unit (a nuisance: an acquisition
    convention, never an effect)."""

    value: float = quantity(GIVEN, "estimate", json="value")
    std: float = quantity(GIVEN, "its standard deviation (0: not assessed)", json="std")
    unit: str = quantity("", "SI unit of value and std", json="unit")


@dataclass(frozen=True)
class Magnitude(Record):
    """One fitted parameter of an effect in physical units, and as a fraction of the nominal quantity it
    changes when it changes one (those keys are left out otherwise)."""

    value: float = quantity(GIVEN, "fitted parameter", json="value")
    std: float = quantity(GIVEN, "its standard error (cluster-robust over brake cycles)", json="std")
    unit: str = quantity("", "SI unit of value and std", json="unit")
    nominal_name: str | None = quantity("", "the nominal twin quantity it changes", json="nominal_name",
                                        omit_none=True, default=None)
    nominal_value: float | None = quantity(GIVEN, "that quantity's nominal value", json="nominal_value",
                                           omit_none=True, default=None)
    fraction: float | None = quantity("-", "value / nominal_value", json="fraction", omit_none=True,
                                      default=None)
    fraction_std: float | None = quantity("-", "std / |nominal_value|", json="fraction_std", omit_none=True,
                                          default=None)


@dataclass(frozen=True)
class Parameter(Record):
    """One fitted parameter in the fit's own terms."""

    value: float = quantity(GIVEN, "fitted parameter", json="value")
    stderr: float = quantity(GIVEN, "its standard error", json="stderr")
    unit: str = quantity("", "SI unit of value and stderr", json="unit")


@dataclass(frozen=True)
class Size(Record):
    """An effect's size in the unit people judge it by, against its detectability floor
    (:mod:`ebm_wear_monitor.diagnosis.catalog`)."""

    value: float = quantity(GIVEN, "size (>= 0)", json="value")
    std: float = quantity(GIVEN, "its standard deviation (delta method)", json="std")
    unit: str = quantity("", "unit of the size: '-' a fraction, 'm' metres", json="unit")
    meaning: str = quantity("", "what the size measures", json="meaning")
    floor: float = quantity(GIVEN, "detectability floor from the model-tolerance budget", json="floor")
    sampling: float | None = quantity(GIVEN, "worst-case change of the size by the transients the sampling "
                                      "does not resolve (reported, not judged; null: not computed)",
                                      json="sampling", default=None)


@dataclass(frozen=True)
class Drift(Record):
    """A friction effect refitted on the early and the late half of the brake cycles."""

    early: float = quantity(GIVEN, "size on the early half, in the size's unit", json="early")
    late: float = quantity(GIVEN, "size on the late half", json="late")
    std: float = quantity(GIVEN, "standard deviation of late - early", json="std")
    p_value: float = quantity("-", "two-sided p-value of a trend with time in the size per cycle, the "
                              "operating mix (peak force, peak speed) held", json="p_value")
    drifting: bool = quantity("", "the sizes differ beyond the floor and 3 std, and the trend is "
                              "significant (p_value below ranking.DRIFT_ALPHA)", json="drifting")


@dataclass(frozen=True)
class RankingEntry(Record):
    """One catalog effect fitted on calibration cycles and judged on held-out ones."""

    effect: str = quantity("", "catalog name (interface.md section 4; two joined by '+' for a pair)",
                           json="effect")
    score: float = quantity("-", "(S_before - S_after - 2k) / S_before on held-out cycles", json="score")
    gap_after: float = quantity("-", "held-out gap with the effect added and fitted (metric)",
                                json="gap_after")
    shrink: float = quantity("-", "share of the held-out gap it closes, 1 - gap_after / gap_before",
                             json="shrink")
    p_value: float = quantity("-", "one-sided p-value of the held-out test (a): the held-out residual "
                               "along the effect's correction, or the held-out improvement for a "
                               "sampling-cautioned size and for an effect added to others",
                               json="p_value")
    p_value_cycles: float | None = quantity(
        "-", "the same test with its statistic scaled by the larger of its independent-row scale and the "
        "cluster-robust one over the held-out brake cycles (rows of one application share model error): "
        "reported, not judged; null when not tested", json="p_value_cycles")
    k: int = quantity("-", "number of fitted parameters", json="k")
    material: bool = quantity("", "its size exceeds its floor with 95 % confidence", json="material")
    at_limit: bool = quantity("", "a parameter ended on its limit: a physical one (a dissipation or the "
                              "clamp's tangent stiffness at zero) or the effect's definition (a clearance "
                              "growth, a viscous drag or a load friction at zero: each only grows); a "
                              "catalog effect so fitted is never named", json="at_limit")
    drift: Drift | None = quantity("", "early/late refit (null: not tested)", json="drift")
    size: Size = quantity("", "its size against its detectability floor", json="size")
    magnitude: dict[str, Magnitude] = quantity("", "fitted size per parameter, in physical units of the unit",
                                               json="magnitude")
    parameters: dict[str, Parameter] = quantity("", "the fitted parameters", json="parameters")


@dataclass(frozen=True)
class FrictionRefit(Record):
    """T_fc, B and G of 004 eq. 9 refitted together (not a catalog entry): the unit's friction law."""

    fit: RankingEntry = quantity("", "the refit judged like a catalog effect", json="")
    nominal: dict[str, float] = quantity(GIVEN, "nominal T_fc [N m], B [N m s/rad], G [N m/N]",
                                         json="nominal")
    refitted: dict[str, float] = quantity(GIVEN, "refitted T_fc [N m], B [N m s/rad], G [N m/N]",
                                          json="refitted")


@dataclass(frozen=True)
class SpeedBin(Record):
    """Torque-channel RMS z-score of the moving blocks in one quartile bin of screw speed."""

    range_rad_s: list[float] = quantity("rad/s", "bin edges of the block's mean screw speed",
                                        json="range_rad_s")
    normalised_rms: float | None = quantity("-", "RMS residual / noise", json="normalised_rms")
    blocks: int = quantity("-", "blocks in the bin", json="blocks")


@dataclass(frozen=True)
class ForceBin(Record):
    """RMS z-score of the blocks in contact in one quartile bin of clamp force."""

    range_N: list[float] = quantity("N", "bin edges of the block's mean clamp force", json="range_N")
    normalised_rms: float | None = quantity("-", "RMS residual / noise", json="normalised_rms")
    blocks: int = quantity("-", "blocks in the bin", json="blocks")


@dataclass(frozen=True)
class Where(Record):
    """Where the twin misses: per phase and signal, and over speed and force (diagnosis/where.py)."""

    phase: str | None = quantity("", "phase of the largest RMS z-score (null: no block)", json="phase",
                                 enum=PHASES)
    signal: str | None = quantity("", "signal of the largest RMS z-score", json="signal", enum=SIGNALS)
    normalised_rms: float | None = quantity("-", "that RMS residual / noise", json="normalised_rms")
    table: dict[str, dict[str, float | None]] = quantity("-", "phase -> signal -> RMS residual / noise",
                                                         json="table")
    by_speed: list[SpeedBin] = quantity("", "torque channel over screw speed", json="by_speed")
    by_force: list[ForceBin] = quantity("", "torque channel over clamp force", json="by_force")
    by_force_axial: list[ForceBin] = quantity("", "force channel over clamp force", json="by_force_axial")


@dataclass(frozen=True)
class PositionTorque(Record):
    """A torque that depends on where the screw is, left by the verdict's model (diagnosis/openset.py)."""

    harmonic: int = quantity("", "k of the harmonic of the screw angle that fits best (over a stroke shorter "
                             "than a turn: only a shape)", json="harmonic")
    amplitude_Nm: float = quantity("N m", "its peak at the motor", json="amplitude_Nm")
    rms_Nm: float = quantity("N m", "RMS of its contribution over the moving blocks", json="rms_Nm")
    rms_std_Nm: float = quantity("N m", "standard deviation of that RMS", json="rms_std_Nm")
    floor_Nm: float = quantity("N m", "materiality bound: 2 % of the RMS motor torque", json="floor_Nm")
    p_value: float = quantity("-", "held-out improvement test beyond force- and speed-shaped terms",
                              json="p_value")
    effects_share: float | None = quantity(
        "-", "share of the explainable held-out error the effects close, (S_W - S_E) / (S_W - S_EP); "
        "null without an effect or when the harmonic removes nothing", json="effects_share")
    decided: bool = quantity("", "it turned the verdict into unexplained", json="decided")


@dataclass(frozen=True)
class TorqueScaleTest(Record):
    """The motor torque's scale K_T x current gain the verdict's model leaves, against its tolerance
    (diagnosis/scale.py)."""

    gain: float = quantity("-", "total relative deviation of K_T x current gain the torque wants, fitted on "
                           "the calibration blocks with the model's other deviations held: a lower bound "
                           "(-0.08: at least 8 % low)", json="gain")
    gain_std: float = quantity("-", "its standard error (the larger of least squares and cluster-robust by "
                               "brake cycle)", json="gain_std")
    fitted: float = quantity("-", "the deviation the verdict's model took within the budget", json="fitted")
    bound: float = quantity("-", "the budget's bound on it; material: |gain| above it with 95 % confidence",
                            json="bound")
    p_value: float = quantity("-", "held-out improvement test of the scale beyond the model's",
                              json="p_value")
    decided: bool = quantity("", "it turned the verdict into unexplained", json="decided")


@dataclass(frozen=True)
class RestTorqueTest(Record):
    """Drive held at rest beyond 004 eq. 9's breakaway band by the verdict's model (diagnosis/stick.py)."""

    cycles: int = quantity("", "held-out applications with a block at rest", json="cycles")
    violated: int = quantity("", "of them, those whose largest excess over the band exceeds 2 block-noise "
                             "standard deviations", json="violated")
    excess_Nm: float = quantity("N m", "median excess over the band of the violating applications (0 without "
                                "any)", json="excess_Nm")
    band_Nm: float = quantity("N m", "median breakaway torque of the verdict's model there (0 without any); "
                              "material: the excess above it and above floor_Nm", json="band_Nm")
    floor_Nm: float = quantity("N m", "materiality bound: 2 % of the RMS motor torque", json="floor_Nm")
    p_value: float = quantity("-", "binomial tail of the violating applications at 0.1 per application",
                              json="p_value")
    decided: bool = quantity("", "it turned the verdict into unexplained", json="decided")


@dataclass(frozen=True)
class HysteresisTest(Record):
    """Apply and release on two force-travel paths below a force (diagnosis/hysteresis.py)."""

    applications: int = quantity("", "held-out applications with force levels on both sides of the split",
                                 json="applications")
    split_N: float = quantity("N", "force below which the step is measured (chosen on the calibration "
                              "applications)", json="split_N")
    step_m: float = quantity("m", "mean step, below the split against above it, of the apply-minus-release "
                             "nut travel at equal force beyond the verdict model's (its force skew and lag) "
                             "and the residual lag's share (a play taken up in contact: its width)",
                             json="step_m")
    step_std_m: float = quantity("m", "standard error of that mean", json="step_std_m")
    lag_s: float = quantity("s", "residual lag of the force reading beyond the verdict model's skew and lag, "
                            "fitted on the calibration applications (0 where the speed does not vary within "
                            "the applications and the step is fitted alone)", json="lag_s")
    floor_m: float = quantity("m", "materiality bound: the thermal part of the clearance's tolerance",
                              json="floor_m")
    p_value: float = quantity("-", "one-sided t test of the mean step against zero", json="p_value")
    decided: bool = quantity("", "it turned the verdict into unexplained", json="decided")


@dataclass(frozen=True)
class LostMotionTest(Record):
    """Friction over the extra clearance of the verdict's model in the release (diagnosis/play.py)."""

    crossings: int = quantity("", "held-out release crossings with both travel windows sampled",
                              json="crossings")
    travel_m: float = quantity("m", "the extra clearance of the verdict's model: the window's length in nut "
                               "travel", json="travel_m")
    deficit_Nm: float = quantity("N m", "mean friction the recording lacks over the extra clearance compared "
                                 "with the travel right after it (a play: the screw's friction)",
                                 json="deficit_Nm")
    deficit_std_Nm: float = quantity("N m", "standard error of that mean", json="deficit_std_Nm")
    budget_Nm: float = quantity("N m", "how far the model-tolerance budget at its bounds moves the mean "
                                "deficit, summed over its entries", json="budget_Nm")
    floor_Nm: float = quantity("N m", "materiality bound: 2 % of the RMS motor torque; material: the "
                               "deficit above it and above budget_Nm with 95 % confidence", json="floor_Nm")
    p_value: float = quantity("-", "one-sided t test of the mean deficit against zero", json="p_value")
    decided: bool = quantity("", "it turned the verdict into unexplained", json="decided")


@dataclass(frozen=True)
class NearTie(Record):
    """Two effects the held-out data do not tell apart, and the experiment that would."""

    between: list[str] = quantity("", "the top effect and the tied one", json="between")
    screw_speed_rad_s: list[float] | None = quantity(
        "rad/s", "screw-speed range of the experiment (null: the force channel separates them)",
        json="screw_speed_rad_s")
    force_N: list[float] = quantity("N", "clamp-force range of the experiment", json="force_N")
    separation_sigma: float = quantity("-", "largest difference of the two fitted models / noise",
                                       json="separation_sigma")
    inside_recorded_range: bool = quantity("", "the experiment lies within the recorded range",
                                           json="inside_recorded_range")
    experiment: str = quantity("", "the experiment in words", json="experiment")


@dataclass(frozen=True)
class Cycles(Record):
    """The brake cycles of the recording and the held-out ones."""

    total: int = quantity("-", "brake cycles found", json="total")
    heldout: list[int] = quantity("-", "indices of the held-out cycles", json="heldout")


@dataclass(frozen=True)
class DiagnosisResult(Record):
    """One unit's sim-to-real diagnosis (interface.md section 4, with extra keys)."""

    unit: str = quantity("", "the unit's namespace", json="unit")
    verdict: str = quantity("", "effect: named; none: the twin explains the data; unexplained: a material "
                            "gap no catalog effect nor pair closes", json="verdict", enum=VERDICTS)
    effect: str | None = quantity("", "the single most likely unmodelled effect", json="effect")
    effects: list[str] = quantity("", "the effects forward selection kept, in the order added (at most "
                                  "three); [] for none / unexplained", json="effects")
    summary: str = quantity("", "the verdict in one plain-words sentence", json="summary")
    ranking: list[RankingEntry] = quantity("", "every catalog effect, best first", json="ranking")
    where: Where = quantity("", "where the twin as given misses", json="where")
    where_after: Where | None = quantity("", "where the explaining model misses (null: no effect)",
                                         json="where_after")
    gap_before: float = quantity("-", "held-out gap of the nominal twin (nuisances fitted)",
                                 json="gap_before")
    gap_tolerance: float = quantity("-", "held-out gap of the twin within its tolerance",
                                    json="gap_tolerance")
    gap_after: float = quantity("-", "held-out gap of the explaining model (gap_before: none)",
                                json="gap_after")
    shrink: float = quantity("-", "1 - gap_after / gap_before", json="shrink")
    shrink_needed: float = quantity("-", "share of the material model error an effect must close",
                                    json="shrink_needed")
    unexplained_share: dict[str, float] = quantity(
        "-", "per channel: the tolerant twin's RMS model error beyond the noise, share of the channel's "
        "signal",
        json="unexplained_share")
    metric: str = quantity("", "name of the gap metric", json="metric")
    significance_level: float = quantity("-", "level of each effect's test (0.05 / effects tried)",
                                         json="significance_level")
    nuisances: dict[str, Estimate] = quantity("", "acquisition conventions estimated from the data: never an "
                                              "effect", json="nuisances")
    near_ties: list[NearTie] = quantity("", "effects tied with the top one", json="near_ties")
    friction_refit: FrictionRefit = quantity("", "004 eq. 9's moving-branch friction refitted",
                                             json="friction_refit")
    cycles: Cycles = quantity("", "brake cycles", json="cycles")
    noise: dict[str, float] = quantity(GIVEN, "white-noise std per signal in its SI unit (rad, rad/s, N, A)",
                                       json="noise")
    residual_method: str = quantity("", "how the residuals are formed", json="residual_method")
    position_torque: PositionTorque | None = quantity(
        "", "torque depending on the screw position left by the verdict's model (null: not tested)",
        json="position_torque", default=None)
    torque_scale: TorqueScaleTest | None = quantity(
        "", "the motor torque's scale the verdict's model leaves, against its tolerance (null: not tested)",
        json="torque_scale", default=None)
    rest_torque: RestTorqueTest | None = quantity(
        "", "drive held at rest beyond the breakaway band of the verdict's model (null: not tested)",
        json="rest_torque", default=None)
    lost_motion: LostMotionTest | None = quantity(
        "", "friction over the extra clearance of the verdict's model: a play or a clearance (null: not "
        "tested, the verdict's effects hold no clearance growth)", json="lost_motion", default=None)
    hysteresis: HysteresisTest | None = quantity(
        "", "apply and release on two force-travel paths below a force: a play crossed in contact with the "
        "angle on the motor side (null: not made, the verdict already unexplained by an earlier test, the "
        "forces spanning too little, or too few applications with levels on both sides of the split)",
        json="hysteresis", default=None)
    sampling_caution: tuple[str, ...] = quantity(
        "", "named effects whose size, fitted alone, the transients the sampling does not resolve could take "
        "under its floor at the worst (ranking's size.sampling above size - 1.645 std - floor): a caution, "
        "not judged by the verdict", json="sampling_caution", default=())


@dataclass(frozen=True)
class LifeFit(Record):
    """One wear-level effect fitted on duty-cycle summaries (diagnosis/life.py)."""

    effect: str = quantity("", "wear-level effect name", json="effect")
    parameters: list[float] = quantity(GIVEN, "fitted parameters (diagnosis/life.py's table)",
                                       json="parameters")
    score: float = quantity("-", "(S_before - S_after - 2k) / S_before on held-out summaries", json="score")
    p_value: float = quantity("-", "one-sided p-value of the held-out improvement", json="p_value")


@dataclass(frozen=True)
class LifeDiagnosis(Record):
    """The wear-level diagnosis: observed clearance growth against the wear model (``--life``)."""

    verdict: str = quantity("", "effect or none", json="verdict", enum=VERDICTS[:2])
    effect: str | None = quantity("", "the best effect when significant", json="effect")
    ranking: list[LifeFit] = quantity("", "every wear-level effect, best first", json="ranking")
    near_ties: list[str] = quantity("", "effects not told apart from the top one", json="near_ties")
    noise_m: float = quantity("m", "noise of the observed clearance", json="noise_m")
    gap_before_m: float = quantity("m", "held-out RMS gap of the wear model", json="gap_before_m")
    summaries: int = quantity("-", "duty-cycle summaries used", json="summaries")
    source: str = quantity("", "where the summaries come from", json="source")


@dataclass(frozen=True)
class UnitDiagnosis(Record):
    """One unit of ``ebm-wear diagnose --json``: the diagnosis, the input screening, the life level."""

    diagnosis: DiagnosisResult = quantity("", "the diagnosis of the unit's recording", json="")
    input_faults_by_signal: dict[str, dict[str, int]] = quantity(
        "-", "samples dropped before the diagnosis, per signal and kind (replay's key)",
        json="input_faults_by_signal")
    input_faults: dict[str, int] = quantity("-", "samples dropped, per kind", json="input_faults")
    life: LifeDiagnosis | None = quantity("", "wear-level diagnosis (only with --life)", json="life",
                                          omit_none=True, default=None)


@dataclass(frozen=True)
class DiagnoseDocument(Record):
    """``ebm-wear diagnose --json``: the first unit's keys at the top level (a one-unit recording reads as
    interface.md's object) and every unit under ``units``."""

    first: UnitDiagnosis = quantity("", "the first unit", json="")
    units: list[UnitDiagnosis] = quantity("", "every unit found in the bags, in name order", json="units")


# ---------------------------------------------------------------------------------------- self-test
@dataclass(frozen=True)
class CaseResult(Record):
    """One in-world self-test case: what was injected and what the diagnosis said."""

    true: str = quantity("", "the catalog effects injected, joined by '+' ('none': no effect)", json="true")
    effects: dict[str, float] = quantity(GIVEN, "the simulator's effects and magnitudes", json="effects")
    relative_change: float = quantity("-", "relative change of the quantity the effect acts on",
                                      json="relative_change")
    seed: int = quantity("-", "noise seed", json="seed")
    demands: list[float] = quantity("N", "clamp-force demands, cycled", json="demands")
    source: str = quantity("", "twin_x8 | twin | reference:instant | reference:mean", json="source")
    rate_hz: float = quantity("Hz", "recording rate", json="rate_hz")
    verdict: str = quantity("", "the diagnosis's verdict", json="verdict", enum=VERDICTS)
    diagnosed: str = quantity("", "the verdict's effect or 'none'", json="diagnosed")
    top2: list[str] = quantity("", "the two best-ranked effects", json="top2")
    gap_before: float = quantity("-", "held-out gap before", json="gap_before")
    gap_after: float = quantity("-", "held-out gap after", json="gap_after")
    gap_after_top: float = quantity("-", "held-out gap of the best-ranked effect", json="gap_after_top")
    top1_ok: bool = quantity("", "the verdict names an injected effect", json="top1_ok")
    top2_ok: bool = quantity("", "an injected effect is among the two best-ranked", json="top2_ok")
    where: list[str | None] = quantity("", "[phase, signal] of where", json="where")


@dataclass(frozen=True)
class SourceFalsePositives(Record):
    """No-effect cases of one source and rate, and how many got an effect verdict."""

    cases: int = quantity("-", "no-effect cases", json="cases")
    false_positives: int = quantity("-", "of them with verdict effect", json="false_positives")


@dataclass(frozen=True)
class ForeignCaseResult(Record):
    """One foreign-world case: the generator's truth and the diagnosis's answer."""

    case: str = quantity("", "the case's bag name", json="case")
    kind: str = quantity("", "none | effect | pair | outside", json="kind")
    true: str = quantity("", "true label: catalog effects joined by '+', 'none', or the outside effect",
                         json="true")
    effects_true: list[str] = quantity("", "the catalog effects in the recording", json="effects_true")
    relative_change: dict[str, float | None] = quantity("-", "per effect: the generator's relative change",
                                                        json="relative_change")
    verdict: str = quantity("", "the diagnosis's verdict ('error': refused)", json="verdict")
    diagnosed: str = quantity("", "the effect named, none, unexplained or error", json="diagnosed")
    error: str | None = quantity("", "why the diagnosis refused the recording", json="error", omit_none=True)
    effects: list[str] = quantity("", "the effects named", json="effects")
    top2: list[str] = quantity("", "the two best-ranked effects", json="top2")
    gap_before: float = quantity("-", "held-out gap before", json="gap_before")
    gap_after: float = quantity("-", "held-out gap after", json="gap_after")
    shrink: float = quantity("-", "1 - gap_after / gap_before", json="shrink")
    top1_ok: bool = quantity("", "the verdict names a true effect", json="top1_ok")
    top2_ok: bool = quantity("", "a true effect is among the two best-ranked", json="top2_ok")
    pair_ok: bool = quantity("", "a two-effect case with both effects named", json="pair_ok")
    where: list[str | None] = quantity("", "[phase, signal] of where", json="where")
    seconds: float = quantity("s", "wall time of the case (writing the bag included)", json="seconds")
    sampling_caution: bool = quantity("", "the verdict carries the sampling caution (DiagnosisResult's "
                                      "sampling_caution not empty)", json="sampling_caution", default=False)


@dataclass(frozen=True)
class ForeignCounts(Record):
    """Cases of the foreign set by kind."""

    none: int = quantity("-", "no-effect cases", json="none")
    single: int = quantity("-", "single-effect cases", json="single")
    single_small: int = quantity("-", "of them below a 10 % relative change", json="single_small")
    pairs: int = quantity("-", "two-effect cases", json="pairs")
    outside: int = quantity("-", "cases with an effect outside the catalog", json="outside")


#: true label -> diagnosed answer -> count
Confusion = dict[str, dict[str, int]]


def confusion_matrix(pairs: Iterable[tuple[str, str]]) -> Confusion:
    """The :data:`Confusion` of (true label, diagnosed answer) pairs."""
    confusion: Confusion = {}
    for true, answer in pairs:
        row = confusion.setdefault(true, {})
        row[answer] = row.get(answer, 0) + 1
    return confusion


@dataclass(frozen=True)
class ForeignSelftest(Record):
    """The foreign-world self-test (diagnosis/foreign_selftest.py): recordings of an independent generator."""

    cases: int = quantity("-", "cases", json="cases")
    top1_accuracy: float | None = quantity("-", "single effects >= 10 %: the verdict names it",
                                           json="top1_accuracy")
    top1_accuracy_small: float | None = quantity("-", "the same for 5-10 % effects",
                                                 json="top1_accuracy_small")
    top2_accuracy: float | None = quantity("-", "a true effect among the two best-ranked",
                                           json="top2_accuracy")
    false_positive_rate: float | None = quantity("-", "verdict other than none on no-effect cases",
                                                 json="false_positive_rate")
    median_shrink: float | None = quantity("-", "median held-out shrink of effect cases",
                                           json="median_shrink")
    unexplained_accuracy: float | None = quantity("-", "outside effects reported unexplained",
                                                  json="unexplained_accuracy")
    catalog_unexplained_rate: float | None = quantity("-", "catalog cases reported unexplained",
                                                      json="catalog_unexplained_rate")
    pair_accuracy: float | None = quantity("-", "two-effect cases with both named", json="pair_accuracy")
    counts: ForeignCounts = quantity("", "cases by kind", json="counts")
    confusion: Confusion = quantity("-", "true label -> answer -> count", json="confusion")
    seconds: float = quantity("s", "wall time", json="seconds")
    case_results: list[ForeignCaseResult] = quantity("", "one row per case, by name", json="case_results")


@dataclass(frozen=True)
class SelftestResult(Record):
    """``ebm-wear diagnose --selftest --json``: interface.md section 4's scores (in-world) and more."""

    cases: int = quantity("-", "in-world cases", json="cases")
    top1_accuracy: float | None = quantity("-", "effects >= 10 %: the verdict names a true effect",
                                           json="top1_accuracy")
    top2_accuracy: float | None = quantity("-", "effects >= 10 %: a true effect among the two best-ranked",
                                           json="top2_accuracy")
    top1_accuracy_all_magnitudes: float | None = quantity("-", "top-1 over every effect case",
                                                          json="top1_accuracy_all_magnitudes")
    false_positive_rate: float | None = quantity("-", "verdict effect on no-effect cases",
                                                 json="false_positive_rate")
    false_positives_by_source: dict[str, SourceFalsePositives] = quantity(
        "", "per 'source@rate': no-effect cases and false positives", json="false_positives_by_source")
    top1_accuracy_by_source: dict[str, float | None] = quantity("-", "top-1 (effects >= 10 %) per source",
                                                               json="top1_accuracy_by_source")
    median_shrink: float | None = quantity("-", "median held-out shrink 1 - gap_after / gap_before of "
                                           "effect cases", json="median_shrink")
    confusion: Confusion = quantity("-", "true effect -> diagnosed effect or none -> count", json="confusion")
    rate_hz: float = quantity("Hz", "recording rate of the twin_x8 cases", json="rate_hz")
    cycles_per_case: int = quantity("-", "brake applications per recording", json="cycles_per_case")
    seconds: float = quantity("s", "wall time of the in-world set", json="seconds")
    case_results: list[CaseResult] = quantity("", "one row per case", json="case_results")
    foreign: ForeignSelftest | None = quantity("", "the foreign world (left out with --in-world-only)",
                                               json="foreign", omit_none=True, default=None)
