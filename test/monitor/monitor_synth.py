"""Closed-form brake applications for the monitor tests (independent of the twin and of the core).

Each application is built from trapezoidal screw-speed moves sampled on the
sample grid (so the trapezoid-rule angle is exact) and a linear clamp spring:
F = K_b * (l / 2 pi) * max(theta - theta_c, 0) with theta_c = x_ag * 2 pi / l
(004 eq. 5-6). The rest position is theta = 0 before every application, so
the true clearance of application k is x_ag,k and the phase boundaries are
known from the construction.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ebm_wear_monitor.params import load_unit

LOAD_GATE_N = 1000.0  # test wear model: wear only above this force (20 sigma of the 50 N noise)


@dataclass
class Synth:
    t: np.ndarray  # [s]
    angle: np.ndarray
    velocity: np.ndarray
    force: np.ndarray
    clearance: list[float] = field(default_factory=list)  # true x_ag per application [m]
    # per application: stamps [s] of motion start, contact, end of apply, start of release, end of release
    marks: list[dict[str, float]] = field(default_factory=list)
    loaded_rotation: list[float] = field(default_factory=list)  # rotation with F > LOAD_GATE per application

    def signals(self) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        return {"angle": (self.t, self.angle), "velocity": (self.t, self.velocity),
                "axial_force": (self.t, self.force)}


def move_profile(rotation: float, speed: float, ramp: int, dt: float) -> np.ndarray:
    """Trapezoidal speed samples (both ends at 0) turning about ``rotation`` [rad] at peak ``speed``."""
    cruise = max(round(abs(rotation) / (speed * dt)) - ramp, 0)
    up = np.arange(1, ramp + 1) / ramp * speed
    prof = np.concatenate([up, np.full(cruise, speed), up[::-1][1:], [0.0]])
    return math.copysign(1.0, rotation) * prof


def synth_cycles(n: int, *, rate_hz: float = 1000.0, clearance=lambda k: 0.2e-3, peak_force=lambda k: 20e3,
                 steps: int = 1, hold_s: float = 0.2, rest_s: float = 0.3, speed: float = 10.0,
                 ramp_s: float = 0.02, noise: bool = False, seed: int = 0, t0: float = 1000.0) -> Synth:
    """``n`` applications (``steps`` equal force steps each, with a hold after each) and their truth."""
    unit = load_unit()
    m = unit.ball_screw.lead / (2.0 * math.pi)
    k_theta = unit.actuator.stiffness * m  # N per rad of screw beyond contact
    dt = 1.0 / rate_hz
    ramp = max(round(ramp_s * rate_hz), 1)
    vel: list[np.ndarray] = []
    theta_c_per_sample: list[np.ndarray] = []
    out = Synth(np.empty(0), np.empty(0), np.empty(0), np.empty(0))
    count = 0
    for k in range(n):
        x_ag = clearance(k)
        theta_c = x_ag / m
        parts = [np.zeros(round(rest_s * rate_hz))]
        total = 0.0
        for j in range(steps):
            target = theta_c + peak_force(k) * (j + 1) / steps / k_theta
            mv = move_profile(target - total, speed, ramp, dt)
            total += float(np.sum(mv)) * dt  # trapezoid rule from the 0 before to the 0 ending the move
            parts += [mv, np.zeros(round(hold_s * rate_hz))]
        parts.append(move_profile(-total, speed, ramp, dt))  # rotations are multiples of speed*dt: back to 0
        cyc = np.concatenate(parts)
        vel.append(cyc)
        theta_c_per_sample.append(np.full(cyc.size, theta_c))
        out.clearance.append(x_ag)
        count += cyc.size
    w = np.concatenate(vel)
    theta = np.concatenate([[0.0], np.cumsum((w[1:] + w[:-1]) / 2.0 * dt)])
    theta_c = np.concatenate(theta_c_per_sample)
    force = k_theta * np.maximum(theta - theta_c, 0.0)
    t = t0 + np.arange(w.size) * dt
    # truth marks per application
    starts = np.cumsum([0] + [v.size for v in vel])
    for k in range(n):
        a, b = starts[k], starts[k + 1]
        ww, ff, tt = w[a:b], force[a:b], t[a:b]
        moving = np.flatnonzero(ww != 0)
        pos, neg = np.flatnonzero(ww > 0), np.flatnonzero(ww < 0)
        out.marks.append({"start": tt[moving[0]] - dt, "contact": tt[np.flatnonzero(ff > 0)[0]],
                          "apply_end": tt[pos[-1]] + dt, "release_start": tt[neg[0]] - dt,
                          "release_end": tt[neg[-1]] + dt})
        loaded = ff > LOAD_GATE_N
        out.loaded_rotation.append(float(np.sum(np.abs(ww[loaded]) * dt)))
    if noise:
        rng = np.random.default_rng(seed)
        q = 2.0 * math.pi / (4096 * unit.actuator.gear_ratio)
        theta = np.round(theta / q) * q  # encoder quantisation
        w = w + rng.normal(0.0, 0.02, w.size)
        force = force + rng.normal(0.0, 50.0, force.size)
    out.t, out.angle, out.velocity, out.force = t, theta, w, force
    return out


def linear_rates(c: float):
    """Test wear model: screw raceway rate c |omega| while loaded (F > LOAD_GATE_N), nothing else [m/s]."""
    def rates(force: np.ndarray, speed: np.ndarray):
        r = c * np.abs(speed) * (force > LOAD_GATE_N)
        return r, np.zeros_like(r), np.zeros_like(r)
    return rates


def screw_growth(s: float, n: float, b: float) -> float:
    """Test clearance growth: equal to the screw wear depth."""
    return s
