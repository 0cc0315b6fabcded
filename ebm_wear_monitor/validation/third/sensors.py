"""Acquisition of the third world: turns the dense true record into sampled, stamped topics.

Conventions (all drawn per recording in cases.py and written to truth.json):
  angle    encoder on the motor (counts per motor turn, scaled by 1/i_g) or on the screw; an
           arbitrary multi-turn zero offset [rad]; floor quantisation.
  velocity computed by the drive at its control rate from the quantised angle: a tracking
           observer (2nd order, bandwidth f_o), the M/T edge-timing method (1/T between encoder
           edges, decaying as q/(t - t_edge) when no edge), or a filtered difference (1st-order tau);
           held until the topic samples it.
  force    strain-gauge amplifier: gain (the force_sensor_bias effect), 1st- or 2nd-order low
           pass, tare offset [N], white noise [N], ADC step [N].
  current  sampled at the stamp, or averaged over the preceding control period; gain, offset,
           noise [A].
  stamps   per-topic rate, phase, Gaussian jitter [s], dropped samples, one short gap.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import signal

from .world import Dense


def stamps(
    rate: float, T: float, rng: np.random.Generator, *, jitter: float, drop: float, gap: float
) -> np.ndarray:
    """Sample times [s] in [0, T): rate [Hz], random phase, jitter, drops and one gap [s]."""
    t = rng.uniform(0, 1.0 / rate) + np.arange(int(T * rate) - 1) / rate
    t = t + np.clip(rng.normal(0, jitter, t.size), -4 * jitter, 4 * jitter)
    keep = rng.random(t.size) >= drop
    if gap > 0:
        g0 = rng.uniform(0.2, 0.8) * T
        keep &= (t < g0) | (t > g0 + gap)
    t = np.sort(t[keep])
    return t[(t > 0) & (t < T)]


def _zoh(t_grid: np.ndarray, v: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Latest value of a causal sequence at times t (zero-order hold)."""
    idx = np.clip(np.searchsorted(t_grid, t, side="right") - 1, 0, len(v) - 1)
    return v[idx]


def angle(d: Dense, t: np.ndarray, cv: dict, i_g: float) -> np.ndarray:
    """Screw angle topic [rad]: encoder side, zero offset, quantisation."""
    q = cv["angle_lsb_rad"]
    src = d.th_motor / i_g if cv["encoder_side"] == "motor" else d.th_screw
    return np.floor((np.interp(t, d.t, src) + cv["angle_offset_rad"]) / q) * q


def velocity(d: Dense, t: np.ndarray, cv: dict, i_g: float) -> np.ndarray:
    """Screw velocity topic [rad/s] from the drive's estimator at the control rate."""
    q = cv["angle_lsb_rad"]
    src = d.th_motor / i_g if cv["encoder_side"] == "motor" else d.th_screw
    tg, th = d.t[:: d.ctrl_every], src[:: d.ctrl_every]
    dt = d.h * d.ctrl_every
    cnt = np.floor((th + cv["angle_offset_rad"]) / q)
    method = cv["velocity_method"]
    if method == "filtered_difference":
        a = 1.0 - math.exp(-dt / cv["velocity_tau_s"])
        v = signal.lfilter([a], [1, a - 1], np.diff(cnt, prepend=cnt[0]) * q / dt)
    elif method == "observer":
        wo = 2 * math.pi * cv["velocity_bw_hz"]
        b, a, _ = signal.cont2discrete(  # type: ignore[call-overload]  # scipy-stubs: (num, den) not overloaded
            ([wo**2, 0], [1, 2 * 0.8 * wo, wo**2]), dt, method="bilinear")
        b = np.ravel(b)
        x = (cnt - cnt[0]) * q
        v = signal.lfilter(b, a, x)
    else:  # M/T edge timing on interpolated edge instants
        src_f = src[:: d.ctrl_every] + cv["angle_offset_rad"]
        e = np.flatnonzero(np.diff(cnt)) + 1
        v = np.zeros_like(tg)
        if e.size >= 2:
            lvl = np.where(cnt[e] > cnt[e - 1], cnt[e], cnt[e] + 1) * q  # last boundary crossed
            frac = np.clip((lvl - src_f[e - 1]) / (src_f[e] - src_f[e - 1]), 0, 1)
            te = tg[e - 1] + frac * dt
            ve = np.zeros(e.size)
            ve[1:] = (cnt[e[1:]] - cnt[e[:-1]]) * q / np.maximum(te[1:] - te[:-1], 1e-6)
            last = np.searchsorted(e, np.arange(tg.size), side="right") - 1
            has = last >= 0
            lv, lt = ve[np.maximum(last, 0)], te[np.maximum(last, 0)]
            decay = q / np.maximum(tg - lt, 1e-6)
            v = np.where(has, np.sign(lv) * np.minimum(np.abs(lv), decay), 0.0)
            v[np.abs(v) < q / cv["velocity_timeout_s"]] = 0.0
    return _zoh(tg, v, t)


def force(d: Dense, t: np.ndarray, cv: dict, gain: float, rng: np.random.Generator) -> np.ndarray:
    """Axial force topic [N], compressive positive."""
    wc = 2 * math.pi * cv["force_lp_hz"]
    den = [1, wc] if cv["force_lp_order"] == 1 else [1, 2 * 0.7 * wc, wc**2]
    b, a, _ = signal.cont2discrete(([den[-1]], den), d.h, method="bilinear")
    y = signal.lfilter(np.ravel(b), a, gain * d.F)
    val = np.interp(t, d.t, y) + cv["force_tare_N"] + rng.normal(0, cv["force_noise_N"], t.size)
    lsb = cv["force_lsb_N"]
    return np.round(val / lsb) * lsb


def current(d: Dense, t: np.ndarray, cv: dict, rng: np.random.Generator) -> np.ndarray:
    """Motor current topic [A]."""
    if cv["current_mode"] == "averaged":
        n = d.ctrl_every
        c = np.cumsum(np.concatenate(([0.0], d.i)))
        avg = (c[n:] - c[:-n]) / n  # mean over the control period ending at d.t[n-1:]
        base = np.interp(t, d.t[n - 1 :], avg)
    else:
        base = np.interp(t, d.t, d.i)
    noise = rng.normal(0, cv["current_noise_A"], t.size)
    return cv["current_gain"] * base + cv["current_offset_A"] + noise
