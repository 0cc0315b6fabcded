"""Acquisition conventions of a recording, estimated from the data: never mistaken for an effect.

A real unit's recording differs from the twin in conventions that are no physical
effect (issue 10): where the encoder's zero is, where the ECU parks the nut between
applications, the force reading with the pads open, how the drive estimates the
speed.  Each is estimated here from the recording itself, with its uncertainty,
and reported under ``nuisances`` (interface.md section 4); the residual model
(:mod:`.residuals`) works with the corrected quantities, so none of them can leak
into an effect.  The timing conventions (force-sensor lag, per-topic stamp skew,
current sampling, current-sensor offset) are fitted with every model instead,
see :mod:`.residuals` and :mod:`.ranking`.

**Speed from the angle.**  The screw speed enters the torque balance of 004 eq. 1
through J_me dw_m/dt, a torque that reaches ~8 N m while the motor accelerates,
25 times the Coulomb friction.  A recorded velocity that lags by 1 ms (a drive's
filtered derivative, a moving average, an observer) turns that into a
friction-sized residual.  The diagnosis therefore differentiates the *angle*
itself, with its true stamps: a local quadratic regression over a window of about
``window_s`` (at least 2 samples each side), theta(t) ~ a + b (t - t_i) + c (t - t_i)^2,
whose slope b at t_i is the speed.  Samples enter a window only from the same
phase run (:mod:`.phases`), so no window straddles a kink of the motion (pad
contact, a stop); at the ends of a run the window is one-sided and the quadratic
term keeps the slope unbiased to first order.  Its noise follows from the
regression, var(b) = sigma_theta^2 [(X'X)^-1]_bb per sample.  sigma_theta is the white angle noise
while moving, 1.4826 MAD of the angle's second differences / sqrt(6) (:mod:`.noise`), and never less
than the encoder's own quantisation noise q / sqrt(12), q its count (:func:`.noise.quantum`, the rule
:func:`.noise.signal_noise` applies to every raw signal): a noise-free encoder that advances a few counts
a sample repeats its increments, about half of its second differences are zero (to rounding), and
when more than half are the MAD is zero while the quantisation noise is not (a 12-bit encoder on the
motor at 2 kHz read 1.7e-14 rad against q / sqrt(12) = 8.8e-5 rad, every speed noiseless, and the
healthy unit ``unexplained``: README, "The encoder's count in the angle noise").  Where the MAD does
not collapse it reads such an encoder at about 2.1 q / sqrt(12) (second differences of 0 and +-q), which
of the two a recording gets being close to chance; the MAD is kept there (on the safe side; a trimmed
RMS as in :func:`.noise.signal_noise` would be consistent, but would move every recording).  The recorded
velocity is not used by the model; its lag d and gain g against the angle speed,
v_rec(t) = g w(t - d), are estimated (least squares over moving samples) and
reported.

**Released rest angle of each application.**  004 eq. 4-5 count the nut travel x
from the released (rest) position.  The ECU does not park the nut at the same
angle every time (position-loop error, overshoot and slow creep back), and the
encoder's zero is arbitrary.  The travel of application c is counted from
theta_rest,c, the median angle over the last ``rest_window_s`` before its first active
sample (the still ones among them; after any creep: where that application actually started).

**Where the ECU parks.**  The unit file's clearance x_ag is counted from where the ECU means to
park the nut; where it does park varies from application to application, over a band whose
position against that target no recording shows (a loop that stops inside its tolerance, on
one side of its target only).  For parks spread evenly over a band of width w, their mean lies
w / 2 from either end of it: when the target is an end, the mean park is w / 2 off it.  That
half-band, ``park_half_band_rad``, is estimated by the interquartile range of the released
applications' rest angles (1.35 sigma for a normal spread; one odd application, a release caught
before it settled, moves it little), over the whole recording: scatter and slow wander alike (the
third world's 62 healthy recordings of seeds 3-7: 0.7-6.5 um; the target may lie anywhere in what
they cover).  It is an estimate, not a bound, and a low one for few applications: for n parks spread
evenly, numpy's interpolated quartiles give (n - 1) / (n + 1) of w / 2 on average (0.83 at n = 11,
0.93 at n = 29, Monte Carlo), its own scatter is 18-25 % of w / 2, and the mean park lies beyond it
in 61-70 % of draws (beyond hypot(5 um, it), the clearance entry, in 1-10 % of draws for a 10 um
band, 24-41 % for 16 um, 50-62 % for 30 um).  Its reported standard deviation is the bootstrap's
over the applications.  The tolerance budget (:mod:`.tolerance`) adds it to the clearance's thermal
entry.  With fewer than four released applications there is nothing to measure it by: the nuisance
is not reported and the clearance entry is the thermal part alone.  A park that is off its target
by the same amount every time has no spread and cannot be told from a clearance.

**Force tare of each application.**  With the pads open the true clamp force is
zero (004 eq. 5, x < x_ag), so the median force reading over the last idle stretch before
application c is that application's tare b_c; the first ``settle_s`` of the
stretch are left out (sensor lag after the release).  A constant offset of the
force reading is thus a tare, not the ``force_sensor_bias`` effect, which is left
with what a tare cannot remove: the gain of the reading.  A release that stops with the
pads still touching leaves a clamp force over the next idle stretch; a tare does not jump
between applications, so each application's tare is the median of the idle readings of
the applications around it (``TARE_SPAN`` each side), and an application whose own idle
reading exceeds that by more than ``max(5 sigma, 20 % of the contact threshold)`` started
*not released*: the nut travel of 004 eq. 4 has no released origin there, and the force
channel leaves that application out (:attr:`Conventions.released`), as it does an application
that starts with the recording (no rest seen before it).

An application with no idle stretch before it (the first one at the start of the
recording) takes the stretch after its release.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ebm_wear_monitor.diagnosis.noise import MAD_TO_SIGMA, mad_sigma, quantum, signal_noise
from ebm_wear_monitor.diagnosis.phases import Segmentation
from ebm_wear_monitor.diagnosis.recording import Resampled
from ebm_wear_monitor.diagnosis.speed import WINDOW_S, angle_speed
from ebm_wear_monitor.domain.phases import Phase
from ebm_wear_monitor.domain.segmentation import run_ids
from ebm_wear_monitor.domain.signals import SIGNALS
from ebm_wear_monitor.schema.diagnose import Estimate

REST_WINDOW_S = 0.02  # idle time before an application over which its rest angle is taken [s]
SETTLE_S = 0.01  # idle time after a release left out of the tare [s]
TARE_SPAN = 3  # applications each side over which the tare is taken [-]
VELOCITY_LAG_RANGE_S = 0.02  # the recorded velocity's lag is searched within +-this [s]
MIN_PARKS = 4  # released applications needed to estimate the park half-band [-]
PARK_BOOTSTRAP = 200  # bootstrap resamples of the park half-band's standard deviation [-]


def _before_each(seg: Segmentation) -> list[tuple[int, int, int]]:
    """Per application c: (first, a, b) with ``first`` its first active sample and [a, b) the last idle
    stretch before it (after the previous application started), else the first one after it."""
    idle = seg.phase == Phase.IDLE
    edges = np.flatnonzero(np.diff(np.concatenate(([0], idle.astype(np.int8), [0]))))
    stretches = list(zip(edges[0::2], edges[1::2], strict=True))  # [a, b) of every idle stretch
    out, previous = [], 0
    for c in range(seg.n_cycles):
        active = np.flatnonzero((seg.cycle == c) & ~idle)
        first = int(active[0]) if active.size else 0
        before = [s for s in stretches if previous <= s[0] and s[1] <= first and s[1] > s[0]]
        after = [s for s in stretches if s[0] > first]
        a, b = before[-1] if before else after[0] if after else (first, first)
        out.append((first, int(a), int(b)))
        previous = first
    return out


@dataclass(frozen=True)
class Conventions:
    """What the recording's conventions are (module docstring), per sample where the model needs it."""

    speed: np.ndarray  # screw speed from the angle, per phase run [rad/s]
    speed_factor: np.ndarray  # var(speed) = speed_factor * sigma_angle^2 [1/s^2]
    sigma_angle: float  # white angle noise while moving [rad]
    rest_angle: np.ndarray  # released rest angle of each application [rad]
    rest_angle_std: np.ndarray  # its standard deviation [rad]
    tare: np.ndarray  # force reading at rest before each application [N]
    tare_std: np.ndarray  # its standard deviation [N]
    released: np.ndarray  # bool per application: the pads were open before it (module docstring)
    park_half_band: float  # half-band of the released rests, 0 unless estimated (module docstring) [rad]
    angle_count: float  # the encoder's count, the smallest step of the angle (module docstring) [rad]
    estimates: dict[str, Estimate]  # the reported nuisances

    def per_sample(self, seg: Segmentation) -> tuple[np.ndarray, np.ndarray]:
        """(rest angle [rad], tare [N]) of the application each sample belongs to."""
        return self.rest_angle[seg.cycle], self.tare[seg.cycle]


