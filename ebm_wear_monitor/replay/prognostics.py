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
                        alpha: float = ALPHA, lam: float = LAMBDA, alpha_ph: float = ALPHA_PH) -> dict:
    """Prognostic horizon, alpha-lambda accuracy and relative accuracy (module docstring).

    Args:
        cycles: application count k at each prediction [-], increasing.
        rul_predicted: predicted remaining applications r(k) (median) [-]; NaN where none was made.
        eol_cycles: true application count at end of life k_EOL [-].
    """
    cycles = np.asarray(cycles, dtype=float)
    rul = np.asarray(rul_predicted, dtype=float)
    keep = np.isfinite(rul) & (cycles < eol_cycles)
    k, r = cycles[keep], rul[keep]
    out: dict = {"eol_cycles": float(eol_cycles), "predictions": len(k), "alpha": alpha, "lambda": lam,
                 "alpha_ph": alpha_ph, "prognostic_horizon_cycles": None, "alpha_lambda_pass": None,
                 "alpha_lambda_fraction": None, "relative_accuracy": None,
                 "cumulative_relative_accuracy": None, "first_prediction_cycles": None}
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
