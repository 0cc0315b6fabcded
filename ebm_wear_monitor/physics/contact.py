"""Direct, vectorised solve of the whole 000 chain for arrays of axial force and screw speed.

For each sample: Fig. 6 equilibrium (eq. 1-5, 8-18, :mod:`equilibrium`), then per
raceway the contact type and area (eq. 6-7, :mod:`plasticity`), the sliding speed
(eq. 19, :mod:`kinematics`) and the Archard wear-depth rate (eq. 20-23,
:mod:`archard`). No Python loop over samples: all samples iterate together.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ebm_wear_monitor.arrays import BoolArray, FloatArray
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.params.unit import UnitParams
from ebm_wear_monitor.physics.archard import wear_rate
from ebm_wear_monitor.physics.equilibrium import Equilibrium, solve_equilibrium
from ebm_wear_monitor.physics.geometry import NUT, SCREW, ScrewGeometry, curvature
from ebm_wear_monitor.physics.options import ModelOptions
from ebm_wear_monitor.physics.plasticity import contact_area


class SideState(NamedTuple):
    """State of one contact (screw or nut raceway), arrays over samples."""

    normal_load: FloatArray  # Q [N]
    alpha: FloatArray  # loaded contact angle [rad]
    deformation: FloatArray  # delta [m]
    area: FloatArray  # A_c [m^2]
    plastic: BoolArray  # elastic-plastic contact (bool)
    sliding_velocity: FloatArray  # V [m/s]
    wear_rate: FloatArray  # dh/dt [m/s]


def area_radius(unit: UnitParams, sum_rho: FloatArray, reading: str) -> FloatArray:
    """R of 000 eq. 6-7 under the chosen reading (see :mod:`plasticity`) [m]."""
    if reading == "hertz":
        return 2.0 / sum_rho
    if reading == "asperity":
        if unit.materials.asperity_radius is None:
            raise InputError("physics option radius='asperity' needs materials.asperity_radius "
                             "in the unit file")
        return np.full_like(sum_rho, unit.materials.asperity_radius)
    return np.full_like(sum_rho, unit.materials.composite_roughness)


def side_state(unit: UnitParams, geo: ScrewGeometry, eq: Equilibrium, side: str,
               options: ModelOptions) -> SideState:
    """Contact area (eq. 6-7) and Archard rate (eq. 23) of one raceway at the converged equilibrium."""
    if side == SCREW:
        q, alpha, delta, v, mat = eq.q_s, eq.alpha_s, eq.delta_s, eq.motion.v_screw, unit.materials.screw
    else:
        q, alpha, delta, v, mat = eq.q_n, eq.alpha_n, eq.delta_n, eq.motion.v_nut, unit.materials.nut
    if mat.hardness is None or mat.yield_strength is None:  # load_unit requires both for raceways
        raise InputError(f"the {side} raceway material needs hardness and yield_strength (000 eq. 6, 23)")
    c = curvature(geo, side, alpha)
    ca = contact_area(delta, c.gamma, area_radius(unit, c.sum_rho, options.radius), hardness=mat.hardness,
                      poisson_ratio=softer_poisson(unit, side), e_red=geo.modulus(side),
                      kappa_reading=options.kappa)
    rate = wear_rate(unit.wear.k_slip, q, v, mat.yield_strength, ca.area)
    return SideState(q, alpha, delta, ca.area, ca.plastic, v, rate)


def softer_poisson(unit: UnitParams, side: str) -> float:
    """Poisson ratio of the softer body of the contact (the raceway, 000 Sec. 3.3) for K of eq. 6."""
    return (unit.materials.screw if side == SCREW else unit.materials.nut).poisson_ratio


def solve(unit: UnitParams, axial_force: FloatArray, omega_s: FloatArray,
          options: ModelOptions) -> tuple[Equilibrium, SideState, SideState]:
    """Fig. 6 equilibrium (000 eq. 1-5, 8-18) plus screw and nut contact states (000 eq. 6-7, 19-23)
    for loaded samples: axial force F_a [N] > 0 and screw speed omega_s [rad/s], both finite."""
    geo = ScrewGeometry.from_unit(unit)
    eq = solve_equilibrium(unit, axial_force, omega_s, options, geo)
    return eq, side_state(unit, geo, eq, SCREW, options), side_state(unit, geo, eq, NUT, options)
