"""Observe the axial clearance x_ag of one brake application from its own signals.

Ball-screw wear opens the axial internal clearance (000 Sec. 1, refs. 27-29);
with the brake's pad gap it is lost motion the screw must turn through, from
the release rest position, before the pads touch and force builds. So

    x_ag,obs = (theta_onset - theta_rest) * l / (2 pi)                      (1)

with ``l`` the lead. ``theta_rest`` is the rest angle before the application
(domain/segmentation/causal.py). ``theta_onset`` is the angle at which the force (above its
rest level) would be zero on the clamp's load line: the clamp is a spring
(004 eq. 5-6, F = K_b (x - x_ag)), so in the force band from the contact
threshold to ``max(4 force_on, 0.5 F_peak)`` the angle is linear in the force,
theta = theta_onset + c F, and the intercept is taken. Regressing angle on
force (not force on angle) keeps the intercept unbiased by force noise to first
order, and the fit uses the measured compliance c, so the unit file's K_b is
not needed.

Force-sensor lag (a convention of the recording, estimated from the data)
-------------------------------------------------------------------------
A load cell and its conditioning lag the true force: to first order
F_meas(t) = F(t - tau) = F(t) - tau dF/dt. With the spring law, dF/dt =
(d theta/dt) / c, so

    theta = theta_onset + c F_meas + tau theta_dot                           (2)

On the apply stroke theta_dot > 0 and fitting (1) alone puts the onset late by
tau theta_dot: a clearance too large by the nut travel during the lag (4 um per
ms at 5 rad/s of a 5 mm lead screw). The release stroke crosses the same band
with theta_dot < 0, so fitting (2) on the apply *and* release samples of the
band identifies tau (theta_dot from the angle's own increments, never from the
velocity topic, whose estimator has a lag of its own). tau is a property of the
sensor, so each application's estimate (with its least-squares variance) is
pooled over the applications by inverse-variance weighting (:func:`pool_lag`,
persisted in the state), and the observation uses the pooled tau in (2) on the
apply band: theta - tau theta_dot = theta_onset + c F_meas. A recording without
lag gives tau ~ 0 and the fit of issue 5. On independently simulated units
(validation/foreign, load-cell lags 0.3-2.0 ms) this removed a clearance bias of
+1.2 to +8.4 um (0.1 um left), the estimated lag within 0.05 ms of the truth.

Error budget (1 sigma, independent terms), the measurement noise R of the filter:

* rest angle: quantisation of the encoder, q = 2 pi / (counts * gear_ratio),
  uniform: variance q^2 / 12 (a median of a constant quantised angle does not
  average it away);
* onset angle: the textbook variance of a regression intercept,
  s^2 (1 / n + mean(F)^2 / S_FF), with s^2 the scatter of the angle about the
  line: the residual variance when n > 2, but never less than the sensors
  explain, q^2 / 12 + (sigma_F c)^2 (force noise through the fitted compliance);
  plus the uncertainty of the pooled lag, mean(theta_dot)^2 var(tau);
* repeatability of the true travel (temperature, pad seating):
  ``clearance_repeatability_m`` squared;

the angle terms times (l / 2 pi)^2. With the reference EMBU (K_b = 4.16e7
N/m), a 4096-count motor encoder and 50 N force noise, one force sample maps to
1.2 um; the band's extrapolation to F = 0 multiplies that by ~sqrt(5 / n):
0.4 um at 1 kHz (n ~ 50), 1.6 um at 100 Hz (n ~ 3); with the 1 um repeatability
sigma is 1.1 um and 1.9 um.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ebm_wear_monitor.monitor.config import MonitorConfig, Thresholds
from ebm_wear_monitor.monitor.segmentation import FG, FR, Segment

_MIN_FIT_SAMPLES = 2
_MIN_LAG_SAMPLES = 3  # per stroke, to estimate the lag from an application
#: a single application's lag estimate further than this many sigma from the pool is not pooled
_LAG_OUTLIER_SIGMA = 5.0
_LAG_POOL_SETTLED = 5.0  # ... once the pool holds this much weight in applications' worth


def onset_band(force_on: float, peak_force: float) -> tuple[float, float]:
    """Force band [N] of the onset fit: from the contact threshold to max(4 force_on, 0.5 peak)."""
    return force_on, max(4.0 * force_on, 0.5 * peak_force)


@dataclass(frozen=True)
class Observation:
    """One application's clearance observation and its force-lag estimate. SI units."""

    clearance_m: float  # NaN when not observable [m]
    std_m: float  # 1-sigma error budget [m]
    lag_s: float  # this application's estimate of the force-sensor lag tau [s]; NaN when not identifiable
    lag_var_s2: float  # its variance [s^2]


_NONE = Observation(math.nan, math.nan, math.nan, math.nan)


def _stroke(seg: Segment, label: int, first: bool) -> np.ndarray:
    """Indices of the first (apply) or last (release) contiguous stretch of ``label``."""
    idx = np.flatnonzero(seg.label == label)
    if idx.size == 0:
        return idx
    breaks = np.flatnonzero(np.diff(idx) != 1)
    if not breaks.size:
        return idx
    return idx[: breaks[0] + 1] if first else idx[breaks[-1] + 1:]


