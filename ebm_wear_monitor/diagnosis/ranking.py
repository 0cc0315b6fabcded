"""Which effect: fit on calibration cycles, judge on held-out cycles, rank, decide, flag near-ties.

**Split by cycle, stratified by force.**  Brake cycles (see :mod:`.phases`) are
ordered by their peak clamp force (then time) and alternate: first, third, ...
calibrate, second, fourth, ... are held out.  Both sides thus cover the whole
range of demands even when the demands repeat with an even period (a plain
even/odd split would then hold out only some force levels); a held-out cycle
never contributes to any fit.  At least four cycles are needed (two held out).

**Acquisition nuisances.**  The sample timing of the current tau (within one
sample) and the quadrature rule of the load tau_M (from the left to the right
rectangle, within half a sample; :mod:`.residuals`) are fitted first on the
calibration cycles with the nominal twin (the "before" model,
:attr:`Scorer.base`) and refitted with every effect; being in both they are not
counted in the penalty.  So an effect is declared only when it explains the data
better than the nominal twin under its *best* admissible acquisition: structure
that a different sampling or integration rule of the same physics could
produce is never attributed to the unit (the false positives of a simulator
stepping at the recording rate came from exactly such structure).

**Normalised residuals.**  Each block gives a torque residual R_T and a force
residual R_F (:mod:`.residuals`), divided by their block noise: z = R / sigma.
sigma is propagated from the sensor noise measured on each signal
(:func:`block_noise`), scaled up if the residual scatters more than that in its
quietest phase (coloured noise), plus the unresolved-current term.

**Fit.**  An effect's parameters theta minimise sum z(theta)^2 over the
calibration blocks (bounded Gauss-Newton, ``scipy.optimize.least_squares``;
most effects are linear in theta so one step solves them).  Their uncertainty
is the cluster-robust (sandwich) covariance with brake cycles as clusters,
(J'J)^-1 (sum_c J_c' z_c z_c' J_c) (J'J)^-1, which stays honest when
residuals within a cycle are correlated.

**Held-out gap.**  ``metric`` = ``excess_rms_over_noise``: over the held-out
blocks, gap = sqrt(max(mean(z^2) - 1, 0)), the RMS model error in units of the
noise (noise alone gives mean(z^2) = 1 and gap 0).  Torque rows of blocks at
rest are left out of the gap (not of the fit): inside the stick band their
dead-zone residual is exactly zero and would pull mean(z^2) below the noise.  ``gap_before`` is the
nominal twin's, ``gap_after`` the twin's with the fitted effect.

**Score** (ranking) = (S_before - S_after - 2k) / S_before, with S the held-out
sum of z^2 and k the effect's number of parameters: the share of the held-out
squared residual the effect removes, less an Akaike penalty of 2 per parameter.

**Verdict.**  Two tests, both needed for ``effect``.  (a) Misfit: where the
top effect acts, the nominal twin's held-out residual exceeds the noise: a
goodness-of-fit test of the held-out gap rows weighted by the square of the
effect's correction (weighted chi-square, Satterthwaite degrees of freedom,
level 0.05; :meth:`Scorer.misfit_p`).  A model error no larger than the noise
is no reason to change the twin, however consistent.  (b) Per held-out cycle c,
the held-out improvement is significant.  The correction an effect makes,
delta = z_before - z_after on the held-out rows, is fixed by the calibration
cycles; with held-out noise z ~ N(0, 1) independent of it, S_before - S_after
= 2 sum(z delta) - sum(delta^2) ~ N(-sum(delta^2), 4 sum(delta^2)) when the
effect is absent.  The statistic U = (S_before - S_after) / (2 |delta|) is thus
at most standard normal under "absent", and the top effect is declared when its
one-sided p-value is below 0.05 / K (Bonferroni over the K effects tried).
Otherwise the verdict is ``none``: the twin already explains the data within its
noise.  (Per-cycle tests were tried first: with 6-10 held-out cycles whose
forces differ, a load effect improving a 26 kN cycle 20-fold more than an
8 kN one left them without power.)  Test (a) guards (b) against residual
structure that is real but not worth a model change (e.g. a simulator's
integration error), since (b) relies on the measured noise level.  No
threshold on the gap size is involved.

**Parsimony.**  When an effect with fewer parameters is tied with the
best-scoring one (below), it is ranked first: e.g. ``efficiency_variation``
nests ``load_friction`` and must beat it significantly to be named.

**Near-ties.**  An effect whose held-out residual does not differ from the top
effect's at p < 0.05 (:func:`tie_p`, the statistic of (b) between two fitted
effects, two-sided) is reported as tied, with the operating
range (speed, force) where the two fitted models differ most in noise units
(:func:`separating_experiment`): the experiment that would separate them.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np
from scipy import optimize, stats

from ebm_wear_monitor.diagnosis.catalog import Effect
from ebm_wear_monitor.diagnosis.noise import series_noise, signal_noise
from ebm_wear_monitor.diagnosis.residuals import (
    NOMINAL,
    Augment,
    Nominal,
    ResidualModel,
    force_from_travel,
    kinetic_friction,
)
from ebm_wear_monitor.errors import InputError

ALPHA = 0.05  # family-wise error rate of the verdict
TIE_ALPHA = 0.05  # level of the paired test that separates the top effect from the next
METRIC = "excess_rms_over_noise"


@dataclass(frozen=True)
class Split:
    """Calibration / held-out assignment of blocks by brake cycle (even / odd)."""

    calibration: np.ndarray  # bool per block
    heldout: np.ndarray  # bool per block
    heldout_cycles: np.ndarray  # cycle indices held out


def split_by_cycle(cycle: np.ndarray, peak_force: np.ndarray | None = None) -> Split:
    """Stratified alternate split (module docstring): cycles ordered by peak force, every second held out.

    ``cycle`` labels blocks; ``peak_force`` [N] (same length) gives each block's force, of which each
    cycle's maximum orders the cycles (time order when absent or tied).
    """
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
class Scorer:
    """Noise-normalised residuals of one recording and the held-out bookkeeping."""

    model: ResidualModel
    split: Split
    sigma_torque: np.ndarray  # block noise of R_T per block [N m]
    sigma_force: np.ndarray  # block noise of R_F per block [N]
    base: Augment = NOMINAL  # the nominal twin with the fitted current timing (the "before" model)

    @classmethod
    def build(cls, model: ResidualModel, reference: Augment = NOMINAL) -> Scorer:
        """Measure the block noise (module docstring, :func:`block_noise`).

        The block noise is propagated from the sensor noise (:func:`block_noise`) and scaled up
        when the residual of ``reference`` (the nominal twin, or in a second pass the best-ranked
        effect, whose residual carries less model error) scatters more than that in its quietest
        phase (:func:`_quietest_phase_noise`; coloured sensor noise).  The torque noise adds,
        in quadrature, the uncertainty of the current integral
        where the sampling does not resolve the electrical transient
        (:meth:`.residuals.ResidualModel._unresolved_torque`).
        """
        b = model.blocks
        r = model.residuals(reference)
        s_t, s_f = block_noise(model)
        # resolution floors keep noise-free data finite
        s_t = np.maximum(s_t, 1e-6 * model.nominal.T_fc + 1e-12)
        s_f = np.maximum(s_f, 1e-3)
        # the sensor estimates assume white noise; coloured noise shows as a larger residual scatter
        c_t = max(_quietest_phase_noise(r["torque"] / s_t, model, b.moving), 1.0)
        c_f = max(_quietest_phase_noise(r["force"] / s_f, model, np.ones(b.size, bool)), 1.0)
        sigma_t = np.hypot(c_t * s_t, model.unresolved_torque)
        sc = cls(model, split_by_cycle(b.cycle, b.force), sigma_t, c_f * s_f)
        return dataclasses.replace(sc, base=fit_timing(sc))

    def z(self, aug: Augment, mask: np.ndarray) -> np.ndarray:
        """Normalised residuals of the masked blocks, torque rows then force rows."""
        r = self.model.residuals(aug)
        return np.concatenate((r["torque"][mask] / self.sigma_torque[mask],
                               r["force"][mask] / self.sigma_force[mask]))

    def row_cycles(self, mask: np.ndarray) -> np.ndarray:
        c = self.model.blocks.cycle[mask]
        return np.concatenate((c, c))

    def cycle_sse(self, aug: Augment) -> np.ndarray:
        """Sum of z^2 per held-out cycle."""
        m = self.split.heldout
        z2 = self.z(aug, m) ** 2
        where = np.searchsorted(self.split.heldout_cycles, self.row_cycles(m))  # held-out cycles are sorted
        return np.bincount(where, weights=z2, minlength=self.split.heldout_cycles.size)

    def gap_rows(self, aug: Augment) -> np.ndarray:
        """Held-out z of the rows the gap metric uses (torque rows of blocks at rest left out)."""
        m = self.split.heldout
        rows = np.concatenate((self.model.blocks.moving[m], np.ones(m.sum(), bool)))
        return self.z(aug, m)[rows]

    def gap(self, aug: Augment) -> float:
        """Held-out gap, metric ``excess_rms_over_noise``."""
        ms = float(np.mean(self.gap_rows(aug) ** 2))
        return float(np.sqrt(max(ms - 1.0, 0.0)))

    def misfit_p(self, aug: Augment) -> float:
        """p-value of "the nominal twin fits the held-out data within the noise where ``aug`` acts".

        (The nominal twin with its fitted current timing, :attr:`base`.)

        Weighted mean square Q = sum(w z^2) / sum(w) with w = delta^2, delta the change of z
        that ``aug`` makes on each held-out gap row.  Under noise alone (z ~ N(0, 1) independent of
        the weights, which come from the calibration cycles) Q nu ~ chi^2(nu) with Satterthwaite's
        nu = (sum w)^2 / sum w^2.
        """
        z = self.gap_rows(self.base)
        w = (z - self.gap_rows(aug)) ** 2
        if not np.any(w > 0.0):
            return 1.0
        nu = w.sum() ** 2 / np.sum(w * w)
        q = float(np.sum(w * z * z) / w.sum())
        return float(stats.chi2.sf(q * nu, nu))


def block_noise(model: ResidualModel) -> tuple[np.ndarray, np.ndarray]:
    """Noise of each block's R_T [N m] and R_F [N], propagated from the measured sensor noise.

    A block of n samples over dt_b seconds: R_T carries the end-point speed noise
    J_me i_g sigma_v sqrt(2) / dt_b and the averaged current and force noise
    (K_T sigma_I)^2 / n + ((l / (2 pi i_g) + G) sigma_F)^2 / n; R_F carries
    (sigma_F^2 + [in contact] (K_b l sigma_theta / (2 pi))^2) / n, with the
    sensor noise sigma of each signal from :func:`.noise.signal_noise`.
    """
    rec, n, b = model.rec, model.nominal, model.blocks
    sv, si, sf, sa = (signal_noise(x) for x in (rec.velocity, rec.current, rec.axial_force, rec.angle))
    ns = (b.stop - b.start + 1).astype(float)
    dt = rec.t[b.stop] - rec.t[b.start]
    var_t = 2.0 * (n.J_me * n.i_g * sv / dt) ** 2 + (
        (n.K_T * si) ** 2 + ((n.load_ratio + n.G) * sf) ** 2) / ns
    contact = b.force > model.seg.force_on
    var_f = (sf**2 + contact * (n.K_b * n.lead * sa / (2.0 * np.pi)) ** 2) / ns
    return np.sqrt(var_t), np.sqrt(var_f)


def _quietest_phase_noise(r: np.ndarray, model: ResidualModel, rows: np.ndarray) -> float:
    """Residual-based noise scale: the smallest :func:`.noise.series_noise` of r over the phases.

    Each phase with enough blocks gives an estimate; model error that the lag-2
    curvature does not cancel (transients, a misfit that varies within a run) can
    only inflate it, so the quietest phase is the closest to the noise.
    """
    b = model.blocks
    est = [series_noise(r[k], b.run[k]) for ph in np.unique(b.phase)
           if (k := rows & (b.phase == ph)).sum() >= 12]
    est = [e for e in est if e > 0.0]
    return min(est) if est else 0.0


@dataclass
class EffectFit:
    """One effect fitted on calibration cycles and judged on held-out ones."""

    effect: Effect
    theta: np.ndarray
    stderr: np.ndarray
    augment: Augment
    gap_after: float
    score: float
    d_cycles: np.ndarray  # held-out S_before,c - S_after,c per cycle
    z_heldout: np.ndarray  # held-out normalised residual with the effect
    p_value: float = 1.0  # one-sided test of a held-out improvement (:func:`improvement_p`)
    ties: list[str] = field(default_factory=list)

    def as_dict(self) -> dict:
        return {
            "effect": self.effect.name, "score": self.score, "gap_after": self.gap_after,
            "p_value": self.p_value, "k": self.effect.k,
            "parameters": {p: {"value": float(v), "stderr": float(s), "unit": u}
                           for p, v, s, u in zip(self.effect.params, self.theta, self.stderr,
                                                 self.effect.units, strict=True)},
        }


def with_timing(effect: Effect, dt: float, start: tuple[float, float] = (0.0, 0.0)) -> Effect:
    """``effect`` plus the two acquisition nuisances tau in [-dt, dt] and tau_M in [-dt/2, dt/2].

    tau: sample timing of the current; tau_M: quadrature rule of the load torque between samples,
    from the left rectangle (-dt/2, a drive or simulator holding the force over the period) over
    the trapezoid (0, a sampled continuous plant) to the right rectangle (+dt/2); see
    :mod:`.residuals`, "Quadrature rule of the load".  Refitted with every effect.
    """
    k = effect.k

    def to_augment(p: np.ndarray) -> Augment:
        return dataclasses.replace(effect.to_augment(p[:k]), current_shift=float(p[k]),
                                   load_shift=float(p[k + 1]))

    lower = (effect.lower or (-np.inf,) * k) + (-dt, -0.5 * dt)
    upper = (effect.upper or (np.inf,) * k) + (dt, 0.5 * dt)
    return Effect(effect.name, effect.meaning, (*effect.params, "tau", "tau_M"), (*effect.units, "s", "s"),
                  to_augment, (*effect.scale, 0.5 * dt, 0.5 * dt),
                  tuple((*s0, *start) for s0 in effect.starts), lower, upper)


TIMING = Effect("acquisition_timing", "sample timing of the current, quadrature rule of the load (nuisance)",
                (), (), lambda p: NOMINAL, (), ((),))


def fit_timing(sc: Scorer) -> Augment:
    """The nominal twin with the nuisances (tau, tau_M) that fit the calibration cycles best."""
    dt = sc.model.rec.dt
    eff = with_timing(TIMING, dt)
    h = 0.5 * dt
    eff = dataclasses.replace(eff, starts=((-h, 0.0), (0.0, 0.0), (h, 0.0), (0.0, -0.5 * h), (h, -0.5 * h)))
    theta, _ = fit_effect(sc, eff, timing=False)
    return eff.to_augment(theta)


def fit_effect(sc: Scorer, effect: Effect, timing: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Least-squares parameters and their cluster-robust standard errors on the calibration cycles.

    With ``timing`` the current timing is refitted with the effect's parameters (a nuisance
    parameter, starting from the nominal fit's value); the returned arrays then end with it.
    """
    if timing:
        effect = with_timing(effect, sc.model.rec.dt, (sc.base.current_shift, sc.base.load_shift))
    mask = sc.split.calibration
    scale = np.asarray(effect.scale, dtype=float)
    lo = -np.inf * np.ones(effect.k) if effect.lower is None else np.asarray(effect.lower, dtype=float)
    hi = np.inf * np.ones(effect.k) if effect.upper is None else np.asarray(effect.upper, dtype=float)

    def fun(u: np.ndarray) -> np.ndarray:  # u = theta / scale keeps the solver well conditioned
        return sc.z(effect.to_augment(u * scale), mask)

    best = None
    for start in effect.starts:
        u0 = np.clip(np.asarray(start, dtype=float) / scale, lo / scale, hi / scale)
        u0[np.abs(u0) < 1e-6] = 0.0  # round-off starts (e.g. -3e-13) stall the solver's first step
        res = optimize.least_squares(fun, u0, bounds=(lo / scale, hi / scale), method="trf",
                                     x_scale=1.0, diff_step=1e-3, max_nfev=60)
        if best is None or res.cost < best.cost:
            best = res
    J, z = best.jac, best.fun
    _, rows = np.unique(sc.row_cycles(mask), return_inverse=True)
    bread = np.linalg.pinv(J.T @ J)
    scores = np.zeros((rows.max() + 1, effect.k))  # per-cycle score vectors J_c' z_c
    np.add.at(scores, rows, J * z[:, None])
    cov = bread @ (scores.T @ scores) @ bread
    return best.x * scale, np.sqrt(np.clip(np.diag(cov), 0.0, None)) * scale


