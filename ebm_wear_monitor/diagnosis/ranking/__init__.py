"""Which effect: fit on calibration cycles, judge on held-out cycles, rank, select, decide, flag near-ties.

**Split by cycle, stratified by force.**  Brake cycles (see :mod:`..phases`) are
ordered by their peak clamp force (then time) and alternate: first, third, ...
calibrate, second, fourth, ... are held out.  Both sides thus cover the whole
range of demands even when the demands repeat with an even period; a held-out
cycle never contributes to any fit.  At least four cycles are needed.  The sides are not balanced in
time: on a foreign clearance ramp + viscous pair (``full_b``), all 10 held-out applications were
among the first 14 of 20, and the constant clearance fitted on the others made the held-out force
worse than none.  A split
that also balances time (one of each pair of force neighbours held out, chosen so the sides' summed
times differ by at most one pair's gap) was tried and not kept: it named that pair but reshuffled
marginal verdicts elsewhere (on two mixed draws, with a drift test asked without (a) and the
open-set rule of :func:`.verdict.open_set_verdict`'s note, all three reverted: exact pairs 13 -> 12 of 20, a
false positive where the tolerant twin's held-out torque error crossed its 2 % bound, catalog
``unexplained`` 2 -> 8 % on one).

**Acquisition nuisances.**  The current timing and offset, the quadrature rule of
the load, the force-sensor skew and lag (:mod:`..residuals`) are fitted first on the
calibration cycles with the nominal twin (the "before" model, :attr:`.scorer.Scorer.base`),
each channel on its own rows, and refitted with every effect in the channels the
effect acts in, each on every row it moves (the force reading's skew and lag time the load torque
too, :func:`.scorer.fit`); being in both models they are not counted in the penalty.  So an effect is
declared only when it explains the data better than the nominal twin
under its *best* admissible acquisition.

**Normalised residuals.**  Each block gives a torque residual R_T and a force
residual R_F (:mod:`..residuals`), divided by their block noise: z = R / sigma.
sigma is propagated from the measured sensor noise (:func:`.blocknoise.block_noise`) and, in the
torque channel, from the transients the sampling does not resolve; each of the two is
rescaled to the scatter the residual of the twin within its tolerance actually shows where
it dominates (:meth:`.scorer.Scorer.noise_scale`).

**Fit.**  An effect's parameters theta minimise sum z(theta)^2 over the calibration
blocks of its channels (bounded Gauss-Newton, ``scipy.optimize.least_squares``),
together with the acquisition nuisances of those channels and the model tolerances
of :mod:`..tolerance` (each bounded to its budget; they enter linearly through their
fixed response columns, z = z(theta, nuisances) + D t, |t| <= 1).  The nominal twin
fitted this way, nuisances and tolerances and no effect, is the "before" model W:
the twin within its tolerance.  The uncertainty of the parameters is the
cluster-robust (sandwich) covariance with brake cycles as clusters,
(J'J)^-1 (sum_c J_c' z_c z_c' J_c) (J'J)^-1.

**Held-out gap.**  ``metric`` = ``excess_rms_over_noise``: over the held-out blocks,
gap = sqrt(max(mean(z^2) - 1, 0)), the RMS model error in units of the noise.  ``gap_before``
is the nominal twin's (as given, nuisances fitted), ``gap_after`` that of the explaining model
(its effects, nuisances and tolerance deviations); the gap of W alone is ``gap_tolerance``.
Torque rows of blocks at rest are left out of the gap (their stick-branch residual
is zero by construction).  **Score** (ranking) = (S_before - S_after - 2k) / S_before
with S the held-out sum of z^2 and k the effect's parameter count.

**Tests for an effect to count** (issue 10, items 3-5):

(a) statistical: the held-out improvement over W_E, the twin within its tolerance with the
    effect's own budget entries held at zero (the model the effect extends: a nested
    comparison, :func:`.effect_fit.base_without_own`), is significant, tested by the held-out
    residual's component along the correction.  The correction an effect
    makes, delta = z_before - z_after on the held-out rows, is fixed by the calibration
    cycles; with held-out noise z ~ N(0, 1) independent of it, V = sum(z delta) / |delta| is
    standard normal when the effect is absent and N(|delta|, 1) when it is present and fitted
    right, and the effect passes when its one-sided p-value is below 0.05 / K (Bonferroni over
    the K effects tried; :func:`..heldout.direction_p`) and its held-out score is positive (it
    lowers the held-out sum of squares by more than 2 k).  Until 2026-11-29 the statistic was
    U = (S_before - S_after) / (2 |delta|) = V - |delta| / 2, with S_before - S_after =
    2 sum(z delta) - sum(delta^2): N(-|delta| / 2, 1) under "absent", so compared with N(0, 1) its
    level fell far below 0.05 / K as |delta| grew: a foreign viscous drag of +98 % of B whose
    correction held out exactly what its calibration fit predicted (U = 1.89 against
    |delta| / 2 = 1.90, ``full_t`` viscous_friction.power.0, 200 Hz) read ``none`` (and still does:
    its size is sampling-cautioned, below).  A size the sampling
    could have made (:func:`.effect_fit.sampling_caution`) keeps U: V alone named healthy
    recordings of the reference simulator at 500 Hz a Stribeck fall (in-world false positives
    2 -> 4 of 64), both added ones cautioned; README "The held-out test's statistic".
    Additions keep U too (:func:`.effect_fit.addition_p`): the model an addition extends
    carries the first effect's form error, structure rather than noise, and V there named
    passengers (three on ``full_t``); a pair fitted jointly (no sampling bound) takes V.  |delta|
    is the standard deviation of z . delta only for independent held-out rows of unit variance: rows
    of one cycle share model error and the measured noise scale is the smaller of two estimates, both
    of which make V liberal (U's offset of -|delta| / 2 had absorbed that).  The same test with both
    statistics divided by the larger of |delta| and the cluster-robust scale over the held-out cycles,
    sqrt(sum_c (sum_{i in c} z_after,i delta_i)^2) (:func:`..heldout.direction_p` with ``clusters``),
    is reported beside it (``p_value_cycles``; the report notes a pass that rests on independent rows)
    and not judged: as the verdict's test it removed two foreign and two in-world false positives, all
    on draws seen before, and on the draws registered blind for it (``full_ac``, ``outside_ab``,
    third-world seeds 28 and 29) it removed none and lost a true Stribeck fall and an ``unexplained``
    ripple (README, "The cycles' scale of the held-out test").
    (A goodness-of-fit test of the before model where the effect acts was tried as a second guard:
    against the twin within its tolerance it rejected a +100 % viscous change on the twin's own data; the
    practical test (b) is the guard against significant but immaterial structure.  Weighted Bonferroni
    was tried and not kept: the effect with the largest calibration gain, S_cal(W) - S_cal - 2k, at
    0.05 / 2 and each other at 0.05 / (2 (K - 1)), a valid split since the weights are fixed before the
    held-out cycles are seen.  Prompted by foreign viscous drags of +100 % of B at p = 0.02 read
    ``none``, it named two of them (``full_e``, ``full_i``), turned one foreign ripple from
    ``unexplained`` into three friction effects (``outside_d``), changed nothing on the blind draws
    ``full_j`` and ``outside_i``, and in-world turned two healthy units of the reference simulator at
    500 Hz into Stribeck friction of 56-88 % of T_fc (false positives 1 -> 3 of 64; the one before is
    the same kind), so the level stays 0.05 / K.)
(b) practical: its fitted size exceeds its detectability floor (:mod:`..tolerance`, from
    the model-tolerance budget) with 95 % confidence, size - 1.645 std > floor, and its fit is off
    the physical limits of the catalog (:meth:`..catalog.Effect.at_limit`,
    :attr:`.effect_fit.EffectFit.nameable`);
(d) stationary: a friction effect is a property of the unit and must hold over the
    recording.  It drifts (fails) when, refitted on the early and on the late half of the brake
    cycles, its sizes differ by more than its floor and three standard deviations, and its size
    per cycle also trends with time once the operating mix is regressed out (at ``DRIFT_ALPHA``:
    the catalog's form fits a real effect only approximately, so its size depends on the
    operating mix of a half too; :func:`.criteria.drift_test`).
    friction that drifts within minutes (warming grease) is outside the catalog.  Clearance
    (wear), sensor and stiffness effects may change within a recording;
(c) explanatory: it (or the pair it is part of) closes at least half (``SHRINK_NEEDED``)
    of the material model error, in every channel where that error is material
    (:meth:`.scorer.Scorer.unexplained_share`), and the held-out gap of the model with the selected effects
    is below the nominal twin's (``shrink`` > 0).  The second half matters where the twin within its
    tolerance leaves no material error: an effect that passes (a), (b), (d) and (e) there but leaves
    the held-out gap where the twin as given has it explains nothing (a healthy foreign unit at 200 Hz,
    ``full_g`` none_g003: viscous +38 ± 7 % of B, p = 3e-4 against the twin within its tolerance,
    held-out gap 1.52 -> 1.54 x noise; found on that blind draw, the rule written after it; no other
    verdict of the 14 foreign case sets or of the 216 in-world cases has shrink <= 0);
(e) consistent: it does not make the model materially wrong in a channel, the error it adds there
    (in quadrature, held out) staying below the channel's materiality share (:func:`.criteria.worsens`): a
    force-sensor gain that closes the force gap by putting a tenth of the load torque into the torque
    residual explains nothing.

**Forward selection** (up to three effects).  After the best single effect passing (a),
(b), (d) and (e), every other effect is fitted *together* with it and *on top of* it (the first
as fitted, the second with its own channels' nuisances and tolerances: :func:`.effect_fit.extend`); the
better of the two on held-out cycles is its candidate, and the best candidate is kept when
its addition again passes (a) against the first alone and against the first refitted with the
candidate's own budget entries held at zero, the larger p-value (held out, at 0.05 over the number of
fits tried, up to two for each of the K - 1 candidates; :func:`.effect_fit.addition_p`), (b), (d)
(refitted within
the model with the addition) and (e); of a candidate's two fits the best-scoring one that passes
(a), (b) and (e) counts.  The first is then chosen again given the second,
by the same rule, and again given the new partner while each swap raises the held-out score (the
floating step, :func:`.selection._rechoose_first`).  A third effect is then fitted on top of the two only (not
jointly) and kept when it passes the same tests against them (at 0.05 / (K - 2)).
When the selection leaves the material model error more than half open (it fails (c), or nothing
was selected), the best subset of size two is searched (:func:`.selection.best_pair`): every pair
fitted jointly
from W, the best-scoring one passing (a) against W with both effects' own entries held at zero (at 0.05
over the number of pairs), each effect's (a) given the other (at half that), (b) for each effect as
fitted in the pair, (d) for each refitted within it, (e) and (c) becomes the selection; not where a
single effect drifts.  ``effects`` lists the selected ones; the verdict's ``effect`` is the largest:
the one that changes the twin's prediction most (:func:`.effect_fit.contribution`).

**Verdict.**  ``effect`` when the selection passes (c); otherwise ``unexplained``
when the model error of the twin within its tolerance is *material* and no effect or
pair closes half of it, or when an effect passes (a), (b) and (e) and fails only (d): a
significant friction change of material size that does not hold over the recording is
no catalog effect (a catalog effect is a property of the unit), whatever share of the
model error the twin within its tolerance leaves; ``none`` otherwise: the twin explains the
data within its tolerance.  Then structure the catalog cannot represent is looked for
(:mod:`..openset`): a significant torque as a function of the screw angle that removes more of the
explaining model's held-out error than its effects removed turns ``effect`` into ``unexplained``
(the effects closed less than half of what is explainable); a significant and material one turns
``none`` into ``unexplained`` (:func:`.verdict.open_set_verdict`).  Then the motor torque's scale
(:mod:`..scale`): when the verdict's model uses the budget's +-2 % on K_T x current gain up to its bound
and the held-out torque wants significantly more, beyond the bound with 95 % confidence, every term
of eq. 1 is read through a scale no catalog effect changes (a torque-constant loss, a current sensor
out of its class), and ``effect`` or ``none`` becomes ``unexplained``.  Then, whatever the model, the
recording's force-travel paths (:mod:`..hysteresis`): when, below some force, the release reaches each
force significantly and materially (5 um with 95 % confidence) earlier in travel than the apply, beyond
what the force reading's lag explains, the motor-side angle crossed a play in contact, which 004 eq. 5's
single force-travel path cannot make, and ``effect`` or ``none`` becomes ``unexplained``.  Last, the band
test at rest
(:mod:`..stick`): when the verdict's model (the selected effects, or the twin within its tolerance)
cannot hold the drive the recording shows at rest within 004 eq. 9's breakaway band, in
significantly many held-out applications and by a material torque, the motor turned where the angle
saw no motion, and ``effect`` or ``none`` becomes ``unexplained``.  And where the verdict's effects
include a clearance growth, the lost-motion test (:mod:`..play`): when the release crosses that extra
clearance with significantly and materially less friction than the travel after it, the lost motion
is a play between motor and screw, not a clearance, and ``effect`` becomes ``unexplained``.
Material means in physical units (:meth:`.scorer.Scorer.unexplained_share`): the RMS model error beyond the
noise exceeds, as a share of what the channel predicts, the budget's bound on that channel
(:data:`..tolerance.MATERIAL_SHARE`).  The point estimate decides.  Deciding with 95 % confidence
instead, one-sided like (b) (the standard error of the weighted mean excess from the held-out
applications, judged with Student t), was tried after the blind draw ``full_h``: it named a
load-relieved preload that the point estimate (2.4 % of the motor torque against 2 %) had read
``unexplained``, and it turned six effects outside the catalog on three outside draws (four
backlashes, two friction drifts, whose model error sits just as near the bound) into ``none`` or
a catalog effect (``outside_b`` 32 -> 28 of 40), so it was not kept.

**Parsimony.**  When an effect with fewer parameters is tied with the best-scoring
one it is ranked first: ``efficiency_variation`` nests ``load_friction`` and must
beat it significantly to be named.

**Near-ties.**  An effect whose held-out residual does not differ from the top
effect's at p < 0.05 (:func:`.effect_fit.tie_p`) is reported as tied, with the operating range
(speed, force) where the two fitted models differ most in noise units
(:func:`.experiment.separating_experiment`): the experiment that would separate them.
"""

from __future__ import annotations

from ebm_wear_monitor.diagnosis.ranking.criteria import ALPHA, SHRINK_NEEDED, TIE_ALPHA, material_channels
from ebm_wear_monitor.diagnosis.ranking.effect_fit import EffectFit, evaluate, nominal_sse, sampling_caution
from ebm_wear_monitor.diagnosis.ranking.experiment import separating_experiment
from ebm_wear_monitor.diagnosis.ranking.scorer import METRIC, Model, Scorer
from ebm_wear_monitor.diagnosis.ranking.verdict import OpenSet, Ranking, rank, ranked_fits

__all__ = [
    "ALPHA",
    "METRIC",
    "SHRINK_NEEDED",
    "TIE_ALPHA",
    "EffectFit",
    "Model",
    "OpenSet",
    "Ranking",
    "Scorer",
    "evaluate",
    "material_channels",
    "nominal_sse",
    "rank",
    "ranked_fits",
    "sampling_caution",
    "separating_experiment",
]
