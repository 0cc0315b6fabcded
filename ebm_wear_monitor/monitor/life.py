"""Remaining life: wear (clearance to its limit, with uncertainty) beside ISO 3408-5 fatigue life.

Wear life
---------
The filter bank (kalman.py) holds M Gaussian components with weights w_i. In
component i the clearance n applications ahead is linear in its state,
Y_n = h_n . x_i + o_n (``Hypotheses.projection``: steady n, exponential
(rho^n - 1) / (rho - 1), constant acceleration n^2 / 2, model n gbar), hence
Gaussian with

    E_i[Y_n] = h_n . mu_i + o_n,      Var_i[Y_n] = h_n P_i h_n'.

The unit reaches the limit L within n applications when Y_m >= L for some m <= n.
Per component this is approximated by the running maximum over m <= n of
Phi((E_i[Y_m] - L) / sd_i[Y_m]) (exact while the mean path rises; a lower bound
where it turns back), and the remaining life N has the mixture distribution

    P(N <= n) = sum_i w_i max_{m <= n} Phi((E_i[Y_m] - L) / sd_i[Y_m]).

Its quantiles p05 / p50 / p95 (z = ``life_confidence_z``) are found on a
logarithmic grid of n from 0.01 to 1e10 applications and refined within the
bracketing interval (relative resolution 0.02 %). A quantile the distribution
never reaches (the unit may never get to the limit: e.g. the model component
allows no growth) is None: never a made-up number. Future process noise is not
added: over n >> 1 applications the scatter of single applications averages out,
and the uncertainty of the rate dominates.

Status (thresholds in the unit file's ``monitor`` block, people act on them):

* ``due``: the clearance estimate is at or over the limit, or p05 <= ``due_cycles``;
* ``warn``: p05 <= ``warn_cycles``;
* ``insufficient_data``: fewer than ``min_cycles_for_life`` clearance observations
  (all numbers None), or p95 is unbounded (growth not yet resolved from the noise:
  the numbers that exist are bounds, the model's or the data's);
* ``ok`` otherwise.

Fatigue life
------------
ISO 3408-5 basic rating life of a ball screw in revolutions, at 90 % reliability:

    L10 = (C_a / F_m)^3 * 1e6,     F_m = (sum_i |F_i|^3 n_i / sum_i n_i)^(1/3)

with C_a the dynamic axial load rating (unit file) and F_m the cubic-mean axial
load over the revolutions n_i turned at load F_i (here sample by sample,
n_i = |d theta_i| / 2 pi). Applications left to L10 follow at the observed
revolutions per application. The limiting mechanism is the one with fewer
applications left, comparing fatigue (90 % reliability) with the wear p05.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import ndtr

from ebm_wear_monitor.monitor.kalman import Bank, Hypotheses
from ebm_wear_monitor.schema.monitor import STATUS_DUE, STATUS_INSUFFICIENT, STATUS_OK, STATUS_WARN

#: coarse grid of remaining applications for the quantile search [-]
_GRID = np.geomspace(1e-2, 1e10, 161)
_REFINE = np.linspace(0.0, 1.0, 33)  # refinement points inside a bracketing interval, in log n
#: components lighter than this (29 of them hold at most 3e-5) do not move a 5 % quantile
_NEGLIGIBLE_WEIGHT = 1e-6


@dataclass(frozen=True)
class WearLife:
    status: str  # one of schema.monitor.STATUSES
    cycles_p05: float | None  # applications to the clearance limit, 5th percentile [-]; None: unbounded
    cycles_p50: float | None
    cycles_p95: float | None


def _first_passage(hyp: Hypotheses, bank: Bank, keep: np.ndarray, n: np.ndarray, *, limit_m: float,
                   mean_growth_m: float) -> np.ndarray:
    """Phi((E_i[Y_n] - L) / sd_i[Y_n]) for the kept components, shape n.shape + (kept,)."""
    growth, var_growth, cov = hyp.moments(bank, n, mean_growth_m, keep)
    mean = bank.x[keep, 0] + growth
    var = bank.P[keep, 0, 0] + 2.0 * cov + var_growth
    phi: np.ndarray = ndtr((mean - limit_m) / np.sqrt(np.maximum(var, 1e-300)))
    return phi


def life_quantiles(hyp: Hypotheses, bank: Bank, limit_m: float, mean_growth_m: float,
                   probabilities: tuple[float, ...]) -> list[float | None]:
    """Remaining applications N with P(N <= n) = p for each p (module docstring); None where never reached."""
    w = bank.weights()
    keep = w > _NEGLIGIBLE_WEIGHT
    w = w[keep] / w[keep].sum()
    coarse = _first_passage(hyp, bank, keep, _GRID, limit_m=limit_m, mean_growth_m=mean_growth_m)
    running = np.maximum.accumulate(coarse, axis=0)
    cdf = running @ w
    p = np.asarray(probabilities, float)
    i = np.searchsorted(cdf, p)
    inside = (i > 0) & (i < _GRID.size)  # others: reached at the first grid point (0) or never (None)
    out: list[float | None] = [0.0 if k == 0 else None for k in i]
    if not inside.any():
        return out
    lo_n, floor = _GRID[np.maximum(i - 1, 0)][inside], running[np.maximum(i - 1, 0)][inside]
    ratio = _GRID[1] / _GRID[0]
    for level in range(2):  # refine every bracketing interval twice, all quantiles in one call: 0.02 %
        fine = lo_n[:, None] * ratio ** (_REFINE / (_REFINE.size - 1) ** level)  # (q, 33)
        cdf_fine = np.maximum(floor[:, None, :], _first_passage(
            hyp, bank, keep, fine, limit_m=limit_m, mean_growth_m=mean_growth_m))  # (q, 33, kept)
        total = cdf_fine @ w
        j = np.array([np.searchsorted(row, q) for row, q in zip(total, p[inside], strict=True)])
        j = np.clip(j, 1, fine.shape[1] - 1)
        rows = np.arange(j.size)
        lo_n, floor = fine[rows, j - 1], cdf_fine[rows, j - 1]
    lo_c, hi_c = total[rows, j - 1], total[rows, j]
    t = np.where(hi_c > lo_c, (p[inside] - lo_c) / np.where(hi_c > lo_c, hi_c - lo_c, 1.0), 0.0)
    refined = fine[rows, j - 1] * (fine[rows, j] / fine[rows, j - 1]) ** t
    for slot, value in zip(np.flatnonzero(inside), refined, strict=True):
        out[slot] = float(value)
    return out


def wear_life(hyp: Hypotheses, bank: Bank, limit_m: float, mean_growth_m: float, *, observations: int,
              min_observations: int, z: float, warn_cycles: float, due_cycles: float) -> WearLife:
    """Applications until the clearance reaches ``limit_m`` (p05 / p50 / p95) and the status (module doc)."""
    clearance, _ = bank.clearance()
    if clearance >= limit_m:
        return WearLife(STATUS_DUE, 0.0, 0.0, 0.0)
    if observations < min_observations:
        return WearLife(STATUS_INSUFFICIENT, None, None, None)
    lo = float(ndtr(-z))
    p05, p50, p95 = life_quantiles(hyp, bank, limit_m, mean_growth_m, (lo, 0.5, 1.0 - lo))
    if p05 is not None and p05 <= due_cycles:
        status = STATUS_DUE
    elif p05 is not None and p05 <= warn_cycles:
        status = STATUS_WARN
    elif p95 is None:
        status = STATUS_INSUFFICIENT
    else:
        status = STATUS_OK
    return WearLife(status, p05, p50, p95)


@dataclass(frozen=True)
class FatigueLife:
    l10_revolutions: float | None  # ISO 3408-5 L10 at the cubic-mean load [rev]
    cubic_mean_load_n: float | None  # F_m [N]
    revolutions: float  # revolutions turned so far [rev]
    remaining_cycles: float | None  # applications left to L10 at the observed revolutions per application


def fatigue_life(load_rating_n: float | None, sum_f3_rot: float, sum_rot_rad: float,
                 cycles: int) -> FatigueLife:
    """ISO 3408-5 L10 from sum |F|^3 |d theta| [N^3 rad] and sum |d theta| [rad] over the life so far."""
    revs = sum_rot_rad / (2.0 * math.pi)
    if load_rating_n is None or sum_rot_rad <= 0.0:
        return FatigueLife(None, None, revs, None)
    f_m = (sum_f3_rot / sum_rot_rad) ** (1.0 / 3.0)
    if f_m <= 0.0:
        return FatigueLife(None, 0.0, revs, None)
    l10 = (load_rating_n / f_m) ** 3 * 1e6
    remaining = (l10 - revs) / (revs / cycles) if cycles > 0 else None
    return FatigueLife(l10, f_m, revs, remaining)


def limiting_mechanism(wear: WearLife, fatigue: FatigueLife) -> str:
    """'wear', 'fatigue' or 'unknown' (one of the two lives is not known yet)."""
    if wear.cycles_p05 == 0.0:
        return "wear"
    if fatigue.remaining_cycles is not None and fatigue.remaining_cycles <= 0.0:
        return "fatigue"
    if wear.cycles_p05 is None or fatigue.remaining_cycles is None:
        return "unknown"
    return "wear" if wear.cycles_p05 <= fatigue.remaining_cycles else "fatigue"

