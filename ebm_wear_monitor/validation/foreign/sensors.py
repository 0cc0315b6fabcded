"""Acquisition of the foreign world: sample clocks, sensors and estimators of one recording.

Every topic has its own clock: nominal rate ``f``, phase ``phi``, sample-time jitter (Gaussian,
clipped to 3 sigma), a few dropped messages (the device sampled there, the bag lacks the sample),
and a stamp equal to the true sample instant. The bag's
log time lags the stamp by ``U(lag_min, lag_max)`` (at most 2 ms), made non-decreasing per topic
(a topic is received in order; topics interleave).

Sensors (each reads the true trajectory of :mod:`simulate` at its own sample instants, linear
interpolation on the 10 kHz plant grid):

* angle: an absolute multi-turn encoder with an arbitrary zero ``offset``, quantised to
  ``2 pi / 2^bits``; either on the screw, or on the motor (then divided by ``i_g``, so its step
  at the screw is ``2 pi / (2^bits i_g)``). Reported: screw angle, positive in apply direction.
* velocity: never the true speed. ``derivative``: backward difference of the quantised encoder
  readings at every tick of the velocity clock, dropped messages included (nominal period ``T``,
  jitter ignored as a real estimator does)
  through a first-order low-pass ``tau``, discretised exactly (``y_k = e y_{k-1} + (1 - e) d_k``,
  ``e = exp(-T / tau)``; lag about ``tau``); ``moving_average``: the mean of the last ``N``
  differences, ``(a_j - a_{j-N}) / (N T)`` (lag ``N T / 2``); ``tracking``: a second-order
  tracking observer running at the velocity clock, ``e_k = a_k - a_hat_k``,
  ``a_hat_{k+1} = a_hat_k + T w_hat_k + g_a e_k``, ``w_hat_{k+1} = w_hat_k + g_w e_k``, whose
  gains place the loop's poles at ``exp(s T)`` of the continuous observer
  (``a_hat' = w_hat + k1 e``, ``w_hat' = k2 e``, ``k1 = 2 zeta wn``, ``k2 = wn^2``, damping 0.7):
  stable at every ``wn T`` (an explicit Euler step is unstable for ``wn T > 2 zeta``, i.e. above
  280 rad/s at 200 Hz), and equal to the continuous observer as ``wn T -> 0``.
* force: the load cell of the plant (first-order lag ``tau_F`` applied in the loop), plus a tare
  offset ``tare`` [N], Gaussian noise and an ADC step ``lsb_F``.
* current: ``instant`` samples the current at an instant *asynchronous* to the PWM carrier, so
  the sample carries the ripple (triangle, peak-to-peak ``V_bus D (1 - D) / (L f_pwm)``, duty
  ``D = |E| / V_bus``) at a carrier phase ``f_pwm t_k + psi(t_k)`` that is independent of the
  sample clock: ``f_pwm`` is incommensurate with every sample rate (:func:`asynchronous_pwm`)
  and ``psi`` a slow random walk (``PWM_PHASE_DIFFUSION``), so the ripple aliases into zero-mean
  noise of that peak-to-peak amplitude; ``centered`` samples at the PWM centre (no ripple; the
  ADC is triggered by the PWM timer); ``average`` is the mean over the control period ending at
  the sample. Noise and an ADC step ``lsb_I`` are added.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.signal import lfilter, ss2tf

from .simulate import PLANT_RATE, Trajectory

TOPICS = ("screw/angle", "screw/velocity", "axial_force", "motor/current")
#: Damping ratio of the tracking observer [-].
ZETA = 0.7
#: Fractional part of ``f_pwm / f_sample`` of an asynchronous PWM: the golden ratio's, the
#: irrational farthest from every fraction, so consecutive carrier phases spread evenly [-].
PWM_PHASE_STEP = (np.sqrt(5.0) - 1.0) / 2.0
#: Random-walk drift of the PWM carrier phase against the sample clock [cycles / sqrt(s)].
PWM_PHASE_DIFFUSION = 0.25


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
    f_pwm: float  # PWM frequency [Hz] (instant: incommensurate with every sample rate)
    noise_I: float  # current noise std [A]
    lsb_I: float  # current ADC step [A]
    lag_min: float  # log-time lag behind the stamp, lower bound [s]
    lag_max: float  # upper bound [s]

    def velocity_lag(self, rate: float) -> float:
        """Delay of the velocity estimate behind the true speed on a ramp (DC group delay) [s].

        derivative: backward difference ``T/2`` plus the discrete low-pass ``T e / (1 - e)``,
        ``e = exp(-T / tau)`` (about ``tau``); moving average: ``N T / 2``; tracking observer:
        ``T g_a / (T g_w) - 3 T / 2`` (-> ``2 zeta / wn`` as ``wn T -> 0``). (Observer on
        ``a = alpha t^2 / 2``: the speed update fixes ``e = alpha T / g_w``; the angle update then
        needs ``w_hat_k + g_a e / T = (a_{k+1} - a_k) / T = alpha (t_k + T / 2)``, and the reported
        estimate after the update is ``w_hat_k + alpha T = alpha (t_k + 3 T / 2 - g_a / g_w)``.)
        """
        T = 1.0 / rate
        if self.velocity_kind == "derivative":
            e = np.exp(-T / self.velocity_param)
            return float(T / 2 + T * e / (1 - e))
        if self.velocity_kind == "moving_average":
            return self.velocity_param * T / 2
        g_a, g_w = tracking_gains(self.velocity_param, T)
        return float(g_a / g_w - 1.5 * T)


def tracking_gains(wn: float, T: float) -> tuple[float, float]:
    """Gains ``(g_a [-], g_w [1/s])`` of the discrete tracking observer at period ``T`` [s].

    The loop ``x_{k+1} = [[1 - g_a, T], [-g_w, 1]] x_k + [g_a, g_w] a_k`` has the characteristic
    polynomial ``z^2 - (2 - g_a) z + (1 - g_a + T g_w)``; matching it to the poles
    ``p = exp(s T)``, ``s = wn (-zeta +- j sqrt(1 - zeta^2))``, of the continuous observer gives
    ``g_a = 2 - c_1``, ``T g_w = 1 - c_1 + c_0 = |1 - p|^2 > 0``, with ``c_1 = p + p* =
    2 exp(-zeta wn T) cos(wn T sqrt(1 - zeta^2))``, ``c_0 = |p|^2 = exp(-2 zeta wn T) < 1``:
    stable for every ``wn T``; ``g_a -> 2 zeta wn T``, ``g_w -> wn^2 T`` as ``wn T -> 0``.
    """
    c1 = 2.0 * np.exp(-ZETA * wn * T) * np.cos(wn * T * np.sqrt(1.0 - ZETA**2))
    c0 = np.exp(-2.0 * ZETA * wn * T)
    return float(2.0 - c1), float((1.0 - c1 + c0) / T)


def asynchronous_pwm(f_nominal: float, rate: float) -> float:
    """PWM frequency [Hz] near ``f_nominal`` whose ratio to the sample ``rate`` [Hz] is an
    integer plus ``PWM_PHASE_STEP``: incommensurate with ``rate`` and with every rational
    multiple of it (every rate this generator draws), and consecutive samples see carrier phases
    that advance by the golden ratio's fraction, i.e. spread evenly over the carrier period."""
    return float(rate * (round(f_nominal / rate - PWM_PHASE_STEP) + PWM_PHASE_STEP))

