"""Structure the catalog cannot represent: torque as a function of where the screw is (issue 10 item 4).

Every catalog effect (:mod:`.catalog`) changes the torque channel of the twin of 004 through the motor
speed (eq. 9's viscous and Stribeck terms) and the clamp force (eq. 9's load term, the efficiency),
per direction of motion. A torque that depends on the screw's position itself (ripple from a raceway
defect or a bent screw, cogging referred to the screw, a seal or a ball return that drags over part of
the stroke) is outside the catalog; a catalog effect fitted to it absorbs a part and leaves the rest.
Position and force are not independent, though: the clamp force is a function of the nut travel
(eq. 5) and every application starts from nearly the same rest angle, so a smooth function of the
angle is also, in contact, a function of the force. The test therefore asks what a position term
explains *beyond* terms shaped like the catalog's.

**Shapes and harmonics.**  The shape terms are, per direction of motion (apply, release), a constant,
a term proportional to the clamp force and one proportional to the speed: the Coulomb, load and
viscous terms of eq. 9 with free coefficients. The position term is a harmonic k = 1 .. :data:`HARMONICS`
of the screw angle q, amplitude and phase free (so the encoder's zero, a nuisance, does not matter).
Over a long stroke it is a ripple per screw turn; where every application covers the same window of
angles (the foreign recordings: 0.7-0.9 rad per application, start varying by ~2 mrad) the harmonics
are only four smooth shapes of the position in the stroke, and k is not identifiable. ``HARMONICS =
4`` was chosen knowing that the foreign generator draws its ripple with k in 1-4 (a disclosure: the
validation of this test on that generator's ripple is not blind to its form).

**Test.**  On the moving blocks (but those whose friction eq. 9 leaves undetermined, stick and slip
not told apart: :func:`.ranking.verdict.screw_periodic`) the torque residual r of the explaining model (the
selected effects, or the twin within its tolerance when none is selected) is normalised by its block
noise, z = r / sigma;
regressors are divided by sigma too, so coefficients are in N m. The shape terms alone, then the shape
terms with each harmonic, are fitted to z on the calibration blocks; the harmonic that lowers the
calibration sum of z^2 most is judged on the held-out blocks (shape terms and harmonic as fitted on
calibration) with the test of :func:`.heldout.improvement_p_floored` at level alpha / K (conservative: k is
chosen on calibration data only), both residuals divided by the held-out RMS after the fit when it
exceeds 1 (the test assumes unit variance; a model error inflates it). The harmonic is *material*
when the RMS of its contribution over the moving blocks exceeds, with 95 % confidence
(RMS - 1.645 std > floor; the covariance scaled by the calibration residual variance when above 1),
``MATERIAL_SHARE['torque']`` (2 %, the K_T x current-gain tolerance) of the RMS motor torque over the
moving blocks (:mod:`.tolerance`): an RMS against an RMS.

**Consequence for the verdict** (:func:`.ranking.verdict.open_set_verdict`).  With S the held-out sum of z^2
of the twin within its tolerance (W, all rows), of the explaining model (E), and, on the moving
torque rows, of E's residual after the shape terms before and after the harmonic (EP): when the
significant harmonic removes more than the effects removed from W's error, S_W - S_E, the effects
closed less than half of the error that is explainable and the verdict ``effect`` becomes
``unexplained``; a ``none`` verdict becomes ``unexplained`` only when the harmonic is also material
(the twin within its tolerance then misses a material torque that no catalog effect makes). A
material harmonic left by effects that close at least half of the explainable error was tried as a
third route (a load friction or preload fitted to a foreign ripple of 0.10-0.16 N m closes 60-70 % and
leaves one): it turned a preload relief and a thermally drifting force sensor of the mixed draws into
``unexplained`` (their catalog form leaves a material shape of the position too) and gained 2 of 42
foreign ripples (measured on the six mixed draws and ``outside_e``, probed on ``outside`` and
``outside_b``), so it is not used.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ebm_wear_monitor.diagnosis import tolerance
from ebm_wear_monitor.diagnosis.heldout import exceeds, improvement_p_floored
from ebm_wear_monitor.diagnosis.residuals import block_mean

#: harmonics of the screw angle tried (per screw revolution)
HARMONICS = 4


@dataclass(frozen=True)
class Periodic:
    """The harmonic of the screw angle that best fits the held-out torque residual of a model, beyond
    the catalog's own shapes (module docstring)."""

    harmonic: int  # k: periods per screw turn (over a stroke much shorter than 2 pi / k only a shape)
    amplitude: float  # A = sqrt(a_k^2 + b_k^2) [N m]: the peak of the fitted harmonic
    rms: float  # RMS of its block contribution over the moving blocks [N m]: what materiality judges
    rms_std: float  # standard deviation of that RMS [N m]
    floor: float  # materiality bound of the torque channel [N m]
    #: held-out improvement test beyond the shape terms (:func:`.heldout.improvement_p_floored`)
    p_value: float
    sse_before: float  # held-out sum of z^2 on the moving blocks after the shape terms
    sse_after: float  # the same with the harmonic added
    sin_cos: tuple[float, float] = (0.0, 0.0)  # (a_k, b_k) of a_k sin(k q) + b_k cos(k q) [N m]
    beyond: np.ndarray = field(default_factory=lambda: np.zeros(0))  # residual - shape terms per block [N m]

    def torque(self, angle: np.ndarray) -> np.ndarray:
        """The fitted harmonic at screw angles ``angle`` [rad], in N m at the motor."""
        a, b = self.sin_cos
        return a * np.sin(self.harmonic * angle) + b * np.cos(self.harmonic * angle)

    def counts(self, level: float) -> bool:
        """Significant at ``level`` and material with 95 % confidence (module docstring)."""
        return self.p_value < level and exceeds(self.rms, self.rms_std, self.floor)