def _median_std(x: np.ndarray) -> tuple[float, float]:
    """Median of a sample and the standard deviation of that median (1.25 sigma / sqrt(n))."""
    if x.size == 0:
        return float("nan"), float("nan")
    sigma = MAD_TO_SIGMA * float(np.median(np.abs(x - np.median(x))))
    return float(np.median(x)), 1.2533 * sigma / np.sqrt(x.size)


def _iqr(x: np.ndarray) -> np.ndarray:
    """Interquartile range along the last axis (numpy's interpolated quartiles)."""
    q75, q25 = np.percentile(x, [75.0, 25.0], axis=-1)
    return np.asarray(q75 - q25)


def park_half_band(rest: np.ndarray, released: np.ndarray) -> Estimate | None:
    """Half the band the ECU parks in [rad]: the interquartile range of the released applications' rest
    angles ``rest`` [rad] (module docstring), with the standard deviation of that range by the bootstrap
    over applications (``PARK_BOOTSTRAP`` resamples with replacement, a fixed seed so that a diagnosis
    repeats); ``None`` with fewer than ``MIN_PARKS`` of them (nothing to measure it by)."""
    r = rest[released]
    if r.size < MIN_PARKS:
        return None
    resampled = np.random.default_rng(0).choice(r, size=(PARK_BOOTSTRAP, r.size))
    return Estimate(float(_iqr(r)), float(np.std(_iqr(resampled), ddof=1)), "rad")


