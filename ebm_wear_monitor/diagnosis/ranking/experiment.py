"""The experiment that would separate two near-tied effects (the package docstring's "Near-ties").
"""

from __future__ import annotations

import numpy as np

from ebm_wear_monitor.diagnosis.ranking.effect_fit import EffectFit
from ebm_wear_monitor.diagnosis.residuals import Augment, clamp_spring, kinetic_friction
from ebm_wear_monitor.schema.diagnose import NearTie
from ebm_wear_monitor.twin.dynamics import ActuatorModel


def separating_experiment(nom: ActuatorModel, a: EffectFit, b: EffectFit, *, max_speed: float,
                          max_force: float, sigma_torque: float, sigma_force: float, n: int = 12) -> NearTie:
    """Operating range where two fitted effects disagree most, in noise units.

    The moving-branch friction (004 eq. 9 + each augmentation) is compared on a
    grid of motor speed 0..1.5 ``max_speed`` and force 0..1.5 ``max_force``; the
    force-travel law (004 eq. 5 + each) on force 0..1.5 ``max_force``.  The cell
    with the largest |difference| / sigma names the experiment (screw speed
    reported at the screw, i.e. motor speed / i_g).
    """
    w = np.linspace(0.0, 1.5 * max_speed, n + 1)
    F = np.linspace(0.0, 1.5 * max_force, n + 1)
    wc, Fc = np.meshgrid(0.5 * (w[1:] + w[:-1]), 0.5 * (F[1:] + F[:-1]), indexing="ij")
    dT = np.abs(kinetic_friction(nom, a.augment, wc, Fc) - kinetic_friction(nom, b.augment, wc, Fc))
    dT /= sigma_torque
    x = nom.clamp.clearance + 0.5 * (F[1:] + F[:-1]) / nom.clamp.stiffness

    def reading(aug: Augment) -> np.ndarray:
        return (1.0 + aug.force_gain) * clamp_spring(nom, aug).force(x)

    dF = np.abs(reading(a.augment) - reading(b.augment)) / sigma_force
    i, j = np.unravel_index(int(np.argmax(dT)), dT.shape)
    if dF.max() > dT[i, j]:
        k = int(np.argmax(dF))
        speed, force, sep = None, [float(F[k]), float(F[k + 1])], float(dF[k])
    else:
        speed = [float(w[i] / nom.gear_ratio), float(w[i + 1] / nom.gear_ratio)]
        force, sep = [float(F[j]), float(F[j + 1])], float(dT[i, j])
    inside = (speed is None or speed[0] * nom.gear_ratio <= max_speed) and force[0] <= max_force
    where = (f"screw speed {speed[0]:.3g}-{speed[1]:.3g} rad/s at " if speed else "") + \
        f"clamp force {force[0]:.4g}-{force[1]:.4g} N"
    return NearTie([a.effect.name, b.effect.name], speed, force, sep, bool(inside),
                   f"record at {where}" + ("" if inside else " (beyond the recorded range)"))
