"""Elastic / elastic-plastic contact type and contact area: 000 eq. 6-7 (CEB [15], Horng [37]).

Critical interference (000 eq. 6, Chang-Etsion-Bogy): plastic flow starts when the
mean pressure reaches K H (Tabor), K = 0.454 + 0.41 nu of the softer body:

    delta_c = (pi K H / (2 E*))^2 R

Contact area (000 eq. 7, Horng's elliptic micro-contact model):

    A = f1 pi R delta                                      delta <  delta_c  (elastic)
    A = f2 pi R delta [2 - delta_c/delta (2 - f3)]         delta >= delta_c  (elastic-plastic)

    f1 = E / (F kappa),  f2 = E (1 - kappa^2) / (2 kappa (E - F kappa^2)),
    f3 = 2 (E - kappa^2 F) / (F (1 - kappa^2))

Horng writes f1..f3 for kappa = b/a <= 1 (semi-minor over semi-major). With that
reading and R = 2 / sum_rho the elastic branch is *exactly* the Hertz ellipse area
pi a b (pi a b / delta = 2 pi (a/b) E / (F sum_rho)), a check the tests use. Taking
kappa = a/b as 000's eq. 4 defines it makes f1 smaller by kappa^2 (about 100 for a
ball screw), see ``kappa_reading``. At delta = delta_c, f2 f3 = f1, so A is
continuous across the switch for either reading.

What R is (000 calls R_A "the average effective curvature radius of asperities,
which is equal to the composite roughness") is a reading, ``radius_reading``:

* ``"hertz"``: R = 2 / sum_rho, the macroscopic contact (A is the Hertz ellipse);
* ``"asperity"``: R = the asperity radius of the unit file (materials.asperity_radius);
* ``"roughness"``: R = the composite roughness R_A taken literally as a length.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ebm_wear_monitor.arrays import BoolArray, FloatArray, Floats
from ebm_wear_monitor.physics.hertz import ellipe_fit, ellipk_fit, ellipticity_fit

KAPPA_READINGS = ("b/a", "a/b")
RADIUS_READINGS = ("hertz", "asperity", "roughness")


def tabor_k(poisson_ratio: float) -> float:
    """K = 0.454 + 0.41 nu of the softer body (000 after eq. 6, Chang et al. [36])."""
    return 0.454 + 0.41 * poisson_ratio


def critical_interference(hardness: float, poisson_ratio: float, e_red: float, radius: Floats) -> FloatArray:
    """000 eq. 6: delta_c = (pi K H / (2 E*))^2 R [m]."""
    factor = (np.pi * tabor_k(poisson_ratio) * hardness / (2.0 * e_red)) ** 2
    return factor * np.asarray(radius, dtype=np.float64)


def horng_functions(gamma: Floats, kappa_reading: str = "b/a") -> tuple[FloatArray, FloatArray, FloatArray]:
    """Horng's f1, f2, f3 of 000 eq. 7 at curvature ratio gamma, kappa = b/a (Horng) or a/b (000 eq. 4)."""
    f, e = ellipk_fit(gamma), ellipe_fit(gamma)
    kap = ellipticity_fit(gamma)
    if kappa_reading == "b/a":
        kap = 1.0 / kap
    elif kappa_reading != "a/b":
        raise ValueError(f"kappa_reading must be one of {KAPPA_READINGS}, got {kappa_reading!r}")
    k2 = kap * kap
    f1 = e / (f * kap)
    f2 = e * (1.0 - k2) / (2.0 * kap * (e - f * k2))
    f3 = 2.0 * (e - k2 * f) / (f * (1.0 - k2))
    return f1, f2, f3


class ContactArea(NamedTuple):
    area: FloatArray  # A_c [m^2]
    plastic: BoolArray  # True where delta >= delta_c (elastic-plastic)
    delta_c: FloatArray  # critical interference [m]


def contact_area(delta: Floats, gamma: Floats, radius: Floats, *, hardness: float,
                 poisson_ratio: float, e_red: float, kappa_reading: str = "b/a") -> ContactArea:
    """000 eq. 6-7: contact type and area for approach ``delta`` [m] with radius R [m]."""
    delta = np.asarray(delta, dtype=np.float64)
    f1, f2, f3 = horng_functions(gamma, kappa_reading)
    d_c = critical_interference(hardness, poisson_ratio, e_red, radius)
    plastic = delta >= d_c
    safe = np.where(delta > 0.0, delta, 1.0)
    elastic_area = f1 * np.pi * radius * delta
    plastic_area = f2 * np.pi * radius * delta * (2.0 - d_c / safe * (2.0 - f3))
    return ContactArea(np.where(plastic, plastic_area, elastic_area), plastic, d_c)