def evaluate(sc: Scorer, effect: Effect, s_before: np.ndarray) -> EffectFit:
    """Fit ``effect`` and compute its held-out gap, score, per-cycle improvements and test."""
    theta, se = fit_effect(sc, effect)
    aug = with_timing(effect, sc.model.rec.dt).to_augment(theta)
    s_after = sc.cycle_sse(aug)
    d = s_before - s_after
    score = float((d.sum() - 2.0 * effect.k) / s_before.sum())
    fit = EffectFit(effect, theta[:-2], se[:-2], aug, sc.gap(aug), score, d, sc.z(aug, sc.split.heldout))
    fit.p_value = improvement_p(sc.z(sc.base, sc.split.heldout), fit.z_heldout)
    return fit


def improvement_p(z_before: np.ndarray, z_after: np.ndarray) -> float:
    """One-sided p-value of "the correction lowers the held-out residual" (module docstring).

    With delta = z_before - z_after fixed by the calibration fit and held-out noise z ~ N(0, 1),
    S_before - S_after = 2 sum(z delta) - sum(delta^2) ~ N(-sum(delta^2), 4 sum(delta^2)) when
    the effect is absent; U = (S_before - S_after) / (2 sqrt(sum(delta^2))) is compared with N(0, 1).
    """
    delta = z_before - z_after
    norm = float(np.sqrt(np.sum(delta * delta)))
    if norm == 0.0:
        return 1.0
    u = float(np.sum(z_before**2 - z_after**2)) / (2.0 * norm)
    return float(stats.norm.sf(u))