def block_basis(angle: np.ndarray, start: np.ndarray, stop: np.ndarray, k: int) -> np.ndarray:
    """Block means of sin(k q) and cos(k q) over samples ``start .. stop`` (inclusive), shape (blocks, 2)."""
    return np.stack([block_mean(f(k * angle), start, stop) for f in (np.sin, np.cos)], axis=1)


def _lstsq(A: np.ndarray, z: np.ndarray) -> np.ndarray:
    coef: np.ndarray = np.linalg.lstsq(A, z, rcond=None)[0]
    return coef


def periodic_structure(angle: np.ndarray, start: np.ndarray, stop: np.ndarray, z: np.ndarray, *,
                       sigma: np.ndarray, shapes: np.ndarray, calibration: np.ndarray,
                       heldout: np.ndarray, drive: np.ndarray) -> Periodic | None:
    """The test of the module docstring on the moving blocks' torque rows.

    ``angle``: screw angle per sample [rad]; ``start``/``stop``: sample range of each block;
    ``z``: normalised torque residual per block; ``sigma``: its block noise [N m]; ``shapes``: the
    catalog-shaped terms per block (columns in N m per unit, e.g. the force and the direction: see
    :func:`.ranking.verdict.screw_periodic`), fitted with every harmonic so that the harmonic counts only
    beyond them; ``calibration``/``heldout``: masks of the moving blocks of each side; ``drive``: block
    mean of the motor torque [N m]. None when a side has too few blocks for the columns.
    """
    ncol = shapes.shape[1] + 2
    if calibration.sum() < 4 * ncol or heldout.sum() < 4 * ncol:
        return None
    moving = calibration | heldout
    floor = tolerance.torque_floor(drive[moving])
    S = shapes / sigma[:, None]
    zc = z[calibration]
    gamma0 = _lstsq(S[calibration], zc)
    rss0 = float(np.sum((zc - S[calibration] @ gamma0) ** 2))
    best: tuple[float, int, np.ndarray, np.ndarray] | None = None
    for k in range(1, HARMONICS + 1):
        A = np.hstack((block_basis(angle, start, stop, k) / sigma[:, None], S))
        coef = _lstsq(A[calibration], zc)
        gain = rss0 - float(np.sum((zc - A[calibration] @ coef) ** 2))
        if best is None or gain > best[0]:
            best = (gain, k, coef, A)
    assert best is not None
    gain, k, coef, A = best
    n_cal = int(calibration.sum())
    rss = rss0 - gain
    # parameter covariance, scaled up by the residual variance when the model error exceeds the noise
    cov = np.linalg.pinv(A[calibration].T @ A[calibration]) * max(1.0, rss / max(n_cal - ncol, 1))
    a, b = float(coef[0]), float(coef[1])
    X = block_basis(angle, start, stop, k)[moving]  # [-] per block
    c = X @ coef[:2]  # the harmonic's block contribution [N m]
    rms = float(np.sqrt(np.mean(c * c)))
    grad = X.T @ c / (c.size * max(rms, 1e-300))  # d rms / d (a, b)
    rms_std = float(np.sqrt(max(float(grad @ cov[:2, :2] @ grad), 0.0)))
    zb = z[heldout] - S[heldout] @ gamma0  # held out, after the shape terms alone
    za = z[heldout] - A[heldout] @ coef  # ... and with the harmonic
    beyond = (z - S @ coef[2:]) * sigma
    return Periodic(k, float(np.hypot(a, b)), rms, rms_std, floor, improvement_p_floored(zb, za),
                    float(np.sum(zb**2)), float(np.sum(za**2)), (a, b), beyond)
