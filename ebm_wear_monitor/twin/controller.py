"""Brake controller of the twin and the closed-loop duty cycle (the four phases of 000 Fig. 2).

One brake application, as paper 000 Sec. 2 / 4.1 describes it, driven by
armature voltage through the drive's limits (:func:`.dynamics.limit_voltage`):

1. ``clearance_elimination``: full supply voltage, the screw runs up to its top
   speed and closes the clearance; ends when the measured force exceeds
   ``onset_force``, or after ``clearance_timeout`` (a force sensor biased so far
   down that it never reads the onset force would otherwise keep the run going
   for ever).
2. ``force_generation``: force control towards the demanded clamp force
   ``F_d``: ``E = E_ff + k_F (F_d - F_meas) - k_ω ω``, with the feed-forward
   ``E_ff = R (T_L(F_d) + T_fc + G F_d) / K_T`` that holds ``F_d`` against
   load and Coulomb friction of the nominal eq. 9 law (the controller knows
   the unit file, not the effects). The force gain is set from a loop
   stiffness at the motor shaft, ``k_F = K_loop R / (K_T K_b l / (2 π i_g))``,
   so the loop behaves alike for any lead and clamp stiffness. Ends when the
   drive is stuck (|ω| <= ε) with the force no lower than ``force_tolerance``
   below the demand (an overshoot is held, the safe side), or after
   ``generation_timeout``.
3. ``force_maintenance``: same law for the demanded hold time.
4. ``force_release``: position control back to the rest angle,
   ``E = -k_θ θ - k_ω ω`` plus a breakaway feed-forward ``R T_fs / K_T`` in
   the direction of motion; ends when within ``rest_tolerance`` of rest with
   the drive stuck, or after ``release_timeout``.

Then ``idle`` (E = 0) for the rest time before the next application. The
controller acts on the force sensor including any bias/gain error (so a
biased sensor changes the real clamp force), and on noise-free angle and
speed; the recorded signals get their noise afterwards (:mod:`.sensors`).

Every cycle of a batch advances together (arrays over the batch axis).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ebm_wear_monitor.arrays import Floats
from ebm_wear_monitor.domain.phases import Phase
from ebm_wear_monitor.twin.dynamics import ActuatorModel, limit_voltage, voltage_interval

#: lowest rate at which the brake controller runs [Hz] (slower recordings are decimated from it)
CONTROL_RATE_HZ = 1000.0


@dataclass(frozen=True)
class BrakeController:
    """Gains and thresholds of the brake controller (SI units, motor-shaft speeds)."""

    onset_force: float = 200.0  # measured force that ends clearance elimination [N]
    # longest clearance elimination [s]: embu_000 closes its 0.2 mm in about 0.04 s at full voltage,
    # so 5 s covers clearances up to about 25 mm (50 times the clearance limit) with margin
    clearance_timeout: float = 5.0
    loop_stiffness: float = 15.0  # K_loop, force-loop stiffness at the motor shaft [N m / rad]
    speed_damping: float = 0.05  # k_ω [V s / rad]
    force_tolerance: float = 0.01  # settled when |F - F_d| <= max(this * F_d, 50 N) [-]
    generation_timeout: float = 1.0  # longest force generation [s]
    position_gain: float = 60.0  # k_θ [V/rad]
    rest_tolerance: float = 0.01  # release ends within this motor angle of rest [rad]
    release_timeout: float = 1.0  # longest release [s]


@dataclass
class ClosedLoopRecord:
    """Samples of a batch of duty cycles, shape (n, batch), and where each cycle ends."""

    motor_angle: np.ndarray  # θ_m [rad]
    motor_speed: np.ndarray  # ω_m [rad/s]
    force: np.ndarray  # true clamp force F_cl [N]
    current: np.ndarray  # I_a [A]
    voltage: np.ndarray  # applied E_a [V]
    motor_torque: np.ndarray  # mean T_m over the step [N m]
    friction_torque: np.ndarray  # T_f over the step [N m]
    phase: np.ndarray  # phase codes (int8)
    length: np.ndarray  # samples of each cycle, up to the end of its rest time [-]


def hold_voltage(model: ActuatorModel, demand: np.ndarray) -> np.ndarray:
    """Feed-forward E_ff = R (T_L(F_d) + T_fc + G F_d) / K_T [V] (stall, 004 eq. 1, 8, 9)."""
    law = model.friction
    torque = model.transmission * demand + law.coulomb + law.load_coefficient * demand
    return model.resistance * torque / model.torque_constant


def run_duty_cycles(model: ActuatorModel, demands: np.ndarray, holds: np.ndarray, *, rest: float,
                    rate_hz: float, controller: BrakeController = BrakeController(),
                    force_offset: float = 0.0, force_gain_error: float = 0.0,
                    substeps: int = 1) -> ClosedLoopRecord:
    """Simulate one brake application per batch entry, each from rest, all in parallel.

    Args:
        model: the actuator (its clamp clearance may be a (batch,) array).
        demands: demanded clamp force per cycle [N], shape (batch,).
        holds: force-maintenance time per cycle [s], shape (batch,).
        rest: idle time after the release [s].
        rate_hz: controller and sample rate [Hz].
        force_offset, force_gain_error: force-sensor error seen by the controller,
            ``F_meas = (1 + gain) F + offset`` [N], [-].
        substeps: integrator steps per sample.
    """
    c = controller
    CLEARANCE, GENERATION, MAINTENANCE, RELEASE, IDLE = Phase
    demands, holds = np.asarray(demands, float), np.asarray(holds, float)
    batch, dt = demands.shape, 1.0 / rate_hz
    e_ff = hold_voltage(model, demands)
    settle_band = np.maximum(c.force_tolerance * demands, 50.0)
    force_gain = c.loop_stiffness * model.resistance / (
        model.torque_constant * model.clamp.stiffness * model.transmission)
    breakaway_volts = model.resistance * model.friction.static / model.torque_constant
    angle, speed, current = np.zeros(batch), np.zeros(batch), np.zeros(batch)
    phase = np.zeros(batch, np.int8)
    since = np.zeros(batch)  # time in the current phase [s]
    length = np.zeros(batch, int)
    rows: list[tuple[Floats, ...]] = []
    k = 0
    while True:
        force = model.clamp_force(angle)
        measured = (1.0 + force_gain_error) * force + force_offset
        stuck = np.abs(speed) <= model.zero_speed_band
        # phase transitions, decided on the sample just taken
        nxt = phase.copy()
        nxt[(phase == CLEARANCE) & ((measured > c.onset_force) | (since >= c.clearance_timeout))] = GENERATION
        settled = stuck & (measured >= demands - settle_band)
        nxt[(phase == GENERATION) & (settled | (since >= c.generation_timeout))] = MAINTENANCE
        nxt[(phase == MAINTENANCE) & (since >= holds)] = RELEASE
        home = stuck & (np.abs(angle) <= c.rest_tolerance)
        nxt[(phase == RELEASE) & (home | (since >= c.release_timeout))] = IDLE
        done = (phase == IDLE) & (since >= rest)
        length[done & (length == 0)] = k
        if np.all(length > 0):
            break
        since = np.where(nxt == phase, since, 0.0)
        phase = nxt
        # control law per phase
        force_law = e_ff + force_gain * (demands - measured) - c.speed_damping * speed
        position_law = -c.position_gain * angle - c.speed_damping * speed
        position_law = position_law + np.sign(position_law) * breakaway_volts
        volts = np.where(phase == CLEARANCE, model.supply_voltage,
                         np.where((phase == GENERATION) | (phase == MAINTENANCE), force_law,
                                  np.where(phase == RELEASE, position_law, 0.0)))
        volts = limit_voltage(model, volts, speed)
        sample = (angle, speed, force, current, volts)
        angle, speed, current, torque, friction = voltage_interval(
            model, angle, speed, current, volts, dt=dt, substeps=substeps, force=force)
        rows.append((*sample, torque, friction, phase))
        since = since + dt
        k += 1
    angle_, speed_, force_, current_, volts_, torque_, friction_, phase_ = (
        np.array(col) for col in zip(*rows, strict=True))
    return ClosedLoopRecord(angle_, speed_, force_, current_, volts_, torque_, friction_, phase_,
                            length=length)
