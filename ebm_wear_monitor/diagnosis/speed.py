"""Screw speed from the angle: a local quadratic regression with the true stamps (see :mod:`.conventions`).

A drive's own velocity estimate (a filtered derivative, a moving average, an
observer) lags the motion; the angle is the motion.  :func:`local_slope` fits
theta(t) ~ a + b (t - t_i) + c (t - t_i)^2 by least squares over the samples within
``half`` indices of sample i (optionally only those of the same group, e.g. the same
phase run, so no window straddles a kink) and returns b with its variance factor
[(X'X)^-1]_bb: var(b) = factor * sigma_theta^2 for white angle noise.  The true
stamps enter the regression, so stamp jitter does not bias the speed.
"""

from __future__ import annotations

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

from ebm_wear_monitor.diagnosis.recording import Resampled

WINDOW_S = 0.005  # length of the speed regression window [s] (at least 5 samples)


def local_slope(t: np.ndarray, y: np.ndarray, half: int, group: np.ndarray | None = None
                ) -> tuple[np.ndarray, np.ndarray]:
    """Slope dy/dt of a local quadratic least-squares fit at every sample, and its variance factor.

    The window holds the samples within ``half`` indices of sample i that share its ``group``
    label (all, when None).  Returns ``(slope, factor)`` with var(slope) = factor * sigma_y^2 for
    white noise of standard deviation sigma_y on ``y``; a window of fewer than 3 samples falls
    back to a straight line, of fewer than 2 to a zero slope with zero weight (factor inf).
    """
    n, w = t.size, 2 * half + 1
    g = np.zeros(n, np.int64) if group is None else np.asarray(group, np.int64)
    pad = np.full(half, -1, np.int64)
    gp = sliding_window_view(np.concatenate((pad, g, pad)), w)
    tp = sliding_window_view(np.concatenate((np.zeros(half), t, np.zeros(half))), w)
    yp = sliding_window_view(np.concatenate((np.zeros(half), y, np.zeros(half))), w)
    inside = gp == g[:, None]
    d = np.where(inside, tp - t[:, None], 0.0)
    scale = np.where(np.abs(d).max(axis=1) > 0.0, np.abs(d).max(axis=1), 1.0)
    u = d / scale[:, None]  # dimensionless abscissa in [-1, 1] keeps the normal equations conditioned
    r = np.where(inside, yp - y[:, None], 0.0)
    m = inside.astype(float)
    s = [np.sum(m * u**k, axis=1) for k in range(5)]
    q = [np.sum(m * u**k * r, axis=1) for k in range(3)]
    A = np.stack([np.stack([s[0], s[1], s[2]], -1), np.stack([s[1], s[2], s[3]], -1),
                  np.stack([s[2], s[3], s[4]], -1)], -2)
    rhs = np.stack(q, -1)
    slope = np.zeros(n)
    factor = np.full(n, np.inf)
    quad = s[0] >= 3.0
    if quad.any():
        inv = np.linalg.inv(A[quad])
        coef = np.einsum("nij,nj->ni", inv, rhs[quad])
        slope[quad], factor[quad] = coef[:, 1], inv[:, 1, 1]
    lin = (s[0] == 2.0)
    if lin.any():
        det = s[0][lin] * s[2][lin] - s[1][lin] ** 2
        ok = det > 0.0
        idx = np.flatnonzero(lin)[ok]
        slope[idx] = (s[0][lin][ok] * q[1][lin][ok] - s[1][lin][ok] * q[0][lin][ok]) / det[ok]
        factor[idx] = s[0][lin][ok] / det[ok]
    return slope / scale, factor / scale**2


def window_half(dt: float, window_s: float = WINDOW_S) -> int:
    """Half-length h of the regression window in samples: ``window_s`` / 2 at sample interval ``dt`` [s],
    at least 2 (a window of 2 h + 1 samples)."""
    return max(2, round(0.5 * window_s / dt))


def angle_speed(rec: Resampled, group: np.ndarray | None = None, window_s: float = WINDOW_S
                ) -> tuple[np.ndarray, np.ndarray]:
    """Screw speed [rad/s] from the angle by :func:`local_slope` and its variance factor [1/s^2]."""
    return local_slope(rec.t, rec.angle, window_half(rec.dt, window_s), group)
