"""Lost motion taken up in contact: apply and release on two paths of force against travel (issue 10 item 4).

004 eq. 5 gives the clamp force as one function of the nut travel, F = K_b (x - x_ag), the same on the way in
and on the way out: a brake application and its release pass through the same (x, F) points.  What a
recording shows besides is the force reading's timing: read s_F late through a first-order lag tau_F (the
``force_skew`` and ``force_lag`` every model fits, :mod:`.residuals`), the apply reaches a force level a
little further in and the release a little further out, and after the pads let go the lag's tail holds
the low levels longer still.  So the test compares the recording with the model, not with zero: at a
force level F, per application,

    h(F) = [x_apply(F) - x_release(F)]_recorded - [x_apply(F) - x_release(F)]_model     [m]

the second term from the force reading the model (the verdict's, with its fitted skew and lag) predicts on
the same samples of the same nut travel (004 eq. 4).  What a lag of another form leaves is first order in
the speed, h = c + tau (|v_apply(F)| + |v_release(F)|) with tau the residual lag and c a constant of the
application (both 0 when the model's timing and contact point are the recording's; see "Limits").

**A play with the angle on the motor side.**  In an apply the motor pushes the screw on one flank of the
play; in the release the clamp force back-drives the screw, which keeps pressing on the same flank while the
load torque l F / (2 pi i_g) exceeds the friction downstream of the play (004 eq. 1, 9).  Below that force
the screw stops under its own friction, the motor turns back through the play alone, and the release
continues on the other flank: below a force F_s the release reaches each force the play's width (in nut
travel) closer to rest than the apply did, above F_s not.  h(F) steps up by that width below F_s, which no
timing and no effect of the catalog makes (every one of them keeps one force-travel path: a stiffness, a
clearance, a sensor gain or tare move both ways alike).  Where the friction downstream is small, F_s is near
zero and the play is crossed after the pads let go, which this test cannot see (the lost-motion test of
:mod:`.play` asks the torque channel there); with the angle on the screw side the play is not in the angle
at all (:mod:`.stick`).  Not in any of the catalog's effects either, but not a play: a hysteresis of the
pads (viscoelastic) or of the load cell that grows with the force also puts the release on a second path,
and can make a positive step; the summary names the play as what makes such a step, not as proven.

**Statistic.**  At ``N_LEVELS`` force levels, geometric from the segmentation's contact threshold (or five
force noises, the larger) to ``TOP_SHARE`` of the median peak force, every application gives h where both
its apply (the last upward crossing before its peak) and its release (the first downward crossing after it)
reach the level, the travel interpolated linearly between the two samples around the crossing, both of them
in contact (above ``IN_CONTACT`` of the threshold: a chord across the contact kink is flatter than the
spring; in the test's first version, compared with zero, it alone made steps of about 5 um at 200 Hz),
for the recording and for the model's reading alike, and the speed taken from the angle's own
derivative (:mod:`.conventions`).  On the calibration applications h is regressed, within each application
(its c removed), on the summed speed and on the indicator of the levels below a split, for every split with
at least ``MIN_SIDE`` levels each side (the step alone where the speed does not vary within the
applications); the split whose step has the largest t statistic is kept with its tau.  On each held-out
application the step is then

    D = mean_{F_k < split} (h - tau S) - mean_{F_k >= split} (h - tau S)       [m],   S = |v_a| + |v_r|

and its mean over the held-out applications is tested against zero with Student's t (one-sided: a play
makes D > 0).  The split and tau come from the calibration applications only, so the held-out D are
independent of that choice; tau's own error, common to them, is left out of the standard error (about a
sixth of it in a review's simulation), so the p-value is somewhat liberal and the floor decides.

**Materiality.**  The step must exceed, with 95 % confidence, the thermal part of the clearance's tolerance
(:data:`.tolerance.THERMAL_CLEARANCE`, 5 um): the budget has no entry for a second path, since no
tolerance of it makes one, and a lost motion the clearance's own tolerance would hide is not worth a
verdict.  Decided, ``effect`` or ``none`` becomes ``unexplained``.

**Level.**  It runs at ``ALPHA`` beside the screw-position harmonic, the motor torque's scale, the band
test at rest and the lost-motion test (:mod:`.ranking`); the materiality condition decides in practice
(on the third world's 62 plays the step was significant at p <= 3e-7).

**Limits** (a second review, on closed-form recordings with a load cell's 5 ms first-order lag and brisk
applies of 0.08-0.15 s).  The model's predicted reading carries the model's contact point; under a lag,
where that is off by dx from the recording's, the lag's tail after the pads let go turns the offset into a
slope across the levels that the split reads as a step of about 0.25-0.3 dx (0.1 dx at slower applies,
nothing without a lag).  So a play the ranking reads as a clearance growth, whose model puts the contact
where the apply touches, reads low: 10 um gave 4.2-4.9 um (not counted, the verdict stayed the clearance
growth), 20 um 8.7-9.7 um; and a model clearance 40 um off the recording's gave a false step of 9-11 um.
With a 2 ms lag or applies of 0.15-0.35 s a 20 um play read 14-16 um.  Where a model misses a force-channel
effect its fitted timing goes to its bounds (lag 5 ms, skew -4 ms) and the step follows: with the twin
within its tolerance as the model, foreign clearance ramps, a force sensor's thermal drift and third-world
clearance growths read 4.2-5.0 um (none counted), with their own verdict models 0.1-0.5 um.  Undoing the
fitted skew and lag on the recorded force (inverse backward Euler) and comparing with zero, which takes
the model's contact point out, was tried on eight recordings and not kept: those three read 6.1-8.1 um
(the distorted timing undone) and two third-world plays 8.7 and 9.1 um against 10.9 and 12.5 (the noise
amplified by tau / dt).  The lowest levels are mostly dropped at 200-250 Hz (both samples in contact),
where a play taken up at a small force would show.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from ebm_wear_monitor.diagnosis.heldout import exceeds, mean_above_zero
from ebm_wear_monitor.diagnosis.noise import signal_noise
from ebm_wear_monitor.diagnosis.residuals import Augment, ResidualModel
from ebm_wear_monitor.diagnosis.tolerance import THERMAL_CLEARANCE

#: force levels at which apply and release are compared [-]
N_LEVELS = 12
#: fewest levels on each side of the split [-]
MIN_SIDE = 2
#: fewest applications of each half with a level on both sides of the split [-]
MIN_APPLICATIONS = 4
#: highest level as a share of the median peak force [-]
TOP_SHARE = 0.8
#: share of the contact threshold both samples around a crossing must exceed (in contact) [-]
IN_CONTACT = 0.5


@dataclass(frozen=True)
class Hysteresis:
    """The step of the apply-release travel difference below a force (module docstring)."""

    applications: int  # held-out applications with levels on both sides of the split
    split: float  # force below which the step is measured [N]
    step: float  # mean D over the held-out applications [m]
    step_std: float  # its standard error [m]
    lag: float  # tau of the calibration fit [s]
    floor: float  # materiality bound [m]
    p_value: float  # one-sided t test of the mean step against zero

    def counts(self, level: float) -> bool:
        """Significant at ``level`` and material with 95 % confidence (module docstring)."""
        material = exceeds(self.step, self.step_std, self.floor, dof=self.applications - 1)
        return self.p_value < level and material


def _crossing(x: np.ndarray, f: np.ndarray, v: np.ndarray, level: float, *, rising: bool,
              contact: float) -> tuple[float, float]:
    """(travel [m], |speed| [m/s]) where the force ``f`` [N] crosses ``level`` [N]: the last upward crossing
    (``rising``) or the first downward one, interpolated linearly between its two samples; NaNs where there
    is none or where one of the two samples lies below ``contact`` [N] (the chord across the contact kink
    is flatter than the spring)."""
    lo, hi = (f[:-1] < level) & (f[1:] >= level), (f[:-1] >= level) & (f[1:] < level)
    at = np.flatnonzero(lo if rising else hi)
    if at.size == 0:
        return np.nan, np.nan
    i = at[-1] if rising else at[0]
    if min(f[i], f[i + 1]) < contact:
        return np.nan, np.nan
    w = (level - f[i]) / (f[i + 1] - f[i])
    return x[i] + w * (x[i + 1] - x[i]), abs(v[i] + w * (v[i + 1] - v[i]))


def _travel_difference(x: np.ndarray, f: np.ndarray, v: np.ndarray, level: float,
                       contact: float) -> tuple[float, float]:
    """(x_apply - x_release [m], |v_apply| + |v_release| [m/s]) of one application at ``level`` [N]."""
    peak = int(np.argmax(f))
    xa, va = _crossing(x[:peak + 1], f[:peak + 1], v[:peak + 1], level, rising=True, contact=contact)
    xr, vr = _crossing(x[peak:], f[peak:], v[peak:], level, rising=False, contact=contact)
    return xa - xr, va + vr


def level_differences(model: ResidualModel, aug: Augment, levels: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(cycles, h, S): per application and force level the recording's apply-minus-release travel minus
    the one the model ``aug`` predicts on the same samples, h [m], and the recording's summed speed S [m/s]
    (module docstring; NaN where a level is not crossed both ways in contact)."""
    cycle = model.seg.cycle
    v = model.nominal.nut_travel(model.conv.speed)
    predicted = model.force_model(aug)
    contact = IN_CONTACT * float(model.seg.force_rise)
    cycles = np.unique(cycle[cycle >= 0])
    h = np.full((cycles.size, levels.size), np.nan)
    s = np.full_like(h, np.nan)
    for n, c in enumerate(cycles):
        idx = np.flatnonzero(cycle == c)
        x, vc = model.x[idx], v[idx]
        for k, level in enumerate(levels):
            h_rec, s[n, k] = _travel_difference(x, model.force[idx], vc, level, contact)
            h[n, k] = h_rec - _travel_difference(x, predicted[idx], vc, level, contact)[0]
    return cycles, h, s


