"""The held-out tests every diagnosis decision uses: does a correction fitted on calibration cycles lower
the residual of the held-out ones more than noise would (:func:`improvement_p`: :mod:`.ranking` for an
effect's addition and a size the sampling could have made, :mod:`.life` for the wear-level effects,
:mod:`.openset` for a torque depending on the screw position, :mod:`.scale` for the motor torque's scale),
or do the held-out residuals lie along it (:func:`direction_p`: :mod:`.ranking` for an effect against the
twin within its tolerance)?  Both take independent held-out rows of unit variance, or, given the held-out
cycle of each row, a cluster-robust scale (:func:`_correction`; :mod:`.ranking` reports its test of an
effect against the twin within its tolerance so scaled too).  And the calibration fits' cluster-robust
covariance.
"""

from __future__ import annotations

import numpy as np
from scipy import stats

#: one-sided 95 % normal quantile: a size exceeds its detectability floor with 95 % confidence when
#: size - MATERIAL_Z std > floor (practical significance, :mod:`.tolerance`)
MATERIAL_Z = 1.6448536269514722


def exceeds(size: float, std: float, floor: float, dof: int | None = None) -> bool:
    """``size`` exceeds ``floor`` with 95 % confidence: size - q std > floor, q the one-sided 95 % quantile
    of the normal distribution (``MATERIAL_Z``) or, for a standard error from ``dof`` degrees of freedom,
    of Student's t."""
    q = MATERIAL_Z if dof is None else float(stats.t.ppf(0.95, dof))
    return size - q * std > floor


def mean_above_zero(d: np.ndarray) -> tuple[float, float, float]:
    """(mean, standard error, p) of per-unit contrasts ``d`` (held-out applications or crossings): the
    one-sided Student t test of mean > 0 with n - 1 degrees of freedom (p 0 or 1 by the sign when every
    contrast is equal).  :mod:`.play` and :mod:`.hysteresis` judge their held-out contrasts by it, with
    :func:`exceeds` at ``dof = n - 1`` for the size."""
    n = d.size
    mean, se = float(d.mean()), float(d.std(ddof=1) / np.sqrt(n))
    p_value = float(stats.t.sf(mean / se, n - 1)) if se > 0.0 else float(mean <= 0.0)
    return mean, se, p_value


def _correction(z_before: np.ndarray, z_after: np.ndarray,
                clusters: np.ndarray | None = None) -> tuple[np.ndarray, float]:
    """The held-out correction delta = z_before - z_after and the scale of its tests' statistics: |delta|,
    the standard deviation of sum(z delta) for independent held-out rows of unit variance, or with
    ``clusters`` (the held-out cycle of each row) the larger of |delta| and the cluster-robust

        sqrt(sum_c (sum_{i in c} z_after,i delta_i)^2),

    rows of one cycle sharing model error.  z_after is the residual under "the correction is present":
    there the estimate is unbiased, and under "absent" (z_after = noise - delta) conservative on average.
    The floor keeps the estimate's own scatter over few cycles from making the test more liberal than
    with independent rows (as Knapp and Hartung's max(1, q)).  Compared with N(0, 1) over 10 held-out
    cycles the test stays liberal where the cycles share error along delta (about 3 times the
    nominal 0.05 / 8 at a shared error of 0.6 noise per cycle, against about 30 times with |delta|;
    ``test_diagnosis_ranking.py``); Student's t with one degree less than the cycles would hold the
    level and lose a sixth of the power at |delta| = 4 with independent rows (README, "The cycles'
    scale of the held-out test")."""
    delta = z_before - z_after
    norm = float(np.sqrt(np.sum(delta * delta)))
    if clusters is not None and len(clusters) != len(delta):
        raise ValueError(f"{len(clusters)} cycle labels for {len(delta)} held-out rows")
    if clusters is None or norm == 0.0:
        return delta, norm
    per_cycle = _cluster_sums(z_after * delta, clusters)
    return delta, max(norm, float(np.sqrt(np.sum(per_cycle * per_cycle))))