def _fill(values: np.ndarray) -> np.ndarray:
    """Replace NaN entries by the nearest finite one (all NaN: zeros)."""
    ok = np.isfinite(values)
    if not ok.any():
        return np.zeros_like(values)
    idx = np.flatnonzero(ok)
    nearest = idx[np.clip(np.searchsorted(idx, np.arange(values.size)), 0, idx.size - 1)]
    return np.where(ok, values, values[nearest])


def _velocity_convention(rec: Resampled, speed: np.ndarray, moving: np.ndarray) -> dict[str, Estimate]:
    """Lag d [s] and gain g [-] of the recorded velocity against the angle speed, v_rec(t) = g w(t - d)."""
    t = rec.t
    if moving.sum() < 20:
        return {}
    tm, vm = t[moving], rec.velocity[moving]
    lags = np.arange(-VELOCITY_LAG_RANGE_S, VELOCITY_LAG_RANGE_S + 1e-12, 0.25 * rec.dt)

    def fit(d: float) -> tuple[float, float]:
        w = np.interp(tm - d, t, speed)
        ww = float(np.dot(w, w))
        g = float(np.dot(w, vm)) / ww if ww > 0.0 else 0.0
        return g, float(np.sum((vm - g * w) ** 2))

    sse = np.array([fit(d)[1] for d in lags])
    k = int(np.argmin(sse))
    d = float(lags[k])
    if 0 < k < lags.size - 1:  # parabolic refinement
        den = sse[k - 1] - 2.0 * sse[k] + sse[k + 1]
        if den > 0.0:
            d += 0.5 * (sse[k - 1] - sse[k + 1]) / den * (lags[1] - lags[0])
    g, s = fit(d)
    w = np.interp(tm - d, t, speed)
    dw = np.gradient(w, tm)
    var_r = s / max(vm.size - 2, 1)
    return {"velocity_lag_s": Estimate(d, float(np.sqrt(var_r / max(g * g * np.dot(dw, dw), 1e-300))), "s"),
            "velocity_gain": Estimate(g, float(np.sqrt(var_r / max(np.dot(w, w), 1e-300))), "-")}


