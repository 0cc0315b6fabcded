"""Closed-form brake applications sampled the way interface.md section 2 allows: each topic at its own rate.

Angle and velocity at 2 kHz, force at 1 kHz, the motor current at 500 Hz; each topic with its own
phase, Gaussian sample-time jitter, a few dropped samples, and a log (receive) time lagging the header
stamp by up to 1.6 ms (non-decreasing per topic). Signals are exact functions of time (000 Fig. 2
phases, force from the clamp law of 004 eq. 6), so any sampling of them is the same unit.
"""

from __future__ import annotations

import numpy as np

LEAD, CLEARANCE, STIFFNESS = 5.0e-3, 0.2e-3, 4.16e7  # reference EMBU (params/reference/embu_000.yaml)
RATES = {"angle": 2000.0, "velocity": 2000.0, "axial_force": 1000.0, "current": 500.0}  # Hz, interface.md 2
PERIOD = 1.6  # s per brake application (closed form below)


def closed_form(t: np.ndarray) -> dict[str, np.ndarray]:
    """Brake applications of 000 Fig. 2 as exact functions of time (force from 004 eq. 6)."""
    theta_p = 2 * np.pi * (CLEARANCE + 20e3 / STIFFNESS) / LEAD
    knots_t = np.array([0.0, 0.4, 0.5, 0.7, 1.0, 1.2, PERIOD])
    knots_theta = np.array([0.0, 0.0, 2 * np.pi * CLEARANCE / LEAD, theta_p, theta_p, 0.0, 0.0])
    phase = t % PERIOD
    theta = np.interp(phase, knots_t, knots_theta)
    seg = np.clip(np.searchsorted(knots_t, phase, side="right") - 1, 0, len(knots_t) - 2)
    omega = (np.diff(knots_theta) / np.diff(knots_t))[seg]
    force = np.maximum(0.0, STIFFNESS * (LEAD * theta / (2 * np.pi) - CLEARANCE))
    return {"angle": theta, "velocity": omega, "axial_force": force, "current": force * 1e-4}


def recording(cycles: int, seed: int, rates: dict[str, float] | None = None, jitter_s: float = 20e-6,
              drop: float = 0.002) -> dict[str, dict[str, np.ndarray]]:
    """Per topic: header stamps [ns], values, log times [ns] (lagging by 0-1.6 ms), own phase and jitter.

    ``rates`` default :data:`RATES` (all four topics); one rate for all, no jitter and no drops give
    the same unit "on one time base".
    """
    rng = np.random.default_rng(seed)
    out = {}
    for signal, rate in (rates or RATES).items():
        n = int(cycles * PERIOD * rate)
        phase = rng.uniform(0, 1e-3) if jitter_s else 0.0
        t = np.arange(n) / rate + phase + rng.normal(0, jitter_s, n)
        t = np.sort(t)
        stamps = 1_700_000_000_000_000_000 + np.rint(t * 1e9).astype(np.int64)
        log = np.maximum.accumulate(stamps + rng.integers(0, 1_600_000, n))  # a topic arrives in order
        keep = rng.random(n) >= drop  # a few dropped samples
        out[signal] = {"stamps": stamps[keep], "values": closed_form(t)[signal][keep], "log": log[keep]}
    return out


