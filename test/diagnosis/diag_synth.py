"""Closed-form test recordings for the diagnosis (independent of the twin's simulator).

The nut follows a prescribed minimum-jerk travel x(t) per brake cycle (apply
0 -> x_ag + F/K_b, hold, release back to 0, idle); force from 004 eq. 5, and
the current is what 004 eq. 1, 7, 9 (plus a known :class:`Augment`) require for
that motion: I = (J_me dw_m/dt + T_L + T_f) / K_T, computed from the analytic
derivatives.  At rest the motor holds T_L exactly (friction inside its band).
Friction and force are written out here from the equations, not taken from
:mod:`ebm_wear_monitor.diagnosis.residuals`, so a sign or factor error in the
diagnosis's model forms shows up as a residual instead of cancelling.
"""

from __future__ import annotations

import math

import numpy as np

from ebm_wear_monitor.diagnosis.recording import Resampled
from ebm_wear_monitor.diagnosis.residuals import Augment
from ebm_wear_monitor.twin.dynamics import ActuatorModel


def _min_jerk(tau: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Position, velocity, acceleration of a unit minimum-jerk move over tau in [0, 1]."""
    tau = np.clip(tau, 0.0, 1.0)
    return (10 * tau**3 - 15 * tau**4 + 6 * tau**5, 30 * tau**2 - 60 * tau**3 + 30 * tau**4,
            60 * tau - 180 * tau**2 + 120 * tau**3)


def synth(nom: ActuatorModel, aug: Augment | None = None, *, cycles: int = 8, rate: float = 500.0,
          seed: int = 0, noise: dict | None = None, forces: tuple[float, float] = (8e3, 30e3),
          durations: tuple[float, float] = (0.15, 0.35), force_offset: float = 0.0,
          drive_gain: float = 0.0, dG_drift: float = 0.0, play: float = 0.0,
          play_share: float = 0.6, play_force: float = 0.0, angle_side: str = "screw",
          rest_pulse: float = 0.0, creep: float = 0.0, creep_friction: float = 1.0,
          angle_quantum: float = 0.0, parks: np.ndarray | None = None) -> Resampled:
    """A recording of ``cycles`` brake applications with effect ``aug`` present in the data.

    ``force_offset`` [N] is a tare of the force reading; ``drive_gain`` a relative loss of the motor's
    torque constant (more current for the same torque: an effect outside the catalog); ``dG_drift``
    [N m/N] a load-friction coefficient growing linearly from 0 in the first cycle to ``dG_drift`` in
    the last (friction drifting within the recording: outside the catalog too).

    ``play`` [m of nut travel]: a play between motor and screw with the angle measured on the screw
    (outside the catalog). The motor travels ``play`` further; the screw follows the forward flank when
    the motor drives it or the clamp pushes it back, the backward flank when the motor pulls it back
    out of contact, and stays put in between, where the motor carries its inertia and only the share
    ``1 - play_share`` of the no-load friction (Coulomb and viscous). ``angle_side="motor"`` records the
    angle and the velocity on the motor side of the play instead (the travel the motor makes).
    ``play_force`` [N]: the clamp pushes the screw back onto the forward flank only while its force exceeds
    this (the friction downstream of the play holds the screw below it); there the screw stops, in contact,
    and the motor turns back through the play without it and without its load torque.

    ``rest_pulse`` [N m]: in every idle a half sine of motor torque of this peak that the recorded screw
    does not feel (a motor turning inside a play, the angle on the screw): the drive at rest alone, the
    moving blocks untouched (outside the catalog).

    ``creep`` [screw rad/s]: during the hold the nut creeps on at this speed (a force loop pushing against
    breakaway), the force rising with it, and its friction there is ``creep_friction`` times eq. 9's
    sliding friction (a stick-slip whose average friction is below the sliding level: how a drive creeps
    is its own convention). ``angle_quantum`` [rad]: the recorded angle is quantised to this step (an
    encoder's count), after its noise.

    ``parks`` [m of nut travel, ``cycles + 1`` values]: where the ECU parks the nut before each application
    and after the last, against the unit file's rest at 0 (a position loop stopping off its target).
    """
    rng = np.random.default_rng(seed)
    aug = Augment() if aug is None else aug
    if noise is None:
        noise = {"angle": 1e-4, "velocity": 0.05, "axial_force": 30.0, "current": 0.03}  # 12-bit resolver
    parts = []
    t0 = 0.0
    parks = np.zeros(cycles + 1) if parks is None else np.asarray(parks, float)
    assert parks.shape == (cycles + 1,), "parks: one before each application and one after the last"
    for c in range(cycles):
        F_target = rng.uniform(*forces)
        T_app = rng.uniform(*durations)
        x_end = nom.clamp.clearance + aug.clearance + F_target / nom.clamp.stiffness + play
        x_hold = x_end + 0.25 * creep * nom.lead / (2.0 * math.pi)  # where the creep ends [m]
        seg = [("apply", T_app, parks[c], x_end), ("hold", 0.25, x_end, x_hold),
               ("release", 0.8 * T_app, x_hold, parks[c + 1]), ("idle", 0.1, parks[c + 1], parks[c + 1])]
        for kind, dur, xa, xb in seg:
            t = np.arange(0.0, dur, 1.0 / rate)
            p, v, a = _min_jerk(t / dur) if kind != "hold" else (t / dur, np.full(t.size, 1.0), 0.0 * t)
            x = xa + (xb - xa) * p
            xd = (xb - xa) * v / dur
            xdd = (xb - xa) * a / dur**2
            pulse = rest_pulse * np.sin(np.pi * t / dur) * (kind == "idle")
            parts.append((t0 + t, x, xd, xdd, np.full(t.size, c / max(cycles - 1, 1)), pulse,
                          np.full(t.size, kind == "hold")))
            t0 += dur
    t, x, xd, xdd, age, pulse, hold = (np.concatenate(c) for c in zip(*parts, strict=True))
    k = 2.0 * math.pi / nom.lead  # screw rad per metre, 004 eq. 4
    x_c = nom.clamp.clearance + aug.clearance  # nut travel at contact [m]
    x_motor, coupled = x, np.ones(x.size, bool)
    if play > 0.0:
        x, coupled = _through_play(x_motor, play, x_c + play_force / nom.clamp.stiffness)
    w_m = nom.gear_ratio * k * xd  # the motor's speed [rad/s]
    d = np.maximum(x - x_c, 0.0)  # pad compression [m]
    F_true = nom.clamp.stiffness * d + aug.stiffness_quad * d**2  # 004 eq. 5 (+ k_2 d^2)
    T_L = nom.lead * F_true / (2.0 * math.pi * nom.gear_ratio)  # 004 eq. 1
    speed = np.abs(w_m)
    # 004 eq. 9 sliding branch with the catalog's corrections (efficiency, Stribeck)
    law = nom.friction
    T_f = np.sign(w_m) * (law.coulomb + aug.dT_fc + (law.load_coefficient + aug.dG + dG_drift * age) * F_true
                          + (law.viscous + aug.dB) * speed
                          + T_L * (aug.eff_base + aug.eff_speed * speed)
                          + aug.stribeck_torque * np.exp(-(speed / aug.stribeck_speed) ** 2))
    T_f = np.where(coupled, T_f, (1.0 - play_share) * np.sign(w_m) * (law.coulomb + law.viscous * speed))
    T_f = np.where(hold, creep_friction * T_f, T_f)
    T_f = np.where(speed > 1e-3, T_f, 0.0)
    current = ((nom.inertia * nom.gear_ratio * k * xdd + T_L * coupled + T_f + pulse)  # 004 eq. 1, 7
               / (nom.torque_constant * (1.0 - drive_gain)))
    force_meas = (1.0 + aug.force_gain) * F_true + force_offset  # sensor gain and tare
    on_motor = play == 0.0 or angle_side == "motor"
    velocity = k * (xd if on_motor else np.gradient(x, t))
    sig = {"angle": k * (x_motor if on_motor else x), "velocity": velocity, "axial_force": force_meas,
           "current": current}
    sig = {n: v + rng.normal(0.0, noise[n], v.size) for n, v in sig.items()}
    if angle_quantum > 0.0:
        sig["angle"] = angle_quantum * np.round(sig["angle"] / angle_quantum)
    return Resampled(t, **sig)


def _through_play(x_motor: np.ndarray, play: float, x_c: float) -> tuple[np.ndarray, np.ndarray]:
    """(screw travel [m], whether a flank is engaged: false while the motor turns and the screw stays)
    behind a play ``play`` [m] (:func:`synth`); the clamp pushes the screw back onto the forward flank down
    to the travel ``x_c`` [m]."""
    x = np.empty_like(x_motor)
    coupled = np.ones(x.size, bool)
    s = 0.0
    for i, xm in enumerate(x_motor):
        if xm - play >= s:  # the forward flank drives the screw
            s_new = xm - play
        elif s > x_c:  # in contact the clamp pushes the screw back onto the forward flank, down to contact
            s_new = max(xm - play, x_c)
        elif xm < s:  # the backward flank pulls it back
            s_new = xm
        else:
            s_new = s
        coupled[i] = s_new != s or i == 0 or xm == x_motor[i - 1]
        x[i] = s = s_new
    return x, coupled
