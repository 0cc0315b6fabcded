"""Hertz point contact of a ball on a groove: 000 eq. 1-5 and 003 eq. 1-5, 14-17.

Elliptic integrals (000 eq. 2-4, the Hamrock-Brewe fits that 000 cites as Markho's)
-------------------------------------------------------------------------------
For the curvature ratio gamma = R_y/R_x (see :mod:`geometry`):

    F(gamma)     = 1.5277 + 0.6023 ln(gamma)      complete elliptic integral, 1st kind
    E(gamma)     = 1.0003 + 0.5968 / gamma        complete elliptic integral, 2nd kind
    kappa(gamma) = 1.0339 gamma^0.636             ellipticity a/b of the contact ellipse

(000 prints 1.003 in eq. 3; the source fit has 1.0003, which makes E = pi/2 at
gamma = 1 as the exact integral does.)

Deformation (000 eq. 1) and its inverse
---------------------------------------
    delta = F/2 * [ sum_rho / E * (3 Q / (pi E* kappa))^2 ]^(1/3)
    Q     = pi E* kappa / 3 * sqrt( (2 delta / F)^3 * E / sum_rho )

with E* the *reduced* modulus (1/E* = sum (1-nu^2)/E). Then the ellipse is

    a = (3 kappa^2 E Q / (pi E* sum_rho))^(1/3),  b = (3 E Q / (pi kappa E* sum_rho))^(1/3)
    p_max = 3 Q / (2 pi a b)

Normal load per ball (000 eq. 5, 003 eq. 1): Q = F_a / (Z sin(alpha) cos(phi)).

003 (Olaru's extension of Houpert, eq. 2-5 and 14-15), with k = R_y / R_x:

    a = 1.1552 R_x k^0.4676  (Q / (E* R_x^2))^(1/3)
    b = 1.1502 R_x k^-0.1876 (Q / (E* R_x^2))^(1/3)
    sigma_max = 0.3593 E* k^-0.2799 (Q / (E* R_x^2))^(1/3)
    sigma(x, y) = sigma_max sqrt(1 - (x/a)^2 - (y/b)^2)          (eq. 16-17)

All functions are numpy-vectorised.
"""

from __future__ import annotations

import math

import numpy as np

from ebm_wear_monitor.arrays import FloatArray, Floats


def ellipk_fit(gamma: Floats) -> FloatArray:
    """000 eq. 2: complete elliptic integral of the first kind, F = 1.5277 + 0.6023 ln(gamma)."""
    return 1.5277 + 0.6023 * np.log(gamma)


def ellipe_fit(gamma: Floats) -> FloatArray:
    """000 eq. 3 (constant as in the source fit, 1.0003): E = 1.0003 + 0.5968 / gamma."""
    return 1.0003 + 0.5968 / np.asarray(gamma, dtype=np.float64)


def ellipticity_fit(gamma: Floats) -> FloatArray:
    """000 eq. 4: kappa = a/b = 1.0339 gamma^0.636 (a across the groove, b along the path)."""
    return 1.0339 * np.power(gamma, 0.636)


def normal_load(axial_force: Floats, z: int, alpha: Floats, phi: float) -> FloatArray:
    """000 eq. 5 / 003 eq. 1: normal load per ball Q = F_a / (Z sin(alpha) cos(phi)) [N]."""
    return np.asarray(axial_force, dtype=np.float64) / (z * np.sin(alpha) * math.cos(phi))


def deformation(q: Floats, sum_rho: Floats, gamma: Floats, e_red: float) -> FloatArray:
    """000 eq. 1: elastic approach delta [m] of ball and raceway under normal load q [N]."""
    f, e, kap = ellipk_fit(gamma), ellipe_fit(gamma), ellipticity_fit(gamma)
    q = np.maximum(np.asarray(q, dtype=np.float64), 0.0)
    return f / 2.0 * np.cbrt(sum_rho / e * (3.0 * q / (np.pi * e_red * kap)) ** 2)


def semi_axes(q: Floats, sum_rho: Floats, gamma: Floats, e_red: float) -> tuple[FloatArray, FloatArray]:
    """Hertz semi-axes (a, b) [m] with the fits of 000 eq. 2-4 (a across the groove, a >= b)."""
    e, kap = ellipe_fit(gamma), ellipticity_fit(gamma)
    base = 3.0 * e * np.maximum(np.asarray(q, dtype=np.float64), 0.0) / (np.pi * e_red * sum_rho)
    return np.cbrt(base * kap**2), np.cbrt(base / kap)


def houpert_semi_axes(q: Floats, r_x: Floats, k: Floats, e_red: float) -> tuple[FloatArray, FloatArray]:
    """003 eq. 2-5: semi-major a and semi-minor b [m] of the contact ellipse."""
    s = np.cbrt(np.maximum(np.asarray(q, dtype=np.float64), 0.0) / (e_red * np.asarray(r_x) ** 2))
    return 1.1552 * r_x * np.power(k, 0.4676) * s, 1.1502 * r_x * np.power(k, -0.1876) * s


def houpert_max_pressure(q: Floats, r_x: Floats, k: Floats, e_red: float) -> FloatArray:
    """003 eq. 14-15: maximum contact pressure sigma_max [Pa]."""
    s = np.cbrt(np.maximum(np.asarray(q, dtype=np.float64), 0.0) / (e_red * np.asarray(r_x) ** 2))
    return 0.3593 * e_red * np.power(k, -0.2799) * s


def pressure(x: Floats, y: Floats, a: float, b: float, p_max: float) -> FloatArray:
    """003 eq. 16-17: Hertz pressure p_max sqrt(1 - (x/a)^2 - (y/b)^2) inside the ellipse, 0 outside [Pa]."""
    inside = 1.0 - (np.asarray(x) / a) ** 2 - (np.asarray(y) / b) ** 2
    return p_max * np.sqrt(np.maximum(inside, 0.0))


def effective_balls(d_m: float, r_b: float, phi: float, turns: int, unloaded: int = 0) -> int:
    """000 eq. 5: Z = i * floor(pi D_m / (cos(phi) 2 r_b) - z_2), loaded balls on i turns."""
    return turns * (math.floor(math.pi * d_m / (math.cos(phi) * 2.0 * r_b) - unloaded))
