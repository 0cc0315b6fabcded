"""The noise of the block residuals: propagated from the sensors, the torque of the transients the
sampling does not resolve, and the estimates from which :meth:`.scorer.Scorer.noise_scale` takes the
scales the residual itself shows.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ebm_wear_monitor.diagnosis.noise import median_scale, series_noise, signal_noise
from ebm_wear_monitor.diagnosis.residuals import ResidualModel

#: the noise scale-up may fall below one (the propagated sensor noise overstates the block noise when the
#: raw signal's second differences carry its own dynamics, a current sampled below its controller's
#: bandwidth), not below this: a residual below a tenth of it is the resolution of a noise-free signal
NOISE_SCALE_MIN = 0.1
#: fewest rows a median scale is measured on (:meth:`.scorer.Scorer.noise_scale`)
MIN_SCALE_ROWS = 10
#: fewest lag-2 differences a phase's residual-based noise is taken from (:func:`quietest_phase_noise`)
QUIET_DIFFS = 12


class NoiseScale(NamedTuple):
    """What the residual says of the noise propagated from the sensors
    (:meth:`.scorer.Scorer.noise_scale`)."""

    torque: float  # c_T [-]: scale of the propagated torque noise
    transient: float  # c_E [-]: scale of the unresolved-transient term
    force: float  # c_F [-]: scale of the propagated force noise
    spread: float  # pad-contact spread [N] (:func:`contact_spread`)


def sensor_noise(model: ResidualModel) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(s_T [N m], s_F [N], extra_T [N m]) per block: :func:`block_noise` above its resolution floors (for
    noise-free data), and the torque uncertainty where the sampling does not resolve a transient or stick
    and slip cannot be told apart (:mod:`..residuals`), added to s_T in quadrature."""
    s_t, s_f = block_noise(model)
    s_t = np.maximum(s_t, 1e-6 * model.nominal.friction.coulomb + 1e-12)
    s_f = np.maximum(s_f, 1e-3)
    return s_t, s_f, np.hypot(model.unresolved_torque, model.ambiguous_torque)


def block_noise(model: ResidualModel) -> tuple[np.ndarray, np.ndarray]:
    """Noise of each block's R_T [N m] and R_F [N], propagated from the measured sensor noise.

    A block of n samples over dt_b seconds: R_T carries the end-point speed noise
    J_me sqrt(sigma_w(t0)^2 + sigma_w(t1)^2) / dt_b (sigma_w of the speed regression,
    :mod:`..speed`) and the averaged current and force noise
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


def noise_scale_estimate(lag2: float | None, r: np.ndarray, s: np.ndarray,
                   extra: np.ndarray | None = None) -> float:
    """One scale of :meth:`.scorer.Scorer.noise_scale`: the smaller of the lag-2 estimate ``lag2`` (None or 0:
    none) and the median scale of the rows ``r`` against their noise ``s`` beside ``extra``
    (:func:`..noise.median_scale`; none under ``MIN_SCALE_ROWS`` rows); 1 without either estimate,
    never below ``NOISE_SCALE_MIN``."""
    estimates = [lag2] if lag2 else []
    if r.size >= MIN_SCALE_ROWS:
        estimates.append(median_scale(r, s, extra))
    return max(min(estimates), NOISE_SCALE_MIN) if estimates else 1.0


def quietest_phase_noise(r: np.ndarray, model: ResidualModel, rows: np.ndarray) -> float:
    """Residual-based noise scale: the smallest :func:`..noise.series_noise` of r over the phases.

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
