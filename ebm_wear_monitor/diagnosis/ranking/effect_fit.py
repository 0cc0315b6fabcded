"""One effect fitted and judged on the held-out cycles (:class:`EffectFit`): its gap, score, test (a), size
against its floor (b), the sampling's share of the size, and its fits with or on top of another effect.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from ebm_wear_monitor.diagnosis import heldout, tolerance
from ebm_wear_monitor.diagnosis.catalog import Effect, combine
from ebm_wear_monitor.diagnosis.heldout import MATERIAL_Z, direction_p, improvement_p
from ebm_wear_monitor.diagnosis.ranking.scorer import NUISANCE_ONLY, Fit, Model, Scorer, fit, merge_augment
from ebm_wear_monitor.diagnosis.residuals import CHANNELS, NOMINAL, Augment
from ebm_wear_monitor.schema.diagnose import Drift, Parameter, RankingEntry, Size


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
    p_value: float = 1.0  # one-sided held-out test (a) (:func:`evaluate`, :func:`addition_p`)
    #: test (a) with the cluster-robust scale over the held-out cycles (:func:`evaluate`; reported, not
    #: judged; None: not computed, an effect added to others)
    p_cycles: float | None = None
    size: float = 0.0  # size in the effect's own unit (:mod:`..catalog`)
    size_std: float = 0.0
    floor: float = 0.0  # detectability floor of the size (:mod:`..tolerance`)
    share: dict[str, float] = field(default_factory=dict)  # unexplained share per channel with the effect
    contribution: float = 0.0  # RMS change of the channel's prediction, share of its RMS signal
    #: early/late refit of a friction effect (:func:`.criteria.drift_test`), when tested
    drift: Drift | None = None
    ties: list[str] = field(default_factory=list)
    #: worst-case change of the size by what the sampling does not resolve (:func:`sampling_bound`; of the
    #: effect fitted alone; None: not computed), in the size's unit
    sampling: float | None = None

    @property
    def drifting(self) -> bool:
        return self.drift is not None and self.drift.drifting

    def rests_on_independent_rows(self, level: float) -> bool:
        """Its test (a) passes at ``level`` only with independent held-out rows: over the brake applications'
        own scatter (``p_cycles``) it does not."""
        return self.p_cycles is not None and self.p_value < level <= self.p_cycles

    @property
    def augment(self) -> Augment:
        return self.model.aug

    @property
    def material(self) -> bool:
        """Its size exceeds its detectability floor with 95 % confidence (practical significance):
        size - 1.645 std > floor."""
        return self.size - MATERIAL_Z * self.size_std > self.floor

    def significant(self, level: float) -> bool:
        """Test (a) of the package docstring at ``level``: its held-out test (:func:`evaluate`: the direction
        test, or the improvement test for a sampling-cautioned size and an addition) is significant and its
        held-out score positive."""
        return self.p_value < level and self.score > 0.0

    @property
    def nameable(self) -> bool:
        """Material and off its physical limits (:meth:`..catalog.Effect.at_limit`): what an effect must be
        to be named."""
        return self.material and not self.at_limit

    @property
    def at_limit(self) -> bool:
        """The fit ended on a physical limit of the catalog (:meth:`..catalog.Effect.at_limit`)."""
        return self.effect.at_limit(self.theta)

    def entry(self) -> RankingEntry:
        """The fit as an entry of the diagnosis' ranking."""
        e = self.effect
        return RankingEntry(
            effect=e.name, score=self.score, gap_after=self.gap_after, shrink=self.shrink,
            p_value=self.p_value, p_value_cycles=self.p_cycles, k=e.k, material=self.material,
            at_limit=self.at_limit, drift=self.drift,
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
    do not resolve and of the friction where stick and slip cannot be told apart (:mod:`..residuals`),
    scaled by c_E, how far the residuals show it (:meth:`Scorer.unresolved`); these errors share a sign
    within a transient and can line up with an effect's shape (a current jump at every start reads like
    a drag at speed).  The fit, linearised at its solution, moves the size by -g' (J^+ dz) for a change dz
    of the normalised residual (J the fit's Jacobian over the parameters off their bounds, everything
    fitted with the effect; g = d size / d theta); over every |dz_b| <= c_E e_b / sigma_b the largest
    change is

        S = sum_b |g' J^+_b| c_E e_b / sigma_b,

    every row's error taking the sign that moves the size most (a worst case, as the tolerances' in
    :mod:`..play`).  It is reported, not judged by the verdict (README, "The sampling's share of a size").
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


