"""Force equilibrium of one ball with load-dependent contact angles: 000 eq. 15-18 and Fig. 6.

Ball equilibrium in its bn-plane (000 eq. 15, n radial towards the axis, b axial),
with normal loads Q_s, Q_n, friction f_X = mu_e Q (eq. 13-14) and centrifugal F_c (eq. 12):

    -Q_s cos a_s + f_Xs sin a_s + Q_n cos a_n + f_Xn sin a_n - F_c = 0     (radial)
     Q_s sin a_s + f_Xs cos a_s - Q_n sin a_n + f_Xn cos a_n       = 0     (axial)

Printed like this the system is homogeneous in the loads except for F_c: nothing in
it carries the axial force, so with F_c -> 0 it has only the trivial solution
(trap 4 of the notes). It is closed here by the load the ball transmits, the
axial share of one ball as in eq. 5:

     Q_s sin a_s + f_Xs cos a_s = P = F_a / (Z cos phi)                     (closure)

With tan(psi) = mu_e the closure and the axial balance give the loads in closed form,
Q_s = P / (sin a_s + mu_s cos a_s), Q_n = P / (sin a_n - mu_n cos a_n), and the radial
balance becomes P [cot(a_n - psi_n) - cot(a_s + psi_s)] = F_c, i.e. the contact angles
differ by the two friction angles (plus the centrifugal correction).

Geometry (000 eq. 16-18): with the nut groove centre fixed, the ball centre sits at
L_n = r_n - r_b + delta_n from it and L_s = r_s - r_b + delta_s from the screw groove
centre, which is displaced to (A_1, A_2). The screw is centred in the nut (delta_r = 0),
so A_2 = (r_s + r_n - 2 r_b) cos a_0, and eq. 17-18 reduce to

    L_s cos a_s + L_n cos a_n = A_2,    A_1 = L_s sin a_s + L_n sin a_n.

A_1 - (r_s + r_n - 2 r_b) sin a_0 = theta' R* + delta_a is the axial approach of screw and
nut: an *output* of the solve. Fixing theta' = 2 deg as 000 Sec. 4.2 suggests makes
theta' R* ~ 0.56 mm, several times L_s + L_n, and eq. 17 has no solution (trap 6).

Iteration (Fig. 6): start from a_s = a_n = a_0 and eq. 5; then repeat
kinematics (eq. 8-12) -> friction (13-14) -> loads (15 + closure) -> deformations
(eq. 1) -> contact angles (16-18), until the largest relative change of the contact
deformations is below ``rel_tol``. Each step is closed-form and vectorised, so all
samples iterate together. Without friction and F_c the solution is the classical
cos a = A_2 / (r_s + r_n - 2 r_b + delta_s + delta_n) (Harris), which the tests check.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ebm_wear_monitor.arrays import FloatArray
from ebm_wear_monitor.params.unit import UnitParams
from ebm_wear_monitor.physics.friction import equivalent_friction
from ebm_wear_monitor.physics.geometry import NUT, SCREW, ScrewGeometry, curvature
from ebm_wear_monitor.physics.hertz import deformation, normal_load
from ebm_wear_monitor.physics.kinematics import BallMotion, ball_motion
from ebm_wear_monitor.physics.options import ModelOptions


class Equilibrium(NamedTuple):
    alpha_s: FloatArray  # loaded contact angle at the screw [rad]
    alpha_n: FloatArray  # loaded contact angle at the nut [rad]
    q_s: FloatArray  # normal load screw contact [N]
    q_n: FloatArray  # normal load nut contact [N]
    delta_s: FloatArray  # Hertz approach screw contact [m]
    delta_n: FloatArray  # Hertz approach nut contact [m]
    mu_s: FloatArray  # equivalent friction coefficient screw contact [-]
    mu_n: FloatArray  # equivalent friction coefficient nut contact [-]
    axial_approach: FloatArray  # theta' R* + delta_a [m]
    motion: BallMotion  # kinematics at the converged angles
    iterations: int  # Fig. 6 iterations used
    converged: bool = True  # False when max_iter ran out before the change fell below rel_tol


def _friction(unit: UnitParams, geo: ScrewGeometry, side: str, *, q: FloatArray, alpha: FloatArray,
              u: FloatArray) -> FloatArray:
    c = curvature(geo, side, alpha)
    lub = unit.lubricant
    return equivalent_friction(q, u, c.r_x, c.gamma, e_red=geo.modulus(side), viscosity=lub.viscosity,
                               pressure_viscosity=lub.pressure_viscosity,
                               roughness=unit.materials.composite_roughness,
                               boundary_friction=unit.wear.boundary_friction)


def _max_rel(new: FloatArray, old: FloatArray) -> float:
    return float(np.max(np.abs(new - old) / np.maximum(new, 1e-300), initial=0.0))


def solve_equilibrium(unit: UnitParams, axial_force: FloatArray, omega_s: FloatArray,
                      options: ModelOptions, geo: ScrewGeometry | None = None) -> Equilibrium:
    """Fig. 6 iteration for arrays of axial force F_a > 0 [N] and screw speed |w_s| [rad/s]."""
    geo = geo or ScrewGeometry.from_unit(unit)
    f_a = np.asarray(axial_force, dtype=np.float64)
    w_s = np.abs(np.asarray(omega_s, dtype=np.float64))
    p = f_a / (geo.z * math.cos(geo.phi))
    a0 = geo.alpha0
    a_s = np.full_like(f_a, a0)
    a_n = np.full_like(f_a, a0)
    q_s = normal_load(f_a, geo.z, a_s, geo.phi)
    q_n = q_s.copy()
    c_s, c_n = curvature(geo, SCREW, a_s), curvature(geo, NUT, a_n)
    delta_s = deformation(q_s, c_s.sum_rho, c_s.gamma, geo.e_s)
    delta_n = deformation(q_n, c_n.sum_rho, c_n.gamma, geo.e_n)
    b0 = geo.centre_distance0
    a2 = b0 * math.cos(a0)
    iterations, change = 0, math.inf
    while iterations < options.max_iter:
        iterations += 1
        motion = ball_motion(geo, w_s, a_s, a_n, reading=options.kinematics, beta=options.beta)
        u = np.abs(motion.omega_r) * geo.r_b
        mu_s = _friction(unit, geo, SCREW, q=q_s, alpha=a_s, u=u)
        mu_n = _friction(unit, geo, NUT, q=q_n, alpha=a_n, u=u)
        psi_s, psi_n = np.arctan(mu_s), np.arctan(mu_n)
        q_s = p / (np.sin(a_s) + mu_s * np.cos(a_s))
        q_n = p / (np.sin(a_n) - mu_n * np.cos(a_n))
        c_s, c_n = curvature(geo, SCREW, a_s), curvature(geo, NUT, a_n)
        new_ds = deformation(q_s, c_s.sum_rho, c_s.gamma, geo.e_s)
        new_dn = deformation(q_n, c_n.sum_rho, c_n.gamma, geo.e_n)
        # radial balance: a_n = psi_n + arccot(cot(a_s + psi_s) + F_c / P), written as a_n - a_s = D
        cot_n = 1.0 / np.tan(a_s + psi_s) + motion.centrifugal / p
        diff = psi_n + np.arctan2(1.0, cot_n) - a_s
        l_s = geo.r_s - geo.r_b + new_ds
        l_n = geo.r_n - geo.r_b + new_dn
        # L_s cos a + L_n cos(a + D) = A_2  ->  R cos(a + eps) = A_2
        big_x = l_s + l_n * np.cos(diff)
        big_y = l_n * np.sin(diff)
        new_as = np.arccos(np.clip(a2 / np.hypot(big_x, big_y), -1.0, 1.0)) - np.arctan2(big_y, big_x)
        change = max(_max_rel(new_ds, delta_s), _max_rel(new_dn, delta_n),
                     float(np.max(np.abs(new_as - a_s), initial=0.0)))
        a_s, a_n = new_as, new_as + diff
        delta_s, delta_n = new_ds, new_dn
        if change < options.rel_tol:
            break
    # loads and deformations at the converged angles (eq. 15 + closure, eq. 1)
    motion = ball_motion(geo, w_s, a_s, a_n, reading=options.kinematics, beta=options.beta)
    q_s = p / (np.sin(a_s) + mu_s * np.cos(a_s))
    q_n = p / (np.sin(a_n) - mu_n * np.cos(a_n))
    c_s, c_n = curvature(geo, SCREW, a_s), curvature(geo, NUT, a_n)
    delta_s = deformation(q_s, c_s.sum_rho, c_s.gamma, geo.e_s)
    delta_n = deformation(q_n, c_n.sum_rho, c_n.gamma, geo.e_n)
    l_s = geo.r_s - geo.r_b + delta_s
    l_n = geo.r_n - geo.r_b + delta_n
    approach = l_s * np.sin(a_s) + l_n * np.sin(a_n) - b0 * math.sin(a0)
    return Equilibrium(a_s, a_n, q_s, q_n, delta_s, delta_n, mu_s, mu_n, approach, motion, iterations,
                       change < options.rel_tol)
