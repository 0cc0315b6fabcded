"""Load-dependent system friction of the EMB actuator, referred to the motor shaft (004 eq. 9).

Paper 004 writes the friction torque of the whole drive train (motor, planetary
gear, thrust bearing, ball screw, moving parts) as one law at the motor shaft::

    T_f = (T_fc + G F_cl) sgn(ω_m) + B ω_m          |ω_m| > ε          (sliding)
    T_f = T_m - T_L                                 |ω_m| < ε and |T_m - T_L| < T_fs + G F_cl   (stuck)
    T_f = (T_fs + G F_cl) sgn(T_m - T_L)            otherwise          (breakaway)

with the load torque ``T_L = l F_cl / (2 π i_g)``. The printed equation drops
the lead ``l`` from ``T_L`` (it reads ``F_cl / (2 π i_g)``, a force, not a
torque); eq. 1 has it, and this module restores it (README.md, paper 004 item 1).

Two optional terms extend the nominal law for the effect catalog of
interface.md section 4 (both off by default, so the law is exactly eq. 9):

* Stribeck: the sliding level falls from the static to the Coulomb level over
  the Stribeck speed ``ω_s`` instead of in one step:
  ``T_c(ω) = T_fc + (T_fs - T_fc) exp(-(ω/ω_s)^2)``.
* Ball-screw efficiency that varies with speed: the screw's mean efficiency
  ``η_0`` (004 reason 3) drops to ``η_0 (1 - d exp(-|ω|/ω_η))`` at low speed
  (mixed lubrication), which adds ``T_L (1/η(ω) - 1/η_0)`` of friction, a term
  proportional to the load torque and largest at standstill.

All functions take numpy arrays (or floats) and broadcast; torques in N m,
speeds in rad/s at the motor shaft, forces in N.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ebm_wear_monitor.arrays import Floats
from ebm_wear_monitor.params import UnitParams

#: mean forward efficiency of the ball screw without preload, η_0 (a catalogue value; 004 prints none)
SCREW_EFFICIENCY = 0.90


@dataclass(frozen=True)
class FrictionLaw:
    """Parameters of 004 eq. 9 (motor shaft) plus the two optional shape terms above."""

    static: float  # T_fs, load-independent breakaway torque [N m]
    coulomb: float  # T_fc, load-independent Coulomb torque [N m]
    viscous: float  # B [N m s / rad]
    load_coefficient: float  # G, friction torque per newton of clamp force [N m / N]
    stribeck_speed: float = 0.0  # ω_s [rad/s]; 0: the step of eq. 9
    efficiency_drop: float = 0.0  # d, fractional drop of the screw efficiency at standstill [-]
    efficiency_speed: float = 10.0  # ω_η, speed over which the efficiency recovers [rad/s]
    screw_efficiency: float = SCREW_EFFICIENCY  # η_0, mean forward efficiency of the ball screw [-]


def friction_law(unit: UnitParams) -> FrictionLaw:
    """The nominal eq. 9 law of a unit's ``actuator.friction`` block."""
    f = unit.require_actuator().friction
    return FrictionLaw(static=f.static, coulomb=f.coulomb, viscous=f.viscous,
                       load_coefficient=f.load_coefficient)


def _efficiency_term(law: FrictionLaw, speed: Floats, load_torque: np.ndarray) -> Floats:
    """Extra friction ``T_L (1/η(ω) - 1/η_0)`` of a speed-dependent screw efficiency [N m]."""
    if law.efficiency_drop == 0.0:
        return 0.0
    drop = law.efficiency_drop * np.exp(-np.abs(speed) / law.efficiency_speed)
    return np.abs(load_torque) * (1.0 / (1.0 - drop) - 1.0) / law.screw_efficiency


def sliding_friction(law: FrictionLaw, speed: np.ndarray, force: np.ndarray,
                     load_torque: np.ndarray) -> np.ndarray:
    """Magnitude of the sliding friction torque at motor speed ``speed`` (first line of eq. 9) [N m].

    ``(T_c(ω) + G F_cl) + B |ω|`` plus the efficiency term; it acts against the motion.
    """
    level: Floats = law.coulomb
    if law.stribeck_speed > 0.0:
        level = law.coulomb + (law.static - law.coulomb) * np.exp(-(speed / law.stribeck_speed) ** 2)
    return (level + law.load_coefficient * force + law.viscous * np.abs(speed)
            + _efficiency_term(law, speed, load_torque))


def breakaway_friction(law: FrictionLaw, force: np.ndarray, load_torque: np.ndarray) -> np.ndarray:
    """Largest friction torque the stuck drive can hold, ``T_fs + G F_cl`` (eq. 9, lines 2-3) [N m]."""
    return law.static + law.load_coefficient * force + _efficiency_term(law, 0.0, load_torque)


def friction_torque(law: FrictionLaw, speed: np.ndarray, force: np.ndarray, load_torque: np.ndarray,
                    drive_torque: np.ndarray, *, zero_speed_band: float) -> np.ndarray:
    """Signed friction torque of eq. 9 as printed (three cases), with the lead restored [N m].

    Args:
        speed: motor speed ω_m [rad/s].
        force: clamp force F_cl [N] (>= 0).
        load_torque: T_L = l F_cl / (2 π i_g) [N m].
        drive_torque: T_m - T_L, the torque the friction has to balance when stuck [N m].
        zero_speed_band: ε [rad/s].
    """
    speed, drive = np.asarray(speed, float), np.asarray(drive_torque, float)
    sliding = np.sign(speed) * sliding_friction(law, speed, force, load_torque)
    limit = breakaway_friction(law, force, load_torque)
    stuck = np.where(np.abs(drive) < limit, drive, np.sign(drive) * limit)
    return np.where(np.abs(speed) > zero_speed_band, sliding, stuck)