def tie_p(a: EffectFit, b: EffectFit) -> float:
    """Two-sided p-value of "two fitted effects explain the held-out data equally well".

    Same construction as :func:`improvement_p` with ``a``'s residual in place of the nominal one.
    """
    delta = a.z_heldout - b.z_heldout
    norm = float(np.sqrt(np.sum(delta * delta)))
    if norm == 0.0:
        return 1.0
    u = float(np.sum(b.z_heldout**2 - a.z_heldout**2)) / (2.0 * norm)
    return float(2.0 * stats.norm.sf(abs(u)))


@dataclass
class Ranking:
    """The outcome of :func:`rank`."""

    fits: list[EffectFit]  # best first
    gap_before: float
    misfit_p: float  # chi-square p-value of the nominal twin on held-out data
    verdict: str  # "effect" | "none"
    alpha: float

    @property
    def top(self) -> EffectFit:
        return self.fits[0]


def nominal_sse(sc: Scorer) -> np.ndarray:
    """Held-out sum of z^2 per cycle of the nominal twin (the baseline of :func:`evaluate`)."""
    return sc.cycle_sse(sc.base)


def rank(sc: Scorer, catalog: dict[str, Effect]) -> Ranking:
    """Fit every effect, rank by score, decide the verdict, mark near-ties with the top effect."""
    s_before = nominal_sse(sc)
    fits = sorted((evaluate(sc, e, s_before) for e in catalog.values()), key=lambda f: -f.score)
    level = ALPHA / len(fits)

    def tied(i: int, j: int) -> bool:
        return fits[j].score > 0.0 and tie_p(fits[i], fits[j]) >= TIE_ALPHA

    # parsimony: an effect with fewer parameters that the top one does not beat significantly goes first
    simpler = [j for j in range(1, len(fits)) if fits[j].effect.k < fits[0].effect.k and tied(0, j)]
    if simpler:
        j = min(simpler, key=lambda j: (fits[j].effect.k, -fits[j].score))
        fits.insert(0, fits.pop(j))
    top = fits[0]
    top.ties = [f.effect.name for j, f in enumerate(fits) if j > 0 and tied(0, j)]
    misfit = sc.misfit_p(top.augment)
    found = misfit < ALPHA and top.p_value < level and top.score > 0.0
    return Ranking(fits, sc.gap(sc.base), misfit, "effect" if found else "none", level)


