"""Paper 004 reproduced: component friction of its actuator and the system law it sums to (Sec. 3, eq. 18-41).

Used to reproduce 004 Table 3 and Fig. 5-6 from components (the twin takes the eq. 9 law from the
unit file, :mod:`ebm_wear_monitor.twin.friction`).

Motor (eq. 18, Table 2 measured), moving parts (eq. 20-22), SKF thrust-bearing
model (eq. 23-25), ball screw with preload and forward/reverse efficiency
(eq. 26-33), planetary-gear mesh (eq. 34-39), summed at the motor shaft by
power equivalence (eq. 40)::

    T_f = T_fm + (T_fg + T_fb + T_fscr) / i_g + l F_fm / (2 π i_g)

and reduced to the four parameters of eq. 9 (Table 3) by
``T_fs/T_fc = motor static/Coulomb + the rest at zero load``,
``G = d T_f / d F_cl`` and ``B = d T_f / d ω`` (least squares over 0-40 rad/s).

The lead is restored where the print drops it: eq. 21 (the key force is the
nut torque ``l F / (2 π)`` over the key radius), eq. 29, 33, 35, 38 (screw
torque ``l F_n / (2 π)``).

Inputs 004 does not print, with the choice made (:class:`ComponentInputs`):

* ball-screw efficiency without preload η = 0.90 (a manufacturer's catalogue
  value for a precision ball screw); reverse efficiency η_r = 2 - 1/η
  (004 Sec. 3.4);
* preload F_p = 10 kN: 004's "F_p = F_cl/3" read as one third of the maximum
  clamp force (30 kN), the classical preload rule; taken literally (a third of
  the momentary force) the screw would have no friction at zero load, against
  Fig. 6a where it carries 45.5 % of the start-up friction;
* thrust bearing: SKF model for a thrust roller bearing, f_1 = 0.0015,
  a = b = 1, f_0 = 3 (grease), ν = 100 mm²/s, mean diameter d_m = 17.5 mm
  (chosen so that the bearing takes Fig. 6b's 17.9 % at 30 kN);
* planetary gear: mesh efficiency 0.985 forward and reverse (single stage,
  chosen for Fig. 6b's 4.9 %); its bearings' share is within the mesh value;
* moving parts: key radius R_k = 15 mm, key friction μ_k = 0.10, pad-disc
  μ_b = 0.35, pad-slot μ_c = 0.07 (Fig. 6b's 6.9 %).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ebm_wear_monitor.arrays import Floats
from ebm_wear_monitor.twin.friction import SCREW_EFFICIENCY


@dataclass(frozen=True)
class ComponentInputs:
    """Component data of the 004 actuator (SI units; choices documented in the module docstring)."""

    lead: float = 2.5e-3  # l [m] (004 Table 1)
    gear_ratio: float = 5.05  # i_g [-] (Table 1)
    motor_static: float = 0.189  # T_fsm [N m] (Table 2)
    motor_coulomb: float = 0.154  # T_fcm [N m] (Table 2)
    motor_viscous: float = 1.77e-3  # B_m [N m s/rad] (Table 2)
    screw_efficiency: float = SCREW_EFFICIENCY  # η, forward, without preload [-]
    preload: float = 10.0e3  # F_p [N]
    bearing_f0: float = 3.0  # SKF f_0 [-]
    bearing_f1: float = 0.0015  # SKF f_1 [-]
    bearing_a: float = 1.0  # SKF exponent a [-]
    bearing_b: float = 1.0  # SKF exponent b [-]
    bearing_mean_diameter: float = 17.5e-3  # d_m = (d + D) / 2 [m]
    lubricant_kinematic_viscosity: float = 100.0e-6  # ν at working temperature [m^2/s]
    gear_efficiency: float = 0.985  # η_g, forward mesh efficiency [-]
    gear_reverse_efficiency: float = 0.985  # η_gr [-]
    key_radius: float = 15.0e-3  # R_k [m]
    key_friction: float = 0.10  # μ_k [-]
    pad_disc_friction: float = 0.35  # μ_b [-]
    pad_slot_friction: float = 0.07  # μ_c [-]

    @property
    def reverse_screw_efficiency(self) -> float:
        """η_r = 2 - 1/η (004 Sec. 3.4)."""
        return 2.0 - 1.0 / self.screw_efficiency


def moving_parts_force(c: ComponentInputs, force: np.ndarray) -> np.ndarray:
    """004 eq. 20-22: ``F_fm = μ_k l F / (2 π R_k) + μ_b μ_c F`` [N] (lead restored in eq. 21)."""
    return (c.key_friction * c.lead / (2.0 * math.pi * c.key_radius) + c.pad_disc_friction
            * c.pad_slot_friction) * np.asarray(force, float)


def bearing_torque(c: ComponentInputs, screw_speed: np.ndarray, load: np.ndarray) -> np.ndarray:
    """SKF model, 004 eq. 23-25: ``T_fb = M_0 + M_1`` [N m] at screw speed [rad/s] and axial load [N].

    In the model's own units (N mm, mm, mm²/s, r/min): ``M_0 = 160e-7 f_0 d_m^3`` when
    ``ν n < 2000``, else ``1e-7 f_0 (ν n)^(2/3) d_m^3``; ``M_1 = f_1 P_1^a d_m^b``.
    """
    dm_mm, nu_mm2 = c.bearing_mean_diameter * 1e3, c.lubricant_kinematic_viscosity * 1e6
    vn = nu_mm2 * np.abs(np.asarray(screw_speed, float)) * 60.0 / (2.0 * math.pi)
    m0 = 1e-7 * c.bearing_f0 * np.maximum(vn, 2000.0) ** (2.0 / 3.0) * dm_mm**3
    m1 = c.bearing_f1 * np.abs(np.asarray(load, float)) ** c.bearing_a * dm_mm**c.bearing_b
    return (m0 + m1) * 1e-3


def screw_torque(c: ComponentInputs, output_force: np.ndarray, forward: bool) -> np.ndarray:
    """Ball-screw friction torque at the screw [N m] (004 eq. 29 apply, eq. 33 release, lead restored).

    Apply: ``(1/η - 1) l F_n / 2π + l F_p (1/η - η) / 2π``;
    release: ``(1 - η_r) l F_n / 2π + l F_p η_r (1 - η_r²) / 2π``.
    """
    k = c.lead / (2.0 * math.pi)
    fn = np.asarray(output_force, float)
    if forward:
        eta = c.screw_efficiency
        return k * ((1.0 / eta - 1.0) * fn + c.preload * (1.0 / eta - eta))
    eta_r = c.reverse_screw_efficiency
    return k * ((1.0 - eta_r) * fn + c.preload * eta_r * (1.0 - eta_r**2))


def component_torques(c: ComponentInputs, motor_speed: Floats, clamp_force: Floats,
                      forward: bool = True) -> dict[str, np.ndarray]:
    """Every component's friction and their eq. 40 sum, at the motor shaft [N m].

    Keys: ``motor``, ``gear``, ``bearing``, ``screw``, ``moving`` (the terms of eq. 40 each
    referred to the motor shaft), ``total`` (T_f), and ``shares`` (eq. 41, fractions of T_f).
    The motor term is its sliding law ``T_fcm + B_m |ω|`` (eq. 18) for ω ≠ 0 and its static
    level ``T_fsm`` at ω = 0.
    """
    omega = np.asarray(motor_speed, float)
    force = np.asarray(clamp_force, float)
    f_fm = moving_parts_force(c, force)
    fn = force + f_fm if forward else force - f_fm  # eq. 27 / eq. 31
    t_scr = screw_torque(c, fn, forward)
    t_b = bearing_torque(c, omega / c.gear_ratio, fn)
    carrier = c.lead * fn / (2.0 * math.pi)
    if forward:  # eq. 36
        t_g = (carrier + t_scr + t_b) * (1.0 / c.gear_efficiency - 1.0)
    else:  # eq. 39
        t_g = (carrier - t_scr - t_b) * (1.0 - c.gear_reverse_efficiency)
    motor = np.where(omega == 0.0, c.motor_static, c.motor_coulomb + c.motor_viscous * np.abs(omega))
    terms = {"motor": motor, "gear": t_g / c.gear_ratio, "bearing": t_b / c.gear_ratio,
             "screw": t_scr / c.gear_ratio, "moving": c.lead * f_fm / (2.0 * math.pi * c.gear_ratio)}
    total = sum(terms.values())
    return terms | {"total": total, "shares": {k: v / total for k, v in terms.items()}}


def system_friction(c: ComponentInputs, forward: bool = True, force_span: float = 30.0e3,
                    speed_span: float = 40.0) -> dict[str, float]:
    """The four eq. 9 parameters the components sum to (004 Table 3 by eq. 40-41).

    T_fs: total at standstill and zero load; T_fc: the sliding total extrapolated to zero
    speed at zero load; B: least-squares slope over 0 < ω <= ``speed_span`` [rad/s] at zero
    load; G: slope of the total from 0 to ``force_span`` [N] (exact: every load term is linear).
    """
    speeds = np.linspace(speed_span / 40.0, speed_span, 40)
    sliding = component_torques(c, speeds, 0.0, forward)["total"]
    viscous, coulomb = np.polyfit(speeds, sliding, 1)
    static = float(component_torques(c, 0.0, 0.0, forward)["total"])
    loaded = float(component_torques(c, 0.0, force_span, forward)["total"])
    return {"static": static, "coulomb": float(coulomb), "viscous": float(viscous),
            "load_coefficient": (loaded - static) / force_span}
