"""Actuator values of one unit file, read with plain pyyaml (no project parser).

Only the *values* of a unit YAML are used (interface.md section 3): the ``actuator`` block (004
Table 1 and eq. 9), the ball-screw ``lead`` and the optional ``monitor.clearance_limit``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

import yaml

#: The project's reference unit file (read as data, never imported).
REFERENCE_UNIT = Path(__file__).resolve().parents[2] / "params" / "reference" / "embu_000.yaml"


@dataclass(frozen=True)
class Actuator:
    """Lumped actuator of 004 (eq. 1-9), every value SI.

    Angles are motor-side unless named ``screw``; ``r_g`` converts motor angle to nut travel.
    """

    K_T: float  # torque constant [N m/A] (004 eq. 7)
    K_E: float  # back-EMF constant [V s/rad] (004 eq. 8)
    R: float  # armature resistance [ohm]
    L: float  # armature inductance [H]
    J_m: float  # motor inertia [kg m^2]
    J_g: float  # gear inertia referred to the motor [kg m^2]
    J_s: float  # screw inertia [kg m^2]
    m_n: float  # nut mass [kg]
    i_g: float  # gear ratio, motor turns per screw turn [-]
    lead: float  # ball-screw lead l [m]
    x_ag: float  # nominal clearance [m]
    K_b: float  # clamp stiffness [N/m] (004 eq. 5-6)
    T_fs: float  # static friction torque [N m] (004 eq. 9)
    T_fc: float  # Coulomb friction torque [N m]
    B: float  # viscous coefficient [N m s/rad]
    G: float  # load coefficient [N m/N]
    clearance_limit: float  # clearance at which maintenance is due [m]

    @property
    def r_g(self) -> float:
        """Nut travel per motor radian l / (2 pi i_g) [m/rad] (004 eq. 3-4)."""
        return self.lead / (2.0 * math.pi * self.i_g)

    @property
    def J_me(self) -> float:
        """Equivalent inertia at the motor, 004 eq. 2 [kg m^2]."""
        return self.J_m + self.J_g + self.J_s / self.i_g**2 + self.r_g**2 * self.m_n

    def with_(self, **changes: float) -> Actuator:
        """A copy with some values changed."""
        return replace(self, **changes)


def load_actuator(path: str | Path = REFERENCE_UNIT) -> Actuator:
    """Read the actuator block of a unit YAML; a missing key raises ``KeyError`` naming it."""
    doc = yaml.safe_load(Path(path).read_text())
    act = doc["actuator"]
    motor = act["motor"]
    fr = act["friction"]
    monitor = doc.get("monitor") or {}
    return Actuator(
        K_T=float(motor["torque_constant"]), K_E=float(motor["back_emf_constant"]),
        R=float(motor["resistance"]), L=float(motor["inductance"]), J_m=float(motor["inertia"]),
        J_g=float(act["gear_inertia"]), J_s=float(act["screw_inertia"]), m_n=float(act["nut_mass"]),
        i_g=float(act["gear_ratio"]), lead=float(doc["ball_screw"]["lead"]),
        x_ag=float(act["clearance"]), K_b=float(act["stiffness"]),
        T_fs=float(fr["static"]), T_fc=float(fr["coulomb"]), B=float(fr["viscous"]),
        G=float(fr["load_coefficient"]),
        clearance_limit=float(monitor.get("clearance_limit", 0.5e-3)),
    )
