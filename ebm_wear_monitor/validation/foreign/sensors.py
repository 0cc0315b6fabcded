"""Acquisition of the foreign world: sample clocks, sensors and estimators of one recording.

Every topic has its own clock: nominal rate ``f``, phase ``phi``, sample-time jitter (Gaussian,
clipped to 3 sigma), a few dropped samples, and a stamp equal to the true sample instant. The bag's
log time lags the stamp by ``U(lag_min, lag_max)`` (at most 2 ms), made non-decreasing per topic
(a topic is received in order; topics interleave).

Sensors (each reads the true trajectory of :mod:`simulate` at its own sample instants, linear
interpolation on the 10 kHz plant grid):

* angle: an absolute multi-turn encoder with an arbitrary zero ``offset``, quantised to
  ``2 pi / 2^bits``; either on the screw, or on the motor (then divided by ``i_g``, so its step
  at the screw is ``2 pi / (2^bits i_g)``). Reported: screw angle, positive in apply direction.
* velocity: never the true speed. ``derivative``: backward difference of the quantised encoder
  readings at the velocity clock (nominal period ``T``, jitter ignored as a real estimator does)
  through a first-order low-pass ``tau`` (lag about ``tau``); ``moving_average``: the mean
  of the last ``N`` differences, ``(a_j - a_{j-N}) / (N T)`` (lag ``N T / 2``); ``tracking``: a
  second-order tracking observer (``a_hat' = w_hat + k1 e``, ``w_hat' = k2 e``, ``e = a - a_hat``,
  natural frequency ``wn``, damping 0.7, ``k1 = 2 zeta wn``, ``k2 = wn^2``).
* force: the load cell of the plant (first-order lag ``tau_F`` applied in the loop), plus a tare
  offset ``tare`` [N], Gaussian noise and an ADC step ``lsb_F``.
* current: ``instant`` samples the current with the PWM ripple (triangle at ``f_pwm``, peak-to-
  peak ``V_bus D (1 - D) / (L f_pwm)``, duty ``D = |E| / V_bus``); ``centered`` samples at the
  PWM centre (no ripple); ``average`` is the mean over the control period ending at the sample.
  Noise and an ADC step ``lsb_I`` are added.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.signal import lfilter, ss2tf

from .simulate import PLANT_RATE, Trajectory

TOPICS = ("screw/angle", "screw/velocity", "axial_force", "motor/current")


@dataclass(frozen=True)
class Clock:
    """Sample clock of one topic."""

    rate: float  # nominal rate [Hz]
    phase: float  # first sample after the recording start [s]
    jitter: float  # sample-instant jitter, standard deviation [s]
    drops: int  # number of samples dropped
    frame_id: str


@dataclass(frozen=True)
class Acquisition:
    """Every acquisition convention of one recording (SI)."""

    clocks: dict  # topic -> Clock
    encoder_side: str  # "screw" | "motor"
    encoder_bits: int
    encoder_offset: float  # zero offset of the encoder, in its own frame [rad]
    velocity_kind: str  # "derivative" | "moving_average" | "tracking"
    velocity_param: float  # tau [s] | N [-] | wn [rad/s]
    tare: float  # load-cell offset [N]
    noise_F: float  # force noise std [N]
    lsb_F: float  # force ADC step [N]
    current_kind: str  # "instant" | "centered" | "average"
    f_pwm: float  # PWM frequency [Hz]
    noise_I: float  # current noise std [A]
    lsb_I: float  # current ADC step [A]
    lag_min: float  # log-time lag behind the stamp, lower bound [s]
    lag_max: float  # upper bound [s]

    def velocity_lag(self, rate: float) -> float:
        """Delay of the velocity estimate behind the true speed on a ramp (DC group delay) [s].

        derivative: backward difference ``T/2`` plus the discrete low-pass ``T e / (1 - e)``,
        ``e = exp(-T / tau)`` (about ``tau``); moving average: ``N T / 2``; tracking observer:
        ``k1 / k2 - 3 T / 2 = 2 zeta / wn - 3 T / 2``. (Observer on ``a = alpha t^2 / 2``: the
        speed update fixes ``e = alpha / k2``; the angle update then needs
        ``w_hat_k + k1 e = (a_{k+1} - a_k) / T = alpha (t_k + T / 2)``, and the reported estimate
        after the update is ``w_hat_k + alpha T = alpha (t_k + 3 T / 2 - k1 / k2)``.)
        """
        T = 1.0 / rate
        if self.velocity_kind == "derivative":
            e = np.exp(-T / self.velocity_param)
            return float(T / 2 + T * e / (1 - e))
        if self.velocity_kind == "moving_average":
            return self.velocity_param * T / 2
        return 2 * 0.7 / self.velocity_param - 1.5 * T


def sample_times(clock: Clock, duration: float, rng: np.random.Generator) -> np.ndarray:
    """Sample instants [s] of one topic inside ``[0, duration)``, jittered, with drops removed."""
    n = int(np.floor((duration - clock.phase) * clock.rate))
    t = clock.phase + np.arange(n) / clock.rate
    jit = np.clip(rng.standard_normal(n), -3.0, 3.0) * clock.jitter
    t = t + jit
    keep = np.ones(n, dtype=bool)
    if clock.drops:
        keep[rng.choice(np.arange(1, n - 1), size=clock.drops, replace=False)] = False
    t = t[keep]
    return t[(t >= 0.0) & (t < duration)]


def _interp(tr: Trajectory, x: np.ndarray, t: np.ndarray) -> np.ndarray:
    return np.interp(t, tr.t, x)


def encoder(acq: Acquisition, tr: Trajectory, t: np.ndarray, i_g: float) -> np.ndarray:
    """Screw angle [rad] as the encoder reports it at instants ``t`` (offset, quantised)."""
    q = 2 * np.pi / 2**acq.encoder_bits
    if acq.encoder_side == "screw":
        raw = _interp(tr, tr.q, t) / i_g + acq.encoder_offset
        return np.round(raw / q) * q
    raw = _interp(tr, tr.theta, t) + acq.encoder_offset
    return np.round(raw / q) * q / i_g


def velocity(acq: Acquisition, angle: np.ndarray, rate: float) -> np.ndarray:
    """Velocity estimate [rad/s] from encoder readings taken at the velocity clock."""
    T = 1.0 / rate
    if acq.velocity_kind == "derivative":
        d = np.diff(angle, prepend=angle[0]) / T
        a = 1.0 - np.exp(-T / acq.velocity_param)
        return lfilter([a], [1.0, a - 1.0], d, zi=[0.0])[0]
    if acq.velocity_kind == "moving_average":
        N = int(acq.velocity_param)
        ext = np.concatenate([np.full(N, angle[0]), angle])
        return (ext[N:] - ext[:-N]) / (N * T)
    wn, zeta = acq.velocity_param, 0.7
    k1, k2 = 2 * zeta * wn, wn**2
    # forward-Euler observer: x+ = A x + b a with x = (a_hat, w_hat); reported w_hat after the update
    A = np.array([[1 - T * k1, T], [-T * k2, 1.0]])
    b = np.array([[T * k1], [T * k2]])
    num, den = ss2tf(A, b, A[1:], b[1:])
    # started converged on the first reading (a_hat = a_0, w_hat = 0): filter the change from it
    return lfilter(num[0], den, angle - angle[0])


def force(acq: Acquisition, tr: Trajectory, t: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Load-cell reading [N]: lagged cell output + tare + noise, quantised."""
    raw = _interp(tr, tr.f_cell, t) + acq.tare + acq.noise_F * rng.standard_normal(t.size)
    return np.round(raw / acq.lsb_F) * acq.lsb_F


def current(acq: Acquisition, tr: Trajectory, t: np.ndarray, *, v_bus: float, inductance: float,
            control_rate: float, rng: np.random.Generator) -> np.ndarray:
    """Current reading [A] by the recording's sampling convention, with noise, quantised."""
    if acq.current_kind == "average":
        cum = np.concatenate([[0.0], np.cumsum(tr.i) / PLANT_RATE])
        tc = np.concatenate([[0.0], tr.t + 1.0 / PLANT_RATE])
        Tc = 1.0 / control_rate
        raw = (np.interp(t, tc, cum) - np.interp(t - Tc, tc, cum)) / Tc
    else:
        raw = _interp(tr, tr.i, t)
        if acq.current_kind == "instant":
            duty = np.clip(np.abs(_interp(tr, tr.E, t)) / v_bus, 0.0, 1.0)
            ripple_pp = v_bus * duty * (1 - duty) / (inductance * acq.f_pwm)
            frac = (t * acq.f_pwm) % 1.0
            raw = raw + ripple_pp * (2 * np.abs(frac - 0.5) - 0.5)
    raw = raw + acq.noise_I * rng.standard_normal(t.size)
    return np.round(raw / acq.lsb_I) * acq.lsb_I
