"""The effect catalog (interface.md section 4): physical effects the nominal twin of 004 leaves out.

Each effect is switched on with one number, its *magnitude* (0 = absent), and
acts either on the actuator model (the plant) or on the force measurement.
The forms are physically sensible choices of this simulator, documented here;
the sim-to-real diagnosis fits its own parametric forms and must not rely on
these being the truth.

=========================  ==========================================================  ============
name                       form (nominal values from the unit file)                    magnitude m
=========================  ==========================================================  ============
viscous_friction           B' = B (1 + m)  (004 reason 1: lubricant drag left out)     relative [-]
load_friction              G' = G (1 + m)  (004 reasons 2, 5: roughness, coaxiality)   relative [-]
efficiency_variation       screw efficiency η(ω) = η_0 (1 - m e^{-|ω|/ω_η}), adds      drop at
                           T_L (1/η(ω) - 1/η_0) of friction (004 reason 3);            standstill
                           η_0 = 0.9, ω_η = 10 rad/s at the motor (:mod:`.friction`)   [-]
preload_change             T_fs' = T_fs + m T_pre, T_fc' = T_fc + m T_pre with the     relative
                           preload share T_pre = 0.5 T_fc (004 Sec. 3.6: the preloaded preload
                           screw carries about half the no-load Coulomb torque)        change [-]
stribeck                   sliding level T_fc + (T_fs - T_fc) e^{-(ω/m)^2} instead     Stribeck
                           of the step of eq. 9                                        speed [rad/s]
stiffness_nonlinearity     tangent stiffness K_b (1 + m δ/δ_ref), δ_ref = 20 kN / K_b  relative at
                           (:mod:`.clamp`)                                             20 kN [-]
clearance_growth           x_ag' = x_ag + m (extra axial clearance from wear)          [m]
force_sensor_bias          F_meas = F + m (the controller closes its loop on it too)   offset [N]
force_sensor_gain          F_meas = (1 + m) F                                          relative [-]
=========================  ==========================================================  ============
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.twin.dynamics import ActuatorModel

#: share of the load-independent Coulomb torque due to the screw preload (004 Sec. 3.6, Fig. 6a)
PRELOAD_SHARE = 0.5

#: effect name -> (what it is, what its magnitude means)
CATALOG: dict[str, tuple[str, str]] = {
    "viscous_friction": ("lubricant viscous drag larger than modelled", "relative change of B [-]"),
    "load_friction": ("load-dependent friction larger than modelled", "relative change of G [-]"),
    "efficiency_variation": ("ball-screw efficiency falling at low speed",
                             "fractional efficiency drop at standstill [-]"),
    "preload_change": ("preload different from design: T_fs and T_fc shift",
                       "relative preload change [-]"),
    "stribeck": ("friction falling from static to Coulomb over a speed range", "Stribeck speed [rad/s]"),
    "stiffness_nonlinearity": ("clamp stiffness growing with force",
                               "relative tangent-stiffness increase at 20 kN [-]"),
    "clearance_growth": ("axial clearance larger than nominal", "extra clearance [m]"),
    "force_sensor_bias": ("offset of the axial-force measurement", "offset [N]"),
    "force_sensor_gain": ("gain error of the axial-force measurement", "relative gain error [-]"),
}


@dataclass(frozen=True)
class ForceSensorError:
    """Error of the force measurement: ``F_meas = (1 + gain) F + offset``."""

    offset: float = 0.0  # [N]
    gain: float = 0.0  # [-]


def check_effects(effects: Mapping[str, float] | None) -> dict[str, float]:
    """Validated copy of an effects mapping (name -> magnitude); InputError on unknown names or values."""
    out: dict[str, float] = {}
    for name, value in (effects or {}).items():
        if name not in CATALOG:
            raise InputError(f"unknown effect {name!r}; known: {', '.join(CATALOG)}")
        try:
            magnitude = float(value)
        except (TypeError, ValueError):
            raise InputError(f"effect {name}: magnitude must be a number, got {value!r}") from None
        if not math.isfinite(magnitude):
            raise InputError(f"effect {name}: magnitude must be finite")
        if name in ("stribeck", "efficiency_variation", "stiffness_nonlinearity") and magnitude < 0.0:
            raise InputError(f"effect {name}: magnitude must be >= 0, got {magnitude:g}")
        if name == "efficiency_variation" and magnitude >= 1.0:
            raise InputError(f"effect {name}: efficiency drop must be < 1, got {magnitude:g}")
        if name in ("viscous_friction", "load_friction", "preload_change", "force_sensor_gain") \
                and magnitude <= -1.0:
            raise InputError(f"effect {name}: relative change must be > -1, got {magnitude:g}")
        out[name] = magnitude
    return out


def apply_effects(model: ActuatorModel, effects: Mapping[str, float] | None) -> ActuatorModel:
    """The plant with every model-side effect of ``effects`` applied (sensor effects are ignored here)."""
    e = check_effects(effects)
    law, clamp = model.friction, model.clamp
    preload_shift = e.get("preload_change", 0.0) * PRELOAD_SHARE * law.coulomb
    law = dataclasses.replace(
        law,
        viscous=law.viscous * (1.0 + e.get("viscous_friction", 0.0)),
        load_coefficient=law.load_coefficient * (1.0 + e.get("load_friction", 0.0)),
        static=law.static + preload_shift,
        coulomb=law.coulomb + preload_shift,
        stribeck_speed=e.get("stribeck", law.stribeck_speed),
        efficiency_drop=e.get("efficiency_variation", law.efficiency_drop),
    )
    clamp = dataclasses.replace(
        clamp,
        clearance=clamp.clearance + e.get("clearance_growth", 0.0),
        stiffening=e.get("stiffness_nonlinearity", clamp.stiffening),
    )
    if np.any(np.asarray(clamp.clearance) <= 0.0):
        raise InputError("effect clearance_growth: the resulting clearance must stay > 0")
    return dataclasses.replace(model, friction=law, clamp=clamp)


def force_sensor_error(effects: Mapping[str, float] | None) -> ForceSensorError:
    """The force-measurement error of ``effects``."""
    e = check_effects(effects)
    return ForceSensorError(offset=e.get("force_sensor_bias", 0.0), gain=e.get("force_sensor_gain", 0.0))