def sample_times(clock: Clock, duration: float, rng: np.random.Generator
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Sample instants [s] of one topic's clock inside ``[0, duration)``, jittered, and which of
    them are delivered (``False``: the message is dropped on its way to the bag; the device
    still sampled there, so an estimator with memory saw that sample)."""
    n = int(np.floor((duration - clock.phase) * clock.rate))
    t = clock.phase + np.arange(n) / clock.rate
    jit = np.clip(rng.standard_normal(n), -3.0, 3.0) * clock.jitter
    t = t + jit
    keep = np.ones(n, dtype=bool)
    if clock.drops:
        keep[rng.choice(np.arange(1, n - 1), size=clock.drops, replace=False)] = False
    inside = (t >= 0.0) & (t < duration)
    return t[inside], keep[inside]


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
    g_a, g_w = tracking_gains(acq.velocity_param, T)
    # x+ = A x + b a with x = (a_hat, w_hat); reported w_hat after the update
    A = np.array([[1.0 - g_a, T], [-g_w, 1.0]])
    b = np.array([[g_a], [g_w]])
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
    noise = acq.noise_I * rng.standard_normal(t.size)
    if acq.current_kind == "instant":
        raw = raw + pwm_ripple(acq, t, _interp(tr, tr.E, t), v_bus=v_bus, inductance=inductance,
                               rng=rng)
    return np.round((raw + noise) / acq.lsb_I) * acq.lsb_I


def pwm_ripple(acq: Acquisition, t: np.ndarray, E: np.ndarray, *, v_bus: float, inductance: float,
               rng: np.random.Generator) -> np.ndarray:
    """PWM ripple [A] in current samples taken at instants ``t`` [s] asynchronous to the carrier.

    ``pp (2 |phi - 1/2| - 1/2)``, ``pp = V_bus D (1 - D) / (L f_pwm)`` the peak-to-peak ripple of
    a centre-aligned PWM at duty ``D = |E| / V_bus`` (``E`` the bridge's mean voltage [V]),
    ``phi = frac(phi_0 + f_pwm t_k + psi_k)`` the carrier phase: ``phi_0`` uniform, ``psi`` a random
    walk of ``PWM_PHASE_DIFFUSION`` cycles per sqrt(s). ``phi`` is spread evenly over [0, 1) and
    independent of the sample clock and of ``D``, so the ripple averages to zero.
    """
    duty = np.clip(np.abs(E) / v_bus, 0.0, 1.0)
    pp = v_bus * duty * (1 - duty) / (inductance * acq.f_pwm)
    step = PWM_PHASE_DIFFUSION * np.sqrt(np.abs(np.diff(t, prepend=t[:1])))
    psi = np.cumsum(step * rng.standard_normal(t.size))
    phi = (rng.random() + acq.f_pwm * t + psi) % 1.0
    return pp * (2 * np.abs(phi - 0.5) - 0.5)

