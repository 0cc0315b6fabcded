"""Kalman filter of the axial clearance with a learned wear-rate correction factor (filterpy).

State (per brake application k)::

    x = [x_ag, f]      x_ag: axial clearance [m];  f: wear-rate correction factor [-]

Process: the wear model (000 eq. 20-23, through the physics core's
``clearance_growth``) predicts the clearance growth g_k of application k; the
truth is assumed to be f times that, with f constant up to a slow random walk::

    x_ag,k = x_ag,k-1 + f_k-1 g_k + w_x      w_x ~ N(0, (s_g g_k)^2)
    f_k    = f_k-1 + w_f                     w_f ~ N(0, d_f^2)

i.e. the transition matrix F_k = [[1, g_k], [0, 1]] varies with the model's
growth (linear in the state, so the plain Kalman filter is exact). s_g
(``growth_scatter``) is the cycle-to-cycle scatter of wear around its mean;
d_f (``factor_drift_per_cycle``) lets the factor wander by ~1 over 1e6
applications. Q_k = diag((s_g g_k)^2, d_f^2).

Measurement: the clearance observed in the application (observation.py),
z_k = x_ag,k + v, v ~ N(0, R_k), H = [1, 0], R_k from the sensor error budget.
An observation whose innovation y = z - x_ag exceeds ``innovation_gate_sigma``
times sqrt(S), S = P_xx + R, is rejected (outlier); several rejections in a row
mean the clearance itself jumped (adjustment, maintenance) and the clearance
state restarts at the observation while the learned factor is kept (core.py).

The factor is observable only through accumulated growth: after N applications
of growth g and noise sigma, var(f) ~ 12 sigma^2 / (g^2 N^3) (least squares on a
line), so with g = 5e-10 m and sigma = 1 um the factor is known to +-50 % after
~600 applications. When the physics under- or over-predicts, f moves away from
1 and says so (``wear_rate_factor`` in the ``wear`` topic).
"""

from __future__ import annotations

import numpy as np
from filterpy.kalman import KalmanFilter

_H = np.array([[1.0, 0.0]])


class ClearanceFilter:
    """Two-state Kalman filter [x_ag, f]; ``x``/``P`` round-trip through lists for persistence."""

    def __init__(self, x: list[float] | np.ndarray, P: list[list[float]] | np.ndarray):
        self._kf = KalmanFilter(dim_x=2, dim_z=1)
        self._kf.x = np.asarray(x, dtype=float).reshape(2, 1).copy()
        self._kf.P = np.asarray(P, dtype=float).reshape(2, 2).copy()
        self._kf.H = _H.copy()

    @classmethod
    def prior(cls, clearance_m: float, clearance_std_m: float, factor_std: float) -> ClearanceFilter:
        """Start at the nominal clearance with factor 1 (model right), independent Gaussian priors."""
        return cls([clearance_m, 1.0], np.diag([clearance_std_m ** 2, factor_std ** 2]))

    def predict(self, growth_m: float, growth_scatter: float, factor_drift: float) -> None:
        """Propagate one application whose model-predicted clearance growth is ``growth_m`` [m]."""
        F = np.array([[1.0, growth_m], [0.0, 1.0]])
        Q = np.diag([(growth_scatter * growth_m) ** 2, factor_drift ** 2])
        self._kf.predict(F=F, Q=Q)

    def update(self, observed_m: float, variance_m2: float) -> None:
        """Fuse one clearance observation [m] with noise variance R [m^2]."""
        self._kf.update(np.array([[observed_m]]), R=np.array([[variance_m2]]))

    def innovation(self, observed_m: float, variance_m2: float) -> tuple[float, float]:
        """(y, S): residual z - H x [m] and its variance H P H' + R [m^2] before an update."""
        return observed_m - float(self._kf.x[0, 0]), float(self._kf.P[0, 0]) + variance_m2

    def restart_clearance(self, observed_m: float, variance_m2: float) -> None:
        """The clearance changed by itself (adjustment): restart it at the observation, keep the factor."""
        self._kf.x[0, 0] = observed_m
        self._kf.P[0, 0] = variance_m2
        self._kf.P[0, 1] = self._kf.P[1, 0] = 0.0

    @property
    def x(self) -> np.ndarray:
        """State mean [x_ag [m], f [-]]."""
        return self._kf.x[:, 0].copy()

    @property
    def P(self) -> np.ndarray:
        """State covariance (2x2) [m^2, m; m, 1]."""
        return self._kf.P.copy()

    @property
    def clearance(self) -> float:
        return float(self._kf.x[0, 0])

    @property
    def clearance_std(self) -> float:
        return float(np.sqrt(max(self._kf.P[0, 0], 0.0)))

    @property
    def factor(self) -> float:
        return float(self._kf.x[1, 0])

    @property
    def factor_std(self) -> float:
        return float(np.sqrt(max(self._kf.P[1, 1], 0.0)))
