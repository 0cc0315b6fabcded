"""The verdict's levels and two of the tests an effect must pass to count (the package docstring's (a)-(e)):
materiality per channel, the consistency test (e) and the stationarity test (d) of a friction effect;
(a) and (b) are properties of a fitted effect (:class:`.effect_fit.EffectFit`), (c) is asked in
:func:`.verdict.rank`.
"""

from __future__ import annotations

import numpy as np
from scipy import stats

from ebm_wear_monitor.diagnosis import tolerance
from ebm_wear_monitor.diagnosis.ranking.effect_fit import EffectFit, delta_method_std, size_gradient
from ebm_wear_monitor.diagnosis.ranking.scorer import Scorer, fit
from ebm_wear_monitor.diagnosis.residuals import CHANNELS
from ebm_wear_monitor.schema.diagnose import Drift

ALPHA = 0.05  # family-wise error rate of the verdict
TIE_ALPHA = 0.05  # level of the paired test that separates the top effect from the next
SHRINK_NEEDED = 0.5  # share of the held-out gap an effect (or pair) must close (issue 10 item 4)


def material_channels(share: dict[str, float]) -> list[str]:
    """The channels whose unexplained share (:meth:`Scorer.unexplained_share`) exceeds its materiality
    bound (:data:`..tolerance.MATERIAL_SHARE`)."""
    return [ch for ch in CHANNELS if share[ch] > tolerance.MATERIAL_SHARE[ch]]



def is_supported(sc: Scorer, f: EffectFit, level: float, w_share: dict[str, float]) -> bool:
    """Tests (a), (b), (d) and (e) of the package docstring (``w_share``: the model error of the twin
    within its tolerance, :meth:`Scorer.unexplained_share`)."""
    if not (f.nameable and f.significant(level)) or worsens(w_share, f.share):
        return False
    f.drift = drift_test(sc, f)
    return not f.drifting


def worsens(before: dict[str, float], after: dict[str, float]) -> bool:
    """Test (e): the model error a change adds in some channel is material.  The shares are RMS errors
    beyond the noise over the same held-out rows (:meth:`Scorer.unexplained_share`), so the error added
    is their difference in quadrature, sqrt(after^2 - before^2), compared with the channel's
    materiality share (:data:`..tolerance.MATERIAL_SHARE`)."""
    return any(after[ch] ** 2 - before[ch] ** 2 > tolerance.MATERIAL_SHARE[ch] ** 2 for ch in CHANNELS)


#: a friction effect drifts only when its size changes with time beyond the operating mix, at this level
#: (two-sided; :func:`_time_trend_p`)
DRIFT_ALPHA = 0.01
#: effects whose size may change within a recording: clearance grows with wear, a sensor drifts with
#: temperature; the friction effects are properties of the unit that must hold over the recording
MAY_DRIFT = frozenset({"clearance_growth", "force_sensor_bias", "stiffness_nonlinearity"})


def drift_test(sc: Scorer, f: EffectFit) -> Drift | None:
    """Does a friction effect hold over the recording?  Refit on the early and the late half (package
    docstring, (d)).

    The brake cycles (calibration and held-out: this tests a property of the unit, not the held-out fit)
    are split at their median time; the effect's parameters alone are refitted on each half (nuisances
    and tolerances as fitted on the calibration cycles).  The effect drifts when its size differs between
    the halves by more than its floor and by more than three standard deviations, and when its size
    trends with time beyond what the operating mix explains (:func:`_time_trend_p`): a real effect's form
    differs from the catalog's, so its fitted size also depends on the demands and speeds a half happens
    to hold, by an amount the data set, not a share assumed in advance.  With fewer than six cycles
    the trend cannot be tested and no effect drifts.
    """
    if f.effect.name in MAY_DRIFT or f.effect.k == 0:
        return None
    cycle = sc.model.blocks.cycle
    cycles = np.unique(cycle)  # every cycle: calibration and held out
    if cycles.size < 4:
        return None
    early = cycles <= np.median(cycles)
    sizes, errs = [], []
    for half in (cycles[early], cycles[~early]):
        g = fit(sc, f.effect, f.model, mask=np.isin(cycle, half), only_effect=True)
        sizes.append(float(f.effect.size(g.theta)))
        errs.append(delta_method_std(f.effect, g.theta, g.stderr))
    diff, sd = sizes[1] - sizes[0], float(np.hypot(errs[0], errs[1]))
    p = _time_trend_p(sc, f, cycles)
    drifting = abs(diff) > max(f.floor, 3.0 * sd) and p < DRIFT_ALPHA
    return Drift(sizes[0], sizes[1], sd, p, bool(drifting))


