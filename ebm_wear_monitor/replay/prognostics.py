"""Standard prognostics metrics of a remaining-life estimate against the simulator's ground truth.

After Saxena, Celaya, Saha, Saha and Goebel, "Metrics for offline evaluation of
prognostic performance", Int. J. PHM 1 (2010) (the metrics of the NASA PCoE
toolkit). Time is counted in brake applications (cycles) here: a prediction
made after application ``k`` says ``r(k)`` applications remain; the truth is
``r*(k) = k_EOL - k`` with ``k_EOL`` the application at which the true axial
clearance reaches the limit (``ground_truth.json``, ``bagio.sidecar``).
``k_P`` is the first application with a prediction. The point prediction is
the median ``cycles_p50``.

* Prognostic horizon (PH): ``PH = k_EOL - k_a`` with ``k_a`` the first
  application from which *every* later prediction stays inside the constant
  band ``r*(k) +- alpha_ph * k_EOL``. Larger is better; null when the last
  prediction is still outside the band.
* alpha-lambda accuracy: at ``k_lambda = k_P + lambda (k_EOL - k_P)``, is
  ``(1 - alpha) r*(k_lambda) <= r(k_lambda) <= (1 + alpha) r*(k_lambda)``? The
  cone narrows with the truth. Evaluated at the last prediction at or before
  ``k_lambda``; null when the recording stops before ``k_lambda``. The share of
  all predictions inside the cone is reported beside it.
* Relative accuracy (RA): ``RA(k_lambda) = 1 - |r*(k_lambda) - r(k_lambda)| / r*(k_lambda)``
  (1 = perfect) and the cumulative relative accuracy, the mean RA over all
  predictions before end of life.
* Coverage: the share of predictions whose band p05..p95 holds the truth (calibrated: 90 %),
  over the predictions that give both bounds.

The naive baseline (:func:`line_forecast`) is what anyone would do first: a least-squares
line through every clearance observed so far, z_i = a + b i (i the application), extrapolated
to the limit L. With s^2 = RSS / (n - 2) and the covariance of (a, b) s^2 (X'X)^-1, the
clearance now c = a + b k and the slope b are Gaussian, and its quantiles solve the same
quadratic as a steady filter component (monitor/life.py): (c + n b - L)^2 = z^2 Var(c + n b).
"""

from __future__ import annotations

import numpy as np

#: width of the prognostic-horizon band as a fraction of k_EOL (Saxena et al. 2010 use 0.05-0.2)
ALPHA_PH = 0.1
#: half-width of the alpha-lambda cone as a fraction of the true remaining life
ALPHA = 0.2
#: fraction of the way from first prediction to end of life where alpha-lambda and RA are judged
LAMBDA = 0.5


