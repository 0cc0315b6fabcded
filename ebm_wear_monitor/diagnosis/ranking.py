"""Which effect: fit on calibration cycles, judge on held-out cycles, rank, select, decide, flag near-ties.

**Split by cycle, stratified by force.**  Brake cycles (see :mod:`.phases`) are
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
open-set rule of :func:`open_set_verdict`'s note, all three reverted: exact pairs 13 -> 12 of 20, a
false positive where the tolerant twin's held-out torque error crossed its 2 % bound, catalog
``unexplained`` 2 -> 8 % on one).

**Acquisition nuisances.**  The current timing and offset, the quadrature rule of
the load, the force-sensor skew and lag (:mod:`.residuals`) are fitted first on the
calibration cycles with the nominal twin (the "before" model, :attr:`Scorer.base`),
each channel on its own rows, and refitted with every effect in the channels the
effect acts in, each on every row it moves (the force reading's skew and lag time the load torque
too, :func:`fit`); being in both models they are not counted in the penalty.  So an effect is
declared only when it explains the data better than the nominal twin
under its *best* admissible acquisition.

**Normalised residuals.**  Each block gives a torque residual R_T and a force
residual R_F (:mod:`.residuals`), divided by their block noise: z = R / sigma.
sigma is propagated from the measured sensor noise (:func:`block_noise`) and, in the
torque channel, from the transients the sampling does not resolve; each of the two is
rescaled to the scatter the residual of the twin within its tolerance actually shows where
it dominates (:meth:`Scorer.noise_scale`).

**Fit.**  An effect's parameters theta minimise sum z(theta)^2 over the calibration
blocks of its channels (bounded Gauss-Newton, ``scipy.optimize.least_squares``),
together with the acquisition nuisances of those channels and the model tolerances
of :mod:`.tolerance` (each bounded to its budget; they enter linearly through their
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
    comparison, :func:`base_without_own`), is significant.  The correction an effect
    makes, delta = z_before - z_after on the held-out rows, is fixed by the calibration
    cycles; with held-out noise z ~ N(0, 1) independent of it, S_before - S_after =
    2 sum(z delta) - sum(delta^2) ~ N(-sum(delta^2), 4 sum(delta^2)) when the effect is
    absent.  U = (S_before - S_after) / (2 |delta|) is thus at most standard normal under
    "absent", and the effect passes when its one-sided p-value is below 0.05 / K
    (Bonferroni over the K effects tried; :func:`.heldout.improvement_p`).  (A goodness-of-fit test of
    the before model where the effect acts was tried as a second guard: against the twin
    within its tolerance it rejected a +100 % viscous change on the twin's own data; the
    practical test (b) is the guard against significant but immaterial structure.  Weighted Bonferroni
    was tried and not kept: the effect with the largest calibration gain, S_cal(W) - S_cal - 2k, at
    0.05 / 2 and each other at 0.05 / (2 (K - 1)), a valid split since the weights are fixed before the
    held-out cycles are seen.  Prompted by foreign viscous drags of +100 % of B at p = 0.02 read
    ``none``, it named two of them (``full_e``, ``full_i``), turned one foreign ripple from
    ``unexplained`` into three friction effects (``outside_d``), changed nothing on the blind draws
    ``full_j`` and ``outside_i``, and in-world turned two healthy units of the reference simulator at
    500 Hz into Stribeck friction of 56-88 % of T_fc (false positives 1 -> 3 of 64; the one before is
    the same kind), so the level stays 0.05 / K.)
(b) practical: its fitted size exceeds its detectability floor (:mod:`.tolerance`, from
    the model-tolerance budget) with 95 % confidence, size - 1.645 std > floor, and its fit is off
    the physical limits of the catalog (:meth:`.catalog.Effect.at_limit`, :attr:`EffectFit.nameable`);
(d) stationary: a friction effect is a property of the unit and must hold over the
    recording.  It drifts (fails) when, refitted on the early and on the late half of the brake
    cycles, its sizes differ by more than its floor and three standard deviations, and its size
    per cycle also trends with time once the operating mix is regressed out (at ``DRIFT_ALPHA``:
    the catalog's form fits a real effect only approximately, so its size depends on the
    operating mix of a half too; :func:`drift_test`).
    friction that drifts within minutes (warming grease) is outside the catalog.  Clearance
    (wear), sensor and stiffness effects may change within a recording;
(c) explanatory: it (or the pair it is part of) closes at least half (``SHRINK_NEEDED``)
    of the material model error, in every channel where that error is material
    (:meth:`Scorer.unexplained_share`), and the held-out gap of the model with the selected effects
    is below the nominal twin's (``shrink`` > 0).  The second half matters where the twin within its
    tolerance leaves no material error: an effect that passes (a), (b), (d) and (e) there but leaves
    the held-out gap where the twin as given has it explains nothing (a healthy foreign unit at 200 Hz,
    ``full_g`` none_g003: viscous +38 ± 7 % of B, p = 3e-4 against the twin within its tolerance,
    held-out gap 1.52 -> 1.54 x noise; found on that blind draw, the rule written after it; no other
    verdict of the 14 foreign case sets or of the 216 in-world cases has shrink <= 0);
(e) consistent: it does not make the model materially wrong in a channel, the error it adds there
    (in quadrature, held out) staying below the channel's materiality share (:func:`_worsens`): a
    force-sensor gain that closes the force gap by putting a tenth of the load torque into the torque
    residual explains nothing.

**Forward selection** (up to three effects).  After the best single effect passing (a),
(b), (d) and (e), every other effect is fitted *together* with it and *on top of* it (the first
as fitted, the second with its own channels' nuisances and tolerances: :func:`extend`); the
better of the two on held-out cycles is its candidate, and the best candidate is kept when
its addition again passes (a) against the first alone and against the first refitted with the
candidate's own budget entries held at zero, the larger p-value (held out, at 0.05 over the number of
fits tried, up to two for each of the K - 1 candidates; :func:`addition_p`), (b), (d) (refitted within
the model with the addition) and (e); of a candidate's two fits the best-scoring one that passes
(a), (b) and (e) counts.  The first is then chosen again given the second,
by the same rule, and again given the new partner while each swap raises the held-out score (the
floating step, :func:`_rechoose_first`).  A third effect is then fitted on top of the two only (not
jointly) and kept when it passes the same tests against them (at 0.05 / (K - 2)).
When the selection leaves the material model error more than half open (it fails (c), or nothing
was selected), the best subset of size two is searched (:func:`best_pair`): every pair fitted jointly
from W, the best-scoring one passing (a) against W with both effects' own entries held at zero (at 0.05
over the number of pairs), each effect's (a) given the other (at half that), (b) for each effect as
fitted in the pair, (d) for each refitted within it, (e) and (c) becomes the selection; not where a
single effect drifts.  ``effects`` lists the selected ones; the verdict's ``effect`` is the largest:
the one that changes the twin's prediction most (:func:`contribution`).

**Verdict.**  ``effect`` when the selection passes (c); otherwise ``unexplained``
when the model error of the twin within its tolerance is *material* and no effect or
pair closes half of it, or when an effect passes (a), (b) and (e) and fails only (d): a
significant friction change of material size that does not hold over the recording is
no catalog effect (a catalog effect is a property of the unit), whatever share of the
model error the twin within its tolerance leaves; ``none`` otherwise: the twin explains the
data within its tolerance.  Then structure the catalog cannot represent is looked for
(:mod:`.openset`): a significant torque as a function of the screw angle that removes more of the
explaining model's held-out error than its effects removed turns ``effect`` into ``unexplained``
(the effects closed less than half of what is explainable); a significant and material one turns
``none`` into ``unexplained`` (:func:`open_set_verdict`).  Then the motor torque's scale
(:mod:`.scale`): when the verdict's model uses the budget's +-2 % on K_T x current gain up to its bound
and the held-out torque wants significantly more, beyond the bound with 95 % confidence, every term
of eq. 1 is read through a scale no catalog effect changes (a torque-constant loss, a current sensor
out of its class), and ``effect`` or ``none`` becomes ``unexplained``.  Last, the band test at rest
(:mod:`.stick`): when the verdict's model (the selected effects, or the twin within its tolerance)
cannot hold the drive the recording shows at rest within 004 eq. 9's breakaway band, in
significantly many held-out applications and by a material torque, the motor turned where the angle
saw no motion, and ``effect`` or ``none`` becomes ``unexplained``.  And where the verdict's effects
include a clearance growth, the lost-motion test (:mod:`.play`): when the release crosses that extra
clearance with significantly and materially less friction than the travel after it, the lost motion
is a play between motor and screw, not a clearance, and ``effect`` becomes ``unexplained``.
Material means in physical units (:meth:`Scorer.unexplained_share`): the RMS model error beyond the
noise exceeds, as a share of what the channel predicts, the budget's bound on that channel
(:data:`.tolerance.MATERIAL_SHARE`).  The point estimate decides.  Deciding with 95 % confidence
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
effect's at p < 0.05 (:func:`tie_p`) is reported as tied, with the operating range
(speed, force) where the two fitted models differ most in noise units
(:func:`separating_experiment`): the experiment that would separate them.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import NamedTuple, Protocol

import numpy as np
from scipy import optimize, stats

from ebm_wear_monitor.diagnosis import heldout, tolerance
from ebm_wear_monitor.diagnosis.catalog import Effect, combine
from ebm_wear_monitor.diagnosis.heldout import MATERIAL_Z, cluster_covariance, improvement_p
from ebm_wear_monitor.diagnosis.noise import median_scale, series_noise, signal_noise
from ebm_wear_monitor.diagnosis.openset import HARMONICS, Periodic, periodic_structure
from ebm_wear_monitor.diagnosis.play import LostMotion, lost_motion
from ebm_wear_monitor.diagnosis.residuals import (
    CHANNELS,
    NOMINAL,
    NUISANCE_UNITS,
    Augment,
    ResidualModel,
    clamp_spring,
    kinetic_friction,
    moves,
)
from ebm_wear_monitor.diagnosis.scale import TorqueScale, budget_bound, entry_index, torque_scale
from ebm_wear_monitor.diagnosis.stick import RestTorque, rest_torque
from ebm_wear_monitor.domain.phases import Phase
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.schema.diagnose import Drift, NearTie, Parameter, RankingEntry, Size
from ebm_wear_monitor.twin.dynamics import ActuatorModel

ALPHA = 0.05  # family-wise error rate of the verdict
TIE_ALPHA = 0.05  # level of the paired test that separates the top effect from the next
#: the noise scale-up may fall below one (the propagated sensor noise overstates the block noise when the
#: raw signal's second differences carry its own dynamics, a current sampled below its controller's
#: bandwidth), not below this: a residual below a tenth of it is the resolution of a noise-free signal
NOISE_SCALE_MIN = 0.1
#: fewest rows a median scale is measured on (:meth:`Scorer.noise_scale`)
MIN_SCALE_ROWS = 10
#: fewest lag-2 differences a phase's residual-based noise is taken from (:func:`_quietest_phase_noise`)
QUIET_DIFFS = 12
SHRINK_NEEDED = 0.5  # share of the held-out gap an effect (or pair) must close (issue 10 item 4)
#: level of the screw-position harmonic (:mod:`.openset`): ALPHA over the harmonics tried
OPEN_SET_LEVEL = ALPHA / HARMONICS
METRIC = "excess_rms_over_noise"
FORCE_TIMING_S = 3e-3  # force skew searched within +-(its sample interval + this) [s]
FORCE_LAG_S = 5e-3  # largest first-order lag of the force reading considered [s]


@dataclass(frozen=True)
class Split:
    """Calibration / held-out assignment of blocks by brake cycle."""

    calibration: np.ndarray  # bool per block
    heldout: np.ndarray  # bool per block
    heldout_cycles: np.ndarray  # cycle indices held out


def split_by_cycle(cycle: np.ndarray, peak_force: np.ndarray | None = None) -> Split:
    """Stratified alternate split (module docstring): cycles ordered by peak force, every second held out."""
    cycles = np.unique(cycle)
    if cycles.size < 4:
        raise InputError(f"only {cycles.size} brake cycle(s) found; the diagnosis needs at least 4 "
                         "(half to fit, half held out)")
    if peak_force is None:
        order = cycles
    else:
        peak = np.array([peak_force[cycle == c].max() for c in cycles])
        order = cycles[np.lexsort((cycles, peak))]
    held = np.sort(order[1::2])
    h = np.isin(cycle, held)
    return Split(~h, h, held)


@dataclass(frozen=True)
class Nuisance:
    """One acquisition nuisance fitted with every model: bounds, solver scale, starting values."""

    name: str
    lower: float
    upper: float
    scale: float
    starts: tuple[float, ...]


def nuisance_specs(model: ResidualModel) -> dict[str, tuple[Nuisance, ...]]:
    """The nuisances of each channel with bounds from the recording's sample intervals."""
    rec = model.rec
    dt = rec.dt
    h_i = max(rec.interval("current"), dt)
    h_f = max(rec.interval("axial_force"), dt) + FORCE_TIMING_S
    i_scale = 0.01 * max(float(np.percentile(np.abs(rec.current), 99)), 1e-3)
    return {
        "torque": (Nuisance("current_shift", -h_i, h_i, 0.5 * h_i, (-0.5 * h_i, 0.0, 0.5 * h_i)),
                   Nuisance("current_offset", -np.inf, np.inf, i_scale, (0.0,)),
                   Nuisance("load_shift", -dt, dt, 0.25 * dt, (0.0, -0.25 * dt))),
        "force": (Nuisance("force_skew", -h_f, h_f, 1e-3, (0.0, 1e-3, -1e-3)),
                  Nuisance("force_lag", 0.0, FORCE_LAG_S, 1e-3, (0.0, 1e-3))),
    }


