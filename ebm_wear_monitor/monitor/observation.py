"""Observe the axial clearance x_ag of one brake application from its own signals.

Ball-screw wear opens the axial internal clearance (000 Sec. 1, refs. 27-29);
with the brake's pad gap it is lost motion the screw must turn through, from
the release rest position, before the pads touch and force builds. So

    x_ag,obs = (theta_onset - theta_rest) * l / (2 pi)                      (1)

with ``l`` the lead. ``theta_rest`` is the median screw angle over the last
rest samples before the application. ``theta_onset`` is the angle at which the
force would be zero on the clamp's load line: force generation is a spring
(004 eq. 5-6, F = K_b (x - x_ag)), so over the first part of the rise
(force between the contact threshold and ``max(4 force_on, 0.3 F_peak)``) the
angle is regressed on the force, theta = theta_onset + c F, and the intercept
is taken. Regressing angle on force (not force on angle) keeps the intercept
unbiased by force noise to first order, and the fit uses the measured
compliance c, so the unit file's K_b is not needed.

Error budget (1 sigma, all independent), the measurement noise R of the filter:

* angle quantisation: each of theta_rest and theta_onset is off by up to half a
  count q = 2 pi / (counts * gear_ratio), uniform: variance (l q / 2 pi)^2 / 6
  for the difference (median and regression do not average quantisation away
  when the angle is constant, so no 1/n);
* force noise sigma_F mapped through the fitted axial compliance
  c l / (2 pi) [m/N], averaged over the n fitted samples: (sigma_F c l / 2 pi)^2 / n;
* repeatability of the true travel (temperature, pad seating):
  ``clearance_repeatability_m`` squared.

With the reference EMBU and a 4096-count motor encoder, q = 3.04e-4 rad, the
quantisation term is 0.098 um, the force term 0.5 um / sqrt(n) at 20 N, and the
1 um repeatability dominates: sigma ~ 1 um per application.
"""

from __future__ import annotations

import math

import numpy as np

from ebm_wear_monitor.monitor.config import MonitorConfig, Thresholds
from ebm_wear_monitor.monitor.segmentation import FG, Segment

_MIN_FIT_SAMPLES = 3


def onset_band(force_on: float, peak_force: float) -> tuple[float, float]:
    """Force band [N] of the onset fit: from the contact threshold to max(4 force_on, 0.3 peak)."""
    return force_on, max(4.0 * force_on, 0.3 * peak_force)


def observe_clearance(seg: Segment, th: Thresholds, config: MonitorConfig) -> tuple[float, float]:
    """(x_ag observed [m], its 1-sigma [m]) for a completed cycle; (NaN, NaN) when not observable.

    Not observable: not a ``cycle``, no known rest angle (after a gap or at start), fewer
    than 3 samples in the first force rise, a non-positive fitted compliance, or x <= 0.
    """
    nan = (math.nan, math.nan)
    if seg.kind != "cycle" or not math.isfinite(seg.rest_angle):
        return nan
    fg = np.flatnonzero(seg.label == FG)
    if fg.size == 0:
        return nan
    # first contiguous force-generation stretch (a re-application after a partial release is not the onset)
    breaks = np.flatnonzero(np.diff(fg) != 1)
    first = fg[: breaks[0] + 1] if breaks.size else fg
    lo, hi = onset_band(th.force_on, seg.peak_force)
    force, angle = seg.force[first], seg.angle[first]
    band = (force >= lo) & (force <= hi)
    n = int(band.sum())
    if n < _MIN_FIT_SAMPLES:
        return nan
    f, a = force[band], angle[band]
    f_mean, a_mean = float(np.mean(f)), float(np.mean(a))
    sxx = float(np.sum((f - f_mean) ** 2))
    if sxx <= 0.0:
        return nan
    compliance = float(np.sum((f - f_mean) * (a - a_mean))) / sxx  # c = d theta / d F [rad/N]
    if compliance <= 0.0:
        return nan
    theta_onset = a_mean - compliance * f_mean
    x_obs = (theta_onset - seg.rest_angle) * th.meters_per_rad
    if x_obs <= 0.0:
        return nan
    return x_obs, math.sqrt(observation_variance(th, config, compliance, n))


def observation_variance(th: Thresholds, config: MonitorConfig, compliance: float, n_fit: int) -> float:
    """Measurement noise R [m^2] of eq. (1): quantisation, force noise via the compliance, repeatability."""
    quant = (th.meters_per_rad * th.angle_resolution) ** 2 / 6.0
    force = (config.force_noise_n * compliance * th.meters_per_rad) ** 2 / max(n_fit, 1)
    return quant + force + config.clearance_repeatability_m ** 2
