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
whole friction over the window Q that directly follows, (x_c - dx - L, x_c - dx] with
L = min(dx, (x_c - dx) / 2) (no longer than P, and in the upper half of the remaining travel, away
from the stop at rest). Samples count when they move backward in the release with the tared force
below the segmentation's contact threshold; each contiguous run of P followed directly by a run of Q
is one crossing, and a crossing counts when both runs hold at least ``MIN_SAMPLES`` samples, one
sampling interval, the least the block formula can integrate over (a release that crosses twice, or a
stop inside a window, splits the runs instead of merging them). For
every crossing of a held-out application the torque residual of that model is taken over P and
over Q (:meth:`.residuals.ResidualModel.span_torque_residual`: the block formula of
:mod:`.residuals` over each run's samples); in the release direction the residual is the twin's
friction minus the recording's, so

    d = R_T(P) - R_T(Q)            [N m]

is the friction the recording lacks over P compared with Q. A clearance gives d = 0; a play with a
share f_s of the no-load friction downstream of it gives d = f_s (T_fc + B |w_m|) (004 eq. 9) over
the part of P it covers, diluted by b / dx when the extra clearance is partly a play b and partly a
real growth. The mean of d over the crossings is tested against zero with Student's t (one-sided,
n - 1 degrees of freedom): the windows come from the force channel's fit, the contrast from the
torque channel at positions no parameter of the model depends on, so the crossings' scatter is its
noise.

**Materiality.**  P and Q do not see the same motion: the release accelerates or decelerates across
them, so the budget's inertia and K_T tolerances (:data:`.tolerance.BUDGET`) act on different
inertia and drive torques in the two windows, and its viscous tolerance on different speeds. Each
entry of the budget, applied at its bound to the model with the windows held, moves the mean
deficit by some amount (linearly, so the sum of the magnitudes is the worst case over the budget's
box; the Coulomb, direction, stiffness and clearance entries move both windows alike or not at all, and
the inertia entry dominates); their sum is what a unit within its tolerance can show (``budget``). The
deficit counts when, with 95 % confidence (Student's t quantile), it exceeds both that sum and the
torque channel's floor (:func:`.tolerance.torque_floor`, ``MATERIAL_SHARE['torque']`` of the RMS motor
torque, the bound of the other open-set tests). The model is the verdict's corrections and nuisances
(its ``aug``) without the tolerance deviations its fit chose: the budget term bounds whatever those
can move the deficit by.

