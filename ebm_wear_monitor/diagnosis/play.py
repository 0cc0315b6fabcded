"""Lost motion crossed without the screw's friction: a play, not a wider clearance (issue 10 item 4).

A clearance growth dx (004 eq. 5, x_ag -> x_ag + dx) and a play b between the motor and the screw
(backlash in the gear or the coupling) delay the contact alike when the angle is measured on the
motor side: the motor turns through dx / r_g more before the pads touch (eq. 3-4, r_g = l / (2 pi
i_g)). The force channel sees only that lost motion, so it cannot tell them apart. The torque channel
can, in one place. A clearance is crossed by the whole drive train: the screw and the nut move and
carry their friction (eq. 9). A play is crossed by the motor alone: the screw stays where it is
until a flank takes it along. In a release the motor keeps the screw on the loaded flank until the
pads let go; from there it turns back through the play with the screw standing still, and only then
drags the screw back to rest. Over that stretch the motor carries only the friction upstream of the
play (its bearings, the gear), not the screw's.

**Statistic.**  The model the verdict rests on puts the contact at the nut travel
x_c = x_ag + dx (:func:`.residuals.clamp_spring`), counted from each application's rest angle
(:mod:`.conventions`). If its extra clearance dx > 0 were a play, the release would cross it over
the travel window P = (x_c - dx, x_c] after the pads let go, and then move the screw with the
whole friction over the next window Q = (x_c - 2 dx, x_c - dx]. For every held-out application the
torque residual of that model (:meth:`.residuals.ResidualModel.span_torque_residual`: the block
formula of :mod:`.residuals` over each window's samples, moving backward, the tared force below the
segmentation's contact threshold) is taken over P and over Q; in the release direction the residual
is the twin's friction minus the recording's, so

    d_c = R_T(P) - R_T(Q)            [N m]

is the friction the recording lacks over P compared with Q. Both windows lie in the same free
travel at nearly the same speed, so the model's own friction errors (a Coulomb or viscous change, a
tolerance) cancel in the difference; a clearance gives d_c = 0, a play with a share f_s of the
friction downstream of it gives d_c = f_s (T_fc + B w_m) over the part of P it covers. The mean of
d_c over the applications is tested against zero with Student's t (one-sided, n - 1 degrees of
freedom): the windows come from the force channel's fit, the contrast from the torque channel at
positions no parameter of the model depends on, so the applications' scatter is its noise.

**Materiality.**  The deficit counts when, with 95 % confidence (mean - 1.645 std), it exceeds the
torque channel's floor (:func:`.tolerance.torque_floor`, 2 % of the RMS motor torque, the bound of the
other open-set tests): the budget has no friction that changes with the nut's position, so nothing
a healthy unit may differ by makes a step at the contact point.

**Reach.**  Each window needs at least ``MIN_SAMPLES`` samples in an application: at 200-250 Hz a
play of 10-25 % of the clearance is crossed in one or two samples of a release, and the test is not
made (None). A play crossed while the motor accelerates from rest (at the start of an application)
is not used: there the inertia torque, 004 eq. 1, dwarfs the friction.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import stats

from ebm_wear_monitor.diagnosis import tolerance
from ebm_wear_monitor.diagnosis.heldout import MATERIAL_Z
from ebm_wear_monitor.diagnosis.residuals import Augment, ResidualModel, clamp_spring
from ebm_wear_monitor.domain.phases import Phase

#: fewest samples of a window in one application
MIN_SAMPLES = 3
#: fewest held-out applications with both windows sampled
MIN_CYCLES = 4


@dataclass(frozen=True)
class LostMotion:
    """Friction over the extra clearance of the verdict's model, compared with the travel after it."""

    cycles: int  # held-out applications with both windows sampled
    travel: float  # dx: the extra clearance of the model, the window's length in nut travel [m]
    deficit: float  # mean friction the recording lacks over P compared with Q [N m]
    deficit_std: float  # its standard error [N m]
    floor: float  # materiality bound of the torque channel [N m]
    p_value: float  # one-sided t test of the mean deficit against zero

    def counts(self, level: float) -> bool:
        """Significant at ``level`` and material with 95 % confidence (module docstring)."""
        return self.p_value < level and self.deficit - MATERIAL_Z * self.deficit_std > self.floor


def _window_spans(model: ResidualModel, window: np.ndarray, cycles: np.ndarray) -> dict[int, tuple[int, int]]:
    """First and last sample of ``window`` (a sample mask) in each of ``cycles`` that holds at least
    ``MIN_SAMPLES`` of it."""
    idx = np.flatnonzero(window & np.isin(model.seg.cycle, cycles))
    if idx.size == 0:
        return {}
    cycle = model.seg.cycle[idx]
    first = np.flatnonzero(np.r_[True, cycle[1:] != cycle[:-1]])
    last = np.r_[first[1:], idx.size] - 1
    return {int(cycle[a]): (int(idx[a]), int(idx[b])) for a, b in zip(first, last, strict=True)
            if b - a + 1 >= MIN_SAMPLES}


def lost_motion(model: ResidualModel, aug: Augment, heldout: np.ndarray) -> LostMotion | None:
    """The test of the module docstring for the model ``aug`` on the held-out blocks ``heldout`` (a block
    mask). None when the model has no extra clearance or fewer than ``MIN_CYCLES`` applications have
    both windows sampled."""
    dx = aug.clearance
    if dx <= 0.0:
        return None
    x_c = float(clamp_spring(model.nominal, aug).clearance)
    free = ((model.seg.phase == Phase.FORCE_RELEASE) & (model.sign < 0.0)
            & (model.force < model.seg.force_rise))
    cycles = np.unique(model.blocks.cycle[heldout])
    p = _window_spans(model, free & (model.x > x_c - dx) & (model.x <= x_c), cycles)
    q = _window_spans(model, free & (model.x > x_c - 2.0 * dx) & (model.x <= x_c - dx), cycles)
    both = sorted(set(p) & set(q))
    if len(both) < MIN_CYCLES:
        return None
    start = np.array([[p[c][0], q[c][0]] for c in both])
    stop = np.array([[p[c][1], q[c][1]] for c in both])
    r = model.span_torque_residual(aug, start.ravel(), stop.ravel()).reshape(-1, 2)
    d = r[:, 0] - r[:, 1]
    n = d.size
    mean, se = float(d.mean()), float(d.std(ddof=1) / np.sqrt(n))
    p_value = float(stats.t.sf(mean / se, n - 1)) if se > 0.0 else float(mean <= 0.0)
    floor = tolerance.torque_floor(model.drive_block()[model.blocks.moving])
    return LostMotion(n, dx, mean, se, floor, p_value)