def separating_experiment(nom: Nominal, a: EffectFit, b: EffectFit, *, max_speed: float, max_force: float,
                          sigma_torque: float, sigma_force: float, n: int = 12) -> dict:
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
    x = nom.x_ag + 0.5 * (F[1:] + F[:-1]) / nom.K_b
    dF = np.abs(force_from_travel(nom, a.augment, x) - force_from_travel(nom, b.augment, x)) / sigma_force
    i, j = np.unravel_index(int(np.argmax(dT)), dT.shape)
    if dF.max() > dT[i, j]:
        k = int(np.argmax(dF))
        speed, force, sep = None, [float(F[k]), float(F[k + 1])], float(dF[k])
    else:
        speed = [float(w[i] / nom.i_g), float(w[i + 1] / nom.i_g)]
        force, sep = [float(F[j]), float(F[j + 1])], float(dT[i, j])
    inside = (speed is None or speed[0] * nom.i_g <= max_speed) and force[0] <= max_force
    where = (f"screw speed {speed[0]:.3g}-{speed[1]:.3g} rad/s at " if speed else "") + \
        f"clamp force {force[0]:.4g}-{force[1]:.4g} N"
    return {"between": [a.effect.name, b.effect.name], "screw_speed_rad_s": speed, "force_N": force,
            "separation_sigma": sep, "inside_recorded_range": bool(inside),
            "experiment": f"record at {where}" + ("" if inside else " (beyond the recorded range)")}
