"""The physics facade: wear-depth rates of screw, nut and ball for arrays of samples.

``wear_model(unit, method)`` returns a :class:`WearModel` (cached per parameter
digest and options) whose ``rates(axial_force, screw_speed)`` maps arrays of
samples to :class:`WearRates` (dh/dt [m/s] of screw raceway, nut raceway and ball
radius). Conventions (interface.md section 2):

* axial force is compressive positive; F <= 0 means the loaded flanks carry no
  load, so the rate is 0 (the retracting nut is pushed only by the small return
  spring through the other flanks, which 000 does not count as wear);
* the speed sign is the direction of rotation; wear uses |w| (000's kinematics is
  symmetric in the direction);
* non-finite inputs (NaN, inf) give a rate of 0, never NaN, so that integrating
  rates * dt stays finite; the monitor is expected to drop such samples first.

``ball`` already contains the 2/3 : 1/3 split of 000 Sec. 4.1
(``unit.wear.raceway_share``): do not apply it again.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ebm_wear_monitor.arrays import FloatArray, Floats
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.params.unit import UnitParams
from ebm_wear_monitor.physics.archard import ball_rate
from ebm_wear_monitor.physics.contact import solve
from ebm_wear_monitor.physics.options import ModelOptions, make_options
from ebm_wear_monitor.physics.surrogate import Envelope, WearTable, operating_envelope

METHODS = ("surrogate", "direct")


class WearRates(NamedTuple):
    """Wear-depth rates dh/dt [m/s]: screw raceway, nut raceway, ball radius (one side)."""

    screw: FloatArray
    nut: FloatArray
    ball: FloatArray


class WearModel:
    """Wear rates of one unit under one set of reading options, by direct solve or surrogate table."""

    def __init__(self, unit: UnitParams, method: str = "surrogate",
                 options: ModelOptions | None = None) -> None:
        if method not in METHODS:
            raise InputError(f"wear model method must be one of {', '.join(METHODS)}, got {method!r}")
        self.unit = unit
        self.method = method
        self.options = options or ModelOptions()
        self.table = WearTable(unit, self.options) if method == "surrogate" else None

    @property
    def operating_envelope(self) -> Envelope:
        """Force/speed range where the rate is monotone and the surrogate is within 0.5 % (see surrogate)."""
        if self.table is not None:
            return self.table.operating
        return operating_envelope(self.unit, self.options)

    def _direct(self, force: FloatArray, speed: FloatArray) -> tuple[FloatArray, FloatArray]:
        if force.size == 0:
            return np.zeros(0), np.zeros(0)
        _, screw, nut = solve(self.unit, force, speed, self.options)
        return screw.wear_rate, nut.wear_rate

    def rates(self, axial_force: Floats, screw_speed: Floats) -> WearRates:
        """Wear-depth rates [m/s] for axial force [N] (compressive > 0) and screw speed [rad/s] arrays.

        Inputs broadcast against each other; the result has their broadcast shape.
        """
        f, w = np.broadcast_arrays(np.asarray(axial_force, dtype=np.float64),
                                   np.asarray(screw_speed, dtype=np.float64))
        shape = f.shape
        f = f.ravel()
        w = np.abs(w.ravel())
        fast = self.table.inside(f, w) & (w > 0.0) if self.table is not None else np.zeros(f.shape, bool)
        if self.table is not None and fast.all():  # the common case: one table look-up, no masking
            screw, nut = self.table.rates(f, w)
        else:
            screw = np.zeros(f.size)
            nut = np.zeros(f.size)
            if self.table is not None and fast.any():
                screw[fast], nut[fast] = self.table.rates(f[fast], w[fast])
            # comparisons with NaN are False, so non-finite samples stay at rate 0
            slow = ~fast & (f > 0.0) & np.isfinite(f) & (w > 0.0) & np.isfinite(w)
            if slow.any():
                screw[slow], nut[slow] = self._direct(f[slow], w[slow])
        ball = ball_rate(screw, nut, self.unit.wear.raceway_share)
        return WearRates(screw.reshape(shape), nut.reshape(shape), ball.reshape(shape))


_CACHE: dict[tuple[object, ...], WearModel] = {}


def wear_model(unit: UnitParams, method: str = "surrogate", **reading_options: object) -> WearModel:
    """Cached :class:`WearModel` for ``unit`` (keyed by ``unit.digest()``, method and options).

    ``reading_options`` are the fields of :class:`ModelOptions` (``kinematics``,
    ``radius``, ``kappa``, ``gyroscopic_angle_deg``, ``rel_tol``, ``max_iter``).
    """
    options = make_options(**reading_options)
    key = (unit.digest(), method, options.key())
    model = _CACHE.get(key)
    if model is None:
        model = _CACHE[key] = WearModel(unit, method, options)
    return model
