"""Single-degree-of-freedom dynamics of the EMB actuator (004 eq. 1-8) and its fixed-step integrator.

The actuator is lumped onto the motor shaft (004 eq. 1-4)::

    J_me dω_m/dt = T_m - T_L - T_f,          T_L = l F_cl / (2 π i_g)          (1)
    J_me = J_m + J_g + J_s / i_g^2 + (l / (2 π i_g))^2 m_n                      (2)
    θ_m = i_g θ_s,     x = l θ_s / (2 π)                                         (3), (4)

with the clamp force F_cl(x) of eq. 5-6 (:mod:`.clamp`), the friction T_f of
eq. 9 (:mod:`.friction`), and the DC motor::

    T_m = K_T I_a                                                                (7)
    E_a = L_a dI_a/dt + R_a I_a + K_E ω_m                                        (8)

Two ways to drive it: by armature voltage (eq. 8, with the drive's current
limit, used by the brake controller) and by a recorded current trace
(T_m = K_T I, eq. 7 alone), which is what the sim-to-real diagnosis does.

Integrator (fixed step ``dt``, every operation vectorised over a batch axis so
many cycles or candidate parameter sets advance together):

* Electrical: over one step the speed is frozen and eq. 8 is linear in I, so it
  is solved exactly, ``I(t+dt) = I_ss + (I - I_ss) e^{-dt/τ_e}`` with
  ``I_ss = (E - K_E ω)/R`` and ``τ_e = L/R`` (0.9 ms for 004's motor): stable
  at any step, and the step-mean current drives the torque.
* Mechanical: semi-implicit Euler on ω with the switched (stick/slip) friction
  of eq. 9 and trapezoidal angle. Stick-slip without chatter: a sliding
  solution whose speed would change sign in a step stops at exactly zero; a
  drive whose speed is inside the zero-speed band ``ε`` stays at exactly zero
  while ``|T_m - T_L| <= T_fs + G F_cl`` and breaks away against the static
  level otherwise. The rules are deterministic and the friction actually
  applied is ``T_f = T_m - T_L - J_me Δω/Δt``, so the discrete energy balance
  ``W_motor = W_load + W_friction + ΔE_kin`` holds to round-off.

Sign convention (interface.md section 2): angles and speeds positive in the
apply direction, clamp force compressive positive; angles count from the
released rest position.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ebm_wear_monitor.arrays import Floats
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.params import UnitParams
from ebm_wear_monitor.twin.clamp import ClampLaw
from ebm_wear_monitor.twin.friction import FrictionLaw, breakaway_friction, friction_law, sliding_friction

#: default zero-speed band ε of eq. 9 at the motor shaft [rad/s] (0.03 % of the 37 rad/s top speed)
ZERO_SPEED_BAND = 0.01


def transmission(lead: float, gear_ratio: float) -> float:
    """``l / (2 π i_g)`` [m/rad]: nut travel per motor radian (eq. 3-4), load torque at the motor per
    newton of clamp force (eq. 1); ``lead`` l [m], ``gear_ratio`` i_g [-]."""
    return lead / (2.0 * math.pi * gear_ratio)


@dataclass(frozen=True)
class ActuatorModel:
    """Everything the integrator needs, referred to the motor shaft (SI units)."""

    inertia: float  # J_me, eq. 2 [kg m^2]
    lead: float  # l [m]
    gear_ratio: float  # i_g [-]
    torque_constant: float  # K_T [N m / A]
    back_emf_constant: float  # K_E [V s / rad]
    resistance: float  # R_a [ohm]
    inductance: float  # L_a [H]
    supply_voltage: float  # E_amax [V]
    current_limit: float  # I_max of the drive [A]
    clamp: ClampLaw
    friction: FrictionLaw
    zero_speed_band: float = ZERO_SPEED_BAND  # ε [rad/s]

    @property
    def transmission(self) -> float:
        """Nut travel per motor radian, ``l / (2 π i_g)`` [m/rad] (eq. 3-4); also T_L per newton."""
        return transmission(self.lead, self.gear_ratio)

    def nut_travel(self, screw_angle: np.ndarray) -> np.ndarray:
        """x = l θ_s / (2 π) [m] (eq. 4): nut travel for a screw angle θ_s [rad] from rest."""
        return self.lead * np.asarray(screw_angle, float) / (2.0 * math.pi)

    def load_torque(self, force: np.ndarray) -> np.ndarray:
        """T_L = l F_cl / (2 π i_g) [N m] (eq. 1)."""
        return self.transmission * np.asarray(force, float)

    def clamp_force(self, motor_angle: np.ndarray) -> np.ndarray:
        """F_cl [N] at motor angle θ_m [rad] from rest (eq. 4-5)."""
        return self.clamp.force(self.transmission * np.asarray(motor_angle, float))


def equivalent_inertia(unit: UnitParams) -> float:
    """004 eq. 2: ``J_me = J_m + J_g + J_s / i_g^2 + (l / (2 π i_g))^2 m_n`` [kg m^2]."""
    a = unit.require_actuator()
    r = transmission(unit.ball_screw.lead, a.gear_ratio)
    return a.motor.inertia + a.gear_inertia + a.screw_inertia / a.gear_ratio**2 + r * r * a.nut_mass


def actuator_model(unit: UnitParams, clearance: float | None = None) -> ActuatorModel:
    """The nominal twin of a unit (its ``actuator`` block and the ball-screw lead).

    ``clearance`` overrides the nominal x_ag [m] (a worn unit's grown clearance).
    """
    a = unit.require_actuator()
    m = a.motor
    return ActuatorModel(
        inertia=equivalent_inertia(unit), lead=unit.ball_screw.lead, gear_ratio=a.gear_ratio,
        torque_constant=m.torque_constant, back_emf_constant=m.back_emf_constant,
        resistance=m.resistance, inductance=m.inductance,
        supply_voltage=a.supply_voltage, current_limit=a.current_limit,
        clamp=ClampLaw(stiffness=a.stiffness, clearance=a.clearance if clearance is None else clearance),
        friction=friction_law(unit))


# --------------------------------------------------------------------------- one integration step


def limit_voltage(model: ActuatorModel, voltage: np.ndarray, speed: np.ndarray) -> np.ndarray:
    """Armature voltage the drive can apply: within ±E_amax, and such that the current it
    settles to, ``(E - K_E ω) / R`` (004 eq. 8 at steady current), stays within ±I_max (a voltage-side
    current limiter) [V]; ``speed`` ω is the motor speed [rad/s]."""
    v = np.clip(voltage, -model.supply_voltage, model.supply_voltage)
    emf = model.back_emf_constant * speed
    headroom = model.resistance * model.current_limit
    return np.clip(v, emf - headroom, emf + headroom)


def electrical_step(model: ActuatorModel, current: np.ndarray, voltage: np.ndarray, speed: np.ndarray,
                    dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Exact solution of eq. 8 over ``dt`` at frozen speed: (current at the end, mean current) [A]."""
    tau = model.inductance / model.resistance
    decay = math.exp(-dt / tau)
    settled = (voltage - model.back_emf_constant * speed) / model.resistance
    gap = current - settled
    return settled + gap * decay, settled + gap * (tau / dt) * (1.0 - decay)


def mechanical_step(model: ActuatorModel, angle: np.ndarray, speed: np.ndarray, motor_torque: np.ndarray,
                    dt: float, *, force: np.ndarray | None = None
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Advance eq. 1 with the switched friction of eq. 9 by ``dt``.

    ``force`` is the clamp force at ``angle`` when the caller has it already.
    Returns (motor angle [rad], motor speed [rad/s], clamp force at the step start [N],
    friction torque applied over the step [N m]).
    """
    if force is None:
        force = model.clamp_force(angle)
    load = model.transmission * force
    drive = motor_torque - load
    law, J = model.friction, model.inertia
    slide = speed + dt * (drive - np.sign(speed) * sliding_friction(law, speed, force, load)) / J
    slide = np.where(slide * speed < 0.0, 0.0, slide)  # would reverse within the step: stops
    limit = breakaway_friction(law, force, load)
    breakaway = np.where(np.abs(drive) > limit, speed + dt * (drive - np.sign(drive) * limit) / J, 0.0)
    new_speed = np.where(np.abs(speed) > model.zero_speed_band, slide, breakaway)
    friction = drive - J * (new_speed - speed) / dt
    return angle + 0.5 * dt * (speed + new_speed), new_speed, force, friction


def voltage_interval(model: ActuatorModel, angle: np.ndarray, speed: np.ndarray, current: np.ndarray,
                     voltage: np.ndarray, *, dt: float, substeps: int = 1, force: np.ndarray | None = None
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray, Floats, Floats]:
    """Advance eq. 1 and 8 over one sample interval ``dt`` at a held armature ``voltage`` in
    ``substeps`` steps. Returns (motor angle [rad], motor speed [rad/s], current [A], mean motor
    torque [N m], mean friction torque [N m]) of the interval; ``force`` as in :func:`mechanical_step`.
    """
    h = dt / substeps
    torque_sum: Floats = 0.0
    friction_sum: Floats = 0.0
    for _ in range(substeps):
        current, mean_current = electrical_step(model, current, voltage, speed, h)
        torque = model.torque_constant * mean_current
        angle, speed, _, friction = mechanical_step(model, angle, speed, torque, h, force=force)
        force = None
        torque_sum, friction_sum = torque_sum + torque, friction_sum + friction
    return angle, speed, current, torque_sum / substeps, friction_sum / substeps


# --------------------------------------------------------------------------- open-loop integrations


@dataclass
class Trajectory:
    """Samples of one integration. Arrays have shape (n,) or (n, batch) like the input.

    Screw-side signals are those of the input topics (interface.md section 2);
    motor-side ones are for energy and friction analyses (004 eq. 42-43).
    """

    t: np.ndarray  # sample times [s]
    angle: np.ndarray  # screw angle θ_s from rest [rad]
    velocity: np.ndarray  # screw speed [rad/s]
    axial_force: np.ndarray  # clamp force F_cl [N]
    current: np.ndarray  # armature current I_a [A]
    motor_torque: np.ndarray  # T_m [N m]: K_T I_a at the sample (current-driven), or its mean over
    # the step that starts at the sample (voltage-driven)
    friction_torque: np.ndarray  # T_f applied over the step that starts at the sample [N m]
    voltage: np.ndarray | None = None  # armature voltage E_a [V] (voltage-driven runs)


def _initial(x0: tuple[float, float] | None, shape: tuple[int, ...], gear_ratio: float
             ) -> tuple[np.ndarray, np.ndarray]:
    angle0, velocity0 = (0.0, 0.0) if x0 is None else x0
    return (np.broadcast_to(np.asarray(angle0, float) * gear_ratio, shape).copy(),
            np.broadcast_to(np.asarray(velocity0, float) * gear_ratio, shape).copy())


def _as_model(model: UnitParams | ActuatorModel) -> ActuatorModel:
    return model if isinstance(model, ActuatorModel) else actuator_model(model)


def _sample_times(t: np.ndarray, n: int) -> tuple[np.ndarray, float]:
    t = np.asarray(t, float)
    if t.ndim != 1 or len(t) != n or n < 2:
        raise InputError("sample times must be a 1-D array as long as the drive signal (>= 2 samples)")
    dt = float(t[1] - t[0])
    if dt <= 0.0 or not np.allclose(np.diff(t), dt, rtol=1e-6, atol=1e-12):
        raise InputError("the twin integrates on a uniform time grid: sample times must be evenly spaced")
    return t, dt


def simulate_current_driven(model: UnitParams | ActuatorModel, t: np.ndarray, current: np.ndarray,
                            x0: tuple[float, float] | None = None, substeps: int = 1) -> Trajectory:
    """Drive the twin by a recorded armature current: T_m = K_T I (eq. 7), eq. 1 and 9 integrated.

    Args:
        model: a unit (its nominal twin) or an :class:`ActuatorModel` (e.g. with friction
            or clamp overrides through ``dataclasses.replace`` or :func:`.effects.apply_effects`).
        t: uniform sample times [s], shape (n,).
        current: armature current [A], shape (n,) or (n, batch); linear between samples.
        x0: initial (screw angle from rest [rad], screw speed [rad/s]), scalars or (batch,) arrays.
        substeps: integrator steps per sample interval.
    """
    model = _as_model(model)
    current = np.asarray(current, float)
    t, dt_sample = _sample_times(t, len(current))
    shape = current.shape[1:]
    angle, speed = _initial(x0, shape, model.gear_ratio)
    n, h = len(t), dt_sample / substeps
    out = {k: np.empty(current.shape) for k in ("angle", "speed", "force", "friction")}
    for k in range(n):
        out["angle"][k], out["speed"][k] = angle, speed
        torque_a = model.torque_constant * current[k]
        torque_b = model.torque_constant * current[min(k + 1, n - 1)]
        friction_sum: Floats = 0.0
        for j in range(substeps):
            torque = torque_a + (torque_b - torque_a) * (j + 0.5) / substeps
            angle, speed, force, friction = mechanical_step(model, angle, speed, torque, h)
            if j == 0:
                out["force"][k] = force
            friction_sum = friction_sum + friction
        out["friction"][k] = friction_sum / substeps
    i_g = model.gear_ratio
    return Trajectory(t=t, angle=out["angle"] / i_g, velocity=out["speed"] / i_g, axial_force=out["force"],
                      current=current, motor_torque=model.torque_constant * current,
                      friction_torque=out["friction"])


def simulate_voltage_driven(model: UnitParams | ActuatorModel, t: np.ndarray, voltage: np.ndarray,
                            x0: tuple[float, float] | None = None, substeps: int = 1) -> Trajectory:
    """Drive the twin by an armature-voltage trace (eq. 8), through the drive's voltage and current
    limits (:func:`limit_voltage`); voltage held over each sample interval. Shapes as in
    :func:`simulate_current_driven`; the current starts at zero."""
    model = _as_model(model)
    voltage = np.asarray(voltage, float)
    t, dt_sample = _sample_times(t, len(voltage))
    angle, speed = _initial(x0, voltage.shape[1:], model.gear_ratio)
    current = np.zeros_like(angle)
    out = {k: np.empty(voltage.shape) for k in ("angle", "speed", "force", "current", "torque", "friction",
                                                "voltage")}
    for k in range(len(t)):
        out["angle"][k], out["speed"][k], out["current"][k] = angle, speed, current
        out["force"][k] = force = model.clamp_force(angle)
        out["voltage"][k] = applied = limit_voltage(model, voltage[k], speed)
        angle, speed, current, out["torque"][k], out["friction"][k] = voltage_interval(
            model, angle, speed, current, applied, dt=dt_sample, substeps=substeps, force=force)
    i_g = model.gear_ratio
    return Trajectory(t=t, angle=out["angle"] / i_g, velocity=out["speed"] / i_g, axial_force=out["force"],
                      current=out["current"], motor_torque=out["torque"], friction_torque=out["friction"],
                      voltage=out["voltage"])
