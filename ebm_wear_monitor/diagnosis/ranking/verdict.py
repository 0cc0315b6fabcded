"""The ranking of the single effects and the verdict (the package docstring's "Verdict", "Parsimony" and
the near-tie flags; the tie test is :func:`.effect_fit.tie_p`, the separating experiment
:func:`.experiment.separating_experiment`), with the open-set, scale, rest and lost-motion tests of the
verdict's model and the recording's force-travel paths (:mod:`..hysteresis`).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from ebm_wear_monitor.diagnosis import tolerance
from ebm_wear_monitor.diagnosis.catalog import Effect
from ebm_wear_monitor.diagnosis.hysteresis import Hysteresis, hysteresis
from ebm_wear_monitor.diagnosis.openset import HARMONICS, Periodic, periodic_structure
from ebm_wear_monitor.diagnosis.play import LostMotion, lost_motion
from ebm_wear_monitor.diagnosis.ranking.criteria import ALPHA, SHRINK_NEEDED, TIE_ALPHA, material_channels
from ebm_wear_monitor.diagnosis.ranking.effect_fit import EffectFit, evaluate, nominal_sse, tie_p
from ebm_wear_monitor.diagnosis.ranking.scorer import Model, Scorer, difference_step, merge_augment
from ebm_wear_monitor.diagnosis.ranking.selection import best_pair, forward_select
from ebm_wear_monitor.diagnosis.scale import TorqueScale, budget_bound, entry_index, torque_scale
from ebm_wear_monitor.diagnosis.stick import RestTorque, rest_torque
from ebm_wear_monitor.domain.phases import Phase

#: level of the screw-position harmonic (:mod:`..openset`): ALPHA over the harmonics tried
OPEN_SET_LEVEL = ALPHA / HARMONICS


class OpenSetTest(Protocol):
    """A test that turns a verdict into ``unexplained`` when it counts (:mod:`..scale`, :mod:`..stick`,
    :mod:`..play`, :mod:`..hysteresis`)."""

    def counts(self, level: float) -> bool: ...


def decides(test: OpenSetTest | None) -> bool:
    """``test`` was made and counts at ``ALPHA``: it turns the verdict into ``unexplained``."""
    return test is not None and test.counts(ALPHA)


@dataclass(frozen=True)
class OpenSet:
    """The open-set test of the verdict's model (:mod:`..openset`, :func:`open_set_verdict`)."""

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
    # (the floating step, :func:`.selection._rechoose_first`, may list the second before the re-chosen
    # first), or
    # the best pair of two (:func:`best_pair`) in the order of its fit
    joint: EffectFit | None  # the selected effects fitted together (None when none is selected)
    best_pair_shrink: float  # largest share of the material gap a single effect or any pair tried closes
    gap_before: float  # held-out gap of the nominal twin as given (nuisances fitted, no tolerance deviation)
    gap_tolerance: float  # held-out gap of the twin within its tolerance, W
    unexplained_share: dict[str, float]  # W's model error beyond the noise per channel (Scorer method)
    verdict: str  # "effect" | "none" | "unexplained"
    alpha: float
    open_set: OpenSet | None = None  # the screw-position test of the verdict's model (None: not tested)
    #: the motor torque's scale the verdict's model leaves, against its tolerance (:mod:`..scale`; None: not
    #: tested)
    scale: TorqueScale | None = None
    #: the breakaway-band test of the verdict's model at rest (:mod:`..stick`; None: not tested)
    rest: RestTorque | None = None
    #: the friction over the extra clearance of the verdict's model (:mod:`..play`; None: not tested)
    play: LostMotion | None = None
    #: the step of the apply-release travel difference below a force (:mod:`..hysteresis`; None: not made)
    hysteresis: Hysteresis | None = None

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
    def hysteresis_decided(self) -> bool:
        """The two-path test turned the verdict into ``unexplained`` (it decides only on another verdict)."""
        return decides(self.hysteresis)

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


def ranked_fits(sc: Scorer, catalog: dict[str, Effect], *, tested: bool = True,
                before: tuple[np.ndarray, float] | None = None) -> list[EffectFit]:
    """Every effect fitted (:func:`evaluate`), ranked by score, an effect with fewer parameters that the
    top one does not beat significantly first (parsimony); ``tested=False`` skips each effect's test
    against the twin within its tolerance (the order does not use it: :func:`..pipeline.analyse` needs
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

    selected, joint, candidates = forward_select(sc, fits, level, s_before, gap_before, w_share=share)
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
    unsettled = verdict != "unexplained"
    two_paths = hysteresis(sc.model, verdict_model.aug, sc.split.heldout_cycles) if unsettled else None
    if decides(two_paths):
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
                   drive_scale, rest, play, two_paths)


def motor_scale(sc: Scorer, m: Model, f: EffectFit | None = None) -> TorqueScale | None:
    """The motor torque's scale ``m`` leaves on the moving blocks' torque rows, against the budget's bound
    (:mod:`..scale`).  ``f``: the verdict's effects, when ``m`` is their fit; where one of them owns the
    scale's entry (it is then no tolerance, :func:`..tolerance.free`), c is refitted with their parameters
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
    where one of them owns the scale's budget entry (:data:`..tolerance.OWN`: an efficiency variation, a
    force-sensor bias), the entry was held at zero while all of them were fitted, so each took what it
    could of a scale (:mod:`..scale`, "Owner").  The torque rows only: the scale acts there, and the
    question is whether any values of the effects make the torque without it.  A parameter on a bound of
    its box (:meth:`..catalog.Effect.on_bound`) is held there, as the solver held it; None when none is
    free."""
    hi = f.effect.bounds()[1]
    scale = np.abs(np.asarray(f.effect.scale, dtype=float))
    moving = sc.model.blocks.moving
    cols = []
    for j in np.flatnonzero(~f.effect.on_bound(f.theta)):
        theta = f.theta.copy()
        step = difference_step(float(theta[j]), float(scale[j]), float(hi[j]))
        theta[j] += step
        aug = merge_augment(f.model.aug, f.effect.to_augment(theta), {})
        col = (sc.z(dataclasses.replace(f.model, aug=aug), moving, ("torque",)) - z0) / step
        if np.all(np.isfinite(col)):
            cols.append(col)
    return np.column_stack(cols) if cols else None


def screw_periodic(sc: Scorer, m: Model) -> Periodic | None:
    """Torque depending on the screw position in the held-out torque residual of ``m`` (:mod:`..openset`),
    beyond the catalog's own shapes: per direction of motion a constant, a term in the clamp force and
    one in the speed (004 eq. 9's Coulomb, load and viscous terms, free per direction).  Blocks whose
    friction eq. 9 leaves undetermined (stick and slip not told apart, :mod:`..residuals`) are left out:
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
    """Share of the explainable held-out error the effects close, (S_W - S_E) / (S_W - S_EP)
    (:mod:`..openset`).

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
    """The verdict once a torque depending on the screw position is accounted for (:mod:`..openset`).

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
