"""Closed forms of paper 004: gap-closing time (eq. 10-16), maximum clamp force (eq. 17), torques in
force maintenance and the effective torque transfer ratio (eq. 42), energy ratio (eq. 43).

Printed-equation problems and how they are resolved here (build/notes/twin.md):

* The lead ``l`` is missing from the load torque in eq. 9, 15, 16, 17 (and
  21, 29 in the components). Eq. 1 has ``T_L = l F_cl / (2 π i_g)``; with it
  the paper's own numbers follow (30 kN -> 2.364 N m), so it is restored.
* Holding friction: Sec. 2.2 and 4.1 write ``T_f = T_fs + G F_cl`` in
  maintenance, but Sec. 4.1's numbers (30 kN: T_f = 0.849 N m, T_m = 3.213
  N m, 73.56 %) are ``T_fc + G F_cl``. Both have a meaning: a force reached by
  pushing forward is held at the kinetic level ``T_fc + G F`` (the torque that
  just keeps pushing, used for ``motor_torque_Nm``), and ``T_fs + G F`` is the
  largest friction the stuck drive can resist (the 0.884 N m of Fig. 5b).
* Eq. 17, ``F_clmax = (T_c - T_fs) / (1/(2 π i_g) - G)``: besides the missing
  ``l``, the sign of G is wrong (friction opposes the apply motion, so G adds
  to the load torque: ``T_c = (l/(2 π i_g) + G) F + T_fs``), and with the
  printed G range (1e-3 N m/N, 12.7 times l/(2 π i_g)) the printed form would
  even turn negative. The continuous stall torque T_c is not given; the
  friction-free 37.30 kN implies T_c = 37.30 kN * l/(2 π i_g) = 2.939 N m.
* Eq. 10-11 take ``T_f = T_fs + B ω`` in the text but ``T_fc`` in the
  formula; a moving drive has the Coulomb level, so ``T_fc`` is used. The peak
  voltage E_amax is not given; the unit's ``actuator.supply_voltage`` is used.
"""

from __future__ import annotations

import math

import numpy as np

from ebm_wear_monitor.params import UnitParams
from ebm_wear_monitor.schema.calc import ActuatorResult
from ebm_wear_monitor.twin.dynamics import equivalent_inertia
from ebm_wear_monitor.twin.friction import FrictionLaw, friction_law


def _transmission(unit: UnitParams) -> float:
    return unit.ball_screw.lead / (2.0 * math.pi * unit.require_actuator().gear_ratio)


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
    load = _transmission(unit) * clamp_force
    friction = law.coulomb + law.load_coefficient * clamp_force
    static = law.static + law.load_coefficient * clamp_force
    motor = load + friction
    return ActuatorResult(
        load_torque_Nm=load, friction_torque_Nm=friction, motor_torque_Nm=motor,
        torque_transfer_ratio=load / motor if motor > 0.0 else 0.0, static_friction_torque_Nm=static,
        release_torque_Nm=load - static,
        motor_current_A=motor / unit.require_actuator().motor.torque_constant)


def gap_closing(unit: UnitParams, law: FrictionLaw | None = None,
                voltage: float | None = None) -> dict[str, float]:
    """004 eq. 12-16 (inductance neglected): top speed K, time constant T, gap-closing time T_ag.

    ``K = (K_T E - T_fc R) / (B R + K_E K_T)``, ``T = J_me R / (B R + K_E K_T)``,
    ``T_ag = 2 π i_g x_ag / (l K) + (1 - e^{-4}) T`` (eq. 16 with the lead restored; the
    printed 0.9817 is 1 - e^{-4}). Speeds at the motor shaft [rad/s], times [s].
    """
    a, law = unit.require_actuator(), law or friction_law(unit)
    m = a.motor
    e = a.supply_voltage if voltage is None else voltage
    denominator = law.viscous * m.resistance + m.back_emf_constant * m.torque_constant
    top = (m.torque_constant * e - law.coulomb * m.resistance) / denominator
    tau = equivalent_inertia(unit) * m.resistance / denominator
    return {"top_speed": top, "time_constant": tau,
            "gap_closing_time": a.clearance / (_transmission(unit) * top) + (1.0 - math.exp(-4.0)) * tau}


def max_clamp_force(unit: UnitParams, law: FrictionLaw | None = None,
                    stall_torque: float | None = None) -> float:
    """004 eq. 17 corrected: ``F_clmax = (T_c - T_fs) / (l/(2 π i_g) + G)`` [N] (0 if T_c <= T_fs)."""
    law = law or friction_law(unit)
    tc = unit.require_actuator().motor.continuous_stall_torque if stall_torque is None else stall_torque
    return max(tc - law.static, 0.0) / (_transmission(unit) + law.load_coefficient)


def max_clamp_force_printed(unit: UnitParams, static: float, load_coefficient: float,
                            stall_torque: float | None = None) -> float:
    """004 eq. 17 exactly as printed, ``(T_c - T_fs) / (1/(2 π i_g) - G)`` (no lead, minus G):
    kept to show what it gives (build/notes/twin.md); not used by the twin."""
    tc = unit.require_actuator().motor.continuous_stall_torque if stall_torque is None else stall_torque
    return (tc - static) / (1.0 / (2.0 * math.pi * unit.require_actuator().gear_ratio) - load_coefficient)


def stall_torque_from_force(unit: UnitParams, force: float) -> float:
    """T_c that gives ``force`` [N] with no friction (eq. 17 with T_fs = G = 0) [N m]."""
    return _transmission(unit) * force


def energy_balance(motor_torque: np.ndarray, friction_torque: np.ndarray, load_torque: np.ndarray,
                   motor_speed: np.ndarray, dt: float) -> dict[str, float]:
    """004 eq. 43: W_i = ∫ T_m ω dt, W_f = ∫ T_f ω dt, W_L = ∫ T_L ω dt [J] and φ_f = W_f / W_i.

    Arrays at the motor shaft sampled every ``dt``; ``motor_speed`` is the mean speed over each
    step (so the sums are exact for the twin's integrator).
    """
    w = np.asarray(motor_speed) * dt
    wi, wf, wl = (float(np.sum(np.asarray(x) * w)) for x in (motor_torque, friction_torque, load_torque))
    return {"motor_work_J": wi, "friction_work_J": wf, "load_work_J": wl,
            "dissipation_ratio": wf / wi if wi > 0.0 else 0.0}
