"""The normalised residuals of one recording (:class:`Scorer`) and the least-squares fit of a model to
them (:func:`fit`): the package docstring's "Split by cycle", "Acquisition nuisances", "Normalised
residuals", "Fit" and "Held-out gap".
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np
from scipy import optimize

from ebm_wear_monitor.diagnosis import tolerance
from ebm_wear_monitor.diagnosis.catalog import Effect
from ebm_wear_monitor.diagnosis.heldout import cluster_covariance
from ebm_wear_monitor.diagnosis.ranking.blocknoise import (
    MIN_SCALE_ROWS,
    NoiseScale,
    contact_spread,
    noise_scale_estimate,
    quietest_phase_noise,
    sensor_noise,
)
from ebm_wear_monitor.diagnosis.residuals import (
    CHANNELS,
    NOMINAL,
    NUISANCE_UNITS,
    Augment,
    ResidualModel,
    moves,
)
from ebm_wear_monitor.domain.phases import Phase
from ebm_wear_monitor.errors import InputError

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
    """Stratified alternate split (package docstring): cycles ordered by peak force, every second held out."""
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


def merge_augment(base: Augment, effect_aug: Augment, nuisances: dict[str, float]) -> Augment:
    """``base`` with the model corrections of ``effect_aug`` and the given nuisance values."""
    corrections = {f: getattr(effect_aug, f) for f in Augment.__dataclass_fields__ if f not in NUISANCE_UNITS}
    return dataclasses.replace(base, **corrections, **nuisances)


@dataclass(frozen=True)
class Model:
    """A fitted model: the twin's corrections and nuisances, and the tolerance deviations t (|t| <= 1)."""

    aug: Augment = NOMINAL
    t: np.ndarray = field(default_factory=lambda: np.zeros(len(tolerance.BUDGET)))


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

        The scorer the diagnosis uses is made in two more steps (:func:`..pipeline.analyse`): the block
        noise is rescaled to the scatter of the residual of a reference (W; in a second pass the
        best-ranked effect, whose residual carries less model error: :meth:`noise_scale`), and W is
        refitted at that noise (:meth:`scaled`). The torque noise adds, in quadrature, the uncertainty
        of the current integral where the sampling does not resolve the electrical transient and of the
        friction where stick and slip cannot be told apart (:mod:`..residuals`).
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
        (c_F s_F)^2 + spread^2, s the noise propagated from the sensors (:func:`.blocknoise.block_noise`),
        e_T the
        torque of the transients the sampling does not resolve (:func:`sensor_noise`). Each scale is
        measured where its term dominates: c_T on the moving blocks with e_T <= s_T (all moving blocks when
        fewer than ``MIN_SCALE_ROWS``), c_E on those with e_T > s_T (given c_T), c_F on every force row;
        the lag-2 estimates below are taken on all moving blocks (torque) and all blocks (force). e_T
        holds the friction where stick and slip cannot be told apart too, and c_E scales it with the rest.
        Why the scales, and why they may fall below one:

        * s is propagated from the raw signals' noise (:func:`..noise.signal_noise`), which counts a
          signal's own dynamics faster than its sampling (a current sampled below its controller's
          bandwidth) as noise; e_T is a bound (the integral anywhere within +-|dI| dt / 2), not a
          standard deviation. Both can overstate the scatter several times, and a torque channel whose
          noise is overstated weighs nothing: on the foreign generator's healthy recordings, with the
          former scale-up only (c >= 1), the held-out mean z^2 of W's moving torque rows was 0.02-0.12.
        * Each scale is the smaller of two estimates that a model error can only inflate, each by a
          different kind: the lag-2 curvature of the quietest phase (:func:`quietest_phase_noise`;
          smooth model error cancels, sharp transients do not) and the median of z^2
          (:func:`..noise.median_scale`; model error in a minority of the blocks does not move it, model
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
        c_t = noise_scale_estimate(quietest_phase_noise(r_t / s_t, model, b.moving),
                           r_t[steady], s_t[steady], extra_t[steady])
        c_e = noise_scale_estimate(None, r_t[trans], extra_t[trans], c_t * s_t[trans])
        c_f = noise_scale_estimate(quietest_phase_noise(r_f / s_f, model, np.ones(b.size, bool)),
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
        """Indices into all rows (torque then force, every block) of the masked blocks of ``channels``, in
        the order of :meth:`z_raw`'s rows."""
        n = self.model.blocks.size
        return np.concatenate([np.flatnonzero(self.valid(mask, ch)) + CHANNELS.index(ch) * n
                               for ch in CHANNELS if ch in channels])

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
        unresolved-transient and stick-or-slip torque (:mod:`..residuals`) as the residuals show it (times
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
        """The brake cycle of each row of :meth:`z_raw` (torque rows then force rows, whatever the order of
        ``channels``)."""
        c = self.model.blocks.cycle
        return np.concatenate([c[self.valid(mask, ch)] for ch in CHANNELS if ch in channels])

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
    :func:`fit`, and the scale test's refit, :func:`.verdict.owner_columns`)."""
    h = 1e-3 * max(unit, abs(x))
    return -h if x + h > upper else h


def fit(sc: Scorer, effect: Effect, start: Model, extra_starts: tuple[dict[str, float], ...] = (), *,
        mask: np.ndarray | None = None, only_effect: bool = False, search: bool = False) -> Fit:
    """Fit ``effect`` with its channels' nuisances and the free tolerances on the calibration cycles.

    ``mask`` fits on other blocks; ``only_effect`` keeps the nuisances and tolerances of ``start``.
    A nuisance is fitted on every row it moves (:func:`..residuals.moves`): the force reading's skew and
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
        aug = merge_augment(start.aug, effect.to_augment(p[:k]), nuisances)
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