**Reach.** At 200-250 Hz a play of 10-25 % of the clearance is crossed in one or two samples of a
release, and the test is mostly not made (None); at 250-500 Hz in two or three, and with two samples a
window (one interval) it found five foreign plays that three samples did not test. Short windows make
the contrast rest on few samples: the speed at a window's ends (:mod:`.speed`) is fitted over two
samples either side, so with one interval the inertia term of P also reads the last contact samples and
the first of Q; and two foreign catalog pairs of a preload change and a clearance scattering ±15 % from
application to application, both at 200 Hz, read deficits of 0.115 and 0.141 N m, the residual over P
near zero and over Q negative (the pair's model misses the free-travel friction right after the window,
and the contrast charges that to a play; README, "Two samples a window for the lost-motion test"). Where
releases are brisk and the extra clearance large, the inertia entry of the budget grows (0.13 N m for
250 µm crossed in diag_synth's releases of 0.08-0.12 s; on the foreign generator's recordings the whole
budget was 0.0003-0.005 N m), and a play much smaller than the extra clearance (its deficit diluted by b
/ dx) is not found. While the play is crossed the motor also moves without the screw's inertia, J_s /
i_g^2 + r_g^2 m_n of eq. 2 (0.03 % of J_me for the unit of 004 Table 1), a share of the inertia torque
left out of d's closed form. A play crossed while the motor accelerates from rest (at the start of an
application) is not used: there the inertia torque, 004 eq. 1, dwarfs the friction (tried on foreign
plays at 200-250 Hz, where that crossing holds 3-4 samples: deficits of both signs, up to 1.5 N m).
Two formulations for 200-250 Hz were tried and not kept (2026-11-28). *Intervals*: each sampling interval
of the free release over P and Q, its residual regressed on the share of its travel inside P within
its crossing (a crossing counts when its intervals' shares differ by 1/2), the slope clustered by
crossing; on diag_synth's 40 µm play (closed form about 0.2 N m) it read 0.025-0.096 N m at 200 Hz,
decided on 0 of 4 seeds (1 of 4 at 250 Hz), and on three foreign plays at 200-250 Hz 0.049 ± 0.009,
-0.085 ± 0.040 and 0.020 ± 0.014 N m, none decided: the speed at the window's ends, fitted over two
samples either side, smears the pick-up of the screw into both windows. *P and Q together against
the next window of their length*: on four foreign plays +0.31 ± 0.02, +0.34 ± 0.02, -0.18 ± 0.02 and
-0.14 ± 0.01 N m, a contrast of both signs from the release's own motion at that rate, so a clearance
could read either way too.

**Level.**  The test runs at ``ALPHA`` beside the screw-position harmonic, the motor torque's scale,
the two force-travel paths (:mod:`.hysteresis`) and the band test at rest (:mod:`.ranking`), so on a
clearance-growth verdict the five routes to ``unexplained`` together may reach about four times
``ALPHA``; the materiality conditions decide in
practice (a play's deficit was significant at p ≤ 1e-4 on every foreign play where the test decided;
the two 200 Hz catalog pairs of "Reach" at p ≤ 0.0012).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ebm_wear_monitor.diagnosis import tolerance
from ebm_wear_monitor.diagnosis.heldout import exceeds, mean_above_zero
from ebm_wear_monitor.diagnosis.residuals import Augment, ResidualModel, clamp_spring
from ebm_wear_monitor.domain.phases import Phase
from ebm_wear_monitor.domain.segmentation import runs

#: fewest samples of a window in one crossing (one sampling interval: the block formula's least)
MIN_SAMPLES = 2
#: fewest held-out crossings with both windows sampled
MIN_CROSSINGS = 4


@dataclass(frozen=True)
class LostMotion:
    """Friction over the extra clearance of the verdict's model, compared with the travel after it."""

    crossings: int  # held-out release crossings with both windows sampled
    travel: float  # dx: the extra clearance of the model, the window P's length in nut travel [m]
    deficit: float  # mean friction the recording lacks over P compared with Q [N m]
    deficit_std: float  # its standard error [N m]
    budget: float  # how far the budget's tolerances at their bounds move the mean deficit, summed [N m]
    floor: float  # materiality bound of the torque channel [N m]
    p_value: float  # one-sided t test of the mean deficit against zero

    def counts(self, level: float) -> bool:
        """Significant at ``level`` and material with 95 % confidence (module docstring)."""
        return self.p_value < level and exceeds(self.deficit, self.deficit_std, max(self.budget, self.floor),
                                                dof=self.crossings - 1)


def _runs(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(first, last) sample of every contiguous run of ``mask``
    (:func:`ebm_wear_monitor.domain.segmentation.runs`)."""
    start, length = runs(mask)
    true = mask[start]
    return start[true], start[true] + length[true] - 1


def crossings(model: ResidualModel, x_c: float, dx: float, cycles: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray]:
    """(start, stop) sample of the windows P and Q of every crossing in ``cycles``, shape (n, 2) each
    (module docstring)."""
    free = ((model.seg.phase == Phase.FORCE_RELEASE) & (model.sign < 0.0)
            & (model.force < model.seg.force_rise) & np.isin(model.seg.cycle, cycles))
    length = min(dx, 0.5 * (x_c - dx))
    p0, p1 = _runs(free & (model.x > x_c - dx) & (model.x <= x_c))
    q0, q1 = _runs(free & (model.x > x_c - dx - length) & (model.x <= x_c - dx))
    follows = np.isin(p1 + 1, q0)  # Q begins where P ends: one crossing
    p0, p1 = p0[follows], p1[follows]
    q = np.searchsorted(q0, p1 + 1)
    q0, q1 = q0[q], q1[q]
    enough = (p1 - p0 + 1 >= MIN_SAMPLES) & (q1 - q0 + 1 >= MIN_SAMPLES)
    return np.column_stack([p0, q0])[enough], np.column_stack([p1, q1])[enough]


def _deficits(model: ResidualModel, aug: Augment, start: np.ndarray, stop: np.ndarray) -> np.ndarray:
    r = model.span_torque_residual(aug, start.ravel(), stop.ravel()).reshape(-1, 2)
    deficit: np.ndarray = r[:, 0] - r[:, 1]
    return deficit


def lost_motion(model: ResidualModel, aug: Augment, heldout_cycles: np.ndarray) -> LostMotion | None:
    """The test of the module docstring for the model ``aug`` on the applications ``heldout_cycles``.
    None when the model has no extra clearance or fewer than ``MIN_CROSSINGS`` crossings have both
    windows sampled."""
    dx = aug.clearance
    if dx <= 0.0:
        return None
    start, stop = crossings(model, float(clamp_spring(model.nominal, aug).clearance), dx, heldout_cycles)
    n = start.shape[0]
    if n < MIN_CROSSINGS:
        return None
    d = _deficits(model, aug, start, stop)
    mean, se, p_value = mean_above_zero(d)
    budget = sum(abs(float(_deficits(model, a, start, stop).mean()) - mean)
                 for a in tolerance.at_bounds(aug, model.nominal, model.park_half_band))
    floor = tolerance.torque_floor(model.drive_block()[model.blocks.moving])
    return LostMotion(n, dx, mean, se, budget, floor, p_value)