def _fit(angle: np.ndarray, columns: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray, float]:
    """Least squares angle = X beta, X = [1, columns...]: (beta, (X'X)^-1, residual variance or 0)."""
    X = np.column_stack([np.ones(angle.size), *columns])
    xtx_inv = np.linalg.pinv(X.T @ X)
    beta = xtx_inv @ (X.T @ angle)
    dof = angle.size - X.shape[1]
    return beta, xtx_inv, float(np.sum((angle - X @ beta) ** 2)) / dof if dof > 0 else 0.0


@dataclass(frozen=True)
class Bands:
    """The samples of one application's fits: indices of the apply and release strokes inside the onset
    band, and the angle's rate d theta / dt = d theta_i / dt_i of every sample [rad/s] (NaN where dt = 0)."""

    apply: np.ndarray
    release: np.ndarray
    rate: np.ndarray


def onset_bands(seg: Segment, th: Thresholds) -> Bands | None:
    """The fit samples of a completed cycle (independent of the force lag, so found once per application).

    None when not observable: not a ``cycle``, no known rest angle (after a gap or at start), fewer
    than 2 samples in the first force rise, or a force constant over them.
    """
    if seg.kind != "cycle" or not math.isfinite(seg.rest_angle):
        return None
    lo, hi = onset_band(th.force_on, seg.peak_force)
    with np.errstate(divide="ignore", invalid="ignore"):
        rate = np.where(seg.dt > 0.0, seg.dangle / seg.dt, np.nan)

    def band(stroke: np.ndarray) -> np.ndarray:
        f = seg.force[stroke]
        kept: np.ndarray = stroke[(f >= lo) & (f <= hi) & np.isfinite(rate[stroke])]
        return kept

    apply_, release = band(_stroke(seg, FG, first=True)), band(_stroke(seg, FR, first=False))
    if apply_.size < _MIN_FIT_SAMPLES:
        return None
    f = seg.force[apply_]
    if float(np.sum((f - float(np.mean(f))) ** 2)) <= 0.0:
        return None
    return Bands(apply_, release, rate)


def observe_clearance(seg: Segment, bands: Bands | None, th: Thresholds, config: MonitorConfig, *,
                      lag: tuple[float, float] = (0.0, 0.0), estimate_lag: bool = True) -> Observation:
    """The clearance of a completed cycle from its fit samples (:func:`onset_bands`), with the pooled force
    lag ``lag`` = (tau [s], its variance [s^2]) applied, and, if ``estimate_lag``, this application's own
    lag estimate for the pool (module docstring; else its lag is NaN).

    Not observable: no fit samples, a non-positive fitted compliance, or x <= 0.
    """
    if bands is None:
        return _NONE
    apply_, release, rate = bands.apply, bands.release, bands.rate
    lag_s, lag_var_s2 = lag
    n = apply_.size
    f, a, w = seg.force[apply_], seg.angle[apply_], rate[apply_]
    q_var = th.angle_resolution ** 2 / 12.0
    beta, xtx_inv, scatter = _fit(a - lag_s * w, [f])
    theta_onset, compliance = float(beta[0]), float(beta[1])
    if compliance <= 0.0:
        return _NONE
    x_obs = (theta_onset - seg.rest_angle) * th.meters_per_rad
    if x_obs <= 0.0:
        return _NONE
    sensors = q_var + (config.force_noise_n * compliance) ** 2
    var_onset = max(scatter, sensors) * float(xtx_inv[0, 0]) + float(np.mean(w)) ** 2 * lag_var_s2
    variance = (var_onset + q_var) * th.meters_per_rad ** 2 + config.clearance_repeatability_m ** 2
    own, own_var = math.nan, math.nan
    if estimate_lag and n >= _MIN_LAG_SAMPLES and release.size >= _MIN_LAG_SAMPLES:
        both = np.concatenate([apply_, release])
        beta3, xtx3, scatter3 = _fit(seg.angle[both], [seg.force[both], rate[both]])
        own_var = max(scatter3, sensors) * float(xtx3[2, 2])
        if float(beta3[1]) > 0.0 and own_var > 0.0:
            own = float(beta3[2])
    return Observation(x_obs, math.sqrt(variance), own, own_var)


def pool_lag(weight_sum: float, weighted_sum: float, lag_s: float, lag_var_s2: float) -> tuple[float, float]:
    """Add one application's lag estimate to the inverse-variance pool (weight_sum = sum 1/var [1/s^2],
    weighted_sum = sum tau/var [1/s]); an estimate more than 5 sigma from a settled pool is left out."""
    if not (math.isfinite(lag_s) and math.isfinite(lag_var_s2) and lag_var_s2 > 0.0):
        return weight_sum, weighted_sum
    if weight_sum > 0.0:
        mean, var = weighted_sum / weight_sum, 1.0 / weight_sum
        settled = weight_sum * lag_var_s2 >= _LAG_POOL_SETTLED  # holds >= 5 applications' worth
        if settled and abs(lag_s - mean) > _LAG_OUTLIER_SIGMA * math.sqrt(lag_var_s2 + var):
            return weight_sum, weighted_sum
    return weight_sum + 1.0 / lag_var_s2, weighted_sum + lag_s / lag_var_s2
