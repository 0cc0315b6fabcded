"""Clamp force against nut travel (004 eq. 5-6), with an optional stiffening law.

004 eq. 5: no force until the nut has closed the brake clearance ``x_ag``, then
a linear spring::

    F_cl = 0                    x <= x_ag
    F_cl = K_b (x - x_ag)       x >  x_ag

with the series stiffness of caliper, two pads and screw (eq. 6)::

    1 / K_b = 1 / K_c + 2 / K_p + 1 / K_s

004 Table 1 prints a row "K_b = 3.00e8 N/m" beside K_c = 6.29e7 and
K_s = 6.80e8 N/m; by eq. 6, K_b must be smaller than K_c, so that row is the pad
stiffness K_p, and K_b = 4.16e7 N/m (:func:`series_stiffness`).

Real pads stiffen as they are compressed. The ``stiffness_nonlinearity`` effect
lets the tangent stiffness grow linearly with the compression ``δ = x - x_ag``::

    k(δ) = K_b (1 + s δ / δ_ref),    F_cl = K_b (δ + s δ^2 / (2 δ_ref))

where ``s`` is the fractional stiffness increase at ``δ_ref = F_ref / K_b``
(``F_ref`` = 20 kN): ``s = 0`` is eq. 5 exactly.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ebm_wear_monitor.arrays import Floats

#: reference clamp force at which the stiffening coefficient s is stated [N]
STIFFENING_REFERENCE_FORCE = 20.0e3


def series_stiffness(caliper: float, pad: float, screw: float) -> float:
    """004 eq. 6: ``K_b = 1 / (1/K_c + 2/K_p + 1/K_s)`` [N/m]."""
    return 1.0 / (1.0 / caliper + 2.0 / pad + 1.0 / screw)


@dataclass(frozen=True)
class ClampLaw:
    """Brake clearance and clamp spring of eq. 5 (plus the stiffening coefficient s)."""

    stiffness: float  # K_b [N/m]
    clearance: Floats  # x_ag, nut travel from the rest position to pad contact [m] (one per batch column)
    stiffening: float = 0.0  # s, fractional tangent-stiffness increase at F_ref [-]

    @property
    def reference_compression(self) -> float:
        """δ_ref = F_ref / K_b [m]."""
        return STIFFENING_REFERENCE_FORCE / self.stiffness

    def force(self, x: np.ndarray) -> np.ndarray:
        """Clamp force F_cl [N] at nut travel ``x`` [m] from the rest position (eq. 5)."""
        delta = np.maximum(np.asarray(x, float) - self.clearance, 0.0)
        return self.stiffness * (delta + self.stiffening * delta * delta / (2.0 * self.reference_compression))

    def travel(self, force: np.ndarray) -> np.ndarray:
        """Inverse of :meth:`force`: nut travel ``x`` [m] at which the clamp force is ``force`` [N] >= 0."""
        f = np.maximum(np.asarray(force, float), 0.0) / self.stiffness
        if self.stiffening == 0.0:
            return self.clearance + f
        a = self.stiffening / (2.0 * self.reference_compression)
        return self.clearance + 2.0 * f / (1.0 + np.sqrt(1.0 + 4.0 * a * f))
