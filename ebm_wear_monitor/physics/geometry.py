"""Ball-raceway contact geometry: principal curvatures of 000 Table 1 and 003 eq. 6-13.

A ball of radius r_b sits between the screw groove (radius r_s = 2 f_s r_b) and
the nut groove (r_n = 2 f_n r_b) on the pitch diameter D_m. At contact angle
alpha the raceway surface is curved in two principal planes:

* along the ball path (direction "1", the rolling/sliding direction): the screw
  is convex with radius D_m/2 / cos(alpha) - r_b, the nut concave, so (000 Table 1)

      rho_s1 =  cos(a_s) / (D_m/2 - r_b cos(a_s))
      rho_n1 = -cos(a_n) / (D_m/2 + r_b cos(a_n))

* across the groove (direction "2"): both grooves are concave, rho_i2 = -1/r_i.

With the ball curvature rho_b = 1/r_b in both planes, the curvature sum and the
effective curvature ratio are

      sum_rho = 2 rho_b + rho_1 + rho_2,      gamma = (rho_b + rho_1) / (rho_b + rho_2)

gamma is R_y / R_x, the transverse over the rolling equivalent radius (003's
radii ratio k, eq. 10-11), > 1 for every ball screw. All functions accept numpy
arrays of contact angles and broadcast.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ebm_wear_monitor.arrays import FloatArray, Floats
from ebm_wear_monitor.params.unit import Material, UnitParams

SCREW = "screw"
NUT = "nut"
SIDES = (SCREW, NUT)


def reduced_modulus(a: Material, b: Material) -> float:
    """Reduced (composite) modulus E* [Pa] of two bodies: 1/E* = (1-nu_a^2)/E_a + (1-nu_b^2)/E_b.

    This is 003 eq. 12-13, and the E' that 000 eq. 1 and eq. 6 need: with the
    Hamrock-Dowson modulus 2 E* in its place eq. 1 would give a deformation
    2^(2/3) = 1.59 times too small (README.md, paper 000 item 1).
    """
    return 1.0 / ((1.0 - a.poisson_ratio**2) / a.elastic_modulus
                  + (1.0 - b.poisson_ratio**2) / b.elastic_modulus)


@dataclass(frozen=True)
class ScrewGeometry:
    """Scalar geometry of one ball screw, taken from a unit file (SI units)."""

    r_b: float  # ball radius [m]
    r_s: float  # screw groove radius [m]
    r_n: float  # nut groove radius [m]
    d_m: float  # pitch diameter D_m [m]
    phi: float  # helix angle [rad]
    alpha0: float  # unloaded contact angle [rad]
    z: int  # effective (loaded) balls Z
    e_s: float  # reduced modulus ball-screw [Pa]
    e_n: float  # reduced modulus ball-nut [Pa]
    ball_mass: float  # m_b [kg] (000 eq. 12)

    @classmethod
    def from_unit(cls, unit: UnitParams) -> ScrewGeometry:
        bs, mat = unit.ball_screw, unit.materials
        r_b = bs.ball_radius
        return cls(r_b=r_b, r_s=bs.screw_groove_radius, r_n=bs.nut_groove_radius,
                   d_m=bs.pitch_diameter, phi=bs.helix_angle, alpha0=bs.contact_angle,
                   z=bs.effective_balls,
                   e_s=reduced_modulus(mat.ball, mat.screw), e_n=reduced_modulus(mat.ball, mat.nut),
                   ball_mass=mat.ball.density * 4.0 / 3.0 * np.pi * r_b**3)

    @property
    def gamma_prime(self) -> float:
        """gamma' = 2 r_b / D_m (000 eq. 8-9)."""
        return 2.0 * self.r_b / self.d_m

    @property
    def centre_distance0(self) -> float:
        """Unloaded distance of the two groove curvature centres, r_s + r_n - 2 r_b [m] (000 eq. 16)."""
        return self.r_s + self.r_n - 2.0 * self.r_b

    def groove_radius(self, side: str) -> float:
        return self.r_s if side == SCREW else self.r_n

    def modulus(self, side: str) -> float:
        return self.e_s if side == SCREW else self.e_n


@dataclass(frozen=True)
class Curvature:
    """Curvatures of one contact (000 Table 1), arrays broadcast like the contact angle."""

    rho_1: FloatArray  # raceway curvature along the ball path [1/m]
    rho_2: FloatArray  # raceway curvature across the groove [1/m]
    sum_rho: FloatArray  # curvature sum [1/m]
    gamma: FloatArray  # effective curvature ratio R_y / R_x [-]
    r_x: FloatArray  # equivalent radius in the rolling direction 1/(rho_b + rho_1) [m]
    r_y: FloatArray  # transverse equivalent radius 1/(rho_b + rho_2) [m]


def curvature(geo: ScrewGeometry, side: str, alpha: Floats) -> Curvature:
    """000 Table 1 for the screw or nut contact at contact angle ``alpha`` [rad]."""
    cos_a = np.cos(np.asarray(alpha, dtype=np.float64))
    rho_b = 1.0 / geo.r_b
    if side == SCREW:
        rho_1 = cos_a / (geo.d_m / 2.0 - geo.r_b * cos_a)
    else:
        rho_1 = -cos_a / (geo.d_m / 2.0 + geo.r_b * cos_a)
    rho_2 = np.full_like(rho_1, -1.0 / geo.groove_radius(side))
    inv_rx = rho_b + rho_1
    inv_ry = rho_b + rho_2
    return Curvature(rho_1=rho_1, rho_2=rho_2, sum_rho=inv_rx + inv_ry, gamma=inv_rx / inv_ry,
                     r_x=1.0 / inv_rx, r_y=1.0 / inv_ry)
