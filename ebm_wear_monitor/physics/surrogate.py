"""Tabulated surrogate of the direct 000 solve, built once per parameter set.

The direct solve (:mod:`contact`) is smooth in force and speed apart from the
elastic / elastic-plastic switch of eq. 6-7. The wear-depth rate is, to first order,
proportional to the screw speed (every sliding velocity of eq. 19 is), so the table
stores g(F, w) = (dh/dt) / w on a grid uniform in ln F and in w, and the surrogate
returns w * bilinear(g). The grid is 1801 x 41 over :data:`ENVELOPE` (0.1 N .. 80 kN,
0 .. 200 rad/s); samples outside it go through the direct solve instead, so the
surrogate is never extrapolated. The tests prove a maximum relative error against the
direct solve of at most 0.5 % over the whole table (measured 0.3 %, at the kink of the
elastic-plastic switch). Per cell the bilinear form is stored as four coefficients so
that one gather fetches a sample's screw and nut cell.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ebm_wear_monitor.arrays import BoolArray, FloatArray
from ebm_wear_monitor.params.unit import UnitParams
from ebm_wear_monitor.physics.contact import solve
from ebm_wear_monitor.physics.options import ModelOptions


class Envelope(NamedTuple):
    """A rectangle of axial force [N] and screw speed [rad/s] magnitudes."""

    force_min: float = 0.1
    force_max: float = 80.0e3
    speed_max: float = 200.0


ENVELOPE = Envelope()  # range of the table (covers overloads past the elastic-plastic switch)
OPERATING_FORCE_MIN = 10.0  # [N]; below ~2 N the centrifugal force of a fast ball rivals its load
SPEED_FLOOR = 1e-6  # speed at which the w = 0 column of g is evaluated [rad/s]


def _below_switch(envelope: Envelope, force: FloatArray, plastic: BoolArray) -> Envelope:
    """Part of ``envelope`` below the first force where a contact is elastic-plastic at any speed."""
    first = plastic.any(axis=1)
    onset = float(force[np.argmax(first)]) if first.any() else envelope.force_max
    return Envelope(max(envelope.force_min, OPERATING_FORCE_MIN), onset, envelope.speed_max)


def operating_envelope(unit: UnitParams, options: ModelOptions, envelope: Envelope = ENVELOPE,
                       n_force: int = 1801) -> Envelope:
    """Operating envelope: ``envelope`` from 10 N up to the first elastic-plastic contact (000 eq. 6).

    Inside it the wear rate is non-decreasing in |F| and |w| (tested). Below a few newtons
    the centrifugal force (eq. 12) of a fast ball rivals its share of the axial load and
    moves the contact angles, so the rate is not monotone there. Past the switch
    Horng's plastic area of eq. 7 grows faster than the Hertz load of eq. 1 allows, so
    the rate dips before it rises again: a property of 000's model, not of the solver.
    """
    force = np.exp(np.linspace(np.log(envelope.force_min), np.log(envelope.force_max), n_force))
    _, screw, nut = solve(unit, force, np.zeros_like(force), options)
    return _below_switch(envelope, force, (screw.plastic | nut.plastic)[:, None])


class WearTable:
    """g(F, w) = (dh/dt)/w for screw and nut on a ln(F) x w grid (see module docstring).

    ``operating`` is the :func:`operating_envelope` of the table's parameter set.
    """

    def __init__(self, unit: UnitParams, options: ModelOptions, envelope: Envelope = ENVELOPE,
                 n_force: int = 1801, n_speed: int = 41) -> None:
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
        grids = [(side.wear_rate / w).reshape(ff.shape) for side in (screw, nut)]
        # per cell (i, j): g = c0 + c1 fu + fv (c2 + c3 fu), screw in columns 0-3, nut in 4-7
        self._coef = np.concatenate([_bilinear_coefficients(g) for g in grids], axis=-1).reshape(-1, 8)
        self.operating = _below_switch(envelope, ff[:, 0], (screw.plastic | nut.plastic).reshape(ff.shape))

    def inside(self, force: FloatArray, speed: FloatArray) -> BoolArray:
        """Mask of samples inside the envelope (|F| in [F_min, F_max], |w| <= w_max)."""
        e = self.envelope
        return (force >= e.force_min) & (force <= e.force_max) & (speed <= e.speed_max)

    def rates(self, force: FloatArray, speed: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Bilinear table look-up for samples inside the envelope: (screw, nut) dh/dt [m/s]."""
        u = np.log(force)
        u -= self._l0
        u *= 1.0 / self._hl
        v = speed * (1.0 / self._hw)
        i = np.minimum(u.astype(np.intp), self._n_force - 2)
        j = np.minimum(v.astype(np.intp), self._n_speed - 2)
        fu = u - i
        fv = v - j
        i *= self._n_speed - 1
        i += j
        c = np.take(self._coef, i, axis=0).T.copy()  # one gather of a cell's 8 coefficients
        screw = c[0] + fu * c[1] + fv * (c[2] + fu * c[3])
        nut = c[4] + fu * c[5] + fv * (c[6] + fu * c[7])
        screw *= speed
        nut *= speed
        return screw, nut


def _bilinear_coefficients(g: FloatArray) -> FloatArray:
    """Coefficients (c0, c1, c2, c3) of g = c0 + c1 fu + fv (c2 + c3 fu) on every grid cell."""
    g00, g10, g01, g11 = g[:-1, :-1], g[1:, :-1], g[:-1, 1:], g[1:, 1:]
    return np.stack([g00, g10 - g00, g01 - g00, g11 - g10 - g01 + g00], axis=-1)
