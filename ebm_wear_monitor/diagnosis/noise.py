"""Measured noise levels: the yardstick that makes residuals of different signals comparable.

Sensor noise is estimated from the data itself, robustly, so that no noise
level has to be configured:

* **Raw signals** (:func:`signal_noise`). For a smooth trajectory x(t) sampled
  at dt plus white noise n_k of standard deviation sigma, the second difference
  d_k = x_{k+1} - 2 x_k + x_{k-1} is x''(t) dt^2 (negligible at 0.1-1 kHz) plus
  n_{k+1} - 2 n_k + n_{k-1}, whose variance is (1 + 4 + 1) sigma^2 = 6 sigma^2.
  Kinks (contact, stops) give a few large d_k, which a robust scale ignores.  The
  median absolute deviation is that scale for continuous noise, but a quantised
  signal (an encoder, an ADC) has second differences in {0, +-q, +-2q}, mostly 0 when
  the noise is below the step, and its MAD collapses to zero while the noise does not
  (a quantum q adds q^2 / 12 per sample).  So the scale is the RMS of the central
  95 % of |d|, divided by its Gaussian trimming factor sqrt(0.759) and by sqrt(6),
  and never below the quantisation noise q / sqrt(12) of the smallest step seen.
* **Block residual series** (:func:`series_noise`). Residuals averaged over
  short blocks (see :mod:`.residuals`) are smooth in their model-error part and
  white in their noise part. A second difference at lag 2 (blocks that share no
  end-point sample) cancels the smooth part up to its curvature; see there.
"""

from __future__ import annotations

import numpy as np
from scipy import optimize, stats

MAD_TO_SIGMA = 1.482602218505602  # 1 / Phi^-1(3/4): MAD -> sigma for a Gaussian


def mad_sigma(x: np.ndarray) -> float:
    """Robust standard deviation 1.4826 median(|x - median(x)|) of a sample (0 when empty)."""
    x = np.asarray(x, dtype=float)
    if x.size == 0:
        return 0.0
    return float(MAD_TO_SIGMA * np.median(np.abs(x - np.median(x))))


TRIM = 0.95  # share of the second differences kept by the robust scale
TRIM_FACTOR = 0.7590  # E[X^2 | |X| < 1.96] for a standard normal X: the variance the trimming keeps


def signal_noise(x: np.ndarray) -> float:
    """White-noise standard deviation of a sampled signal, from its second differences (see module doc)."""
    x = np.asarray(x, dtype=float)
    if x.size < 3:
        return 0.0
    d = np.abs(x[2:] - 2.0 * x[1:-1] + x[:-2])
    kept = d[d <= np.quantile(d, TRIM)]
    sigma = float(np.sqrt(np.mean(kept * kept) / TRIM_FACTOR / 6.0)) if kept.size else 0.0
    return max(sigma, quantum(x) / np.sqrt(12.0))


def quantum(x: np.ndarray) -> float:
    """The smallest nonzero step between consecutive samples (the count of a quantised signal; for a
    continuous one a tiny number), 0 when the signal never changes."""
    x = np.asarray(x, dtype=float)
    if x.size < 2:
        return 0.0
    steps = np.abs(np.diff(x))
    steps = steps[steps > 1e-12 * max(1.0, float(np.max(np.abs(x))))]
    return float(np.min(steps)) if steps.size else 0.0


def series_noise(r: np.ndarray, group: np.ndarray | None = None, min_diffs: int = 1) -> float:
    """Noise standard deviation of a block-residual series from lag-2 curvature within groups.

    d_b = r_b - (r_{b-2} + r_{b+2}) / 2 cancels any part of the residual that is
    linear over five blocks (a model error that grows with force during force
    generation, say) and, for independent noise, has variance (1 + 1/4 + 1/4)
    sigma^2; hence sigma = 1.4826 MAD(d) / sqrt(1.5).  Blocks two apart share no
    end-point sample.  ``group`` (same length) labels contiguous segments;
    differences never cross a segment boundary.  Returns 0 when fewer than 5
    blocks, or fewer than ``min_diffs`` differences within segments, are available
    (the MAD of a handful of differences is no scale: of three, it is 0 one time in
    three... and far below sigma often).
    """
    r = np.asarray(r, dtype=float)
    if r.size < 5:
        return 0.0
    d = r[2:-2] - 0.5 * (r[:-4] + r[4:])
    if group is not None:
        group = np.asarray(group)
        d = d[(group[:-4] == group[2:-2]) & (group[4:] == group[2:-2])]
    if d.size < min_diffs:
        return 0.0
    return mad_sigma(d) / np.sqrt(1.5)


#: median of the chi-square distribution with one degree of freedom: median(z^2) for z ~ N(0, 1)
CHI2_1_MEDIAN = float(stats.chi2.ppf(0.5, 1))


def median_scale(r: np.ndarray, s: np.ndarray, extra: np.ndarray | None = None) -> float:
    """Robust scale c of a residual series against a propagated noise: median(r^2 / (c^2 s^2 + e^2)) is
    the median of chi-square(1), ``CHI2_1_MEDIAN``, so that r / sqrt(c^2 s^2 + e^2) is standard
    normal in its central half (0 when ``extra`` e alone, or nothing, explains the residual).

    A model error confined to a minority of the blocks (the transients where a motion starts or stops)
    does not move the median; one present in most blocks raises it, never lowers it. The lag-2 scale of
    :func:`series_noise` errs the other way (smooth model error cancels, sharp transients do not): the
    noise is at most the smaller of the two.
    """
    r2 = np.asarray(r, dtype=float) ** 2
    s2 = np.asarray(s, dtype=float) ** 2
    e2 = np.zeros_like(s2) if extra is None else np.asarray(extra, dtype=float) ** 2
    if r2.size == 0:
        return 0.0

    def excess(c: float) -> float:
        with np.errstate(over="ignore"):  # c = 0 without e: a residual over the 1e-300 guard is infinite
            return float(np.median(r2 / (c * c * s2 + e2 + 1e-300))) - CHI2_1_MEDIAN

    if excess(0.0) <= 0.0:
        return 0.0
    hi = 1.0
    while excess(hi) > 0.0:
        hi *= 2.0
    return float(optimize.brentq(excess, 0.0, hi, xtol=1e-6 * hi))
