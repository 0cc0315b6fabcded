"""Sensor model of the recorded signals: what a real EMBU's data acquisition adds to the truth.

Noise levels (1 σ, white, Gaussian; independent per sample at the 1 kHz
reference rate), chosen from the instruments such a unit carries:

* ``angle``: a 12-bit resolver on the motor shaft resolves 2π/4096 rad, i.e.
  3.0e-4 rad of screw angle through i_g = 5.05; its quantisation noise
  (LSB/√12) is 8.8e-5 rad: σ = 1.0e-4 rad (screw).
* ``velocity``: the drive differentiates the resolver angle and low-pass
  filters it (about 100 Hz): σ = 0.02 rad/s (screw).
* ``axial_force``: a strain-gauge load cell of 50 kN full scale with 0.1 %
  noise: σ = 50 N.
* ``current``: a shunt/Hall sensor on a ±20 A range through a 12-bit
  converter with PWM ripple left after filtering: σ = 0.02 A.

A force-sensor bias or gain (:mod:`.effects`) is applied before the noise.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from ebm_wear_monitor.twin.effects import ForceSensorError


@dataclass(frozen=True)
class SensorNoise:
    """1-σ white noise of each recorded signal (SI units, screw-side angle and speed)."""

    angle: float = 1.0e-4  # [rad]
    velocity: float = 0.02  # [rad/s]
    axial_force: float = 50.0  # [N]
    current: float = 0.02  # [A]

    def as_dict(self) -> dict[str, float]:
        return asdict(self)


NOISELESS = SensorNoise(0.0, 0.0, 0.0, 0.0)


def measure(truth: dict[str, np.ndarray], noise: SensorNoise, force_error: ForceSensorError,
            rng: np.random.Generator) -> dict[str, np.ndarray]:
    """Recorded signals from true ones: force-sensor error, then white noise per signal."""
    out = dict(truth)
    out["axial_force"] = (1.0 + force_error.gain) * truth["axial_force"] + force_error.offset
    for name, sigma in noise.as_dict().items():
        if sigma > 0.0:
            out[name] = out[name] + rng.normal(0.0, sigma, size=np.shape(out[name]))
    return out
