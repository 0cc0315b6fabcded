"""Structure no catalog effect can make: a torque periodic in the screw angle (issue 10 item 4, open set).

Every catalog effect (:mod:`.catalog`) changes the twin of 004 as a function of the motor speed
(eq. 9's viscous and Stribeck terms), the clamp force (eq. 9's load term, the efficiency) or the nut
travel (eq. 5's clearance and stiffness), and every acquisition nuisance as a function of time
(:mod:`.residuals`). None of them depends on *where the screw is within its turn*. A torque that
repeats with the screw angle q (ripple from a raceway defect or a bent screw, cogging referred to
the screw, a ball-return obstruction) is therefore outside the catalog; fitted with a catalog effect
it is absorbed in part (over one application q rises with the force, so a periodic torque looks
like a little load friction) and the rest stays in the residual.

**Test.**  On the moving blocks the held-out torque residual r of the explaining model (the selected
effects, or the twin within its tolerance when none is selected) is normalised by its block noise,
z = r / sigma.  For each harmonic k = 1 .. :data:`HARMONICS` of q the block means of sin(k q) and
cos(k q) (two columns: amplitude and phase free, so the encoder's zero, a nuisance, does not
matter) are fitted to z by least squares on the calibration blocks, the regressors divided by sigma
too, so the coefficients a_k, b_k are in N m.  The harmonic whose fit lowers the calibration sum of
z^2 most is judged on the held-out blocks with the test of :func:`.ranking.improvement_p` at level
alpha / K (Bonferroni over the harmonics).  It *counts* when that test passes and it is
**material**: its amplitude A = sqrt(a_k^2 + b_k^2) exceeds, with 95 % confidence
(A - 1.645 std(A) > floor), the bound that makes any model error of the torque channel material,
``MATERIAL_SHARE['torque']`` (2 %, the K_T x current-gain tolerance) of the RMS motor torque over the
moving blocks (:mod:`.tolerance`).

**Consequence for the verdict** (:func:`.ranking.rank`).  Material periodic structure means the
explaining model leaves a material part of the model error that no catalog effect can represent.
With S the held-out sum of z^2 of the twin within its tolerance (W), of the explaining model (E) and
of E plus the periodic term (EP): when the catalog's part, S_W - S_E, is less than half of what
both remove together, S_W - S_EP, the effects did not close half of the explainable error and the
verdict is ``unexplained``; a ``none`` verdict with material periodic structure becomes
``unexplained`` too (the twin misses a material torque that no catalog effect makes).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ebm_wear_monitor.diagnosis import tolerance

#: harmonics of the screw angle tried (per screw revolution)
HARMONICS = 4
MATERIAL_Z = 1.6448536269514722  # one-sided 95 % normal quantile


@dataclass(frozen=True)
class Periodic:
    """The strongest harmonic of the screw angle in the held-out torque residual of a model."""

    harmonic: int  # k: periods per screw revolution
    amplitude: float  # A [N m]
    amplitude_std: float  # its standard deviation [N m]
    floor: float  # materiality bound of the torque channel [N m]
    p_value: float  # held-out improvement test (:func:`.ranking.improvement_p`)
    sse_before: float  # held-out sum of z^2 of the model on the moving blocks
    sse_after: float  # the same with the harmonic removed

    def counts(self, level: float) -> bool:
        """Significant at ``level`` and material with 95 % confidence (module docstring)."""
        return self.p_value < level and self.amplitude - MATERIAL_Z * self.amplitude_std > self.floor


def block_basis(angle: np.ndarray, start: np.ndarray, stop: np.ndarray, k: int) -> np.ndarray:
    """Block means of sin(k q) and cos(k q) over samples ``start .. stop`` (inclusive), shape (blocks, 2)."""
    cols = []
    for f in (np.sin, np.cos):
        c = np.concatenate(([0.0], np.cumsum(f(k * angle))))
        cols.append((c[stop + 1] - c[start]) / (stop + 1 - start))
    return np.stack(cols, axis=1)


def periodic_structure(angle: np.ndarray, start: np.ndarray, stop: np.ndarray, z: np.ndarray, *,
                       sigma: np.ndarray, calibration: np.ndarray, heldout: np.ndarray,
                       drive: np.ndarray, test: Callable[[np.ndarray, np.ndarray], float]
                       ) -> Periodic | None:
    """The test of the module docstring on the moving blocks' torque rows.

    ``angle``: screw angle per sample [rad]; ``start``/``stop``: sample range of each block;
    ``z``: normalised torque residual per block; ``sigma``: its block noise [N m];
    ``calibration``/``heldout``: masks of the moving blocks of each side; ``drive``: block mean of
    the motor torque [N m]; ``test(z_before, z_after)``: the held-out improvement's p-value
    (:func:`.ranking.improvement_p`). None when a side has too few blocks to fit two columns.
    """
    if calibration.sum() < 8 or heldout.sum() < 8:
        return None
    moving = calibration | heldout
    floor = tolerance.MATERIAL_SHARE["torque"] * float(np.sqrt(np.mean(drive[moving] ** 2)))
    best: tuple[float, int, np.ndarray, np.ndarray, np.ndarray] | None = None
    for k in range(1, HARMONICS + 1):
        X = block_basis(angle, start, stop, k) / sigma[:, None]
        Xc, zc = X[calibration], z[calibration]
        coef, *_ = np.linalg.lstsq(Xc, zc, rcond=None)
        gain = float(np.sum(zc**2) - np.sum((zc - Xc @ coef) ** 2))
        if best is None or gain > best[0]:
            best = (gain, k, coef, X, np.linalg.pinv(Xc.T @ Xc))
    assert best is not None
    _, k, coef, X, cov = best
    a, b = float(coef[0]), float(coef[1])
    amp = float(np.hypot(a, b))
    var = (a * a * cov[0, 0] + b * b * cov[1, 1] + 2 * a * b * cov[0, 1]) / max(amp * amp, 1e-300)
    zb = z[heldout]
    za = zb - X[heldout] @ coef
    return Periodic(k, amp, float(np.sqrt(max(var, 0.0))), floor, test(zb, za),
                    float(np.sum(zb**2)), float(np.sum(za**2)))