def _time_trend_p(sc: Scorer, f: EffectFit, cycles: np.ndarray) -> float:
    """p-value (two-sided) of a trend with time in the effect's size per cycle, the operating mix held.

    The effect's parameters are refitted on all ``cycles`` (nuisances and tolerances kept) and linearised
    there: with J = dz/dtheta (the fit's Jacobian) and z the normalised residual, per cycle
    A_c = J_c' J_c and b_c = J_c' z_c; the fit on cycle c alone is one Gauss-Newton step,
    theta_c = theta - A_c^+ b_c (exact for an effect linear in its parameters), and its size, to first
    order, s_c = size(theta) - g' A_c^+ b_c with variance v_c = g' A_c^+ g in noise units (g: the
    gradient of the size; the constant size(theta) is left to the regression's intercept).  The sizes
    are regressed, weights 1 / v_c, on a constant, the cycle's time, its peak clamp force and its peak
    speed; the time coefficient is tested with a standard error robust to the scatter the weights do not
    describe (:func:`trend_p`).  Where the demands themselves change with time, time and mix are
    collinear and the test loses its power instead of charging the mix to time; a size depending on the
    demand other than linearly is only partly held (the early/late gates of :func:`drift_test` then
    guard).  1 with fewer than six cycles.
    """
    e, channels = f.effect, f.effect.channels
    if cycles.size < 6:
        return 1.0
    blocks = sc.model.blocks
    mask = np.ones(blocks.size, bool)
    g = fit(sc, e, f.model, mask=mask, only_effect=True)
    J, z0 = g.jac, g.z
    grad = size_gradient(e, g.theta)
    pos = np.searchsorted(cycles, sc.row_cycles(mask, channels))
    A = np.zeros((cycles.size, e.k, e.k))
    b = np.zeros((cycles.size, e.k))
    np.add.at(A, pos, J[:, :, None] * J[:, None, :])
    np.add.at(b, pos, J * z0[:, None])
    Ainv = np.linalg.pinv(A)
    start = -blocks.cycle_max(-sc.model.rec.t[blocks.start])[cycles]  # each cycle's first block [s]
    mix = np.column_stack([blocks.cycle_max(blocks.force)[cycles], blocks.cycle_max(blocks.speed)[cycles]])
    return trend_p(-np.einsum("k,ckl,cl->c", grad, Ainv, b), np.einsum("k,ckl,l->c", grad, Ainv, grad),
                   start, mix)


def trend_p(s: np.ndarray, v: np.ndarray, time: np.ndarray, mix: np.ndarray) -> float:
    """Two-sided p-value of the time coefficient in the regression of ``s`` on a constant, ``time`` and the
    columns of ``mix``, weighted by the stated variances ``v``; 1 when no scatter is left to test against.

    The scatter of a catalog form fitted to another form is not proportional to ``v`` (it comes from the
    mismatch, not from the noise), so the standard error is heteroscedasticity-robust (HC3: each
    squared residual divided by (1 - h_i)^2, h_i its leverage; MacKinnon and White 1985), the statistic
    Student t with n - 2 - (mix columns) degrees of freedom.
    """
    ok = v > 0.0
    X = np.column_stack([np.ones(time.size), *((x - x.mean()) / (x.std() or 1.0)
                                              for x in (time, *np.asarray(mix, dtype=float).T))])[ok]
    n, q = X.shape
    if n - q < 2:
        return 1.0
    w = 1.0 / np.sqrt(v[ok])
    Xw = X * w[:, None]
    bread = np.linalg.pinv(Xw.T @ Xw)
    beta = bread @ Xw.T @ (s[ok] * w)
    resid = s[ok] * w - Xw @ beta
    leverage = np.clip(np.einsum("ij,jk,ik->i", Xw, bread, Xw), 0.0, 1.0 - 1e-9)
    meat = (Xw * (resid / (1.0 - leverage))[:, None] ** 2).T @ Xw
    se = float(np.sqrt(max((bread @ meat @ bread)[1, 1], 0.0)))
    return float(2.0 * stats.t.sf(abs(beta[1]) / se, n - q)) if se > 0.0 else 1.0
