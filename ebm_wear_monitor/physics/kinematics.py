"""Ball kinematics and sliding velocities: 000 eq. 8-12 and 19 (after Wei & Lin [38], Lin et al. [41]).

Angular velocities (000 eq. 8-9), screw speed w_s [rad/s], gamma' = 2 r_b / D_m,
gyroscopic angle beta (47 deg, 000 Sec. 3.2):

    w_m = w_s / (1 + (1 + g' cos a_n)(cos a_s + tan(beta) sin a_s)
                     / ((1 - g' cos a_s)(cos a_n + tan(beta) sin a_n)))      orbit (cyclic) speed
    w_R = -(1 + g' cos a_n) cos(phi) / (g' cos(beta - a_n)) * w_m             ball spin

Eq. 8 and 9 are exactly the no-slip conditions along the ball path at the screw and at
the nut written in the frame that turns with the ball orbit: the ball's rolling rate
-w_R cos(beta - a) carries its surface past the nut at (D_m/2 + r_b cos a_n) w_m cos(phi)
and past the screw at (D_m/2 - r_b cos a_s)(w_s - w_m) cos(phi).

Centrifugal force (000 eq. 12): F_c = m_b D_m w_m^2 / 2.

Sliding velocities (000 eq. 19), two readings (``KINEMATICS``):

``"literal"`` (default): eq. 10-11 and 19 exactly as printed, with d = D_m/2 and
    w_t = 0:  w_n = -w_R sin(beta), w_b = -w_R cos(beta),
        V_Xs = r_b w_s sin(phi),   V_Ys = r_b[(w_b - w_s cos phi) cos a_s - w_n sin a_s] - d (w_m - w_s)
        V_Xn = 0,                  V_Yn = -d w_m + r_b (w_n sin a_n - w_b cos a_n)
    The ball-spin terms then combine to r_b w_R cos(a + beta) ~ 0 (a + beta ~ 92 deg),
    so both contacts slide at about d w_m ~ D_m w_s / 4: half the raceway surface speed.
    It is the reading that reproduces 000's Table 3 (screw and nut nearly equal, screw
    slightly larger) with 000's own wear constant, so it is what 000 evaluated.

``"rolling"``: the self-consistent signs (w_b = +w_R cos(beta) so that the rolling
    component is -w_R cos(beta - a); d = orbit radius of each contact point,
    D_m/2 -+ r_b cos a). Then V_Ys = V_Yn = 0 identically (eq. 8-9 *are* the rolling
    conditions) and only the helix side-slip V_Xs = r_b w_s sin(phi) remains; the nut
    contact rolls (V_n = 0). 000 has no spin-sliding term, so this reading gives no nut
    wear; it is kept to show what the printed model predicts once its signs are repaired.

All functions are vectorised; speeds enter as magnitudes (the wear does not depend on
the direction of rotation), angles as arrays broadcast together.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ebm_wear_monitor.arrays import FloatArray, Floats
from ebm_wear_monitor.physics.geometry import ScrewGeometry

KINEMATICS = ("literal", "rolling")
GYROSCOPIC_ANGLE = math.radians(47.0)  # beta_b, 000 Sec. 3.2 (46-48 deg below 1000 rpm)


class BallMotion(NamedTuple):
    omega_m: FloatArray  # orbit (cyclic) angular velocity of the ball [rad/s], 000 eq. 8
    omega_r: FloatArray  # spin angular velocity of the ball [rad/s], 000 eq. 9
    centrifugal: FloatArray  # F_c [N], 000 eq. 12
    v_screw: FloatArray  # sliding speed at the screw contact [m/s], 000 eq. 19
    v_nut: FloatArray  # sliding speed at the nut contact [m/s], 000 eq. 19


def orbit_speed(geo: ScrewGeometry, omega_s: Floats, a_s: Floats, a_n: Floats,
                beta: float = GYROSCOPIC_ANGLE) -> FloatArray:
    """000 eq. 8: orbit angular velocity w_m [rad/s] of the ball centre for screw speed w_s."""
    g, tb = geo.gamma_prime, math.tan(beta)
    cs, cn = np.cos(a_s), np.cos(a_n)
    ratio = (1.0 + g * cn) * (cs + tb * np.sin(a_s)) / ((1.0 - g * cs) * (cn + tb * np.sin(a_n)))
    return np.asarray(omega_s, dtype=np.float64) / (1.0 + ratio)


def spin_speed(geo: ScrewGeometry, omega_m: Floats, a_n: Floats,
               beta: float = GYROSCOPIC_ANGLE) -> FloatArray:
    """000 eq. 9: ball spin w_R [rad/s] (cos(beta) cos(a_n) + sin(beta) sin(a_n) = cos(beta - a_n))."""
    g = geo.gamma_prime
    return -(1.0 + g * np.cos(a_n)) * math.cos(geo.phi) / (g * np.cos(beta - np.asarray(a_n))) * omega_m


def ball_motion(geo: ScrewGeometry, omega_s: Floats, a_s: Floats, a_n: Floats, *,
                reading: str = "literal", beta: float = GYROSCOPIC_ANGLE) -> BallMotion:
    """000 eq. 8-12 and 19 for screw speed magnitude |w_s| [rad/s] at contact angles a_s, a_n [rad]."""
    w_s = np.abs(np.asarray(omega_s, dtype=np.float64))
    w_m = orbit_speed(geo, w_s, a_s, a_n, beta)
    w_r = spin_speed(geo, w_m, a_n, beta)
    f_c = 0.5 * geo.ball_mass * geo.d_m * w_m**2
    r_b, phi = geo.r_b, geo.phi
    v_xs = r_b * w_s * math.sin(phi)
    if reading == "literal":
        w_n, w_b = -w_r * math.sin(beta), -w_r * math.cos(beta)
        d = geo.d_m / 2.0
        v_ys = r_b * ((w_b - w_s * math.cos(phi)) * np.cos(a_s) - w_n * np.sin(a_s)) - d * (w_m - w_s)
        v_yn = -d * w_m + r_b * (w_n * np.sin(a_n) - w_b * np.cos(a_n))
    elif reading == "rolling":
        # with w_b = +w_R cos(beta) and d the contact-point orbit radius, V_Ys and V_Yn are the
        # residuals of the rolling conditions that define eq. 8-9: identically zero
        v_ys = np.zeros_like(w_m)
        v_yn = np.zeros_like(w_m)
    else:
        raise ValueError(f"kinematics reading must be one of {KINEMATICS}, got {reading!r}")
    return BallMotion(w_m, w_r, f_c, np.hypot(v_xs, v_ys), np.abs(v_yn))