def improvement_u(z_before: np.ndarray, z_after: np.ndarray,
                  clusters: np.ndarray | None = None) -> float | None:
    """The statistic U of the held-out comparison of two fitted corrections (None when they agree).

    With delta = z_before - z_after fixed by the calibration fits and held-out noise z ~ N(0, 1),
    S_before - S_after = 2 sum(z delta) - sum(delta^2) ~ N(-sum(delta^2), 4 sum(delta^2)) when
    the correction is absent; U = (S_before - S_after) / (2 sqrt(sum(delta^2))) is compared with N(0, 1).
    With ``clusters`` the denominator is :func:`_correction`'s cluster-robust scale.
    """
    _, scale = _correction(z_before, z_after, clusters)
    if scale == 0.0:
        return None
    return float(np.sum(z_before**2 - z_after**2)) / (2.0 * scale)


def improvement_p(z_before: np.ndarray, z_after: np.ndarray, clusters: np.ndarray | None = None) -> float:
    """One-sided p-value of "the correction lowers the held-out residual" (:func:`improvement_u`)."""
    u = improvement_u(z_before, z_after, clusters)
    return 1.0 if u is None else float(stats.norm.sf(u))


def direction_p(z_before: np.ndarray, z_after: np.ndarray, clusters: np.ndarray | None = None) -> float:
    """One-sided p-value of "the held-out residual has a component along the correction".

    With delta = z_before - z_after fixed by the calibration fits and held-out noise z_before ~ N(0, 1)
    independent of it, V = sum(z_before delta) / |delta| ~ N(0, 1) exactly when the correction is absent,
    and ~ N(|delta|, 1) when it is present and right.  V = U + |delta|^2 / (2 scale), scale the common
    denominator (|delta| without ``clusters``: V = U + |delta| / 2; :func:`improvement_u`): U also
    asks that the correction, at its calibrated size, lowers the held-out sum of squares, which puts its
    mean at -|delta| / 2 under "absent" and only |delta| / 2 under "present", half V's separation; the
    p-value of U against N(0, 1) is valid but its level falls far below the nominal one as |delta| grows
    (|delta| = 3.8, nominal 0.05 / 8: 5e-6).  With ``clusters`` the denominator is :func:`_correction`'s
    cluster-robust scale: rows of one cycle share model error, and independent rows would overstate V.
    1 when the correction changes nothing."""
    delta, scale = _correction(z_before, z_after, clusters)
    if scale == 0.0:
        return 1.0
    return float(stats.norm.sf(float(np.sum(z_before * delta)) / scale))


def improvement_p_floored(z_before: np.ndarray, z_after: np.ndarray) -> float:
    """:func:`improvement_p` with both residuals divided by the held-out RMS after the correction when it
    exceeds 1: the test assumes unit variance, and a model error the correction leaves inflates it (never
    scaled below 1)."""
    norm = max(1.0, float(np.sqrt(np.mean(z_after * z_after))))
    return improvement_p(z_before / norm, z_after / norm)


def cluster_covariance(J: np.ndarray, z: np.ndarray, clusters: np.ndarray) -> np.ndarray:
    """Cluster-robust (sandwich) covariance of the least-squares coefficients of ``z`` on the columns of
    ``J`` with residual ``z`` at the fit: (J'J)^-1 (sum_c J_c' z_c z_c' J_c) (J'J)^-1, ``clusters`` the
    cluster label of each row (the brake cycle: neighbouring blocks of one application share model error)."""
    bread = np.linalg.pinv(J.T @ J)
    scores = _cluster_sums(J * z[:, None], clusters)  # per-cluster score vectors J_c' z_c
    cov: np.ndarray = bread @ (scores.T @ scores) @ bread
    return cov


def _cluster_sums(x: np.ndarray, clusters: np.ndarray) -> np.ndarray:
    """The rows of ``x`` summed per cluster label (one row per distinct label, in sorted label order)."""
    _, c = np.unique(clusters, return_inverse=True)
    sums = np.zeros((int(c.max()) + 1, *x.shape[1:]))
    np.add.at(sums, c, x)
    return sums


def tie_p(z_a: np.ndarray, z_b: np.ndarray) -> float:
    """Two-sided p-value of "two fitted corrections explain the held-out data equally well"."""
    u = improvement_u(z_b, z_a)
    return 1.0 if u is None else float(2.0 * stats.norm.sf(abs(u)))
