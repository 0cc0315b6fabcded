"""Paper 000 reproduced: the duty cycle of Sec. 4.1 / Fig. 5 reconstructed, its wear, 000's own gap.

000 describes the shape of one brake application but prints no axis values for
Fig. 5; the numbers below are this project's reconstruction (README.md, "Reading the papers
critically", paper 000):

* clearance elimination: screw speed ramps 0 -> w_max in ``t_ramp`` and holds for
  ``t_clear``; the axial force is the small drag of moving nut and lever, ``f_drag``;
* force generation: the speed falls linearly w_max -> 0 over ``t_force`` while the
  force grows from ``f_drag`` to ``f_max`` in proportion to the screw angle turned
  (a linear clamp stiffness), i.e. F = f_drag + (f_max - f_drag)(1 - (1 - t/t_force)^2);
* force maintenance: speed 0, force f_max for ``t_hold`` (no sliding, no wear);
* force release: the speed ramps 0 -> -w_max in ``t_ramp``, holds, then decays to 0 in
  ``t_decay``; the force falls with the screw angle along the same stiffness line and
  reaches zero exactly when the screw stops (000: "the screw angular velocity reduces to
  zero and the axial force also decreases to zero").

Sampled at dt = 0.01 s, the discretisation 000 Sec. 5 uses. :func:`paper000_example` works out
000's own gap between the model (Table 3) and its endurance test with the wear-level effects of
:mod:`ebm_wear_monitor.diagnosis.life`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ebm_wear_monitor.arrays import FloatArray, IntArray
from ebm_wear_monitor.diagnosis.life import BALL_SHARE_000
from ebm_wear_monitor.domain.phases import Phase


@dataclass(frozen=True)
class DutyCycle000:
    """Reconstructed 000 Fig. 5 duty cycle (SI units)."""

    w_max: float = 25.0  # peak screw speed [rad/s] (~240 rpm, "slow-moving" EMBU screw, 000 Sec. 1)
    f_max: float = 20.0e3  # peak axial force [N]
    f_drag: float = 300.0  # axial force while the clearance closes [N]
    t_ramp: float = 0.05  # speed ramp-up time [s]
    t_clear: float = 0.25  # clearance-elimination hold at w_max [s]
    t_force: float = 0.30  # force-generation time [s]
    t_hold: float = 1.0  # force-maintenance time [s]
    t_decay: float = 0.10  # final speed decay in release [s]
    dt: float = 0.01  # time step [s] (000 Sec. 5)

    def scaled(self, speed: float = 1.0, force: float = 1.0, time: float = 1.0) -> DutyCycle000:
        """Same shape with speeds, forces and durations scaled (for elasticity studies)."""
        return DutyCycle000(self.w_max * speed, self.f_max * force, self.f_drag * force,
                            self.t_ramp * time, self.t_clear * time, self.t_force * time,
                            self.t_hold * time, self.t_decay * time, self.dt)

    def sample(self) -> tuple[FloatArray, FloatArray, FloatArray, IntArray]:
        """(t [s], axial force [N], screw speed [rad/s], Phase code) at step dt, midpoints."""
        apply_angle = 0.5 * self.w_max * self.t_force  # screw angle of force generation [rad]
        ramp_angle = 0.5 * self.w_max * (self.t_ramp + self.t_decay)
        t_rel_hold = max(apply_angle - ramp_angle, 0.0) / self.w_max
        edges = np.cumsum([0.0, self.t_ramp + self.t_clear, self.t_force, self.t_hold,
                           self.t_ramp + t_rel_hold + self.t_decay])
        n = round(edges[-1] / self.dt)
        t = (np.arange(n) + 0.5) * self.dt
        phase = np.clip(np.searchsorted(edges, t, side="right") - 1, 0, Phase.FORCE_RELEASE)
        w = np.zeros(n)
        f = np.zeros(n)
        # clearance elimination
        m = phase == Phase.CLEARANCE_ELIMINATION
        w[m] = self.w_max * np.clip(t[m] / self.t_ramp, 0.0, 1.0)
        f[m] = self.f_drag
        # force generation
        m = phase == Phase.FORCE_GENERATION
        tau = (t[m] - edges[1]) / self.t_force
        w[m] = self.w_max * (1.0 - tau)
        f[m] = self.f_drag + (self.f_max - self.f_drag) * (1.0 - (1.0 - tau) ** 2)
        # force maintenance
        f[phase == Phase.FORCE_MAINTENANCE] = self.f_max
        # force release: trapezoidal speed, force linear in the angle turned back
        m = phase == Phase.FORCE_RELEASE
        tr = t[m] - edges[3]
        t1, t2 = self.t_ramp, self.t_ramp + t_rel_hold
        speed = np.where(tr < t1, tr / t1, np.where(tr < t2, 1.0, np.clip((edges[4] - edges[3] - tr)
                                                                      / self.t_decay, 0.0, 1.0)))
        w[m] = -self.w_max * speed
        angle = np.where(tr < t1, 0.5 * tr**2 / t1, np.where(
            tr < t2, 0.5 * t1 + (tr - t1),
            0.5 * t1 + (t2 - t1) + (self.t_decay - 0.5 * ((edges[4] - edges[3] - tr) ** 2) / self.t_decay)
            - 0.5 * self.t_decay)) * self.w_max
        f[m] = np.maximum(self.f_max * (1.0 - angle / apply_angle), 0.0)
        return t, f, w, phase


def cycle_wear(rates_fn: Callable[[FloatArray, FloatArray], Any],
               cycle: DutyCycle000 | None = None) -> dict[str, float]:
    """Wear depths [m] of one duty cycle: sum of rates * dt (000 Sec. 4.1), totals and per phase group.

    ``rates_fn`` is a :meth:`WearModel.rates`. Keys: ``screw``, ``nut``, ``ball`` (whole cycle) and
    ``screw_apply`` / ``screw_release`` / ``nut_apply`` / ``nut_release`` (000 Table 3 columns:
    clearance elimination + force generation, and force release).
    """
    cycle = cycle or DutyCycle000()
    _, f, w, phase = cycle.sample()
    r = rates_fn(f, w)
    apply = phase <= Phase.FORCE_GENERATION
    release = phase == Phase.FORCE_RELEASE
    out = {name: float(np.sum(getattr(r, name)) * cycle.dt) for name in ("screw", "nut", "ball")}
    for name in ("screw", "nut"):
        rate = getattr(r, name)
        out[f"{name}_apply"] = float(np.sum(rate[apply]) * cycle.dt)
        out[f"{name}_release"] = float(np.sum(rate[release]) * cycle.dt)
    return out


def paper000_example(model_per_cycle: float = 1.4843e-10, observed_per_cycle: float = 1.65e-10) -> dict:
    """000's own gap: model 1.4843e-10 m per duty cycle (Table 3, screw) against 1.65e-10 m measured.

    One end-of-test average (0.033 mm after 200,000 cycles) fixes one number, the
    ratio; each scale-type effect explains it exactly with its own parameter, and
    only further data separates them:

    * wear_coefficient: s = ratio - 1 (Archard's k 11.2 % higher than used);
    * ball_share: (1 - 1/3) / (1 - beta) = ratio, beta = 1 - (2/3) / ratio (0.400 instead of 1/3);
    * running_in: A = (ratio - 1) x model growth x 200,000 cycles of extra early wear
      (3.3 um), with n_0 unidentifiable from an end point.
    """
    ratio = observed_per_cycle / model_per_cycle
    cycles = 200_000
    return {
        "ratio": ratio,
        "wear_coefficient": {"s": ratio - 1.0},
        "ball_share": {"beta": 1.0 - (1.0 - BALL_SHARE_000) / ratio},
        "running_in": {"A_m": (ratio - 1.0) * model_per_cycle * cycles, "n0_cycles": None},
        "separating_experiments": {
            "wear_coefficient vs running_in": "clearance at intermediate cycle counts: running-in bends the "
                                              "growth curve early, a k change keeps it straight",
            "wear_coefficient vs ball_share": "ball diameters at teardown (ball share of the wear)",
            "load/speed dependence": "duty-cycle groups at different clamp forces or speeds",
        },
    }
