"""The actuator of paper 004 as published (Xia & Deng): Table 1 dynamics, Table 3 friction.

The project's reference unit (``embu_000``) pairs 004's motor, gear and clamp
with the railway ball screw of paper 000 (lead 5 mm). Paper 004's own figures
(30 kN load torque 2.364 N m, 73.56 % torque transfer, Table 3) belong to its
2.5 mm-lead screw, so the tests that reproduce them use this unit: the
reference file with 004's lead and the stiffness of eq. 6 from Table 1.
"""

from __future__ import annotations

import copy

from ebm_wear_monitor.params import UnitParams, load_unit, unit_from_dict
from ebm_wear_monitor.twin.clamp import series_stiffness

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
