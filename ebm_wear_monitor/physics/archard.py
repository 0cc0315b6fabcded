"""Archard wear of the raceways, ball share and axial clearance growth: 000 eq. 20-23, Sec. 4.1.

Archard (000 eq. 20-23): the wear volume dV = k_slip Q ds / (3 sigma_s) spread over
the contact area A_c gives the wear-depth rate of the softer body (the raceway)

    dh/dt = k_slip Q V / (3 sigma_s A_c)                                    [m/s]

with V = ds/dt the sliding speed of eq. 19 and sigma_s the compressive yield limit
of the raceway.

Ball wear (000 Sec. 4.1 after [45,46]): the raceway takes the share s (2/3) of the
wear depth at a contact, the ball 1 - s (1/3). A ball touches both raceways, so its
radius shrinks at ((1 - s)/s) (dh_s + dh_n)/2 per unit time on average over its
surface: the "wear on one side of the ball" of 000 Sec. 5.

Axial clearance growth: the wear depths are measured along the contact normal,
which is tilted by the contact angle alpha from the radial direction and by the
helix angle phi about it. Along the load line of one ball the material removed is
h_s + h_n + 2 h_b (the ball loses h_b at both its contacts), and the nut must move
axially by that over sin(alpha) cos(phi) (the axial component of the normal, as in
eq. 5) to close it again:

    dx = (h_s + h_n + 2 h_b) / (sin(alpha_0) cos(phi))

The axial force on the screw stays compressive through the whole duty cycle (apply,
hold and release: release only lowers it to zero), so the same flank pair carries
the load and wears in all four phases; the other flanks only guide the retracting
nut. For the same screw angle the nut therefore stands dx further back, and the
brake clearance observed is x_ag = x_ag,nominal + dx. The unloaded contact angle
alpha_0 is used: wear happens over the whole load range, and the ball sits at
alpha_0 when the clearance is measured (force ~ 0).
"""

from __future__ import annotations

import math

import numpy as np

from ebm_wear_monitor.arrays import FloatArray, Floats
from ebm_wear_monitor.params.unit import UnitParams


def wear_rate(k_slip: float, q: Floats, v: Floats, yield_strength: float, area: Floats) -> FloatArray:
    """000 eq. 23: wear-depth rate dh/dt = k_slip Q V / (3 sigma_s A_c) [m/s] (0 where A_c = 0)."""
    num = k_slip * np.asarray(q, dtype=np.float64) * np.asarray(v, dtype=np.float64)
    den = 3.0 * yield_strength * np.asarray(area, dtype=np.float64)
    out: FloatArray = np.zeros(np.broadcast(num, den).shape)
    return np.divide(num, den, out=out, where=den > 0.0)


def ball_rate(screw_rate: Floats, nut_rate: Floats, raceway_share: float) -> FloatArray:
    """Ball radius wear rate ((1 - s)/s) (dh_s + dh_n)/2 from the 2/3 : 1/3 split of 000 Sec. 4.1 [m/s]."""
    return (1.0 - raceway_share) / raceway_share * 0.5 * (np.asarray(screw_rate, dtype=np.float64)
                                                                 + np.asarray(nut_rate, dtype=np.float64))


def clearance_growth(unit: UnitParams, screw_m: Floats, nut_m: Floats, ball_m: Floats) -> FloatArray:
    """Axial clearance growth dx = (h_s + h_n + 2 h_b) / (sin(alpha_0) cos(phi)) [m] from wear depths [m].

    Not an equation of 000 (which names the clearance growth only, Sec. 2): the axial projection of
    the normal as in 000 eq. 5, derived in the module docstring.

    ``ball_m`` is the ball radius loss (one side), as :class:`WearRates.ball` integrates to.
    """
    bs = unit.ball_screw
    axial = math.sin(bs.contact_angle) * math.cos(bs.helix_angle)
    return (np.asarray(screw_m, dtype=np.float64) + np.asarray(nut_m, dtype=np.float64)
            + 2.0 * np.asarray(ball_m, dtype=np.float64)) / axial
