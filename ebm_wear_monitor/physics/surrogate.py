"""Tabulated surrogate of the direct 000 solve, built once per parameter set.

The direct solve (:mod:`contact`) is smooth in force and speed apart from the
elastic / elastic-plastic switch of eq. 6-7. The wear-depth rate is, to first order,
proportional to the screw speed (every sliding velocity of eq. 19 is), so the table
stores g(F, w) = (dh/dt) / w on a grid uniform in ln F and in w, and the surrogate
returns w * bilinear(g). Samples outside the envelope (documented in
:data:`ENVELOPE`) go through the direct solve instead, so the surrogate is never
extrapolated; the tests prove the maximum relative error against the direct solve
inside the envelope.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from ebm_wear_monitor.params.unit import UnitParams
from ebm_wear_monitor.physics.contact import solve
from ebm_wear_monitor.physics.options import ModelOptions


class Envelope(NamedTuple):
    """Operating envelope covered by the table: axial force [N] and screw speed [rad/s] magnitudes."""

    force_min: float = 10.0
    force_max: float = 80.0e3
    speed_max: float = 200.0


ENVELOPE = Envelope()
SPEED_FLOOR = 1e-6  # speed at which the w = 0 column of g is evaluated [rad/s]


class WearTable:
    """g(F, w) = (dh/dt)/w for screw and nut on a ln(F) x w grid (see module docstring)."""

    def __init__(self, unit: UnitParams, options: ModelOptions, envelope: Envelope = ENVELOPE,
                 n_force: int = 1201, n_speed: int = 41) -> None:
        self.envelope = envelope
        self._l0 = np.log(envelope.force_min)
        self._hl = (np.log(envelope.force_max) - self._l0) / (n_force - 1)
        self._hw = envelope.speed_max / (n_speed - 1)
        self._n_speed = n_speed
        self._n_force = n_force
        log_f = self._l0 + self._hl * np.arange(n_force)
        speed = np.maximum(self._hw * np.arange(n_speed), SPEED_FLOOR)
        ff, ww = np.meshgrid(np.exp(log_f), speed, indexing="ij")
        _, screw, nut = solve(unit, ff.ravel(), ww.ravel(), options)
        w = ww.ravel()
        self._screw = screw.wear_rate / w
        self._nut = nut.wear_rate / w

    def inside(self, force: NDArray, speed: NDArray) -> NDArray:
        """Mask of samples inside the envelope (|F| in [F_min, F_max], |w| <= w_max)."""
        e = self.envelope
        return (force >= e.force_min) & (force <= e.force_max) & (speed <= e.speed_max)

    def rates(self, force: NDArray, speed: NDArray) -> tuple[NDArray, NDArray]:
        """Bilinear table look-up for samples inside the envelope: (screw, nut) dh/dt [m/s]."""
        u = (np.log(force) - self._l0) / self._hl
        v = speed / self._hw
        i = np.minimum(u.astype(np.intp), self._n_force - 2)
        j = np.minimum(v.astype(np.intp), self._n_speed - 2)
        fu = u - i
        fv = v - j
        k00 = i * self._n_speed + j
        k10 = k00 + self._n_speed
        w00 = (1.0 - fu) * (1.0 - fv) * speed
        w01 = (1.0 - fu) * fv * speed
        w10 = fu * (1.0 - fv) * speed
        w11 = fu * fv * speed
        out = []
        for tab in (self._screw, self._nut):
            out.append(tab[k00] * w00 + tab[k00 + 1] * w01 + tab[k10] * w10 + tab[k10 + 1] * w11)
        return out[0], out[1]
