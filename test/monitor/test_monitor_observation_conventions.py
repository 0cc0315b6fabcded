"""Recording conventions the clearance observation estimates from the data (issue 11 item 2).

Found on the independently simulated units (validation/foreign): a lagging load cell put the
observed clearance 1-8 um above the truth, and an approach that stops before (or in) contact made
the rest angle the stop's, an observed clearance near zero. Checked here on closed-form
applications (monitor_synth.py) with a first-order force lag written out independently of the
code, and with a controller that eases in.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from ebm_wear_monitor.monitor import MonitorCore
from ebm_wear_monitor.params import load_unit

from monitor_synth import linear_rates, move_profile, screw_growth, synth_cycles


def _lagged(force: np.ndarray, dt: float, tau: float) -> np.ndarray:
    """First-order lag dy/dt = (x - y) / tau, exact for a piecewise-linear input (ramp-invariant)."""
    a = math.exp(-dt / tau)
    b = tau / dt * (1.0 - a)
    y = np.empty_like(force)
    y[0] = force[0]
    for i in range(1, force.size):
        y[i] = a * y[i - 1] + (1.0 - b) * force[i] + (b - a) * force[i - 1]
    return y


def _core(unit, signals):
    core = MonitorCore(unit, wear_rates=linear_rates(1e-9), clearance_growth=screw_growth)
    for s, (t, v) in signals.items():
        core.add(s, t, v)
    return core, core.process(final=True)


@pytest.mark.parametrize("tau", [0.0, 0.8e-3, 2e-3])
def test_force_sensor_lag_is_estimated_and_removed(unit, tau):
    """With a lag tau the apply stroke alone overstates the clearance by tau x nut speed (4 um per ms at
    5 rad/s here); apply and release together give tau, and the clearance is unbiased."""
    truth = [0.2e-3 + 2e-6 * (k % 4) for k in range(30)]
    synth = synth_cycles(30, rate_hz=1000.0, noise=True, seed=5, clearance=lambda k: truth[k],
                         peak_force=lambda k: 8e3 + 2e3 * (k % 5), speed=5.0)
    signals = synth.signals()
    if tau:
        signals["axial_force"] = (synth.t, _lagged(synth.force, 1e-3, tau))
    core, cycles = _core(unit, signals)
    lag, lag_var = core.force_lag()
    assert lag == pytest.approx(tau, abs=max(0.05 * tau, 2e-5))
    assert math.sqrt(lag_var) < 2e-5
    err = np.array([c.clearance_observed_m for c in cycles]) - np.array(truth)
    assert abs(np.nanmean(err)) < 0.3e-6  # the apply-only fit would be off by 5 rad/s * l / 2 pi * tau
    assert np.isfinite(err).all()
    state = core.state
    assert state.force_lag_weighted_sum / state.force_lag_weight == lag  # persisted with the state


def _eased_in(unit, *, stop_short: bool, rate_hz: float = 1000.0):
    """Applications whose approach stops (0.2 s) 50 um before contact, or creeps into contact slowly."""
    m = unit.ball_screw.lead / (2 * math.pi)
    k_theta = unit.actuator.stiffness * m
    dt, x_ag = 1.0 / rate_hz, 0.25e-3
    theta_c, peak = x_ag / m, 15e3 / k_theta
    vel = []
    for _ in range(6):
        first = theta_c - 50e-6 / m if stop_short else theta_c - 0.02
        parts = [np.zeros(300), move_profile(first, 10.0, 20, dt), np.zeros(200 if stop_short else 0)]
        if not stop_short:  # creep into contact at 0.3 rad/s: below the 'moving' threshold
            parts.append(np.full(round(0.04 / 0.3 / dt), 0.3))
        done = sum(float(np.sum(p)) * dt for p in parts)
        parts += [move_profile(theta_c + peak - done, 10.0, 20, dt), np.zeros(200)]
        total = sum(float(np.sum(p)) * dt for p in parts)
        parts.append(move_profile(-total, 10.0, 20, dt))
        vel.append(np.concatenate(parts))
    w = np.concatenate(vel)
    theta = np.concatenate([[0.0], np.cumsum((w[1:] + w[:-1]) / 2.0 * dt)])
    force = k_theta * np.maximum(theta - theta_c, 0.0)
    t = 1000.0 + np.arange(w.size) * dt
    return {"angle": (t, theta), "velocity": (t, w), "axial_force": (t, force)}, x_ag


@pytest.mark.parametrize("stop_short", [True, False])
def test_an_approach_that_eases_in_counts_the_clearance_from_home(stop_short):
    """A stop 50 um short of the pads is not a new rest position, nor is a creep (below the moving
    threshold) that reaches the pads: the clearance is the travel from home, the force level home's."""
    unit = load_unit()
    signals, x_ag = _eased_in(unit, stop_short=stop_short)
    _, cycles = _core(unit, signals)
    assert len(cycles) == 6
    observed = np.array([c.clearance_observed_m for c in cycles])
    assert observed == pytest.approx(x_ag, abs=2e-6)