def delta_method_std(effect: Effect, theta: np.ndarray, stderr: np.ndarray) -> float:
    """Standard deviation of the size by the delta method (independent parameters)."""
    return float(np.sqrt(np.sum((size_gradient(effect, theta) * stderr) ** 2)))


def nominal_sse(sc: Scorer) -> np.ndarray:
    """Held-out sum of z^2 per cycle of the twin within its tolerance (the baseline of
    :func:`evaluate`)."""
    return sc.cycle_sse(sc.base)


def evaluate(sc: Scorer, effect: Effect, s_before: np.ndarray, gap_before: float,
             fitted: Fit | None = None, *, tested: bool = True) -> EffectFit:
    """Fit ``effect`` (unless ``fitted`` is given) and compute its held-out gap, score, test and size
    against its floor.

    The test against the twin within its tolerance (a fit of W_E, :func:`base_without_own`) is the
    direction test :func:`..heldout.direction_p`, or the improvement test :func:`..heldout.improvement_p`
    for a material size the sampling could have made (:func:`sampling_caution`; package docstring, test
    (a)).  A fit without a sampling bound (a pair fitted jointly, the friction refit) and a size not
    material (which (b) does not name) take the direction test.  The same test with its statistic scaled
    by the larger of |delta| and the cluster-robust scale over the held-out cycles
    (:func:`..heldout._correction`) is ``p_cycles``: reported, not judged (package docstring, test (a)).
    ``tested=False`` skips both (``p_value`` stays 1, ``p_cycles`` None): an effect added in the forward
    selection is tested against the effects it extends instead (:func:`.selection._addition`), which
    sets ``p_value``, and the first noise pass (:func:`.verdict.ranked_fits`) needs only the order.
    """
    f = fit(sc, effect, sc.base) if fitted is None else fitted
    s_after = sc.cycle_sse(f.model)
    d = s_before - s_after
    score = float((d.sum() - 2.0 * effect.k) / s_before.sum())
    gap = sc.gap(f.model)
    shrink = float(1.0 - gap / gap_before) if gap_before > 0.0 else 0.0
    z_after = sc.z(f.model, sc.split.heldout)
    ef = EffectFit(effect, f.theta, f.stderr, f.model, gap, score, shrink, d, z_after)
    ef.size = float(effect.size(f.theta))
    ef.size_std = delta_method_std(effect, f.theta, f.stderr)
    ef.sampling = sampling_bound(effect, f)
    ef.floor = tolerance.floor(effect.name, sc.model.park_half_band)
    if tested:
        h = sc.split.heldout
        z_before = sc.z(base_without_own(sc, effect), h)
        ef.p_value = against_tolerance_p(ef, z_before)
        ef.p_cycles = against_tolerance_p(ef, z_before, sc.row_cycles(h))
    ef.share = sc.unexplained_share(f.model)
    ef.contribution = contribution(sc, effect, f.theta)
    return ef


def against_tolerance_p(ef: EffectFit, z_before: np.ndarray, clusters: np.ndarray | None = None) -> float:
    """Test (a) of ``ef`` against the twin within its tolerance W_E, whose held-out normalised residual is
    ``z_before`` (:func:`base_without_own`): the improvement test :func:`..heldout.improvement_p` for a
    material size the sampling could have made (:func:`sampling_caution`; its statistic
    U = V - |delta|^2 / (2 scale) asks more of the correction than that the held-out residual lies along
    it), the direction test :func:`..heldout.direction_p` otherwise; either scaled over the held-out
    cycle of each row, ``clusters`` (:meth:`.scorer.Scorer.row_cycles`; None: independent rows)."""
    return (improvement_p if sampling_caution(ef) else direction_p)(z_before, ef.z_heldout, clusters)


def extend(sc: Scorer, first: EffectFit, second: Effect, s_before: np.ndarray,
           gap_before: float) -> EffectFit:
    """The pair ``first`` + ``second`` as a nested extension: ``first``'s parameters stay as fitted, and
    so do its nuisances and tolerances outside ``second``'s channels; ``second`` is fitted on top of it
    with the nuisances and free tolerances of its own channels (:func:`.scorer._free_tolerances`:
    refitted from
    ``first``'s values, ``second``'s own budget entries held at zero). ``second``'s standard errors are
    conditional on ``first``'s parameters (their uncertainty is not propagated).

    The joint fit of a pair (:func:`evaluate` of :func:`..catalog.combine`) frees the tolerances of both
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
    """Test (a) of an addition (:func:`.selection._addition`): ``together`` must improve on held-out
    cycles both on
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
    aug = merge_augment(NOMINAL, effect.to_augment(theta), {})
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
    (:func:`..heldout.tie_p`)."""
    return heldout.tie_p(a.z_heldout, b.z_heldout)
