"""Structure the catalog cannot represent: torque as a function of where the screw is (issue 10 item 4).

Every catalog effect (:mod:`.catalog`) changes the twin of 004 as a function of the motor speed
(eq. 9's viscous and Stribeck terms) or the clamp force (eq. 9's load term, the efficiency) in the
torque channel, and of the nut travel only through the force (eq. 5's clearance and stiffness). None
depends on *where the screw is* while the force is zero (clearance elimination) or at a given force
(the same force is reached at other angles on the way back). A torque that does (ripple from a
raceway defect or a bent screw, cogging referred to the screw, a seal or a ball return that drags
over part of the stroke) is outside the catalog; a catalog effect fitted to it absorbs a part and
leaves the rest.

**A generic function of the screw angle.**  The harmonics k = 1 .. :data:`HARMONICS` of the screw
angle q, amplitude and phase free (so the encoder's zero, a nuisance, does not matter), serve as a
smooth generic function of q. Over a long stroke they are a ripple periodic in the screw's turn;
where every application covers the same window of angles (the foreign recordings: about 0.7-0.9 rad
per application with a start that varies by ~2 mrad) they are a smooth function of the position
within the stroke. Either way no combination of catalog effects can produce them at zero force.

**Test.**  On the moving blocks the held-out torque residual r of the explaining model (the selected
effects, or the twin within its tolerance when none is selected) is normalised by its block noise,
z = r / sigma.  For each k the block means of sin(k q) and cos(k q), divided by sigma too (so the
coefficients a_k, b_k are in N m), are fitted to z by least squares on the calibration blocks.  The
harmonic whose fit lowers the calibration sum of z^2 most is judged on the held-out blocks with the
test of :func:`.ranking.improvement_p` at level alpha / K (Bonferroni over the harmonics).  It is
*material* when its amplitude A = sqrt(a_k^2 + b_k^2) exceeds, with 95 % confidence
(A - 1.645 std(A) > floor), the bound that makes any model error of the torque channel material,
``MATERIAL_SHARE['torque']`` (2 %, the K_T x current-gain tolerance) of the RMS motor torque over the
moving blocks (:mod:`.tolerance`).

**Consequence for the verdict** (:func:`.ranking.open_set_verdict`).  With S the held-out sum of z^2
of the twin within its tolerance (W, all rows), of the explaining model (E) and, on the moving
torque rows, of E without the harmonic's prediction (EP): when the significant harmonic removes more
of E's error, S_E - S_EP, than the effects removed from W's, S_W - S_E, the effects closed less than
half of the error that is explainable and the verdict ``effect`` becomes ``unexplained``; a ``none``
verdict becomes ``unexplained`` only when the harmonic is also material (the twin within its
tolerance then misses a material torque that no catalog effect makes).
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
    sin_cos: tuple[float, float] = (0.0, 0.0)  # (a_k, b_k) of a_k sin(k q) + b_k cos(k q) [N m]

    def torque(self, angle: np.ndarray) -> np.ndarray:
        """The fitted harmonic at screw angles ``angle`` [rad], in N m at the motor."""
        a, b = self.sin_cos
        return a * np.sin(self.harmonic * angle) + b * np.cos(self.harmonic * angle)

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
                    float(np.sum(zb**2)), float(np.sum(za**2)), (a, b))
