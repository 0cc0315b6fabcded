"""Brake ECUs of the foreign world: three controller variants, vectorised over applications.

Every variant sees what a real ECU sees: its own resolver (motor angle with noise), its own
current sensor (noise), the load cell (lagged, auto-tared at rest) and a speed it estimates itself
from the resolver (first-order filtered backward difference). It knows only the *nominal* unit
values (unit file), never the effects of the recording. All ECUs drive the armature voltage
``E`` [V] (PWM average), limited to the supply ``+-V_bus``.

Variants (``EcuConfig.variant``):

``cascade``
    apply: force P+I -> speed reference (limited to ``w_max``) -> speed PI -> current reference
    (limited to ``I_max``) -> current PI with back-EMF feed-forward -> voltage.
``position``
    apply: target angle from the nominal force-travel map ``(x_ag + F_d / K_b) / r_g``, position P
    -> speed PI -> current PI; after ``trim_delay`` a slow force trim integrates the force error
    into the target angle (time constant ``trim_tau``).
``voltage``
    apply: voltage-mode speed control at ``w_app`` until the load cell reads ``F_contact``, then a
    force PID on the voltage with a feed-forward of the nominal stall voltage
    ``R (r_g F_d + T_fs + G F_d) / K_T`` (004 eq. 1, 7-9); its D part acts on the estimated
    speed (``-kd_v K_E w``), i.e. on the force rate through the clamp stiffness.

Release back to rest:

``cascade`` / ``position``: position P -> speed PI -> current PI toward the rest target (overshoot
from the speed integrator), then a *parking* stage: position PI straight to a current reference
limited to ``I_park`` (barely above breakaway), which creeps the last milliradians in stick-slip
steps and stops inside the static-friction dead band; then the bridge is switched off.

``voltage``: reverse voltage ``-V_rel`` until the load cell reads below ``F_contact``, then
voltage-mode speed control toward the target, then voltage pulses ``V_pulse`` of width
``pulse_on`` every ``pulse_period`` while the error exceeds ``dead_band``; then off.

The rest target is ``home + eps_k``: the ECU's home angle plus a per-application position-reference
error ``eps_k`` (resolver drift). Together with the dead bands this makes rest angles differ from
application to application by a few mrad at the screw.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .unit import Actuator

VARIANTS = ("cascade", "position", "voltage")


@dataclass(frozen=True)
class EcuConfig:
    """Controller variant and its settings (SI; angles and speeds at the motor)."""

    variant: str
    rate: float  # control rate [Hz]
    V_bus: float  # supply [V]
    I_max: float  # current limit [A]
    w_max: float  # apply speed limit [rad/s]
    f_current: float  # current-loop crossover [Hz]
    f_speed: float  # speed-loop crossover [Hz]
    f_force: float  # force-loop crossover [Hz] (cascade, position trim, voltage PID scale)
    f_pos: float  # release position-loop crossover [Hz]
    w_rel: float  # release speed limit [rad/s]
    t_pos: float  # duration of the release position stage [s]
    t_park: float  # duration of the parking / pulse stage [s]
    I_park: float  # parking current limit [A]
    K_park: float  # parking proportional gain [A/rad]
    Ki_park: float  # parking integral gain [A/(rad s)]
    noise_theta: float  # resolver noise [rad]
    noise_i: float  # current-sensor noise [A]
    noise_f: float  # force noise seen by the ECU [N]
    w_filter: float  # speed-estimate filter time constant [s]
    trim_delay: float = 0.15  # position variant: start of the force trim after the demand [s]
    trim_tau: float = 0.08  # position variant: trim time constant [s]
    F_contact: float = 300.0  # voltage variant: contact / release threshold [N]
    w_app: float = 25.0  # voltage variant: approach speed [rad/s]
    V_rel: float = 20.0  # voltage variant: release voltage [V]
    pulse_on: float = 0.004  # voltage variant: pulse width [s]
    pulse_period: float = 0.03  # voltage variant: pulse period [s]
    V_pulse: float = 4.0  # voltage variant: pulse voltage [V]
    dead_band: float = 0.01  # voltage variant: pulse dead band [rad]
    ki_v: float = 2.0  # voltage variant: integral gain relative to the proportional one [1/s]
    kd_v: float = 0.5  # voltage variant: speed damping as a share of the back-EMF [-]


class Ecu:
    """One ECU (one variant) driving ``n`` applications side by side."""

    def __init__(self, cfg: EcuConfig, act: Actuator, n: int, rng: np.random.Generator) -> None:
        if cfg.variant not in VARIANTS:
            raise ValueError(f"unknown controller variant {cfg.variant!r}; known: {VARIANTS}")
        self.cfg, self.act, self.n, self.rng = cfg, act, n, rng
        self.T = 1.0 / cfg.rate
        J = act.J_me
        wc = 2 * np.pi * cfg.f_current
        self.kp_i, self.ki_i = act.L * wc, act.R * wc
        ws = 2 * np.pi * cfg.f_speed
        self.kp_w = J * ws / act.K_T
        self.ki_w = self.kp_w * ws / 5.0
        self.dF_dtheta = act.K_b * act.r_g  # nominal force per motor radian [N/rad]
        self.kp_f = 2 * np.pi * cfg.f_force / self.dF_dtheta
        self.ki_f = self.kp_f * 2 * np.pi * cfg.f_force / 6.0
        self.kp_pos = 2 * np.pi * cfg.f_pos
        self._a_w = 1.0 - np.exp(-self.T / cfg.w_filter)
        self.reset()

    def reset(self) -> None:
        """Clear every controller state (start of a segment)."""
        z = np.zeros(self.n)
        self.int_i, self.int_w, self.int_f, self.int_p = z.copy(), z.copy(), z.copy(), z.copy()
        self.w_est = z.copy()
        self.th_prev: np.ndarray | None = None
        self.trim = z.copy()
        self.contact = np.zeros(self.n, dtype=bool)
        self.released = np.zeros(self.n, dtype=bool)

    # --- measurements ----------------------------------------------------------------------
    def measure(self, theta: np.ndarray, i: np.ndarray, f_cell: np.ndarray, tare: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """ECU readings: resolver angle, current and tared force, with the ECU's noise."""
        c, n = self.cfg, self.n
        th = theta + c.noise_theta * self.rng.standard_normal(n)
        im = i + c.noise_i * self.rng.standard_normal(n)
        fm = f_cell - tare + c.noise_f * self.rng.standard_normal(n)
        if self.th_prev is not None:
            self.w_est += self._a_w * ((th - self.th_prev) / self.T - self.w_est)
        self.th_prev = th
        return th, im, fm

    # --- inner loops -------------------------------------------------------------------------
    def _current(self, i_ref: np.ndarray, im: np.ndarray) -> np.ndarray:
        """Current PI with back-EMF feed-forward and clamping anti-windup -> voltage."""
        c = self.cfg
        e = i_ref - im
        v = self.kp_i * e + self.int_i + self.act.K_E * self.w_est
        sat = np.clip(v, -c.V_bus, c.V_bus)
        free = (sat == v) | (np.sign(e) != np.sign(v))
        self.int_i = np.where(free, self.int_i + self.ki_i * e * self.T, self.int_i)
        return sat

    def _speed(self, w_ref: np.ndarray, i_max: float) -> np.ndarray:
        """Speed PI -> current reference limited to ``i_max`` (clamping anti-windup)."""
        e = w_ref - self.w_est
        u = self.kp_w * e + self.int_w
        sat = np.clip(u, -i_max, i_max)
        free = (sat == u) | (np.sign(e) != np.sign(u))
        self.int_w = np.where(free, self.int_w + self.ki_w * e * self.T, self.int_w)
        return sat

    # --- apply -------------------------------------------------------------------------------
    def apply(self, t: float, demand: np.ndarray, th: np.ndarray, im: np.ndarray, fm: np.ndarray
              ) -> np.ndarray:
        """Voltage during apply and hold (``t`` from the demand onset)."""
        c, a = self.cfg, self.act
        if c.variant == "voltage":
            return self._apply_voltage(demand, im, fm)
        if c.variant == "cascade":
            e = demand - fm
            self.int_f = np.clip(self.int_f + self.ki_f * e * self.T, -0.2 * c.w_max, 0.2 * c.w_max)
            w_ref = np.clip(self.kp_f * e + self.int_f, -c.w_max, c.w_max)
        else:  # position
            target = (a.x_ag + demand / a.K_b) / a.r_g + self.trim
            if t >= c.trim_delay:
                self.trim += (demand - fm) / self.dF_dtheta * self.T / c.trim_tau
            w_ref = np.clip(self.kp_pos * (target - th), -c.w_max, c.w_max)
        return self._current(self._speed(w_ref, c.I_max), im)

    def _apply_voltage(self, demand: np.ndarray, im: np.ndarray, fm: np.ndarray) -> np.ndarray:
        c, a = self.cfg, self.act
        self.contact |= fm > c.F_contact
        approach = a.K_E * c.w_app + 0.5 * (c.w_app - self.w_est) + a.R * a.T_fc / a.K_T
        e = demand - fm
        kp = self.kp_f * a.K_E  # force error -> speed -> back-EMF voltage [V/N]
        self.int_f = np.where(self.contact, self.int_f + c.ki_v * kp * e * self.T, 0.0)
        v_ff = a.R * (a.r_g * demand + a.T_fs + a.G * demand) / a.K_T
        force = v_ff + kp * e + self.int_f - c.kd_v * a.K_E * self.w_est
        return np.clip(np.where(self.contact, force, approach), -c.V_bus, c.V_bus)

    # --- release -----------------------------------------------------------------------------
    def release(self, t: float, target: np.ndarray, th: np.ndarray, im: np.ndarray,
                fm: np.ndarray) -> np.ndarray:
        """Voltage during release (``t`` from the release command) toward ``target`` [rad]."""
        c = self.cfg
        if t >= c.t_pos + c.t_park:
            return np.zeros(self.n)
        e = target - th
        if c.variant == "voltage":
            return self._release_voltage(t, e, fm)
        if t < c.t_pos:
            w_ref = np.clip(self.kp_pos * e, -c.w_rel, c.w_rel)
            return self._current(self._speed(w_ref, c.I_max), im)
        self.int_p += c.Ki_park * e * self.T
        self.int_p = np.clip(self.int_p, -c.I_park, c.I_park)
        i_ref = np.clip(c.K_park * e + self.int_p, -c.I_park, c.I_park)
        return self._current(i_ref, im)

    def _release_voltage(self, t: float, e: np.ndarray, fm: np.ndarray) -> np.ndarray:
        c, a = self.cfg, self.act
        self.released |= fm < c.F_contact
        if t < c.t_pos:
            w_ref = np.clip(self.kp_pos * e, -c.w_rel, c.w_rel)
            v = a.K_E * w_ref + 0.5 * (w_ref - self.w_est) + np.sign(w_ref) * a.R * a.T_fc / a.K_T
            return np.clip(np.where(self.released, v, -c.V_rel), -c.V_bus, c.V_bus)
        phase = (t - c.t_pos) % c.pulse_period
        on = (phase < c.pulse_on) & (np.abs(e) > c.dead_band)
        return np.where(on, np.sign(e) * c.V_pulse, 0.0)