def prognostics_metrics(cycles: np.ndarray, rul_predicted: np.ndarray, eol_cycles: float, *,
                        alpha: float = ALPHA, lam: float = LAMBDA, alpha_ph: float = ALPHA_PH,
                        rul_p05: np.ndarray | None = None, rul_p95: np.ndarray | None = None) -> dict:
    """Prognostic horizon, alpha-lambda accuracy, relative accuracy and coverage (module docstring).

    Args:
        cycles: application count k at each prediction [-], increasing.
        rul_predicted: predicted remaining applications r(k) (median) [-]; NaN where none was made.
        eol_cycles: true application count at end of life k_EOL [-].
        rul_p05, rul_p95: the band of each prediction [-] (NaN: unbounded or none) for the coverage.
    """
    cycles = np.asarray(cycles, dtype=float)
    rul = np.asarray(rul_predicted, dtype=float)
    out: dict = {"eol_cycles": float(eol_cycles), "predictions": 0, "alpha": alpha, "lambda": lam,
                 "alpha_ph": alpha_ph, "prognostic_horizon_cycles": None, "alpha_lambda_pass": None,
                 "alpha_lambda_fraction": None, "relative_accuracy": None,
                 "cumulative_relative_accuracy": None, "first_prediction_cycles": None,
                 "coverage": None, "predictions_with_band": 0}
    if rul_p05 is not None and rul_p95 is not None:
        lo, hi = np.asarray(rul_p05, float), np.asarray(rul_p95, float)
        banded = np.isfinite(lo) & np.isfinite(hi) & (cycles < eol_cycles)
        truth_b = eol_cycles - cycles[banded]
        out["predictions_with_band"] = int(banded.sum())
        if banded.any():
            out["coverage"] = float(np.mean((lo[banded] <= truth_b) & (truth_b <= hi[banded])))
    keep = np.isfinite(rul) & (cycles < eol_cycles)
    k, r = cycles[keep], rul[keep]
    out["predictions"] = len(k)
    if not len(k):
        return out
    truth = eol_cycles - k
    inside_ph = np.abs(r - truth) <= alpha_ph * eol_cycles
    if inside_ph[-1]:
        last_out = np.flatnonzero(~inside_ph)
        first_in = 0 if not len(last_out) else last_out[-1] + 1
        out["prognostic_horizon_cycles"] = float(eol_cycles - k[first_in])
    in_cone = (r >= (1 - alpha) * truth) & (r <= (1 + alpha) * truth)
    ra = 1.0 - np.abs(truth - r) / truth
    out["first_prediction_cycles"] = float(k[0])
    out["alpha_lambda_fraction"] = float(in_cone.mean())
    out["cumulative_relative_accuracy"] = float(ra.mean())
    k_lambda = k[0] + lam * (eol_cycles - k[0])
    at = np.searchsorted(k, k_lambda, side="right") - 1
    if k[-1] >= k_lambda:
        out["alpha_lambda_pass"] = bool(in_cone[at])
        out["relative_accuracy"] = float(ra[at])
    return out


def line_forecast(cycles: np.ndarray, observed_m: np.ndarray, limit_m: float, *,
                  z: float = 1.6448536269514722, min_observations: int = 10) -> np.ndarray:
    """The naive baseline after each application: (len(cycles), 3) remaining applications p05/p50/p95
    from a least-squares line through every observation so far (module docstring); NaN where fewer than
    ``min_observations`` observations, where the quantile does not exist (slope not resolved) or the
    fitted clearance is at the limit (then 0)."""
    k = np.asarray(cycles, float)
    z_obs = np.asarray(observed_m, float)
    seen = np.isfinite(z_obs)
    i, y = np.where(seen, k, 0.0), np.where(seen, z_obs, 0.0)
    n, s1, s2 = np.cumsum(seen), np.cumsum(i), np.cumsum(i * i)
    sy, siy, syy = np.cumsum(y), np.cumsum(i * y), np.cumsum(y * y)
    out = np.full((k.size, 3), np.nan)
    ok = n >= max(min_observations, 3)
    n, s1, s2, sy, siy, syy, kk = (a[ok] for a in (n, s1, s2, sy, siy, syy, k))
    det = n * s2 - s1 * s1
    with np.errstate(divide="ignore", invalid="ignore"):
        b = (n * siy - s1 * sy) / det
        a = (sy - b * s1) / n
        s_sq = np.maximum(syy - a * sy - b * siy, 0.0) / (n - 2)
        var_a, var_b, cov_ab = s_sq * s2 / det, s_sq * n / det, -s_sq * s1 / det
        c = a + b * kk  # the fitted clearance now
        p_cc, p_cb, p_bb = var_a + 2 * kk * cov_ab + kk * kk * var_b, cov_ab + kk * var_b, var_b
        gap = c - limit_m  # < 0 below the limit
        res = np.full((kk.size, 3), np.nan)
        res[:, 1] = np.where(b > 0, -gap / b, np.nan)
        qa = b * b - z * z * p_bb
        qb = 2.0 * (gap * b - z * z * p_cb)
        qc = gap * gap - z * z * p_cc
        root = np.sqrt(np.maximum(qb * qb - 4.0 * qa * qc, 0.0))
        small, large = (-qb - root) / (2.0 * qa), (-qb + root) / (2.0 * qa)
        resolved = qa > 0.0  # the slope's lower bound is above zero: p95 exists
        res[:, 0] = np.where(resolved, small, np.where(b > 0, np.maximum(small, large), np.nan))
        res[:, 2] = np.where(resolved, large, np.nan)
        res = np.where(gap[:, None] >= 0.0, 0.0, np.maximum(res, 0.0))
    out[ok] = res
    return out
