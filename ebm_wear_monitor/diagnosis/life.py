"""Life-level gap: observed clearance growth over many duty cycles against the wear model's prediction.

The same question as the actuator-level diagnosis, one level up.  Input: for
each duty-cycle summary c (cycle count n_c), the observed axial clearance
growth x_c [m] (e.g. the monitor's clearance estimate minus its initial value)
and the wear model's predicted growth g_c [m] of that cycle (000 eq. 20-23 and
the clearance of :func:`ebm_wear_monitor.physics.clearance_growth`, with the
cycle's force and speed), optionally its mean clamp force F_c [N] and screw
speed w_c [rad/s].  The model's cumulative growth is X_c = sum_{k <= c} g_k.

Wear-level effects (few parameters, each with a physical meaning):

=====================  ======================================================  ============
name                   observed growth per cycle                              parameters
=====================  ======================================================  ============
wear_coefficient       (1 + s) g  (k of 000 eq. 20 off by the factor 1 + s)    s [-]
running_in             g + (A / n_0) exp(-n / n_0): an extra, decaying          A [m], n_0
                       running-in wear of total A                              [cycles]
load_dependent_wear    g (1 + b (F / F_mean - 1)): Archard's k growing with     b [-]
                       load
speed_dependent_wear   g (1 + b (w / w_mean - 1))                              b [-]
ball_share             g (1 - 1/3) / (1 - beta): the ball's share of the wear   beta [-]
                       beta instead of 000's 1/3 (raceways fixed by Archard)
=====================  ======================================================  ============

``ball_share`` and ``wear_coefficient`` scale the growth alike and cannot be
told apart from clearance alone: they are always reported as a near-tie, to be
separated by measuring the balls at teardown.  Held-out points (every second
summary), noise from the second differences of x (:func:`.noise.signal_noise`),
an offset (the noisy first clearance reading) fitted with every model,
score and test as in :mod:`.ranking` (:func:`.heldout.improvement_p`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import optimize

from ebm_wear_monitor.diagnosis.heldout import improvement_p
from ebm_wear_monitor.diagnosis.noise import signal_noise
from ebm_wear_monitor.diagnosis.ranking import ALPHA, TIE_ALPHA
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.schema.diagnose import LifeDiagnosis, LifeFit

BALL_SHARE_000 = 1.0 / 3.0  # 000 Sec. 4.1: raceway / ball wear split 2/3 : 1/3


@dataclass(frozen=True)
class LifeData:
    """Duty-cycle summaries of one unit."""

    n: np.ndarray  # cycle count of each summary [-]
    observed: np.ndarray  # observed clearance growth since the first summary [m]
    predicted: np.ndarray  # model growth of each cycle [m]
    force: np.ndarray | None = None  # mean clamp force per cycle [N]
    speed: np.ndarray | None = None  # mean screw speed per cycle [rad/s]


def _growth(d: LifeData, name: str, p: np.ndarray) -> np.ndarray:
    """Per-cycle growth [m] under effect ``name`` with parameters ``p``."""
    g = d.predicted
    if name == "wear_coefficient":
        return (1.0 + p[0]) * g
    if name == "running_in":
        n0 = max(p[1], 1e-9)
        return g + p[0] / n0 * np.exp(-d.n / n0)
    if name == "load_dependent_wear":
        assert d.force is not None  # in the catalog only with forces (:func:`_effects`)
        return g * (1.0 + p[0] * (d.force / d.force.mean() - 1.0))
    if name == "speed_dependent_wear":
        assert d.speed is not None  # in the catalog only with speeds
        return g * (1.0 + p[0] * (d.speed / d.speed.mean() - 1.0))
    if name == "ball_share":
        return g * (1.0 - BALL_SHARE_000) / (1.0 - p[0])
    return g


def _cumulative(d: LifeData, g: np.ndarray) -> np.ndarray:
    """Model clearance growth at each summary: trapezoid sum of per-cycle growth over cycle counts."""
    steps = np.diff(d.n) * 0.5 * (g[1:] + g[:-1])
    return np.concatenate(([0.0], np.cumsum(steps)))


def _effects(d: LifeData) -> dict[str, tuple[np.ndarray, tuple]]:
    """Effects applicable to ``d``: name -> (start, (lower, upper) bounds)."""
    span = float(d.n[-1] - d.n[0])
    out = {"wear_coefficient": (np.array([0.0]), ([-0.99], [np.inf])),
           "running_in": (np.array([0.0, max(0.1 * span, 1.0)]),
                          ([-np.inf, 0.5], [np.inf, max(10.0 * span, 10.0)])),
           "ball_share": (np.array([BALL_SHARE_000]), ([-0.99], [0.99]))}
    if d.force is not None:
        out["load_dependent_wear"] = (np.array([0.0]), ([-10.0], [10.0]))
    if d.speed is not None:
        out["speed_dependent_wear"] = (np.array([0.0]), ([-10.0], [10.0]))
    return out


def life_data_from_applications(apps) -> LifeData:
    """The monitor core's duty-cycle summaries (the replay's per-application table) as :class:`LifeData`.

    ``apps`` has the columns of :data:`ebm_wear_monitor.replay.result.APPLICATION_COLUMNS`
    (a pandas DataFrame or a mapping of arrays).  Applications whose clearance was
    observable (``clearance_observed_m`` finite: the contact point seen in the force-angle
    law) are kept; observed = that clearance [m]; predicted growth per cycle = the slope of
    ``clearance_model_m`` (the wear model, 000 eq. 20-23 through
    :func:`ebm_wear_monitor.physics.clearance_growth`) over the application count at each kept
    application (``numpy.gradient``: second order inside, so the trapezoid sum of
    :func:`diagnose_life` gives back the model's own growth) [m/cycle]; force =
    ``peak_force_n`` [N].
    """
    observed = np.asarray(apps["clearance_observed_m"], dtype=float)
    keep = np.isfinite(observed)
    if keep.sum() < 2:
        raise InputError(f"life diagnosis: only {int(keep.sum())} application(s) with an observed clearance")
    n = np.asarray(apps["index"], dtype=float)[keep]
    model = np.asarray(apps["clearance_model_m"], dtype=float)[keep]
    return LifeData(n, observed[keep], np.gradient(model, n),
                    force=np.asarray(apps["peak_force_n"], dtype=float)[keep])


#: where :func:`diagnose_life`'s summaries come from unless the caller says otherwise
MONITOR_SUMMARIES = ("monitor core duty-cycle summaries (clearance observed per application vs the wear "
                     "model's growth)")


def diagnose_life(d: LifeData, source: str = MONITOR_SUMMARIES) -> LifeDiagnosis:
    """Rank the wear-level effects on held-out summaries (module docstring)."""
    if d.n.size < 8:
        raise InputError(f"life diagnosis needs at least 8 duty-cycle summaries, got {d.n.size}")
    x = d.observed - d.observed[0]
    sigma = max(signal_noise(x), 1e-15)
    held = np.arange(x.size) % 2 == 1
    # the clearance at the first summary is itself measured with noise: every model, the nominal
    # one included, carries a fitted offset c (a nuisance parameter, not counted in the penalty)
    r0 = x - _cumulative(d, d.predicted)
    z0 = (r0 - r0[~held].mean()) / sigma
    scale = max(float(np.abs(x).max()), 1e-12)
    fits = []
    for name, (start, bounds) in _effects(d).items():
        # solve in scaled units u = p / unit so that every parameter is of order one
        unit = np.where(np.abs(start) > 0, np.abs(start), 1.0)
        if name == "running_in":
            unit = np.array([scale, start[1]])

        def resid(p: np.ndarray, name: str = name) -> np.ndarray:
            r = x - _cumulative(d, _growth(d, name, p))
            return (r - r[~held].mean()) / sigma

        def res(u: np.ndarray, unit: np.ndarray = unit, resid=resid) -> np.ndarray:
            return resid(u * unit)[~held]

        r = optimize.least_squares(res, start / unit, bounds=(np.array(bounds[0]) / unit,
                                                              np.array(bounds[1]) / unit),
                                   xtol=1e-14, ftol=1e-14, gtol=1e-14)
        r.x = r.x * unit
        z1 = resid(r.x)
        s_b, s_a = float(np.sum(z0[held] ** 2)), float(np.sum(z1[held] ** 2))
        fits.append((LifeFit(effect=name, parameters=[float(v) for v in r.x],
                             score=(s_b - s_a - 2.0 * r.x.size) / s_b if s_b > 0 else 0.0,
                             p_value=improvement_p(z0[held], z1[held])), z1[held]))
    fits.sort(key=lambda fz: -fz[0].score)
    top, z_top = fits[0]
    verdict = "effect" if top.p_value < ALPHA / len(fits) and top.score > 0 else "none"

    def tied(z: np.ndarray) -> bool:
        # numerically the same curve (within 1e-3 noise), or neither significantly better
        return bool(np.max(np.abs(z - z_top)) < 1e-3) or (
            improvement_p(z, z_top) >= TIE_ALPHA and improvement_p(z_top, z) >= TIE_ALPHA)

    return LifeDiagnosis(
        verdict=verdict, effect=top.effect if verdict == "effect" else None, ranking=[f for f, _ in fits],
        near_ties=[f.effect for f, z in fits[1:] if f.score > 0 and tied(z)], noise_m=sigma,
        gap_before_m=float(np.sqrt(np.mean((z0[held] * sigma) ** 2))), summaries=int(d.n.size), source=source)