def _merge(base: Augment, effect_aug: Augment, nuisances: dict[str, float]) -> Augment:
    """``base`` with the model corrections of ``effect_aug`` and the given nuisance values."""
    corrections = {f: getattr(effect_aug, f) for f in Augment.__dataclass_fields__ if f not in NUISANCE_UNITS}
    return dataclasses.replace(base, **corrections, **nuisances)


@dataclass(frozen=True)
class Model:
    """A fitted model: the twin's corrections and nuisances, and the tolerance deviations t (|t| <= 1)."""

    aug: Augment = NOMINAL
    t: np.ndarray = field(default_factory=lambda: np.zeros(len(tolerance.BUDGET)))


class NoiseScale(NamedTuple):
    """What the residual says of the noise propagated from the sensors (:meth:`Scorer.noise_scale`)."""

    torque: float  # c_T [-]: scale of the propagated torque noise
    transient: float  # c_E [-]: scale of the unresolved-transient term
    force: float  # c_F [-]: scale of the propagated force noise
    spread: float  # pad-contact spread [N] (:func:`contact_spread`)


@dataclass(frozen=True)
class Scorer:
    """Noise-normalised residuals of one recording and the held-out bookkeeping."""

    model: ResidualModel
    split: Split
    sigma_torque: np.ndarray  # block noise of R_T per block [N m]
    sigma_force: np.ndarray  # block noise of R_F per block [N]
    nuisances: dict[str, tuple[Nuisance, ...]]
    #: response of z (all rows: torque then force, every block) to each budget entry at its bound
    D: np.ndarray = field(default_factory=lambda: np.zeros((0, len(tolerance.BUDGET))))
    base: Model = field(default_factory=Model)  # the twin within its tolerance, W (the "before" model)
    base_std: dict[str, float] = field(default_factory=dict)  # standard errors of base's nuisances
    #: block noise of the materiality test: propagated from the sensors, raised by the residual-based scale
    #: only where that exceeds 1 (:meth:`unexplained_share`), torque [N m], force [N]
    sensor_sigma: tuple[np.ndarray, np.ndarray] = (np.zeros(0), np.zeros(0))
    cache: dict = field(default_factory=dict, compare=False, repr=False)  # fits shared by the effects
    #: c_E of :meth:`noise_scale`: how far the residuals show the unresolved-transient torque (1: unscaled)
    transient_scale: float = 1.0

    @classmethod
    def sensors(cls, model: ResidualModel) -> Scorer:
        """The scorer of the block noise propagated from the sensors alone (:func:`sensor_noise`), with
        its tolerance responses at the nominal twin and W fitted with it.

        The scorer the diagnosis uses is made in two more steps (:func:`.pipeline.analyse`): the block
        noise is rescaled to the scatter of the residual of a reference (W; in a second pass the
        best-ranked effect, whose residual carries less model error: :meth:`noise_scale`), and W is
        refitted at that noise (:meth:`scaled`). The torque noise adds, in quadrature, the uncertainty
        of the current integral where the sampling does not resolve the electrical transient and of the
        friction where stick and slip cannot be told apart (:mod:`.residuals`).
        """
        b = model.blocks
        s_t, s_f, extra_t = sensor_noise(model)
        pre = cls(model, split_by_cycle(b.cycle, b.force), np.hypot(s_t, extra_t), s_f, nuisance_specs(model))
        pre = dataclasses.replace(pre, D=pre.responses(NOMINAL))
        return dataclasses.replace(pre, base=fit_base(pre)[0])

    def noise_scale(self, reference: Model | None = None) -> NoiseScale:
        """(c_T, c_E, c_F, spread [N]): the scales of the propagated noise that the residual of
        ``reference`` (default: W, the twin within its tolerance as this scorer fitted it) shows, and the
        pad-contact spread (:func:`contact_spread`) at the scaled force noise.

        The noise the block residuals carry is sigma_T^2 = (c_T s_T)^2 + (c_E e_T)^2 and sigma_F^2 =
        (c_F s_F)^2 + spread^2, s the noise propagated from the sensors (:func:`block_noise`), e_T the
        torque of the transients the sampling does not resolve (:func:`sensor_noise`). Each scale is
        measured where its term dominates: c_T on the moving blocks with e_T <= s_T (all moving blocks when
        fewer than ``MIN_SCALE_ROWS``), c_E on those with e_T > s_T (given c_T), c_F on every force row;
        the lag-2 estimates below are taken on all moving blocks (torque) and all blocks (force). e_T
        holds the friction where stick and slip cannot be told apart too, and c_E scales it with the rest.
        Why the scales, and why they may fall below one:

        * s is propagated from the raw signals' noise (:func:`.noise.signal_noise`), which counts a
          signal's own dynamics faster than its sampling (a current sampled below its controller's
          bandwidth) as noise; e_T is a bound (the integral anywhere within +-|dI| dt / 2), not a
          standard deviation. Both can overstate the scatter several times, and a torque channel whose
          noise is overstated weighs nothing: on the foreign generator's healthy recordings, with the
          former scale-up only (c >= 1), the held-out mean z^2 of W's moving torque rows was 0.02-0.12.
        * Each scale is the smaller of two estimates that a model error can only inflate, each by a
          different kind: the lag-2 curvature of the quietest phase (:func:`_quietest_phase_noise`;
          smooth model error cancels, sharp transients do not) and the median of z^2
          (:func:`.noise.median_scale`; model error in a minority of the blocks does not move it, model
          error everywhere does); either is left out where it has no estimate (no quiet phase, fewer
          than ``MIN_SCALE_ROWS`` rows), and a scale without either is 1 (c_E has the median only).
          Not below ``NOISE_SCALE_MIN``.
        * The residual is the reference's with its tolerance deviations (R + sigma D t, the responses being
          linear): a deviation a healthy unit may have (a K_T x current-gain error carries every step of
          the current) is no noise.
        """
        model, b = self.model, self.model.blocks
        s_t, s_f, extra_t = sensor_noise(model)
        ref = self.base if reference is None else reference
        r = model.residuals(ref.aug)
        dev = self.D @ ref.t  # tolerance deviations, in units of this scorer's block noise
        r_t = r["torque"] + self.sigma_torque * dev[:b.size]
        r_f = r["force"] + self.sigma_force * dev[b.size:]
        rows_f = self.valid(np.ones(b.size, bool), "force")
        trans = b.moving & (extra_t > s_t)
        steady = b.moving & ~trans
        if steady.sum() < MIN_SCALE_ROWS:
            steady = b.moving
        c_t = _noise_scale(_quietest_phase_noise(r_t / s_t, model, b.moving),
                           r_t[steady], s_t[steady], extra_t[steady])
        c_e = _noise_scale(None, r_t[trans], extra_t[trans], c_t * s_t[trans])
        c_f = _noise_scale(_quietest_phase_noise(r_f / s_f, model, np.ones(b.size, bool)),
                           r_f[rows_f], s_f[rows_f])
        return NoiseScale(c_t, c_e, c_f, contact_spread(model, r_f, c_f * s_f))

    def scaled(self, scale: NoiseScale) -> Scorer:
        """The scorer of this :meth:`sensors` scorer's noise scaled by ``scale`` (:meth:`noise_scale`):
        sigma_T = hypot(c_T s_T, c_E extra_T), sigma_F = hypot(c_F s_F, spread), with its tolerance responses
        and W refitted from this scorer's; the materiality test's noise ``sensor_sigma`` is
        hypot(max(c_T, 1) s_T, extra_T) and hypot(max(c_F, 1) s_F, spread)."""
        model, b = self.model, self.model.blocks
        s_t, s_f, extra_t = sensor_noise(model)
        c_t, c_e, c_f, spread_all = scale
        # where pads touch or are about to (every block of an application but idle): a shifted contact
        # position moves the force there, and the model's own contact point may fall on either side
        spread = spread_all * (b.phase != Phase.IDLE)
        sc = type(self)(model, self.split, np.hypot(c_t * s_t, c_e * extra_t), np.hypot(c_f * s_f, spread),
                    self.nuisances, sensor_sigma=(np.hypot(max(c_t, 1.0) * s_t, extra_t),
                                                  np.hypot(max(c_f, 1.0) * s_f, spread)), transient_scale=c_e)
        sc = dataclasses.replace(sc, D=sc.responses(self.base.aug))
        base, std = fit_base(sc, self.base)
        return dataclasses.replace(sc, base=base, base_std=std)

    def responses(self, aug: Augment) -> np.ndarray:
        """dz/dt of every budget entry at ``aug``, all rows (torque then force, every block)."""
        z0 = self.z_all(aug)
        bounds = tolerance.at_bounds(aug, self.model.nominal, self.model.park_half_band)
        return np.stack([self.z_all(a) - z0 for a in bounds], axis=1)

    def z_all(self, aug: Augment) -> np.ndarray:
        """Normalised residuals of every block, torque then force, none left out (the layout of ``D``)."""
        r = self.model.residuals(aug)
        return np.concatenate((r["torque"] / self.sigma_torque, r["force"] / self.sigma_force))

    def valid(self, mask: np.ndarray, channel: str) -> np.ndarray:
        """``mask`` restricted to the blocks with a row in ``channel`` (force: released applications)."""
        if channel == "force":
            return mask & self.model.conv.released[self.model.blocks.cycle]
        return mask

    def rows(self, mask: np.ndarray, channels: tuple[str, ...] = CHANNELS) -> np.ndarray:
        """Indices into all rows (torque then force, every block) of the masked blocks of ``channels``."""
        n = self.model.blocks.size
        return np.concatenate([np.flatnonzero(self.valid(mask, ch)) + CHANNELS.index(ch) * n
                               for ch in channels])

    def z_raw(self, aug: Augment, mask: np.ndarray, channels: tuple[str, ...] = CHANNELS) -> np.ndarray:
        """Normalised residuals of the masked blocks, torque rows then force rows (of ``channels``)."""
        parts = []
        if "torque" in channels:
            k = self.valid(mask, "torque")
            parts.append(self.model.torque_residual(aug)[k] / self.sigma_torque[k])
        if "force" in channels:
            k = self.valid(mask, "force")
            parts.append(self.model.force_residual(aug)[k] / self.sigma_force[k])
        return np.concatenate(parts)

    def z(self, m: Model, mask: np.ndarray, channels: tuple[str, ...] = CHANNELS) -> np.ndarray:
        """:meth:`z_raw` of ``m.aug`` plus the tolerance deviations ``m.t`` through their responses."""
        return self.z_raw(m.aug, mask, channels) + self.D[self.rows(mask, channels)] @ m.t

    def unresolved(self, mask: np.ndarray, channels: tuple[str, ...] = CHANNELS) -> np.ndarray:
        """Per row of :meth:`z_raw`, the bound on |dz| of what the sampling does not resolve: a torque row's
        unresolved-transient and stick-or-slip torque (:mod:`.residuals`) as the residuals show it (times
        c_E of :meth:`noise_scale`; the torque itself is a bound, not a standard deviation, and overstates
        the scatter up to ten times) over its block noise, of which it is a part (so at most 1); 0 on force
        rows."""
        model = self.model
        shown = self.transient_scale * np.hypot(model.unresolved_torque, model.ambiguous_torque)
        extra = shown / self.sigma_torque
        parts = [extra[self.valid(mask, "torque")]] if "torque" in channels else []
        if "force" in channels:
            parts.append(np.zeros(int(self.valid(mask, "force").sum())))
        return np.concatenate(parts)

    def row_cycles(self, mask: np.ndarray, channels: tuple[str, ...] = CHANNELS) -> np.ndarray:
        c = self.model.blocks.cycle
        return np.concatenate([c[self.valid(mask, ch)] for ch in channels])

    def gap_mask(self) -> np.ndarray:
        """Held-out rows (torque then force) the gap uses: torque rows of blocks at rest are left out."""
        m = self.split.heldout
        return np.concatenate((self.model.blocks.moving[m], np.ones(int(self.valid(m, "force").sum()), bool)))

    def cycle_sse(self, m: Model) -> np.ndarray:
        """Sum of z^2 per held-out cycle."""
        h = self.split.heldout
        z2 = self.z(m, h) ** 2
        where = np.searchsorted(self.split.heldout_cycles, self.row_cycles(h))  # held-out cycles are sorted
        return np.bincount(where, weights=z2, minlength=self.split.heldout_cycles.size)

    def gap_rows(self, m: Model) -> np.ndarray:
        """Held-out z of the rows the gap metric uses."""
        return self.z(m, self.split.heldout)[self.gap_mask()]

    def gap(self, m: Model) -> float:
        """Held-out gap, metric ``excess_rms_over_noise``."""
        ms = float(np.mean(self.gap_rows(m) ** 2))
        return float(np.sqrt(max(ms - 1.0, 0.0)))

    def unexplained_share(self, m: Model) -> dict[str, float]:
        """RMS model error beyond the noise on the held-out blocks, per channel, as a share of the
        signal the channel predicts: sqrt(mean(R^2 - sigma_s^2)) over the RMS motor torque (moving
        blocks) and over the RMS clamp force (released blocks in contact), both means weighted by
        sigma_s^-4 (the inverse variance of R^2 - sigma_s^2 under noise alone: a block whose sensor
        noise is large, a transient the sampling does not resolve, says little about the model).

        sigma_s is the block noise propagated from the sensors, raised by the scale :meth:`noise_scale`
        measured where that exceeds 1 (the unresolved-transient term as propagated).  That scale is the
        smaller of two residual-based estimates, each inflated by model error of a different kind (the
        lag-2 curvature by error that is not linear over five blocks, the median by error in most blocks),
        so where both exist it exceeds 1 only where both see more scatter than the sensors explain.  That
        is mostly noise the propagation missed, but not only: a model error raises both estimates too (a
        15 % torque-constant loss on a closed-form unit whose current jitters: lag-2 1.46 -> 2.29, median
        1.95 -> 4.06), so the floor can take part of a model error for noise; where one estimate is
        missing the scale is the other alone.  What it costs on effects outside the catalog is measured
        on the foreign outside draws (README).  Without it, a healthy foreign unit of the blind draw
        ``full_j`` (none_j003, 2 kHz, a cascade ECU), whose free-travel blocks scatter 11 times the
        propagated noise with adjacent blocks anti-correlated, the signature of speed noise at the blocks'
        shared ends, read 2.7 % of the motor torque beyond the noise against the 2 % bound: ``unexplained``.
        The lag-2
        estimate alone was tried as the floor and not kept: a foreign motor-side backlash (``outside_i``
        backlash.play.8) whose twin leaves 9.3 % then read as a load friction.
        """
        h, mdl, b = self.split.heldout, self.model, self.model.blocks
        z = self.z_all(m.aug) + self.D @ m.t
        out = {}
        for ch, sigma, sensor, rows, ref in (
                ("torque", self.sigma_torque, self.sensor_sigma[0], h & b.moving, mdl.drive_block()),
                ("force", self.sigma_force, self.sensor_sigma[1],
                 self.valid(h, "force") & (b.force > mdl.seg.force_rise), b.force)):
            zc = z[:b.size] if ch == "torque" else z[b.size:]
            if rows.sum() < 2:
                out[ch] = 0.0
                continue
            w = sensor[rows] ** -4.0  # inverse variance of R^2 - sigma_s^2 under noise alone
            excess = float(np.sum(w * ((zc[rows] * sigma[rows]) ** 2 - sensor[rows] ** 2)) / np.sum(w))
            scale = float(np.sqrt(np.sum(w * ref[rows] ** 2) / np.sum(w)))
            out[ch] = float(np.sqrt(max(excess, 0.0)) / max(scale, 1e-12))
        return out


