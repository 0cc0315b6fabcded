"""Effects of the third world: functional forms and magnitude ranges (README, effects table).

Each effect has one relative magnitude ``s``; the form string in truth.json names its equation.
Catalog effects are the ones the diagnosis knows; outside effects are not in its catalog.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .plant import Modifiers, Nominal

CATALOG = (
    "viscous_friction",
    "load_friction",
    "efficiency_variation",
    "preload_change",
    "stribeck",
    "stiffness_nonlinearity",
    "clearance_growth",
    "force_sensor_bias",
)
OUTSIDE = ("torque_constant_loss", "backlash", "torque_ripple", "friction_drift")

# name: (low, high, signed) -- |s| drawn in [low, high]; signed effects take either sign
RANGES: dict[str, tuple[float, float, bool]] = {
    "viscous_friction": (0.5, 1.5, False),
    "load_friction": (0.3, 1.0, False),
    "efficiency_variation": (0.15, 0.4, False),
    "preload_change": (0.15, 0.4, True),
    "stribeck": (0.2, 0.6, False),
    "stiffness_nonlinearity": (0.1, 0.3, False),
    "clearance_growth": (0.1, 0.4, False),
    "force_sensor_bias": (0.1, 0.2, True),
    "torque_constant_loss": (0.1, 0.2, False),
    "backlash": (0.05, 0.12, False),
    "torque_ripple": (0.25, 0.5, False),
    "friction_drift": (0.2, 0.4, True),
}

FORMS = {
    "viscous_friction": "T_f += s*B*w_r*sgn(w)*(|w|/w_r)^0.8, w_r = 20 rad/s (shear-thinning grease drag)",
    "load_friction": "T_f, T_fs += s*G*F_r*(F/F_r)^1.5, F_r = 20 kN (friction rising as a power of load)",
    "efficiency_variation": "screw loss lam = s*(F/30kN)^0.7*exp(-|w|/20 rad/s); T_f += T_L*lam/(1-lam) "
    "driving, T_L*lam back-driven and at rest",
    "preload_change": "T_fs, T_fc += s*T_fc*(1 - 0.5*min(1, F/15kN)) (preload partly relieved by load)",
    "stribeck": "T_f = T_fc+G F + (T_fs-T_fc + s*T_fc)*exp(-(w/4 rad/s)^2); breakaway T_fs + s*T_fc",
    "stiffness_nonlinearity": "F = K_b*d*(1 + s*d/d_r), d = x - x_c, d_r = 20kN/K_b (hardening pads)",
    "clearance_growth": "x_c,k = x_ag*(1 + s*(0.7 + 0.6*k/(N-1))), application k of N (mean excess s*x_ag)",
    "force_sensor_bias": "F_meas = (1 + s)*F (bridge gain error; ECU and log both see it)",
    "torque_constant_loss": "K_T, K_E *= (1 - s) (demagnetisation)",
    "backlash": "dead zone of total width s*x_ag/c_x (motor rad) between gear and screw; encoder on motor",
    "torque_ripple": "T_m += s*T_fc*sin(N*theta_m + phi), N cogging periods per motor turn",
    "friction_drift": "T_fs, T_fc, B, G *= 1 + s*(1-exp(-t/tau))/(1-exp(-T/tau)), tau = 0.4 T",
}


@dataclass
class Realised:
    """An effect turned into plant modifiers, a force-sensor gain and a clearance schedule."""

    mods: Modifiers
    force_gain: float
    clearance: list[float]  # contact position x_c [m] per application
    detail: dict


def draw_magnitude(name: str, rng: np.random.Generator, half: int, sign: int) -> float:
    """Magnitude in the lower (half=0) or upper (half=1) half of the range, with a sign if signed."""
    lo, hi, signed = RANGES[name]
    mid = 0.5 * (lo + hi)
    s = float(rng.uniform(lo, mid) if half == 0 else rng.uniform(mid, hi))
    return round(s * (sign if signed else 1), 4)


#: effects that are one magnitude of the plant's modifiers (:class:`.plant.Modifiers`): effect -> field
_PLANT_SCALE = {"viscous_friction": "visc_s", "load_friction": "load_s", "efficiency_variation": "eff_s",
                "preload_change": "pre_s", "stribeck": "strib_s", "stiffness_nonlinearity": "stiff_s"}


def realise(
    name: str | None, s: float, nom: Nominal, *, n_app: int, T_rec: float, rng: np.random.Generator
) -> Realised:
    """Build the modifiers of effect ``name`` at magnitude ``s`` (None: healthy)."""
    m = Modifiers(drift_T=T_rec)
    gain, x_c, detail = 1.0, [nom.x_ag] * n_app, {}
    if name is None:
        pass
    elif name in _PLANT_SCALE:
        setattr(m, _PLANT_SCALE[name], s)
    elif name == "clearance_growth":
        x_c = [nom.x_ag * (1 + s * (0.7 + 0.6 * k / max(n_app - 1, 1))) for k in range(n_app)]
    elif name == "force_sensor_bias":
        gain = 1.0 + s
    elif name == "torque_constant_loss":
        m.kt_scale = 1.0 - s
    elif name == "backlash":
        m.play = 0.5 * s * nom.x_ag / nom.c_x
        detail = {"play_total_motor_rad": 2 * m.play, "play_total_screw_rad": 2 * m.play / nom.i_g}
    elif name == "torque_ripple":
        m.ripple_a = s * nom.T_fc
        m.ripple_n = int(rng.choice([6, 8, 12]))
        m.ripple_phase = float(rng.uniform(0, 2 * math.pi))
        detail = {"amplitude_Nm": m.ripple_a, "periods_per_motor_rev": m.ripple_n}
    elif name == "friction_drift":
        m.drift_s = s
        detail = {"tau_s": 0.4 * T_rec}
    else:
        raise ValueError(f"unknown effect {name!r}")
    return Realised(m, gain, x_c, detail)
