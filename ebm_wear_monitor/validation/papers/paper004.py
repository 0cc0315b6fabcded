"""Paper 004 (Xia & Deng) reproduced: its actuator, its tables and the closed forms of its figures.

The project's reference unit (``embu_000``) pairs 004's motor, gear and clamp
with the railway ball screw of paper 000 (lead 5 mm). Paper 004's own figures
(30 kN load torque 2.364 N m, 73.56 % torque transfer, Table 3) belong to its
2.5 mm-lead screw, so the tests that reproduce them use :func:`paper_unit`: the
reference file with 004's lead and the stiffness of eq. 6 from Table 1.

Closed forms of 004 used only to reproduce its figures: gap-closing time (eq. 10-16), maximum
clamp force (eq. 17, corrected and as printed), energy ratio (eq. 43), and the system friction the
components sum to (Table 3 by eq. 40-41). The twin itself integrates eq. 1-9
(:mod:`ebm_wear_monitor.twin.dynamics`); the holding torques of ``calc actuator`` (eq. 1, 9, 42) are
:mod:`ebm_wear_monitor.twin.holding`. Printed-equation problems and how they are resolved (README.md,
"Reading the papers critically", paper 004):

* The lead ``l`` is missing from the load torque in eq. 9, 15, 16, 17 (and
  21, 29 in the components). Eq. 1 has ``T_L = l F_cl / (2 π i_g)``; with it
  the paper's own numbers follow (30 kN -> 2.364 N m), so it is restored.
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

import copy
import math

import numpy as np

from ebm_wear_monitor.params import UnitParams, load_unit, unit_from_dict
from ebm_wear_monitor.twin.clamp import series_stiffness
from ebm_wear_monitor.twin.dynamics import equivalent_inertia
from ebm_wear_monitor.twin.friction import FrictionLaw, friction_law
from ebm_wear_monitor.twin.holding import load_ratio

#: 004 Table 1 rows used beyond the unit file [N/m]; "K_b" of the table is the pad stiffness K_p
CALIPER_STIFFNESS = 6.29e7  # K_c
PAD_STIFFNESS = 3.00e8  # K_p (printed as K_b)
SCREW_STIFFNESS = 6.80e8  # K_s
LEAD = 2.5e-3  # l [m]

#: 004 Table 3, system friction referred to the motor shaft, computed from the components
TABLE3 = {
    "forward": {"static": 0.362, "coulomb": 0.327, "viscous": 1.8e-3, "load_coefficient": 1.74e-5},
    "reverse": {"static": 0.338, "coulomb": 0.303, "viscous": 1.8e-3, "load_coefficient": 1.69e-5},
}

#: 004 Table 4: friction identified on six actuators of the same design (T_fs, T_fc, B, G)
TABLE4 = [
    {"static": 0.352, "coulomb": 0.282, "viscous": 2.50e-3, "load_coefficient": 3.80e-5},
    {"static": 0.392, "coulomb": 0.302, "viscous": 2.10e-3, "load_coefficient": 3.30e-5},
    {"static": 0.302, "coulomb": 0.242, "viscous": 2.60e-3, "load_coefficient": 2.80e-5},
    {"static": 0.462, "coulomb": 0.352, "viscous": 2.90e-3, "load_coefficient": 4.80e-5},
    {"static": 0.292, "coulomb": 0.212, "viscous": 2.20e-3, "load_coefficient": 2.90e-5},
    {"static": 0.201, "coulomb": 0.192, "viscous": 2.00e-3, "load_coefficient": 2.20e-5},
]


def paper_unit(friction: dict | None = None, **actuator: float) -> UnitParams:
    """The 004 actuator: reference unit with l = 2.5 mm, K_b from eq. 6, Table 3 forward friction.

    ``friction`` replaces friction keys (e.g. a Table 4 row); ``actuator`` replaces actuator keys
    (e.g. ``supply_voltage=...``).
    """
    data = copy.deepcopy(load_unit("embu_000").raw)
    data["name"] = "actuator_004"
    data["ball_screw"]["lead"] = LEAD
    data["ball_screw"]["helix_angle_deg"] = None
    act = data["actuator"]
    act["stiffness"] = series_stiffness(CALIPER_STIFFNESS, PAD_STIFFNESS, SCREW_STIFFNESS)
    act["friction"] = dict(TABLE3["forward"]) | (friction or {})
    act.update(actuator)
    return unit_from_dict(data, "actuator_004")


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
            "gap_closing_time": a.clearance / (load_ratio(unit) * top) + (1.0 - math.exp(-4.0)) * tau}


def max_clamp_force(unit: UnitParams, law: FrictionLaw | None = None,
                    stall_torque: float | None = None) -> float:
    """004 eq. 17 corrected: ``F_clmax = (T_c - T_fs) / (l/(2 π i_g) + G)`` [N] (0 if T_c <= T_fs)."""
    law = law or friction_law(unit)
    tc = unit.require_actuator().motor.continuous_stall_torque if stall_torque is None else stall_torque
    return max(tc - law.static, 0.0) / (load_ratio(unit) + law.load_coefficient)


def max_clamp_force_printed(unit: UnitParams, static: float, load_coefficient: float,
                            stall_torque: float | None = None) -> float:
    """004 eq. 17 exactly as printed, ``(T_c - T_fs) / (1/(2 π i_g) - G)`` (no lead, minus G):
    kept to show what it gives (README.md, paper 004 item 3); not used by the twin."""
    tc = unit.require_actuator().motor.continuous_stall_torque if stall_torque is None else stall_torque
    return (tc - static) / (1.0 / (2.0 * math.pi * unit.require_actuator().gear_ratio) - load_coefficient)


def stall_torque_from_force(unit: UnitParams, force: float) -> float:
    """T_c that gives ``force`` [N] with no friction (eq. 17 with T_fs = G = 0) [N m]."""
    return load_ratio(unit) * force


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
