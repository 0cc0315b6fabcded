"""The catalog of unmodelled effects (interface.md section 4), each a small parametric augmentation.

Every effect maps a parameter vector ``theta`` (one or two numbers with a
physical meaning and a unit) onto an :class:`~.residuals.Augment` of the
nominal twin of 004.  Most effects are linear in their parameters, so their fit
is a linear least-squares problem; :mod:`.ranking` solves all of them with the
same bounded Gauss-Newton solver.

==========================  ==============================================================  =============
name                        augmentation (motor shaft, s = sgn(w_m); nut side for forces)   parameters
==========================  ==============================================================  =============
viscous_friction            T_f += dB w_m (004 eq. 9, reason 1: lubricant drag left out)    dB [N m s/rad]
load_friction               G -> G + dG in the moving and stick branches of 004 eq. 9        dG [N m/N]
                            (reasons 2 and 5: roughness, lubrication, coaxiality)
efficiency_variation        T_f += s T_L (a_0 + a_w |w_m|): the loss factor 1/eta - 1 of   a_0 [-],
                            004 eq. 29 varying with speed                                   a_w [s/rad]
                            (reason 3); a_0 alone equals a change of G, so this effect
                            nests load_friction and must earn its extra parameter
preload_change              T_fs += dT, T_fc += dT (004 eq. 28-29, reason 4: the preload    dT [N m]
                            torque shifts both; only T_fc is seen while moving)
stribeck                    T_f += s T_S exp(-(|w_m| / w_S)^2): friction falling from        T_S [N m],
                            static towards Coulomb over a speed range                       w_S [rad/s]
stiffness_nonlinearity      F = K_b d + k_2 d^2, d = x - x_ag (004 eq. 5 made progressive)   k_2 [N/m^2]
clearance_growth            x_ag -> x_ag + dx (004 eq. 5; wear of balls and raceways)         dx [m]
force_sensor_bias           F_meas = (1 + g) F + b                                           b [N], g [-]
==========================  ==============================================================  =============

``scale`` gives a typical magnitude per parameter (for the solver's scaling and
for the self-test's sense of "10 % of the affected quantity"); ``start`` lists
starting points for the one non-linear parameter (the Stribeck speed).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ebm_wear_monitor.diagnosis.residuals import Augment, Nominal


@dataclass(frozen=True)
class Effect:
    """One catalog entry: parameters with units and their map onto an :class:`Augment`."""

    name: str
    meaning: str
    params: tuple[str, ...]
    units: tuple[str, ...]
    to_augment: Callable[[np.ndarray], Augment]
    scale: tuple[float, ...]
    starts: tuple[tuple[float, ...], ...]  # starting points of the fit
    lower: tuple[float, ...] | None = None  # bounds (None: unbounded)
    upper: tuple[float, ...] | None = None

    @property
    def k(self) -> int:
        """Number of fitted parameters."""
        return len(self.params)


def build_catalog(nom: Nominal, max_speed: float = 200.0, max_force: float = 3.0e4) -> dict[str, Effect]:
    """The eight effects of interface.md section 4 for a nominal twin.

    ``max_speed`` (motor, [rad/s]) and ``max_force`` [N] of the recording set the
    parameter scales (a 10 % change of the affected quantity at the recording's range).
    """
    d_max = max_force / nom.K_b  # clamp deflection at the largest force [m]
    s_grid = [max_speed * f for f in (0.02, 0.08, 0.3)]
    effects = [
        Effect("viscous_friction", "lubricant viscous drag larger than modelled (004 reason 1)",
               ("dB",), ("N m s/rad",), lambda p: Augment(dB=p[0]), (0.1 * max(nom.B, 1e-4),), ((0.0,),)),
        Effect("load_friction", "load-dependent friction larger than modelled (004 reasons 2, 5)",
               ("dG",), ("N m/N",), lambda p: Augment(dG=p[0]), (0.1 * max(nom.G, 1e-6),), ((0.0,),)),
        Effect("efficiency_variation", "ball-screw efficiency changing with speed and load (004 reason 3)",
               ("a_0", "a_w"), ("-", "s/rad"), lambda p: Augment(eff_base=p[0], eff_speed=p[1]),
               (0.1, 0.1 / max_speed), ((0.0, 0.0),)),
        Effect("preload_change", "preload different from design: static and Coulomb shift (004 reason 4)",
               ("dT",), ("N m",), lambda p: Augment(dT_fs=p[0], dT_fc=p[0]), (0.1 * nom.T_fc,), ((0.0,),)),
        Effect("stribeck", "friction falling from static to Coulomb over a speed range",
               ("T_S", "w_S"), ("N m", "rad/s"),
               lambda p: Augment(stribeck_torque=p[0], stribeck_speed=p[1]),
               (0.1 * nom.T_fc, 0.1 * max_speed), tuple((0.0, s) for s in s_grid),
               (-np.inf, 0.2), (np.inf, 2.0 * max_speed)),
        Effect("stiffness_nonlinearity", "clamp stiffness growing with force (004 eq. 5 progressive)",
               ("k_2",), ("N/m^2",), lambda p: Augment(stiffness_quad=p[0]), (0.1 * nom.K_b / d_max,),
               ((0.0,),)),
        Effect("clearance_growth", "axial clearance larger than nominal (wear)", ("dx",), ("m",),
               lambda p: Augment(clearance=p[0]), (0.1 * nom.x_ag,), ((0.0,),)),
        Effect("force_sensor_bias", "offset and gain error of the axial-force measurement",
               ("b", "g"), ("N", "-"), lambda p: Augment(force_bias=p[0], force_gain=p[1]),
               (0.01 * max_force, 0.01), ((0.0, 0.0),), (-np.inf, -0.5), (np.inf, 1.0)),
    ]
    return {e.name: e for e in effects}


def friction_refit(nom: Nominal) -> Effect:
    """The moving-branch parameters of 004 eq. 9 (T_fc, B, G) corrected at once, as behind 004 Table 4.

    (T_fs is not identified by the torque balance at rest, see :mod:`.residuals`.)

    Not a catalog entry (it nests viscous_friction, load_friction and preload_change and
    would explain any friction effect at the price of three parameters, plus the two timing
    nuisances); the diagnosis reports it beside the ranking as the unit's refitted friction law.
    """
    return Effect("friction_refit", "T_fc, B and G of 004 eq. 9 refitted together",
                  ("dT_fc", "dB", "dG"), ("N m", "N m s/rad", "N m/N"),
                  lambda p: Augment(dT_fc=p[0], dB=p[1], dG=p[2]),
                  (0.1 * nom.T_fc, 0.1 * max(nom.B, 1e-4), 0.1 * max(nom.G, 1e-6)), ((0.0, 0.0, 0.0),))