def _levels(model: ResidualModel) -> np.ndarray | None:
    """The geometric force levels of the module docstring [N], None when the forces span too little."""
    cycle = model.seg.cycle
    peaks = [model.force[cycle == c].max() for c in np.unique(cycle[cycle >= 0])]
    lo = max(float(model.seg.force_rise), 5.0 * signal_noise(model.force))
    hi = TOP_SHARE * float(np.median(peaks)) if peaks else 0.0
    return np.geomspace(lo, hi, N_LEVELS) if hi > 2.0 * lo > 0.0 else None


def _step(h: np.ndarray, s: np.ndarray, m: int, lag: float) -> np.ndarray:
    """D per application for the split after level ``m`` and the lag ``lag`` (NaN without both sides)."""
    r = h - lag * s
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # an application without one side: NaN
        step: np.ndarray = np.nanmean(r[:, :m], axis=1) - np.nanmean(r[:, m:], axis=1)
    return step


def _calibrate(h: np.ndarray, s: np.ndarray) -> tuple[int, float] | None:
    """The split (levels below it) and lag whose within-application fit gives the step the largest t."""
    ok = np.isfinite(h) & np.isfinite(s)
    best: tuple[float, int, float] | None = None
    for m in range(MIN_SIDE, h.shape[1] - MIN_SIDE + 1):
        low = np.broadcast_to(np.arange(h.shape[1]) < m, h.shape)
        cols = [np.where(ok, a, 0.0) for a in (h, s, low.astype(float))]
        count = ok.sum(axis=1, keepdims=True)
        keep = (count[:, 0] >= 2) & (ok & low).any(axis=1) & (ok & ~low).any(axis=1)
        if keep.sum() < MIN_APPLICATIONS:
            continue
        y, sx, ix = ((a - a.sum(axis=1, keepdims=True) / np.maximum(count, 1))[keep][ok[keep]] for a in cols)
        X = np.column_stack([sx, ix])
        coef, _, rank, _ = np.linalg.lstsq(X, y, rcond=None)
        if rank < 2:  # the speed does not vary within the applications: the lag cancels in D
            X = ix[:, None]
            coef, _, rank, _ = np.linalg.lstsq(X, y, rcond=None)
        dof = y.size - X.shape[1] - int(keep.sum())
        if rank < X.shape[1] or dof < 1:
            continue
        sigma2 = float(np.sum((y - X @ coef) ** 2)) / dof
        se = float(np.sqrt(sigma2 * np.linalg.inv(X.T @ X)[-1, -1]))
        t = coef[-1] / se if se > 0.0 else math.copysign(math.inf, coef[-1])
        if best is None or t > best[0]:
            best = (float(t), m, float(coef[0]) if X.shape[1] == 2 else 0.0)
    return None if best is None else (best[1], best[2])


def hysteresis(model: ResidualModel, aug: Augment, heldout_cycles: np.ndarray) -> Hysteresis | None:
    """The test of the module docstring against the model ``aug`` (its force timing: skew, lag) on the
    applications ``heldout_cycles``; None when the forces span too little or too few applications have
    levels on both sides of the split."""
    levels = _levels(model)
    if levels is None:
        return None
    cycles, h, s = level_differences(model, aug, levels)
    held = np.isin(cycles, heldout_cycles)
    fit = _calibrate(h[~held], s[~held])
    if fit is None:
        return None
    m, lag = fit
    d = _step(h[held], s[held], m, lag)
    d = d[np.isfinite(d)]
    n = d.size
    if n < MIN_APPLICATIONS:
        return None
    mean, se, p_value = mean_above_zero(d)
    return Hysteresis(n, float(np.sqrt(levels[m - 1] * levels[m])), mean, se, lag, THERMAL_CLEARANCE, p_value)
