"""Torques at the motor shaft while the brake holds a clamp force: `calc actuator` (004 eq. 1, 9, 42).

004 eq. 1's load torque is printed without the screw lead in eq. 9 and 15-17; with
``T_L = l F / (2 π i_g)`` (eq. 1) the paper's own 30 kN figure follows (2.364 N m), so the lead is
restored here as in :mod:`.friction`. Holding friction: a force reached by pushing forward is held
at the kinetic level ``T_fc + G F`` (Sec. 4.1's numbers: 0.849 N m, 3.213 N m, 73.56 % at 30 kN);
``T_fs + G F`` is the largest friction the stuck drive can resist (Fig. 5b's 0.884 N m). The other
closed forms of 004 (eq. 10-17, 43), which only reproduce the paper's figures, live in
:mod:`ebm_wear_monitor.validation.papers.paper004`; the printing problems are listed in README.md
("Reading the papers critically", paper 004).
"""

from __future__ import annotations

from ebm_wear_monitor.params import UnitParams
from ebm_wear_monitor.schema.calc import ActuatorResult
from ebm_wear_monitor.twin.dynamics import transmission
from ebm_wear_monitor.twin.friction import friction_law


def load_ratio(unit: UnitParams) -> float:
    """004 eq. 1: load torque per clamp force at the motor shaft, l / (2 π i_g) [N m/N] of a unit file
    (:func:`~ebm_wear_monitor.twin.dynamics.transmission`)."""
    return transmission(unit.ball_screw.lead, unit.require_actuator().gear_ratio)


def actuator_torques(unit: UnitParams, clamp_force: float) -> ActuatorResult:
    """Torques at the motor shaft holding ``clamp_force`` [N] (force maintenance, 004 eq. 1, 9, 42).

    Fields (schema/calc.py): ``load_torque_Nm`` T_L = l F / (2 π i_g); ``friction_torque_Nm`` T_fc + G F (the
    kinetic level the force was reached at); ``motor_torque_Nm`` T_m = T_L + T_f;
    ``torque_transfer_ratio`` l_e = T_L / T_m (eq. 42, a fraction). Extra keys:
    ``static_friction_torque_Nm`` T_fs + G F (most the stuck drive resists),
    ``release_torque_Nm`` T_L - (T_fs + G F) (below it the screw back-drives; may be < 0),
    ``motor_current_A`` T_m / K_T.
    """
    law = friction_law(unit)
    load = load_ratio(unit) * clamp_force
    friction = law.coulomb + law.load_coefficient * clamp_force
    static = law.static + law.load_coefficient * clamp_force
    motor = load + friction
    return ActuatorResult(
        load_torque_Nm=load, friction_torque_Nm=friction, motor_torque_Nm=motor,
        torque_transfer_ratio=load / motor if motor > 0.0 else 0.0, static_friction_torque_Nm=static,
        release_torque_Nm=load - static,
        motor_current_A=motor / unit.require_actuator().motor.torque_constant)