def sensor_noise(model: ResidualModel) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(s_T [N m], s_F [N], extra_T [N m]) per block: :func:`block_noise` above its resolution floors (for
    noise-free data), and the torque uncertainty where the sampling does not resolve a transient or stick
    and slip cannot be told apart (:mod:`.residuals`), added to s_T in quadrature."""
    s_t, s_f = block_noise(model)
    s_t = np.maximum(s_t, 1e-6 * model.nominal.friction.coulomb + 1e-12)
    s_f = np.maximum(s_f, 1e-3)
    return s_t, s_f, np.hypot(model.unresolved_torque, model.ambiguous_torque)


def block_noise(model: ResidualModel) -> tuple[np.ndarray, np.ndarray]:
    """Noise of each block's R_T [N m] and R_F [N], propagated from the measured sensor noise.

    A block of n samples over dt_b seconds: R_T carries the end-point speed noise
    J_me sqrt(sigma_w(t0)^2 + sigma_w(t1)^2) / dt_b (sigma_w of the speed regression,
    :mod:`.speed`) and the averaged current and force noise
    (K_T sigma_I)^2 / n + ((l / (2 pi i_g) + G) sigma_F)^2 / n; R_F carries
    (sigma_F^2 + [in contact] (K_b l sigma_theta / (2 pi))^2) / n plus, shared by every
    block of an application, the uncertainty of its tare and (in contact) of its rest angle.
    """
    rec, n, b, conv = model.rec, model.nominal, model.blocks, model.conv
    si, sf = signal_noise(rec.current), signal_noise(rec.axial_force)
    ns = (b.stop - b.start + 1).astype(float)
    dt = rec.t[b.stop] - rec.t[b.start]
    var_w = model.sigma_w[b.stop] ** 2 + model.sigma_w[b.start] ** 2
    var_t = n.inertia**2 * var_w / dt**2 \
        + ((n.torque_constant * si) ** 2 + ((n.transmission + n.friction.load_coefficient) * sf) ** 2) / ns
    contact = (b.force > model.seg.force_rise).astype(float)
    k_theta = n.clamp.stiffness * n.lead / (2.0 * np.pi)  # force per screw radian in contact [N/rad]
    var_f = (sf**2 + contact * (k_theta * conv.sigma_angle) ** 2) / ns \
        + conv.tare_std[b.cycle] ** 2 + contact * (k_theta * conv.rest_angle_std[b.cycle]) ** 2
    return np.sqrt(var_t), np.sqrt(var_f)


def contact_spread(model: ResidualModel, r_force: np.ndarray, sigma: np.ndarray) -> float:
    """Spread of the pad-contact position between applications, as a force [N] (a random effect).

    Where the ECU parks the nut varies from application to application; whether the pads then
    touch after the same travel (004 eq. 5 counted from each rest angle, the reference) or at
    the same absolute angle (the travel varies by the parking error) is a property of the brake,
    not of the twin.  A per-application offset u_c of the contact position moves every contact
    block of that application by K_b u_c, and decides whether the blocks around the contact see
    force at all.  Its variance is estimated from the per-application
    mean residual of the contact blocks at low force (below 30 % of the application's peak, where
    shape effects are small): var(mean) minus its noise share, zero when the spread is within the
    noise.  Added in quadrature to the noise of every block of an application but its idle ones, it
    keeps the parking convention from reading as a misfit; an extra clearance shifts every
    application alike and stays visible.
    """
    b = model.blocks
    contact = b.force > model.seg.force_rise
    low = contact & (b.force < 0.3 * b.cycle_max(b.force)[b.cycle])
    means, noise = [], []
    for c in np.unique(b.cycle[low]):
        k = low & (b.cycle == c)
        if k.sum() >= 2:
            means.append(float(np.mean(r_force[k])))
            noise.append(float(np.mean(sigma[k] ** 2)) / k.sum())
    if len(means) < 3:
        return 0.0
    return float(np.sqrt(max(np.var(means, ddof=1) - np.mean(noise), 0.0)))


def _noise_scale(lag2: float | None, r: np.ndarray, s: np.ndarray, extra: np.ndarray | None = None) -> float:
    """One scale of :meth:`Scorer.noise_scale`: the smaller of the lag-2 estimate ``lag2`` (None or 0:
    none) and the median scale of the rows ``r`` against their noise ``s`` beside ``extra``
    (:func:`.noise.median_scale`; none under ``MIN_SCALE_ROWS`` rows); 1 without either estimate,
    never below ``NOISE_SCALE_MIN``."""
    estimates = [lag2] if lag2 else []
    if r.size >= MIN_SCALE_ROWS:
        estimates.append(median_scale(r, s, extra))
    return max(min(estimates), NOISE_SCALE_MIN) if estimates else 1.0


def _quietest_phase_noise(r: np.ndarray, model: ResidualModel, rows: np.ndarray) -> float:
    """Residual-based noise scale: the smallest :func:`.noise.series_noise` of r over the phases.

    Each phase gives an estimate from the blocks inside its runs, two blocks away from either end, when
    they hold at least ``QUIET_DIFFS`` lag-2 differences within a run (the force generation of a short
    application may hold one or two inner blocks per run: 28 such blocks of a closed-form recording at
    500 Hz read 0.39 times the propagated noise where the block noise was 2.8 times it, and the minimum
    over the phases took that).  A model error is sharpest where a motion starts or stops (an inertia or
    a timing error then carries the acceleration's step), and the lag-2 curvature would take it for
    noise; inside a run a model error varies smoothly and cancels.  Model error that still does not
    cancel can only inflate the estimate, so the quietest phase is the closest to the noise.
    """
    b = model.blocks
    first = np.concatenate(([True], b.run[1:] != b.run[:-1]))
    start = np.maximum.accumulate(np.where(first, np.arange(b.size), 0))
    last = np.concatenate((b.run[1:] != b.run[:-1], [True]))
    stop = np.minimum.accumulate(np.where(last, np.arange(b.size), b.size)[::-1])[::-1]
    inner = (np.arange(b.size) - start >= 2) & (stop - np.arange(b.size) >= 2)
    est = [series_noise(r[k], b.run[k], min_diffs=QUIET_DIFFS) for ph in np.unique(b.phase)
           if (k := rows & inner & (b.phase == ph)).any()]
    est = [e for e in est if e > 0.0]
    return min(est) if est else 0.0


@dataclass
class Fit:
    """A least-squares fit of an effect (with nuisances and tolerances) on the calibration cycles."""

    theta: np.ndarray  # effect parameters
    stderr: np.ndarray  # their cluster-robust standard errors
    model: Model  # the fitted model, nuisances and tolerance deviations included
    nuisance_std: dict[str, float]  # cluster-robust standard errors of the fitted nuisances
    z: np.ndarray = field(default_factory=lambda: np.zeros(0))  # normalised residual of the fitted rows
    jac: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))  # dz/d(effect parameters), per unit
    #: d(effect parameters)/dz of the fitted rows, linearised at the solution (everything fitted with them
    #: that is off its bounds free: :func:`_response`), and each row's bound |dz| of what the sampling does
    #: not resolve (:meth:`Scorer.unresolved`)
    response: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    bound: np.ndarray = field(default_factory=lambda: np.zeros(0))


def _free_tolerances(sc: Scorer, effect_names: list[str], channels: tuple[str, ...]
                     ) -> tuple[np.ndarray, np.ndarray]:
    """Budget entries fitted with these effects, and those held at zero.

    Free: not an effect's own quantity, and acting only in the fitted channels.  An entry that also
    moves another channel keeps the value fitted there; an effect's own quantity is held at zero
    (the effect takes all of it: ``tolerance.OWN``).
    """
    n = sc.model.blocks.size
    outside = [ch for ch in CHANNELS if ch not in channels]
    moved = np.zeros(len(tolerance.BUDGET), bool)
    for ch in outside:
        i = CHANNELS.index(ch)
        moved |= np.any(sc.D[i * n:(i + 1) * n] != 0.0, axis=0)
    own = ~np.array(tolerance.free(effect_names))
    return ~own & ~moved, own


def difference_step(x: float, unit: float, upper: float) -> float:
    """Forward-difference step at ``x`` for a quantity of typical magnitude ``unit``: 1e-3 of the larger
    of the two, taken backward where it would cross the ``upper`` bound (the solver's Jacobian,
    :func:`fit`, and the scale test's refit, :func:`owner_columns`)."""
    h = 1e-3 * max(unit, abs(x))
    return -h if x + h > upper else h


def fit(sc: Scorer, effect: Effect, start: Model, extra_starts: tuple[dict[str, float], ...] = (), *,
        mask: np.ndarray | None = None, only_effect: bool = False, search: bool = False) -> Fit:
    """Fit ``effect`` with its channels' nuisances and the free tolerances on the calibration cycles.

    ``mask`` fits on other blocks; ``only_effect`` keeps the nuisances and tolerances of ``start``.
    A nuisance is fitted on every row it moves (:func:`.residuals.moves`): the force reading's skew and
    lag time the load torque too, so a force-channel effect refits them on the torque rows as well, with
    the torque channel's tolerances held as ``start`` has them.  Refitted on the force rows alone they
    would buy the force fit with a torque error no score of the fit sees; held, they would keep what
    the twin within its tolerance made them absorb of the effect.  ``search``: on the effect's channels'
    rows only (a first search of one channel's nuisances, :func:`fit_base`).
    """
    channels = effect.channels
    specs = [] if only_effect else [n for ch in channels for n in sc.nuisances[ch]]
    seen = channels if search else tuple(ch for ch in CHANNELS if ch in channels
                                         or any(ch in moves(n.name) for n in specs))
    k, m = effect.k, len(specs)
    names = [n.name for n in specs]
    mask = sc.split.calibration if mask is None else mask
    rows = sc.rows(mask, seen)
    free, own = _free_tolerances(sc, effect.name.split("+"), channels)
    if only_effect:
        free, own = np.zeros_like(free), np.zeros_like(own)
    D = sc.D[rows][:, free]
    t_fixed = np.where(free | own, 0.0, start.t)
    fixed_part = sc.D[rows] @ t_fixed
    q = int(free.sum())
    scale = np.array([*effect.scale, *(n.scale for n in specs), *np.ones(q)], dtype=float)
    e_lo, e_hi = effect.bounds()
    lo = np.array([*e_lo, *(n.lower for n in specs), *-np.ones(q)], dtype=float)
    hi = np.array([*e_hi, *(n.upper for n in specs), *np.ones(q)], dtype=float)

    def to_model(u: np.ndarray) -> Model:
        p = u * scale
        nuisances = dict(zip(names, map(float, p[k:k + m]), strict=True))
        aug = _merge(start.aug, effect.to_augment(p[:k]), nuisances)
        t = t_fixed.copy()
        t[free] = p[k + m:]
        return Model(aug, t)

    cache: dict[bytes, np.ndarray] = {}

    def nonlinear(u: np.ndarray) -> np.ndarray:
        key = u[:k + m].tobytes()
        if key not in cache:
            cache.clear()
            cache[key] = sc.z_raw(to_model(u).aug, mask, seen) + fixed_part
        return cache[key]

    def fun(u: np.ndarray) -> np.ndarray:  # u = parameters / scale keeps the solver well conditioned
        return nonlinear(u) + D @ u[k + m:]

    def jac(u: np.ndarray) -> np.ndarray:
        z0 = nonlinear(u)
        cols = []
        for i in range(k + m):
            h = difference_step(float(u[i]), 1.0, float(hi[i] / scale[i]))
            v = u.copy()
            v[i] += h
            cols.append((sc.z_raw(to_model(v).aug, mask, seen) + fixed_part - z0) / h)
        return np.column_stack([*cols, D]) if cols else D

    here = [getattr(start.aug, nm) for nm in names]
    t0 = list(start.t[free])
    starts = [(*s0, *here, *t0) for s0 in effect.starts]
    starts += [(*effect.starts[0], *[st.get(nm, h) for nm, h in zip(names, here, strict=True)], *t0)
               for st in extra_starts]
    best: optimize.OptimizeResult | None = None
    for s in starts:
        u0 = np.clip(np.asarray(s, dtype=float) / scale, lo / scale, hi / scale)
        u0[np.abs(u0) < 1e-6] = 0.0  # round-off starts stall the solver's first step
        res = optimize.least_squares(fun, u0, jac=jac, bounds=(lo / scale, hi / scale), method="trf",
                                     x_scale=1.0, max_nfev=60)
        if best is None or res.cost < best.cost:
            best = res
    assert best is not None  # every effect has at least one start
    J, z = np.asarray(best.jac, dtype=float), np.asarray(best.fun, dtype=float)  # dense (``jac`` above)
    cov = cluster_covariance(J, z, sc.row_cycles(mask, seen))
    p = best.x * scale
    se = np.sqrt(np.clip(np.diag(cov), 0.0, None)) * scale
    fitted = Fit(p[:k], se[:k], to_model(best.x), dict(zip(names, map(float, se[k:k + m]), strict=True)),
                 z, J[:, :k] / scale[:k])
    if k == 0:  # nuisances and tolerances only (W and its relatives): no size to bound
        return fitted
    return dataclasses.replace(fitted, response=_response(J, best.active_mask, k) * scale[:k, None],
                               bound=sc.unresolved(mask, seen))


def _response(J: np.ndarray, active: np.ndarray, k: int) -> np.ndarray:
    """d u / d z of the first ``k`` parameters of a least-squares solution with Jacobian ``J`` (rows x
    parameters, scaled): minus the pseudo-inverse's rows of the parameters off their bounds, zero for those
    held on one (``active`` non-zero, scipy's ``active_mask``), which a small change of z leaves there."""
    free = np.flatnonzero(active == 0)
    own = free < k
    out = np.zeros((k, J.shape[0]))
    out[free[own]] = -np.linalg.pinv(J[:, free])[own]
    return out


NUISANCE_ONLY = Effect("acquisition", "acquisition nuisances only", (), (), lambda p: NOMINAL, (), ((),),
                       channels=CHANNELS)


def fit_base(sc: Scorer, start: Model | None = None) -> tuple[Model, dict[str, float]]:
    """The twin within its tolerance, W: nuisances and tolerances that fit the calibration cycles best,
    and the nuisances' standard errors.

    Without a ``start``, each channel's nuisances are first searched from a grid of starting values on
    that channel alone (cheap), then everything is refitted together.
    """
    if start is None:
        start = Model()
        for ch in CHANNELS:
            specs = sc.nuisances[ch]
            grid = [dict(zip([n.name for n in specs], combo, strict=True))
                    for combo in np.array(np.meshgrid(*[n.starts for n in specs])).reshape(len(specs), -1).T]
            start = fit(sc, dataclasses.replace(NUISANCE_ONLY, channels=(ch,)), start, tuple(grid),
                        search=True).model
    f = fit(sc, NUISANCE_ONLY, start)
    return f.model, f.nuisance_std


@dataclass
class EffectFit:
    """One effect fitted on calibration cycles and judged on held-out ones."""

    effect: Effect
    theta: np.ndarray
    stderr: np.ndarray
    model: Model
    gap_after: float
    score: float
    shrink: float  # share of the held-out gap it closes, 1 - gap_after / gap_before
    d_cycles: np.ndarray  # held-out S_before,c - S_after,c per cycle
    z_heldout: np.ndarray  # held-out normalised residual with the effect
    p_value: float = 1.0  # one-sided test of a held-out improvement (:func:`.heldout.improvement_p`)
    size: float = 0.0  # size in the effect's own unit (:mod:`.catalog`)
    size_std: float = 0.0
    floor: float = 0.0  # detectability floor of the size (:mod:`.tolerance`)
    share: dict[str, float] = field(default_factory=dict)  # unexplained share per channel with the effect
    contribution: float = 0.0  # RMS change of the channel's prediction, share of its RMS signal
    drift: Drift | None = None  # early/late refit of a friction effect (:func:`drift_test`), when tested
    ties: list[str] = field(default_factory=list)
    #: worst-case change of the size by what the sampling does not resolve (:func:`sampling_bound`; of the
    #: effect fitted alone; None: not computed), in the size's unit
    sampling: float | None = None

    @property
    def drifting(self) -> bool:
        return self.drift is not None and self.drift.drifting

    @property
    def augment(self) -> Augment:
        return self.model.aug

    @property
    def material(self) -> bool:
        """Its size exceeds its detectability floor with 95 % confidence (practical significance):
        size - 1.645 std > floor."""
        return self.size - MATERIAL_Z * self.size_std > self.floor

    def significant(self, level: float) -> bool:
        """Test (a) of the module docstring at ``level``: its held-out improvement is significant and its
        held-out score positive."""
        return self.p_value < level and self.score > 0.0

    @property
    def nameable(self) -> bool:
        """Material and off its physical limits (:meth:`.catalog.Effect.at_limit`): what an effect must be
        to be named."""
        return self.material and not self.at_limit

    @property
    def at_limit(self) -> bool:
        """The fit ended on a physical limit of the catalog (:meth:`.catalog.Effect.at_limit`)."""
        return self.effect.at_limit(self.theta)

    def entry(self) -> RankingEntry:
        """The fit as an entry of the diagnosis' ranking."""
        e = self.effect
        return RankingEntry(
            effect=e.name, score=self.score, gap_after=self.gap_after, shrink=self.shrink,
            p_value=self.p_value, k=e.k, material=self.material, at_limit=self.at_limit, drift=self.drift,
            size=Size(self.size, self.size_std, e.size_unit, e.size_meaning, self.floor, self.sampling),
            magnitude=e.magnitude(self.theta, self.stderr),
            parameters={p: Parameter(float(v), float(s), u)
                        for p, v, s, u in zip(e.params, self.theta, self.stderr, e.units, strict=True)})


def size_gradient(effect: Effect, theta: np.ndarray) -> np.ndarray:
    """d size / d theta by central differences (the size is a plain function of the parameters)."""
    grad = np.zeros(effect.k)
    for i in range(effect.k):
        h = np.zeros(effect.k)
        h[i] = max(1e-6 * abs(theta[i]), 1e-9 * effect.scale[i] + 1e-300)
        grad[i] = (effect.size(theta + h) - effect.size(theta - h)) / (2.0 * h[i])
    return grad


def sampling_bound(effect: Effect, f: Fit) -> float | None:
    """Worst-case change of the effect's size by the torque the sampling does not resolve [size unit].

    Each torque row (block) of the fit may be off by up to e_b, the torque of the transients its samples
    do not resolve and of the friction where stick and slip cannot be told apart (:mod:`.residuals`),
    scaled by c_E, how far the residuals show it (:meth:`Scorer.unresolved`); these errors share a sign
    within a transient and can line up with an effect's shape (a current jump at every start reads like
    a drag at speed).  The fit, linearised at its solution, moves the size by -g' (J^+ dz) for a change dz
    of the normalised residual (J the fit's Jacobian over the parameters off their bounds, everything
    fitted with the effect; g = d size / d theta); over every |dz_b| <= c_E e_b / sigma_b the largest
    change is

        S = sum_b |g' J^+_b| c_E e_b / sigma_b,

    every row's error taking the sign that moves the size most (a worst case, as the tolerances' in
    :mod:`.play`).  It is reported, not judged by the verdict (README, "The sampling's share of a size").
    None for a fit without its linearisation (an effect fitted on top of another, :func:`extend`) and for
    a combination of effects, whose joint size is no quantity of its own."""
    if f.response.size == 0 or "+" in effect.name:
        return None
    return float(np.sum(np.abs(size_gradient(effect, f.theta) @ f.response) * f.bound))


def sampling_caution(f: EffectFit) -> bool:
    """A material effect whose size's worst-case change by what the sampling does not resolve
    (:func:`sampling_bound`) exceeds its margin over the floor, size - 1.645 std - floor: at the worst it
    could be under its floor.  An effect not material alone (a part of a pair) has no margin to lose."""
    margin = f.size - MATERIAL_Z * f.size_std - f.floor
    return f.sampling is not None and margin > 0.0 and f.sampling > margin


def _size_std(effect: Effect, theta: np.ndarray, stderr: np.ndarray) -> float:
    """Standard deviation of the size by the delta method (independent parameters)."""
    return float(np.sqrt(np.sum((size_gradient(effect, theta) * stderr) ** 2)))


def evaluate(sc: Scorer, effect: Effect, s_before: np.ndarray, gap_before: float,
             fitted: Fit | None = None, *, tested: bool = True) -> EffectFit:
    """Fit ``effect`` (unless ``fitted`` is given) and compute its held-out gap, score, test and size
    against its floor.

    ``tested=False`` skips the test against the twin within its tolerance (a fit of W_E,
    :func:`base_without_own`; ``p_value`` stays 1): an effect added in the forward selection is tested
    against the effects it extends instead (:func:`_addition`), which sets ``p_value``, and the first
    noise pass (:func:`ranked_fits`) needs only the order.
    """
    f = fit(sc, effect, sc.base) if fitted is None else fitted
    s_after = sc.cycle_sse(f.model)
    d = s_before - s_after
    score = float((d.sum() - 2.0 * effect.k) / s_before.sum())
    gap = sc.gap(f.model)
    shrink = float(1.0 - gap / gap_before) if gap_before > 0.0 else 0.0
    z_after = sc.z(f.model, sc.split.heldout)
    ef = EffectFit(effect, f.theta, f.stderr, f.model, gap, score, shrink, d, z_after)
    if tested:
        ef.p_value = improvement_p(sc.z(base_without_own(sc, effect), sc.split.heldout), z_after)
    ef.size = float(effect.size(f.theta))
    ef.size_std = _size_std(effect, f.theta, f.stderr)
    ef.sampling = sampling_bound(effect, f)
    ef.floor = tolerance.floor(effect.name, sc.model.park_half_band)
    ef.share = sc.unexplained_share(f.model)
    ef.contribution = contribution(sc, effect, f.theta)
    return ef


def extend(sc: Scorer, first: EffectFit, second: Effect, s_before: np.ndarray,
           gap_before: float) -> EffectFit:
    """The pair ``first`` + ``second`` as a nested extension: ``first``'s parameters stay as fitted, and
    so do its nuisances and tolerances outside ``second``'s channels; ``second`` is fitted on top of it
    with the nuisances and free tolerances of its own channels (:func:`_free_tolerances`: refitted from
    ``first``'s values, ``second``'s own budget entries held at zero). ``second``'s standard errors are
    conditional on ``first``'s parameters (their uncertainty is not propagated).

    The joint fit of a pair (:func:`evaluate` of :func:`.catalog.combine`) frees the tolerances of both
    effects' channels at once; when the effects act in different channels (a force-channel effect and a
    torque-channel one), budget entries that move both channels trade one channel's fit against the
    other's, and the pair can end worse on held-out data than its first effect alone. The nested
    extension cannot undo what the first effect explained: forward selection in its textbook form.
    """
    pair = combine(first.effect, second)
    theta1 = first.theta

    def on_top(p: np.ndarray) -> Augment:
        return pair.to_augment(np.concatenate([theta1, p]))

    g = fit(sc, dataclasses.replace(second, name=pair.name, to_augment=on_top), first.model)
    both = Fit(np.concatenate([theta1, g.theta]), np.concatenate([first.stderr, g.stderr]), g.model,
               g.nuisance_std)
    return evaluate(sc, pair, s_before, gap_before, both, tested=False)


def base_without_own(sc: Scorer, effect: Effect) -> Model:
    """The twin within its tolerance with the effect's own budget entries held at zero, W_E: the model the
    effect extends by its parameters (its significance test is against W_E, a nested comparison; against
    W, whose own entries already mimic the effect up to its floor, a real effect would look weaker)."""
    own = frozenset(n for part in effect.name.split("+") for n in tolerance.OWN.get(part, ()))
    if not own:
        return sc.base
    key = tuple(sorted(own))
    cache = sc.cache.setdefault("base_without_own", {})
    if key not in cache:
        probe = dataclasses.replace(NUISANCE_ONLY, name=effect.name)
        cache[key] = fit(sc, probe, sc.base).model
    return cache[key]


def addition_p(sc: Scorer, current: EffectFit, added: Effect, together: EffectFit) -> float:
    """Test (a) of an addition (:func:`_addition`): ``together`` must improve on held-out cycles both on
    ``current`` and on ``current`` refitted with the added effect's own budget entries held at zero
    (:func:`without_own`); the larger of the two one-sided p-values.  Against ``current`` alone, whose
    tolerances already mimic the candidate up to its floor, a real second effect would look weaker than
    a first one of the same size; against the nested model alone, a candidate whose own entry was
    carrying another effect (load friction and a preload change share the direction asymmetry) would
    look strong for what zeroing that entry costs."""
    z = together.z_heldout
    return max(improvement_p(current.z_heldout, z),
               improvement_p(sc.z(without_own(sc, current, added), sc.split.heldout), z))


def without_own(sc: Scorer, current: EffectFit, added: Effect) -> Model:
    """The model ``current`` with the budget entries of ``added`` held at zero, refitted over both's channels:
    the model a joint fit of the two extends by ``added``'s parameters (nested, as :func:`base_without_own`
    is for the first effect; :func:`addition_p`)."""
    names = current.effect.name.split("+")
    own = frozenset(tolerance.OWN.get(added.name, ())) - {n for e in names for n in tolerance.OWN.get(e, ())}
    if not own:
        return current.model
    cache = sc.cache.setdefault("without_own", {})
    channels = tuple(ch for ch in CHANNELS if ch in current.effect.channels or ch in added.channels)
    key = (current.effect.name, tuple(current.theta), tuple(sorted(own)), channels)
    if key not in cache:
        probe = dataclasses.replace(current.effect, name="+".join((*names, added.name)), channels=channels,
                                    starts=(tuple(current.theta),))
        cache[key] = fit(sc, probe, current.model).model
    return cache[key]


def contribution(sc: Scorer, effect: Effect, theta: np.ndarray) -> float:
    """How much an effect changes the twin's prediction: the RMS change, over the blocks of its channel
    (moving blocks for the torque, released contact blocks for the force), as a share of that channel's
    RMS signal (motor torque, clamp force); the largest over its channels.  This is what "largest"
    means when the verdict names one of two effects: the one that moves the twin's output most."""
    mdl, b = sc.model, sc.model.blocks
    aug = _merge(NOMINAL, effect.to_augment(theta), {})
    out = 0.0
    if "torque" in effect.channels:
        rows = b.moving
        d = mdl.torque_residual(NOMINAL)[rows] - mdl.torque_residual(aug)[rows]
        scale = max(np.sqrt(np.mean(mdl.drive_block()[rows] ** 2)), 1e-12)
        out = max(out, float(np.sqrt(np.mean(d * d)) / scale))
    if "force" in effect.channels:
        rows = sc.valid(np.ones(b.size, bool), "force") & (b.force > mdl.seg.force_rise)
        if rows.any():
            d = mdl.force_residual(NOMINAL)[rows] - mdl.force_residual(aug)[rows]
            out = max(out, float(np.sqrt(np.mean(d * d)) / max(np.sqrt(np.mean(b.force[rows] ** 2)), 1e-12)))
    return out


def tie_p(a: EffectFit, b: EffectFit) -> float:
    """Two-sided p-value of "two fitted effects explain the held-out data equally well"
    (:func:`.heldout.tie_p`)."""
    return heldout.tie_p(a.z_heldout, b.z_heldout)


class OpenSetTest(Protocol):
    """A test that turns a verdict into ``unexplained`` when it counts (:mod:`.scale`, :mod:`.stick`,
    :mod:`.play`)."""

    def counts(self, level: float) -> bool: ...


def decides(test: OpenSetTest | None) -> bool:
    """``test`` was made and counts at ``ALPHA``: it turns the verdict into ``unexplained``."""
    return test is not None and test.counts(ALPHA)


@dataclass(frozen=True)
class OpenSet:
    """The open-set test of the verdict's model (:mod:`.openset`, :func:`open_set_verdict`)."""

    periodic: Periodic  # the screw-position harmonic its held-out torque residual leaves
    on_effects: bool  # tested on the selected effects' residual (else on the twin within its tolerance)
    share: float | None  # share of the explainable error the effects close (:func:`effects_share`)
    decided: bool  # it turned the verdict into ``unexplained``

    @property
    def significant(self) -> bool:
        """The harmonic is significant at the open-set level (:data:`OPEN_SET_LEVEL`), material or not."""
        return self.periodic.p_value < OPEN_SET_LEVEL


@dataclass
class Ranking:
    """The outcome of :func:`rank`."""

    fits: list[EffectFit]  # single effects, best first
    selected: list[EffectFit]  # forward selection: the effects the data support, in order of selection
    # (the floating step, :func:`_rechoose_first`, may list the second before the re-chosen first), or
    # the best pair of two (:func:`best_pair`) in the order of its fit
    joint: EffectFit | None  # the selected effects fitted together (None when none is selected)
    best_pair_shrink: float  # largest share of the material gap a single effect or any pair tried closes
    gap_before: float  # held-out gap of the nominal twin as given (nuisances fitted, no tolerance deviation)
    gap_tolerance: float  # held-out gap of the twin within its tolerance, W
    unexplained_share: dict[str, float]  # W's model error beyond the noise per channel (Scorer method)
    verdict: str  # "effect" | "none" | "unexplained"
    alpha: float
    open_set: OpenSet | None = None  # the screw-position test of the verdict's model (None: not tested)
    #: the motor torque's scale the verdict's model leaves, against its tolerance (:mod:`.scale`; None: not
    #: tested)
    scale: TorqueScale | None = None
    #: the breakaway-band test of the verdict's model at rest (:mod:`.stick`; None: not tested)
    rest: RestTorque | None = None
    #: the friction over the extra clearance of the verdict's model (:mod:`.play`; None: not tested)
    play: LostMotion | None = None

    @property
    def scale_decided(self) -> bool:
        """The scale test turned the verdict into ``unexplained`` (it runs only on another verdict)."""
        return decides(self.scale)

    @property
    def rest_decided(self) -> bool:
        """The rest test turned the verdict into ``unexplained`` (it runs only on another verdict)."""
        return decides(self.rest)

    @property
    def play_decided(self) -> bool:
        """The lost-motion test turned the verdict into ``unexplained`` (it runs only on ``effect``)."""
        return decides(self.play)

    @property
    def top(self) -> EffectFit:
        return self.fits[0]

    @property
    def explained(self) -> EffectFit | None:
        """The model the verdict rests on: the selected effects together (None unless an effect)."""
        return self.joint if self.verdict == "effect" else None

    @property
    def effect(self) -> EffectFit | None:
        """The verdict's effect: of the selected ones, the largest (:attr:`EffectFit.contribution`)."""
        if self.verdict != "effect":
            return None
        return max(self.selected, key=lambda f: f.contribution)


def material_channels(share: dict[str, float]) -> list[str]:
    """The channels whose unexplained share (:meth:`Scorer.unexplained_share`) exceeds its materiality
    bound (:data:`.tolerance.MATERIAL_SHARE`)."""
    return [ch for ch in CHANNELS if share[ch] > tolerance.MATERIAL_SHARE[ch]]


def nominal_sse(sc: Scorer) -> np.ndarray:
    """Held-out sum of z^2 per cycle of the twin within its tolerance (the baseline of :func:`evaluate`)."""
    return sc.cycle_sse(sc.base)


def _supported(sc: Scorer, f: EffectFit, level: float, w_share: dict[str, float]) -> bool:
    """Tests (a), (b), (d) and (e) of the module docstring (``w_share``: the model error of the twin
    within its tolerance, :meth:`Scorer.unexplained_share`)."""
    if not (f.nameable and f.significant(level)) or _worsens(w_share, f.share):
        return False
    f.drift = drift_test(sc, f)
    return not f.drifting


def _worsens(before: dict[str, float], after: dict[str, float]) -> bool:
    """Test (e): the model error a change adds in some channel is material.  The shares are RMS errors
    beyond the noise over the same held-out rows (:meth:`Scorer.unexplained_share`), so the error added
    is their difference in quadrature, sqrt(after^2 - before^2), compared with the channel's
    materiality share (:data:`.tolerance.MATERIAL_SHARE`)."""
    return any(after[ch] ** 2 - before[ch] ** 2 > tolerance.MATERIAL_SHARE[ch] ** 2 for ch in CHANNELS)


#: a friction effect drifts only when its size changes with time beyond the operating mix, at this level
#: (two-sided; :func:`_time_trend_p`)
DRIFT_ALPHA = 0.01

#: effects whose size may change within a recording: clearance grows with wear, a sensor drifts with
#: temperature; the friction effects are properties of the unit that must hold over the recording
MAY_DRIFT = frozenset({"clearance_growth", "force_sensor_bias", "stiffness_nonlinearity"})


def drift_test(sc: Scorer, f: EffectFit) -> Drift | None:
    """Does a friction effect hold over the recording?  Refit on the early and the late half (module doc).

    The brake cycles (calibration and held-out: this tests a property of the unit, not the held-out fit)
    are split at their median time; the effect's parameters alone are refitted on each half (nuisances
    and tolerances as fitted on the calibration cycles).  The effect drifts when its size differs between
    the halves by more than its floor and by more than three standard deviations, and when its size
    trends with time beyond what the operating mix explains (:func:`_time_trend_p`): a real effect's form
    differs from the catalog's, so its fitted size also depends on the demands and speeds a half happens
    to hold, by an amount the data set, not a share assumed in advance.  With fewer than six cycles
    the trend cannot be tested and no effect drifts.
    """
    if f.effect.name in MAY_DRIFT or f.effect.k == 0:
        return None
    cycle = sc.model.blocks.cycle
    cycles = np.unique(cycle)  # every cycle: calibration and held out
    if cycles.size < 4:
        return None
    early = cycles <= np.median(cycles)
    sizes, errs = [], []
    for half in (cycles[early], cycles[~early]):
        g = fit(sc, f.effect, f.model, mask=np.isin(cycle, half), only_effect=True)
        sizes.append(float(f.effect.size(g.theta)))
        errs.append(_size_std(f.effect, g.theta, g.stderr))
    diff, sd = sizes[1] - sizes[0], float(np.hypot(errs[0], errs[1]))
    p = _time_trend_p(sc, f, cycles)
    drifting = abs(diff) > max(f.floor, 3.0 * sd) and p < DRIFT_ALPHA
    return Drift(sizes[0], sizes[1], sd, p, bool(drifting))


def _time_trend_p(sc: Scorer, f: EffectFit, cycles: np.ndarray) -> float:
    """p-value (two-sided) of a trend with time in the effect's size per cycle, the operating mix held.

    The effect's parameters are refitted on all ``cycles`` (nuisances and tolerances kept) and linearised
    there: with J = dz/dtheta (the fit's Jacobian) and z the normalised residual, per cycle
    A_c = J_c' J_c and b_c = J_c' z_c; the fit on cycle c alone is one Gauss-Newton step,
    theta_c = theta - A_c^+ b_c (exact for an effect linear in its parameters), and its size, to first
    order, s_c = size(theta) - g' A_c^+ b_c with variance v_c = g' A_c^+ g in noise units (g: the
    gradient of the size; the constant size(theta) is left to the regression's intercept).  The sizes
    are regressed, weights 1 / v_c, on a constant, the cycle's time, its peak clamp force and its peak
    speed; the time coefficient is tested with a standard error robust to the scatter the weights do not
    describe (:func:`trend_p`).  Where the demands themselves change with time, time and mix are
    collinear and the test loses its power instead of charging the mix to time; a size depending on the
    demand other than linearly is only partly held (the early/late gates of :func:`drift_test` then
    guard).  1 with fewer than six cycles.
    """
    e, channels = f.effect, f.effect.channels
    if cycles.size < 6:
        return 1.0
    blocks = sc.model.blocks
    mask = np.ones(blocks.size, bool)
    g = fit(sc, e, f.model, mask=mask, only_effect=True)
    J, z0 = g.jac, g.z
    grad = size_gradient(e, g.theta)
    pos = np.searchsorted(cycles, sc.row_cycles(mask, channels))
    A = np.zeros((cycles.size, e.k, e.k))
    b = np.zeros((cycles.size, e.k))
    np.add.at(A, pos, J[:, :, None] * J[:, None, :])
    np.add.at(b, pos, J * z0[:, None])
    Ainv = np.linalg.pinv(A)
    start = -blocks.cycle_max(-sc.model.rec.t[blocks.start])[cycles]  # each cycle's first block [s]
    mix = np.column_stack([blocks.cycle_max(blocks.force)[cycles], blocks.cycle_max(blocks.speed)[cycles]])
    return trend_p(-np.einsum("k,ckl,cl->c", grad, Ainv, b), np.einsum("k,ckl,l->c", grad, Ainv, grad),
                   start, mix)


def trend_p(s: np.ndarray, v: np.ndarray, time: np.ndarray, mix: np.ndarray) -> float:
    """Two-sided p-value of the time coefficient in the regression of ``s`` on a constant, ``time`` and the
    columns of ``mix``, weighted by the stated variances ``v``; 1 when no scatter is left to test against.

    The scatter of a catalog form fitted to another form is not proportional to ``v`` (it comes from the
    mismatch, not from the noise), so the standard error is heteroscedasticity-robust (HC3: each
    squared residual divided by (1 - h_i)^2, h_i its leverage; MacKinnon and White 1985), the statistic
    Student t with n - 2 - (mix columns) degrees of freedom.
    """
    ok = v > 0.0
    X = np.column_stack([np.ones(time.size), *((x - x.mean()) / (x.std() or 1.0)
                                              for x in (time, *np.asarray(mix, dtype=float).T))])[ok]
    n, q = X.shape
    if n - q < 2:
        return 1.0
    w = 1.0 / np.sqrt(v[ok])
    Xw = X * w[:, None]
    bread = np.linalg.pinv(Xw.T @ Xw)
    beta = bread @ Xw.T @ (s[ok] * w)
    resid = s[ok] * w - Xw @ beta
    leverage = np.clip(np.einsum("ij,jk,ik->i", Xw, bread, Xw), 0.0, 1.0 - 1e-9)
    meat = (Xw * (resid / (1.0 - leverage))[:, None] ** 2).T @ Xw
    se = float(np.sqrt(max((bread @ meat @ bread)[1, 1], 0.0)))
    return float(2.0 * stats.t.sf(abs(beta[1]) / se, n - q)) if se > 0.0 else 1.0


def ranked_fits(sc: Scorer, catalog: dict[str, Effect], *, tested: bool = True,
                before: tuple[np.ndarray, float] | None = None) -> list[EffectFit]:
    """Every effect fitted (:func:`evaluate`), ranked by score, an effect with fewer parameters that the
    top one does not beat significantly first (parsimony); ``tested=False`` skips each effect's test
    against the twin within its tolerance (the order does not use it: :func:`.pipeline.analyse` needs
    only the top effect of a first pass). ``before``: (:func:`nominal_sse`, held-out gap of W) when
    known."""
    s_before, gap_before = before or (nominal_sse(sc), sc.gap(Model(sc.base.aug)))
    fits = sorted((evaluate(sc, e, s_before, gap_before, tested=tested) for e in catalog.values()),
                  key=lambda f: -f.score)
    simpler = [j for j in range(1, len(fits)) if fits[j].effect.k < fits[0].effect.k and _tied(fits, 0, j)]
    if simpler:
        j = min(simpler, key=lambda j: (fits[j].effect.k, -fits[j].score))
        fits.insert(0, fits.pop(j))
    return fits


def _tied(fits: list[EffectFit], i: int, j: int) -> bool:
    """Effect j explains the held-out data as well as effect i (a near-tie, :func:`tie_p`)."""
    return fits[j].score > 0.0 and tie_p(fits[i], fits[j]) >= TIE_ALPHA


def rank(sc: Scorer, catalog: dict[str, Effect]) -> Ranking:
    """Fit every effect, rank by score, select, decide the verdict, mark near-ties with the top effect."""
    s_before = nominal_sse(sc)
    gap_before = sc.gap(Model(sc.base.aug))
    fits = ranked_fits(sc, catalog, before=(s_before, gap_before))
    level = ALPHA / len(fits)
    top = fits[0]
    top.ties = [f.effect.name for j, f in enumerate(fits) if j > 0 and _tied(fits, 0, j)]
    share = sc.unexplained_share(sc.base)
    material = material_channels(share)

    def closes_half(f: EffectFit) -> bool:
        return all(f.share[ch] <= SHRINK_NEEDED * share[ch] for ch in material)

    selected, joint, candidates = _forward_select(sc, fits, level, s_before, gap_before, w_share=share)
    drifting = any(f.drifting for f in fits)
    if material and (joint is None or not closes_half(joint)) and not drifting:
        pair = best_pair(sc, fits, s_before, gap_before, w_share=share, closes=closes_half, tried=candidates)
        if pair is not None:
            joint, selected = pair
    if joint is not None and joint.shrink <= 0.0:  # (c): the held-out gap does not shrink at all
        joint, selected = None, []
    if joint is not None:
        verdict = "effect" if closes_half(joint) else "unexplained"
    elif (material and not any(closes_half(f) for f in candidates)) or drifting:
        verdict = "unexplained"
    else:
        verdict = "none"
    open_set = None
    explaining = joint if verdict == "effect" else None
    verdict_model = sc.base if explaining is None else explaining.model
    periodic = screw_periodic(sc, verdict_model) if verdict != "unexplained" else None
    if periodic is not None:
        share_closed = effects_share(explaining, periodic) if explaining is not None else None
        opened = open_set_verdict(verdict, periodic, share_closed)
        open_set = OpenSet(periodic, explaining is not None, share_closed, opened != verdict)
        verdict = opened
    drive_scale = motor_scale(sc, verdict_model, explaining) if verdict != "unexplained" else None
    if decides(drive_scale):
        verdict = "unexplained"
    rest = rest_torque(sc.model, verdict_model.aug, sc.sigma_torque, sc.split.calibration,
                       sc.split.heldout) if verdict != "unexplained" else None
    if decides(rest):
        verdict = "unexplained"
    play = lost_motion(sc.model, verdict_model.aug, sc.split.heldout_cycles) if verdict == "effect" else None
    if decides(play):
        verdict = "unexplained"
    best = max((1.0 - max((f.share[ch] / share[ch] for ch in material), default=0.0)) for f in candidates) \
        if material else 1.0
    return Ranking(fits, selected, joint, best, gap_before, sc.gap(sc.base), share, verdict, level, open_set,
                   drive_scale, rest, play)


def motor_scale(sc: Scorer, m: Model, f: EffectFit | None = None) -> TorqueScale | None:
    """The motor torque's scale ``m`` leaves on the moving blocks' torque rows, against the budget's bound
    (:mod:`.scale`).  ``f``: the verdict's effects, when ``m`` is their fit; where one of them owns the
    scale's entry (it is then no tolerance, :func:`.tolerance.free`), c is refitted with their parameters
    on the same rows (:func:`owner_columns`)."""
    b, i = sc.model.blocks, entry_index()
    moving = b.moving
    z = sc.z(m, moving, ("torque",))
    owned = f is not None and not tolerance.free(f.effect.name.split("+"))[i]
    return torque_scale(z, sc.D[sc.rows(moving, ("torque",)), i], float(m.t[i]),
                        bound=budget_bound(sc.model.nominal), cycles=b.cycle[moving],
                        calibration=sc.split.calibration[moving], heldout=sc.split.heldout[moving],
                        owner=owner_columns(sc, f, z) if f is not None and owned else None)


def owner_columns(sc: Scorer, f: EffectFit, z0: np.ndarray) -> np.ndarray | None:
    """dz/d(theta) on the moving blocks' torque rows (``z0``: z there at the fit) of every parameter of
    ``f``'s effects that its fit left free, by forward differences at the fit (:func:`difference_step`):
    where one of them owns the scale's budget entry (:data:`.tolerance.OWN`: an efficiency variation, a
    force-sensor bias), the entry was held at zero while all of them were fitted, so each took what it
    could of a scale (:mod:`.scale`, "Owner").  The torque rows only: the scale acts there, and the
    question is whether any values of the effects make the torque without it.  A parameter on a bound of
    its box (:meth:`.catalog.Effect.on_bound`) is held there, as the solver held it; None when none is
    free."""
    hi = f.effect.bounds()[1]
    scale = np.abs(np.asarray(f.effect.scale, dtype=float))
    moving = sc.model.blocks.moving
    cols = []
    for j in np.flatnonzero(~f.effect.on_bound(f.theta)):
        theta = f.theta.copy()
        step = difference_step(float(theta[j]), float(scale[j]), float(hi[j]))
        theta[j] += step
        aug = _merge(f.model.aug, f.effect.to_augment(theta), {})
        col = (sc.z(dataclasses.replace(f.model, aug=aug), moving, ("torque",)) - z0) / step
        if np.all(np.isfinite(col)):
            cols.append(col)
    return np.column_stack(cols) if cols else None


def screw_periodic(sc: Scorer, m: Model) -> Periodic | None:
    """Torque depending on the screw position in the held-out torque residual of ``m`` (:mod:`.openset`),
    beyond the catalog's own shapes: per direction of motion a constant, a term in the clamp force and
    one in the speed (004 eq. 9's Coulomb, load and viscous terms, free per direction).  Blocks whose
    friction eq. 9 leaves undetermined (stick and slip not told apart, :mod:`.residuals`) are left out:
    how a drive creeps is its own convention, the same in every application, and many such blocks would
    add up to a position-shaped torque as significant as any ripple."""
    mdl, b = sc.model, sc.model.blocks
    resolved = b.moving & (mdl.ambiguous_torque == 0.0)
    z = sc.z_raw(m.aug, np.ones(b.size, bool), ("torque",)) + sc.D[:b.size] @ m.t
    forward = np.isin(b.phase, (Phase.CLEARANCE_ELIMINATION, Phase.FORCE_GENERATION)).astype(float)
    backward = (b.phase == Phase.FORCE_RELEASE).astype(float)
    shapes = np.column_stack([forward, backward, forward * b.force, backward * b.force,
                              forward * b.speed, backward * b.speed])
    return periodic_structure(mdl.rec.angle, b.start, b.stop, z, sigma=sc.sigma_torque, shapes=shapes,
                              calibration=sc.split.calibration & resolved,
                              heldout=sc.split.heldout & resolved, drive=mdl.drive_block())


def effects_share(joint: EffectFit, periodic: Periodic) -> float | None:
    """Share of the explainable held-out error the effects close, (S_W - S_E) / (S_W - S_EP), :mod:`.openset`.

    What the effects removed from the twin within its tolerance (all held-out rows), over that plus what
    the screw-position harmonic removes beyond the shape terms (moving torque rows); in [0, 1]; None when
    the harmonic removes nothing (no share to speak of).
    """
    by_effects = float(joint.d_cycles.sum())  # S_W - S_E, held out per cycle (:func:`evaluate`)
    by_harmonic = periodic.sse_before - periodic.sse_after
    if by_harmonic <= 0.0:
        return None
    return float(np.clip(by_effects / (by_effects + by_harmonic), 0.0, 1.0)) if by_effects > 0.0 else 0.0


def open_set_verdict(verdict: str, periodic: Periodic | None, share: float | None) -> str:
    """The verdict once a torque depending on the screw position is accounted for (:mod:`.openset`).

    ``effect`` becomes ``unexplained`` when the harmonic is significant and the effects close less than
    half of the explainable error (``share`` < 1/2: the harmonic removes more of the effects' held-out
    error than they removed from the twin within its tolerance); ``none`` becomes ``unexplained`` when
    the harmonic is significant and material in the twin within its tolerance.  A material harmonic
    left by effects that close at least half does not decide (tried: it cost more catalog effects than
    it gained ripples, README "Open set").
    """
    if periodic is None:
        return verdict
    if verdict == "none":
        return "unexplained" if periodic.counts(OPEN_SET_LEVEL) else verdict
    significant = periodic.p_value < OPEN_SET_LEVEL
    if verdict == "effect" and share is not None and significant and share < SHRINK_NEEDED:
        return "unexplained"
    return verdict


#: forward selection stops after this many effects (issue 10 item 5 asks for two; a third step lets a
#: selection whose second effect took the larger channel's gap still add the effect the other channel needs)
MAX_EFFECTS = 3


def _part(f: EffectFit, theta: np.ndarray, stderr: np.ndarray) -> EffectFit:
    """The entry of effect ``f`` as fitted within a model of several effects: its parameters and their
    errors from that fit, its size and size error from them (its model and held-out scores stay those of
    ``f`` alone)."""
    return dataclasses.replace(f, theta=theta, stderr=stderr, size=float(f.effect.size(theta)),
                               size_std=_size_std(f.effect, theta, stderr))


def _in_model(part: EffectFit, model: EffectFit, offset: int) -> EffectFit:
    """``part`` (an effect's entry within ``model``, whose parameters start at ``offset``) as an effect of
    its own on ``model``'s fit: its parameters free, the other effects' held as ``model`` fitted them
    (what :func:`drift_test` refits on the early and the late half)."""
    k, theta = part.effect.k, model.theta.copy()

    def to_augment(p: np.ndarray) -> Augment:
        theta[offset:offset + k] = p
        return model.effect.to_augment(theta)

    return dataclasses.replace(part, effect=dataclasses.replace(part.effect, to_augment=to_augment),
                               model=model.model)


def best_pair(sc: Scorer, fits: list[EffectFit], s_before: np.ndarray, gap_before: float, *,
              w_share: dict[str, float], closes: Callable[[EffectFit], bool],
              tried: list[EffectFit] | None = None) -> tuple[EffectFit, list[EffectFit]] | None:
    """Best subset of size two, for when forward selection leaves the material model error open: every
    pair fitted jointly from the twin within its tolerance (:func:`evaluate`), the best-scoring one that
    passes (a) against W with both effects' own budget entries held at zero, (b) for each of its effects
    as fitted in the pair, each effect's own (a) given the other (:func:`addition_p` of the pair against
    the other effect alone: no passenger), (d) for each effect refitted within the pair
    (:func:`_in_model`), (e) against W, and (c) (``closes``).  The pair's test runs at ALPHA over the
    number of pairs, each effect's given the other at half that.

    Greedy selection needs its first effect to stand alone.  Two effects whose signatures overlap do not:
    fitted alone, each takes part of the other's signature and the misfit it leaves makes its size
    uncertain (a clearance growth beside a force-sensor gain: the contact point moves with both), so
    neither is material while the pair, fitted together, is sharp.  A second route to ``effect`` beside
    the greedy one: the verdict's family-wise rate of a false ``effect`` is bounded by 2 ALPHA.

    Returns (the pair's fit, its two effects' entries) or None; every pair's fit is appended to ``tried``.
    """
    pairs = [(a, b) for i, a in enumerate(fits) for b in fits[i + 1:]]
    level = ALPHA / max(len(pairs), 1)
    best: tuple[EffectFit, list[EffectFit]] | None = None
    for a, b in pairs:
        q = evaluate(sc, combine(a.effect, b.effect), s_before, gap_before)
        if tried is not None:
            tried.append(q)
        if not (q.significant(level) and closes(q) and not _worsens(w_share, q.share)) \
                or (best is not None and q.score <= best[0].score):
            continue
        k = a.effect.k
        parts = [_part(a, q.theta[:k], q.stderr[:k]), _part(b, q.theta[k:], q.stderr[k:])]
        if not all(f.nameable for f in parts) \
                or addition_p(sc, b, a.effect, q) >= level / 2 or addition_p(sc, a, b.effect, q) >= level / 2:
            continue
        for f, offset in zip(parts, (0, k), strict=True):
            f.drift = drift_test(sc, _in_model(f, q, offset))
            f.contribution = contribution(sc, f.effect, f.theta)
        if not any(f.drifting for f in parts):
            best = (q, parts)
    return best


def _pairs(sc: Scorer, lead: EffectFit, f: EffectFit, s_before: np.ndarray, gap_before: float, *,
           nested: bool) -> list[EffectFit]:
    """The pairs of ``lead`` with ``f`` to try: fitted jointly (when ``f`` alone improves on the twin)
    and, with ``nested``, as an extension of ``lead`` (:func:`extend`; tried whatever ``f`` scores alone:
    an effect whose own budget entries are held at zero can score below the twin and still close what
    ``lead`` leaves, e.g. a force-sensor bias beside a clearance growth)."""
    out = [evaluate(sc, combine(lead.effect, f.effect), s_before, gap_before, tested=False)] \
        if f.score > 0.0 else []
    if nested:
        out.append(extend(sc, lead, f.effect, s_before, gap_before))
    return out


def _addition(sc: Scorer, current: EffectFit, options: list[tuple[EffectFit, list[EffectFit]]]
              ) -> tuple[EffectFit, EffectFit] | None:
    """The best supported addition to ``current``: per candidate effect the best-scoring of its fits with
    ``current`` (``options``: (single fit, its fits together with ``current``)) that passes (a)
    (:func:`addition_p`; held out, at ALPHA over the number of fits tried, Bonferroni over both fits of
    every candidate), (b), (d) (refitted within the model with the addition, :func:`_in_model`) and
    (e).  The joint fit frees the budget entries that move both channels, and a candidate's parameter
    can be nearly collinear with them there and sharp on top of ``current``: the two are two
    parametrisations of one hypothesis, both paid for in the level.

    Returns (the fit of the model with the addition, the added effect's entry) or None.
    """
    k0 = current.effect.k
    level = ALPHA / max(sum(len(fitted) for _, fitted in options), 1)
    best: tuple[EffectFit, EffectFit] | None = None
    for f, fitted in options:
        for together in sorted(fitted, key=lambda q: -q.score):
            theta, se = together.theta[k0:], together.stderr[k0:]
            added = _part(f, theta, se)
            if not (added.nameable and together.score > current.score
                    and not _worsens(current.share, together.share)):
                continue
            together.p_value = addition_p(sc, current, f.effect, together)
            if together.p_value >= level:
                continue
            added.drift = drift_test(sc, _in_model(added, together, k0))
            if not added.drifting and (best is None or together.score > best[0].score):
                added.contribution = contribution(sc, f.effect, theta)
                best = (together, added)
            break
    return best


def _forward_select(sc: Scorer, fits: list[EffectFit], level: float, s_before: np.ndarray,
                    gap_before: float, *, w_share: dict[str, float]
                    ) -> tuple[list[EffectFit], EffectFit | None, list[EffectFit]]:
    """Best supported single effect, then, up to ``MAX_EFFECTS``, the best supported next one
    (:func:`_addition`): the second fitted together with the first or on top of it (:func:`_pairs`),
    the first then chosen again given the second, and again while a swap raises the held-out score
    (:func:`_rechoose_first`), a third on top of the two.

    Also returns every single effect and every pair with the lead effect (the supported one, else the
    best-scoring): the candidates of the ``unexplained`` test (does any effect, or pair, close half of
    the material gap at all?).  ``w_share``: the model error of the twin within its tolerance
    (:meth:`Scorer.unexplained_share`), the baseline of test (e) for the first effect.
    """
    first = next((f for f in fits if _supported(sc, f, level, w_share)), None)
    lead = first if first is not None else fits[0]
    options = [(f, _pairs(sc, lead, f, s_before, gap_before, nested=first is not None))
               for f in fits if f is not lead]
    candidates = list(fits) + [pair for _, pairs in options for pair in pairs]
    if first is None:
        return [], None, candidates
    selected, current = [first], first
    while len(selected) < MAX_EFFECTS:
        step = _addition(sc, current, [(f, pairs) for f, pairs in options if pairs])
        if step is None:
            break
        current = step[0]
        selected.append(step[1])
        while len(selected) == 2:  # float while it helps: each swap raises the held-out score
            floated = _rechoose_first(sc, fits, current, selected, s_before=s_before, gap_before=gap_before)
            if floated[1] is selected:
                break
            current, selected = floated
        names = {e.effect.name for e in selected}
        options = [(f, [extend(sc, current, f.effect, s_before, gap_before)])
                   for f in fits if f.effect.name not in names] if len(selected) < MAX_EFFECTS else []
    return selected, current, candidates


def _rechoose_first(sc: Scorer, fits: list[EffectFit], current: EffectFit, selected: list[EffectFit], *,
                    s_before: np.ndarray, gap_before: float) -> tuple[EffectFit, list[EffectFit]]:
    """The floating step of forward selection (sequential floating forward selection): once a second
    effect is in, the first is chosen again *given the second*, by the same rule that chose the second
    given the first (:func:`_addition` on top of the second alone, every other effect a candidate).  A
    greedy first choice can take part of the second effect's signature (an efficiency varying with
    speed where a load friction and a Stribeck fall act together).  The other pair replaces the selected
    one when it scores higher on held-out cycles, does not make a channel materially wrong beside the
    selected pair (test (e)), and the second effect still earns its place beside the re-chosen first:
    material (b), its addition to the re-chosen first alone significant (a) and not making a channel
    materially wrong (e), as if the re-chosen effect had been chosen first.

    Returns the model with the selected effects and the selected effects (changed or not; after a
    change the second effect is listed first, in the order of the model's parameters)."""
    second = selected[1]
    alone = next(f for f in fits if f.effect.name == second.effect.name)
    options = [(f, _pairs(sc, alone, f, s_before, gap_before, nested=True)) for f in fits if f is not alone]
    step = _addition(sc, alone, options)
    if step is None or step[1].effect.name == selected[0].effect.name or step[0].score <= current.score:
        return current, selected
    together, added = step
    k = alone.effect.k
    kept = _part(second, together.theta[:k], together.stderr[:k])
    first = next(f for f in fits if f.effect.name == added.effect.name)
    earns = kept.nameable and together.score > first.score and not _worsens(first.share, together.share) \
        and addition_p(sc, first, alone.effect, together) < ALPHA / max(len(fits) - 1, 1)
    if not earns or _worsens(current.share, together.share):
        return current, selected
    kept.contribution = contribution(sc, alone.effect, kept.theta)
    return together, [kept, added]


def separating_experiment(nom: ActuatorModel, a: EffectFit, b: EffectFit, *, max_speed: float,
                          max_force: float, sigma_torque: float, sigma_force: float, n: int = 12) -> NearTie:
    """Operating range where two fitted effects disagree most, in noise units.

    The moving-branch friction (004 eq. 9 + each augmentation) is compared on a
    grid of motor speed 0..1.5 ``max_speed`` and force 0..1.5 ``max_force``; the
    force-travel law (004 eq. 5 + each) on force 0..1.5 ``max_force``.  The cell
    with the largest |difference| / sigma names the experiment (screw speed
    reported at the screw, i.e. motor speed / i_g).
    """
    w = np.linspace(0.0, 1.5 * max_speed, n + 1)
    F = np.linspace(0.0, 1.5 * max_force, n + 1)
    wc, Fc = np.meshgrid(0.5 * (w[1:] + w[:-1]), 0.5 * (F[1:] + F[:-1]), indexing="ij")
    dT = np.abs(kinetic_friction(nom, a.augment, wc, Fc) - kinetic_friction(nom, b.augment, wc, Fc))
    dT /= sigma_torque
    x = nom.clamp.clearance + 0.5 * (F[1:] + F[:-1]) / nom.clamp.stiffness

    def reading(aug: Augment) -> np.ndarray:
        return (1.0 + aug.force_gain) * clamp_spring(nom, aug).force(x)

    dF = np.abs(reading(a.augment) - reading(b.augment)) / sigma_force
    i, j = np.unravel_index(int(np.argmax(dT)), dT.shape)
    if dF.max() > dT[i, j]:
        k = int(np.argmax(dF))
        speed, force, sep = None, [float(F[k]), float(F[k + 1])], float(dF[k])
    else:
        speed = [float(w[i] / nom.gear_ratio), float(w[i + 1] / nom.gear_ratio)]
        force, sep = [float(F[j]), float(F[j + 1])], float(dT[i, j])
    inside = (speed is None or speed[0] * nom.gear_ratio <= max_speed) and force[0] <= max_force
    where = (f"screw speed {speed[0]:.3g}-{speed[1]:.3g} rad/s at " if speed else "") + \
        f"clamp force {force[0]:.4g}-{force[1]:.4g} N"
    return NearTie([a.effect.name, b.effect.name], speed, force, sep, bool(inside),
                   f"record at {where}" + ("" if inside else " (beyond the recorded range)"))
