"""Remaining life: wear (clearance to its limit, with uncertainty) beside ISO 3408-5 fatigue life.

Wear life
---------
With the filter's Gaussian state (x_ag, f) ~ N(mu, P) and the model's mean
clearance growth per application g (at the usage seen so far), the clearance
after n more applications is Y_n = x_ag + n g f, Gaussian with

    E[Y_n] = mu_x + n g mu_f,   Var[Y_n] = P_xx + 2 n g P_xf + n^2 g^2 P_ff.

The unit reaches the limit L within n applications when Y_n >= L, so the
distribution of the remaining life N is P(N <= n) = Phi((E[Y_n] - L) / sd[Y_n]).
Its p-quantile solves E[Y_n] - L = z_p sd[Y_n]; squaring gives the quadratic

    (a^2 - z^2 g^2 P_ff) n^2 + 2 (a b - z^2 g P_xf) n + (b^2 - z^2 P_xx) = 0,
    a = g mu_f,  b = mu_x - L,

whose root with sign(b + a n) = sign(z_p) is the quantile (p50: n = -b / a).
The band is finite only when a^2 > z^2 g^2 P_ff, i.e. mu_f > z sigma_f: the
factor's lower bound must be positive, which is exactly "growth is measurable".
Before that (or before ``min_cycles_for_life`` observations) the status is
``insufficient_data`` and the numbers are None, never made up.

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

STATUS_OK = "ok"
STATUS_INSUFFICIENT = "insufficient_data"
STATUS_LIMIT = "limit_reached"


@dataclass(frozen=True)
class WearLife:
    status: str  # "ok" | "insufficient_data" | "limit_reached"
    cycles_p05: float | None  # applications to the limit, 5th percentile [-]
    cycles_p50: float | None
    cycles_p95: float | None


def _quantile(mu: np.ndarray, P: np.ndarray, limit: float, g: float, z: float) -> float:
    a, b = g * mu[1], mu[0] - limit
    if z == 0.0:
        return -b / a
    A = a * a - z * z * g * g * P[1, 1]
    B = 2.0 * (a * b - z * z * g * P[0, 1])
    C = b * b - z * z * P[0, 0]
    disc = max(B * B - 4.0 * A * C, 0.0)
    roots = ((-B - math.sqrt(disc)) / (2.0 * A), (-B + math.sqrt(disc)) / (2.0 * A))
    # p05 (z < 0): the mean path is still below the limit, b + a n < 0: the smaller root
    return roots[0] if z < 0 else roots[1]


def wear_life(mu: np.ndarray, P: np.ndarray, limit_m: float, growth_per_cycle_m: float, *,
              observations: int, min_cycles: int, z: float) -> WearLife:
    """Applications until the clearance x_ag reaches ``limit_m``: p05 / p50 / p95 (see module doc)."""
    mu, P = np.asarray(mu, float), np.asarray(P, float)
    if mu[0] >= limit_m:
        return WearLife(STATUS_LIMIT, 0.0, 0.0, 0.0)
    sigma_f = math.sqrt(max(P[1, 1], 0.0))
    if (observations < min_cycles or not growth_per_cycle_m > 0.0 or not math.isfinite(growth_per_cycle_m)
            or mu[1] - z * sigma_f <= 0.0):
        return WearLife(STATUS_INSUFFICIENT, None, None, None)
    q = [max(_quantile(mu, P, limit_m, growth_per_cycle_m, zz), 0.0) for zz in (-z, 0.0, z)]
    return WearLife(STATUS_OK, *q)


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
    if wear.status == STATUS_LIMIT:
        return "wear"
    if fatigue.remaining_cycles is not None and fatigue.remaining_cycles <= 0.0:
        return "fatigue"
    if wear.cycles_p05 is None or fatigue.remaining_cycles is None:
        return "unknown"
    return "wear" if wear.cycles_p05 <= fatigue.remaining_cycles else "fatigue"