def estimate_conventions(rec: Resampled, seg: Segmentation, window_s: float = WINDOW_S) -> Conventions:
    """Estimate every convention of the module docstring from ``rec`` and its phases ``seg``."""
    speed, factor = angle_speed(rec, run_ids(seg.phase, seg.cycle), window_s)
    sigma_w = signal_noise(speed)
    moving = np.abs(speed) > 5.0 * max(sigma_w, 1e-12)
    d2 = np.diff(rec.angle, 2)[moving[1:-1]]
    count = quantum(rec.angle)  # the encoder's count (smallest step of the angle) [rad]
    # white noise of the angle while moving, never below its count's (module docstring)
    sigma_angle = max(mad_sigma(d2) / np.sqrt(6.0), count / np.sqrt(12.0))
    rest_n = max(5, round(REST_WINDOW_S / rec.dt))
    settle = max(3, round(SETTLE_S / rec.dt))
    rest, rest_sd, tare, tare_sd = (np.full(seg.n_cycles, np.nan) for _ in range(4))
    still = np.abs(speed) <= 5.0 * max(sigma_w, 1e-12)
    seen_rest = np.zeros(seg.n_cycles, bool)
    for c, (first, a, b) in enumerate(_before_each(seg)):
        window = np.arange(max(first - rest_n, 0), first)
        seen_rest[c] = window.size == rest_n and np.mean(seg.phase[window] == Phase.IDLE) >= 0.5
        window = window[still[window]] if still[window].any() else window
        if window.size:
            rest[c], rest_sd[c] = _median_std(rec.angle[window])
        if b > a:
            tare[c], tare_sd[c] = _median_std(rec.axial_force[a + settle:b] if b - a > 2 * settle
                                              else rec.axial_force[a:b])
    rest, idle_force = _fill(rest), _fill(tare)
    tare = np.array([np.median(idle_force[max(c - TARE_SPAN, 0):c + TARE_SPAN + 1])
                     for c in range(idle_force.size)])
    excess = np.maximum(5.0 * _fill(tare_sd), 0.2 * seg.force_rise)
    released = (idle_force - tare <= excess) & seen_rest
    # a constant quantised angle is not averaged by the median: keep the noise of one sample / sqrt(12)
    rest_sd = np.hypot(_fill(rest_sd), sigma_angle / np.sqrt(12.0))
    tare_sd = _fill(tare_sd)
    n = max(seg.n_cycles, 1)
    spread = lambda x: float(np.std(x, ddof=1)) if x.size > 1 else 0.0  # noqa: E731
    est = {
        "rest_angle_rad": Estimate(float(np.mean(rest)), spread(rest) / np.sqrt(n), "rad"),
        "rest_angle_spread_rad": Estimate(spread(rest), 0.0, "rad"),
        "force_tare_N": Estimate(float(np.mean(tare)), spread(tare) / np.sqrt(n), "N"),
        "force_tare_spread_N": Estimate(spread(tare), 0.0, "N"),
        "applications_not_released": Estimate(float(np.sum(~released)), 0.0, "-"),
        "angle_noise_rad": Estimate(sigma_angle, 0.0, "rad"),
        "angle_count_rad": Estimate(count, 0.0, "rad"),
    }
    band = park_half_band(rest, released)
    if band is not None:
        est["park_half_band_rad"] = band
    est |= _velocity_convention(rec, speed, moving)
    for name in SIGNALS:
        est[f"{name}_rate_Hz"] = Estimate(1.0 / rec.interval(name), 0.0, "Hz")
    return Conventions(speed, factor, sigma_angle, rest, rest_sd, tare, tare_sd, released,
                       0.0 if band is None else band.value, count, est)
