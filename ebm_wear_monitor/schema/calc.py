"""The calculators' results (``ebm-wear calc contact|wear|actuator --json``), declared once.

Keys are interface.md section 4's (``normal_load_N``, ``max_pressure_Pa`` ...: the contract spells
the unit into the name) plus the project's additions. ``physics/reports.py`` and
``twin/holding.py`` build these records; the CLI writes their JSON.
"""

from __future__ import annotations

from dataclasses import dataclass

from ebm_wear_monitor.schema.fields import Record, quantity

#: contact type of 000 eq. 6 (interference below or above the critical one)
CONTACT_TYPES = ("elastic", "elastic-plastic")


@dataclass(frozen=True)
class ContactSide(Record):
    """Static contact of one ball with one raceway (000 eq. 1-7, 003 eq. 1-5, 14-15)."""

    normal_load_N: float = quantity("N", "normal load per ball Q (003 eq. 1 / 000 eq. 5)",
                                    json="normal_load_N")
    semi_major_m: float = quantity("m", "semi-major axis a of the contact ellipse (003 eq. 2-5)",
                                   json="semi_major_m")
    semi_minor_m: float = quantity("m", "semi-minor axis b of the contact ellipse", json="semi_minor_m")
    max_pressure_Pa: float = quantity("Pa", "peak Hertz pressure (003 eq. 14-15)", json="max_pressure_Pa")
    deformation_m: float = quantity("m", "elastic approach delta (000 eq. 1)", json="deformation_m")
    contact_type: str = quantity("", "elastic or elastic-plastic (000 eq. 6)", json="contact_type",
                                 enum=CONTACT_TYPES)
    contact_area_m2: float = quantity("m^2", "real contact area (000 eq. 7)", json="contact_area_m2")
    contact_angle_deg: float = quantity("deg", "contact angle (unloaded)", json="contact_angle_deg")
    critical_interference_m: float = quantity("m", "critical interference delta_c (000 eq. 6)",
                                              json="critical_interference_m")


@dataclass(frozen=True)
class ContactResult(Record):
    """``ebm-wear calc contact``: one ball on the screw and on the nut raceway."""

    screw: ContactSide = quantity("", "ball on the screw raceway", json="screw")
    nut: ContactSide = quantity("", "ball on the nut raceway", json="nut")


@dataclass(frozen=True)
class WearSide(Record):
    """Wear state of one raceway at a constant force and speed (000 eq. 5-23)."""

    normal_load_N: float = quantity("N", "normal load per ball from the Fig. 6 equilibrium",
                                    json="normal_load_N")
    contact_angle_deg: float = quantity("deg", "loaded contact angle", json="contact_angle_deg")
    sliding_velocity_m_s: float = quantity("m/s", "sliding velocity in the contact (000 eq. 19)",
                                           json="sliding_velocity_m_s")
    contact_area_m2: float = quantity("m^2", "real contact area (000 eq. 7)", json="contact_area_m2")
    contact_type: str = quantity("", "elastic or elastic-plastic (000 eq. 6)", json="contact_type",
                                 enum=CONTACT_TYPES)
    wear_rate_m_s: float = quantity("m/s", "wear-depth rate dh/dt of that raceway (000 eq. 20-23)",
                                    json="wear_rate_m_s")
    deformation_m: float = quantity("m", "elastic approach delta (000 eq. 1)", json="deformation_m")


@dataclass(frozen=True)
class ReadingOptions(Record):
    """The readings of paper 000 a result was computed with (physics/options.py ``ModelOptions``)."""

    kinematics: str = quantity("", "reading of 000 eq. 10-11, 19", json="kinematics")
    radius: str = quantity("", "R of 000 eq. 6-7", json="radius")
    kappa: str = quantity("", "kappa in Horng's functions of 000 eq. 7", json="kappa")
    gyroscopic_angle_deg: float = quantity("deg", "gyroscopic angle beta_b (000 Sec. 3.2)",
                                           json="gyroscopic_angle_deg")
    rel_tol: float = quantity("-", "stop tolerance of the Fig. 6 iteration", json="rel_tol")
    max_iter: int = quantity("-", "iteration limit of Fig. 6", json="max_iter")


@dataclass(frozen=True)
class WearResult(Record):
    """``ebm-wear calc wear``: wear state at a constant axial force and screw speed (000 eq. 5-23)."""

    screw: WearSide = quantity("", "screw raceway", json="screw")
    nut: WearSide = quantity("", "nut raceway", json="nut")
    ball_wear_rate_m_s: float = quantity("m/s", "wear-depth rate of the balls (radius loss)",
                                         json="ball_wear_rate_m_s")
    clearance_growth_rate_m_s: float = quantity("m/s", "growth rate of the axial clearance x_ag",
                                                json="clearance_growth_rate_m_s")
    iterations: int = quantity("-", "iterations of the Fig. 6 equilibrium", json="iterations")
    options: ReadingOptions = quantity("", "the readings used", json="options")


@dataclass(frozen=True)
class ActuatorResult(Record):
    """``ebm-wear calc actuator``: torques at the motor shaft holding a clamp force (004 eq. 1, 9, 42)."""

    load_torque_Nm: float = quantity("N m", "load torque T_L = l F / (2 pi i_g) (004 eq. 1)",
                                     json="load_torque_Nm")
    friction_torque_Nm: float = quantity("N m", "kinetic friction T_fc + G F (004 eq. 9)",
                                         json="friction_torque_Nm")
    motor_torque_Nm: float = quantity("N m", "motor torque T_m = T_L + T_f", json="motor_torque_Nm")
    torque_transfer_ratio: float = quantity("-", "l_e = T_L / T_m, a fraction 0 to 1 (004 eq. 42)",
                                            json="torque_transfer_ratio")
    static_friction_torque_Nm: float = quantity("N m",
                                                "static friction T_fs + G F: most the stuck drive resists",
                                                json="static_friction_torque_Nm")
    release_torque_Nm: float = quantity("N m",
                                        "T_L - (T_fs + G F): below it the screw back-drives (may be < 0)",
                                        json="release_torque_Nm")
    motor_current_A: float = quantity("A", "armature current T_m / K_T", json="motor_current_A")
