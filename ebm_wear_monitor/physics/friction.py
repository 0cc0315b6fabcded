"""Contact friction of 000 eq. 13-14: lubricant rolling drag plus asperity (boundary) friction.

Viscous drag (000 eq. 13, Houpert [39]), in the Hamrock-Dowson groups with the
EHL modulus E' = 2 E* (the convention of the correlation's source):

    f_0 = 2.86 E' R^2 k^0.348 (alpha' E')^0.022 (eta_0 u / (E' R))^0.66 (Q / (E' R^2))^0.47

with R = R_x = 1/(rho_b + rho_1), k = R_y / R_x (the curvature ratio gamma) and the
entrainment speed u = |w_R| r_b.

Asperity friction (000 eq. 14): f_a = mu_a F_aN. 000 leaves the asperity load F_aN
open; here the share psi = F_aN / Q follows the film parameter Lambda = h_c / R_A with
the Hamrock-Dowson central film thickness

    h_c = 2.69 R U^0.67 G^0.53 W^-0.067 (1 - 0.61 exp(-0.73 k)),
    U = eta_0 u / (E' R), G = alpha' E', W = Q / (E' R^2),

and the usual regime boundaries: psi = 1 at Lambda = 0 (boundary lubrication)
falling linearly to 0 at Lambda = 3 (full film). The equivalent coefficient
(000 after eq. 14) is mu_e = mu_a psi + mu_0 (1 - psi), mu_0 = f_0 / Q.
"""

from __future__ import annotations

import math

import numpy as np

from ebm_wear_monitor.arrays import FloatArray, Floats

FULL_FILM_LAMBDA = 3.0  # film parameter above which asperities carry no load


def viscous_drag(q: Floats, u: Floats, r_x: Floats, k: Floats, *, e_red: float,
                 viscosity: float, pressure_viscosity: float) -> FloatArray:
    """000 eq. 13: lubricant rolling drag f_0 [N] at normal load q [N], entrainment speed u [m/s]."""
    e1 = 2.0 * e_red
    q = np.maximum(np.asarray(q, dtype=np.float64), 0.0)
    u = np.abs(np.asarray(u, dtype=np.float64))
    r_x, k = np.asarray(r_x, dtype=np.float64), np.asarray(k, dtype=np.float64)
    return (2.86 * e1 * r_x**2 * np.power(k, 0.348) * math.pow(pressure_viscosity * e1, 0.022)
            * np.power(viscosity * u / (e1 * r_x), 0.66) * np.power(q / (e1 * r_x**2), 0.47))


def film_thickness(q: Floats, u: Floats, r_x: Floats, k: Floats, *, e_red: float,
                   viscosity: float, pressure_viscosity: float) -> FloatArray:
    """Hamrock-Dowson central film thickness h_c [m] (0 at zero speed), for F_aN left open by 000 eq. 14.

    ``h_c = 2.69 R U^0.67 G^0.53 W^-0.067 (1 - 0.61 exp(-0.73 k))`` with the groups of the module docstring.
    """
    e1 = 2.0 * e_red
    q = np.maximum(np.asarray(q, dtype=np.float64), 1e-30)
    u = np.abs(np.asarray(u, dtype=np.float64))
    r_x, k = np.asarray(r_x, dtype=np.float64), np.asarray(k, dtype=np.float64)
    return (2.69 * r_x * np.power(viscosity * u / (e1 * r_x), 0.67) * math.pow(pressure_viscosity * e1, 0.53)
            * np.power(q / (e1 * r_x**2), -0.067) * (1.0 - 0.61 * np.exp(-0.73 * np.asarray(k))))


def asperity_share(film: Floats, roughness: float) -> FloatArray:
    """psi = F_aN / Q of 000 eq. 14: 1 in boundary lubrication, 0 from Lambda = h_c / R_A >= 3 (linear
    between) [-]; ``film`` h_c [m], ``roughness`` R_A [m]."""
    return np.clip(1.0 - np.asarray(film) / (FULL_FILM_LAMBDA * roughness), 0.0, 1.0)


def equivalent_friction(q: Floats, u: Floats, r_x: Floats, k: Floats, *, e_red: float,
                        viscosity: float, pressure_viscosity: float, roughness: float,
                        boundary_friction: float) -> FloatArray:
    """mu_e = mu_a psi + mu_0 (1 - psi) of 000 eq. 13-14 [-]."""
    q = np.asarray(q, dtype=np.float64)
    groups = {"e_red": e_red, "viscosity": viscosity, "pressure_viscosity": pressure_viscosity}
    psi = asperity_share(film_thickness(q, u, r_x, k, **groups), roughness)
    drag = viscous_drag(q, u, r_x, k, **groups)
    mu_0 = np.divide(drag, q, out=np.zeros_like(drag), where=q > 0.0)
    return boundary_friction * psi + mu_0 * (1.0 - psi)
