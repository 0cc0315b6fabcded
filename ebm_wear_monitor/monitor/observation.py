"""Observe the axial clearance x_ag of one brake application from its own signals.

Ball-screw wear opens the axial internal clearance (000 Sec. 1, refs. 27-29);
with the brake's pad gap it is lost motion the screw must turn through, from
the release rest position, before the pads touch and force builds. So

    x_ag,obs = (theta_onset - theta_rest) * l / (2 pi)                      (1)

with ``l`` the lead. ``theta_rest`` is the median screw angle over the last
rest samples before the application. ``theta_onset`` is the angle at which the
force (above its rest level) would be zero on the clamp's load line: force
generation is a spring (004 eq. 5-6, F = K_b (x - x_ag)), so over the first
part of the rise (force between the contact threshold and
``max(4 force_on, 0.5 F_peak)``) the angle is regressed on the force,
theta = theta_onset + c F, and the intercept is taken. Regressing angle on
force (not force on angle) keeps the intercept unbiased by force noise to first
order, and the fit uses the measured compliance c, so the unit file's K_b is
not needed. Two samples in the band suffice (100 Hz recordings).

Error budget (1 sigma, independent terms), the measurement noise R of the filter:

* rest angle: quantisation of the encoder, q = 2 pi / (counts * gear_ratio),
  uniform: variance q^2 / 12 (a median of a constant quantised angle does not
  average it away);
* onset angle: the textbook variance of a regression intercept,
  s^2 (1 / n + mean(F)^2 / S_FF), with s^2 the scatter of the angle about the
  line: the residual variance when n > 2, but never less than the sensors
  explain, q^2 / 12 + (sigma_F c)^2 (force noise through the fitted compliance);
* repeatability of the true travel (temperature, pad seating):
  ``clearance_repeatability_m`` squared;

the two angle terms times (l / 2 pi)^2. With the reference EMBU (K_b = 4.16e7
N/m), a 4096-count motor encoder and 50 N force noise, one force sample maps to
1.2 um; the band's extrapolation to F = 0 multiplies that by ~sqrt(5 / n):
0.4 um at 1 kHz (n ~ 50), 1.6 um at 100 Hz (n ~ 3); with the 1 um repeatability
sigma is 1.1 um and 1.9 um.
"""

from __future__ import annotations

import math

import numpy as np

from ebm_wear_monitor.monitor.config import MonitorConfig, Thresholds
from ebm_wear_monitor.monitor.segmentation import FG, Segment

_MIN_FIT_SAMPLES = 2


def onset_band(force_on: float, peak_force: float) -> tuple[float, float]:
    """Force band [N] of the onset fit: from the contact threshold to max(4 force_on, 0.5 peak)."""
    return force_on, max(4.0 * force_on, 0.5 * peak_force)


def observe_clearance(seg: Segment, th: Thresholds, config: MonitorConfig) -> tuple[float, float]:
    """(x_ag observed [m], its 1-sigma [m]) for a completed cycle; (NaN, NaN) when not observable.

    Not observable: not a ``cycle``, no known rest angle (after a gap or at start), fewer
    than 2 samples in the first force rise, a non-positive fitted compliance, or x <= 0.
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
    residual = a - (theta_onset + compliance * f)
    scatter = float(np.sum(residual ** 2)) / (n - 2) if n > 2 else 0.0
    sensors = th.angle_resolution ** 2 / 12.0 + (config.force_noise_n * compliance) ** 2
    var_onset = max(scatter, sensors) * (1.0 / n + f_mean ** 2 / sxx)
    var_rest = th.angle_resolution ** 2 / 12.0
    variance = (var_onset + var_rest) * th.meters_per_rad ** 2 + config.clearance_repeatability_m ** 2
    return x_obs, math.sqrt(variance)
