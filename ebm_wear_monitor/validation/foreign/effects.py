"""Effects of the foreign world: physical deviations from the nominal 004 plant, each in its own forms.

Every catalog effect of interface.md section 4 has two functional forms that differ from the
diagnosis catalog's own parametrisation; four more effects are outside the catalog. A form is
built from one number, its *magnitude* ``s``: the relative change of a named nominal quantity at a
stated reference point (``REFERENCE``), so that ``s = 0.2`` means "+20 % of that quantity there".
The truth record of each effect gives the equation, every parameter in SI, the quantity and
``relative_change`` (= ``s``).

Reference point: clamp force ``F_REF`` = 20 kN, motor speed ``W_REF`` = 20 rad/s; ``T_L = r_g F``
is the load torque at the motor, ``th`` the absolute motor angle, ``th / i_g`` the screw angle.
Friction terms add to the kinetic level ``C_k`` (sliding) and, where the effect exists at
standstill, to the static level ``C_s`` too (004 eq. 9 structure).

| effect | form | equation |
|---|---|---|
| viscous_friction | power | ``C_k += c |w|^0.6``, ``c = s B W_REF^0.4`` |
| viscous_friction | shear_thinning | ``C_k += s B W_REF (|w|/W_REF) (1 + W_REF/w_c) / (1 + |w|/w_c)`` |
| load_friction | power | ``C_k, C_s += g F^1.2``, ``g = s G F_REF^-0.2`` |
| load_friction | coaxiality | ``C_k, C_s += s G F (1 + m cos(th/i_g + phi))`` |
| efficiency_variation | lowspeed_load | ``C_k += a T_L sqrt(F/F_REF) exp(-|w|/w_e)``; ``C_s`` at w=0 |
| efficiency_variation | churning | ``C_k += a T_L (F/F_REF)^2 / (1 + (F/F_REF)^2) * 2 |w| / (|w| + w_h)`` |
| preload_change | coulomb_only | ``T_fc -> (1 + s) T_fc``; ``C_s`` raised only if needed to stay >= ``C_k`` |
| preload_change | relief | ``C_k, C_s += s T_fc max(0, 1 - F/F_r)`` (double-nut preload relieved by load) |
| stribeck | exponential | ``C_k += s T_fc exp(-|w|/w_s)`` |
| stribeck | rational | ``C_k += s T_fc / (1 + (|w|/w_s)^2)`` |
| stiffness_nonlinearity | power | ``F = K_b d_5 (d/d_5)^p``, ``p = 1 + ln(1+s)/ln(28/5)`` |
| stiffness_nonlinearity | bilinear | ``F = K_b d`` below ``d_k``, slope ``K_b (1 + r)`` above |
| clearance_growth | scatter | ``x_ag,k = x_ag + s x_ag (1 + 0.15 N(0,1))`` per application |
| clearance_growth | ramp | ``x_ag,k = x_ag + s x_ag (0.5 + k/(n-1))`` across the recording |
| force_sensor_bias | gain_offset_quadratic | ``F_cell = (1+g) F + b + c F^2 / 50 kN`` |
| force_sensor_bias | thermal_drift | ``F_cell = (1 + g_k) F + b_k``, gain and offset drifting with time |
| torque_constant_loss (outside) | flux | ``K_T, K_E -> (1 - s) K_T, (1 - s) K_E`` |
| backlash (outside) | play | play ``b`` (motor side), ``s = b r_g / x_ag``; in it ``J_m + J_g``, ``1-f_s`` |
| torque_ripple (outside) | screw_periodic | ``T_d += s T_fc sin(k th/i_g + phi)`` |
| friction_drift (outside) | rising / warming | ``C_k, C_s`` times ``m_k`` per application (drifting) |

In the backlash play the motor is decoupled from what lies past the gear mesh: it carries only its
own and the gear's inertia and the share ``1 - f_s`` of the whole friction, eq. 9's levels and any
friction effect's (``f_s`` drawn in 0.5-0.8: the screw-nut preload and the support bearing make most
of a ball-screw drive's no-load friction). For the reference unit J_m + J_g is 99.97 % of J_me, so
in practice only the friction share makes the play visible.

Stribeck and Coulomb-only preload forms keep ``C_s >= C_k`` at standstill (``C_s`` raised by
``max(0, C_k(0) - T_fs)``): friction cannot exceed its breakaway level.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .plant import Physics
from .unit import Actuator

F_REF = 20e3  # reference clamp force [N]
W_REF = 20.0  # reference motor speed [rad/s]
REFERENCE = {"force_N": F_REF, "motor_speed_rad_s": W_REF}
CATALOG = ("viscous_friction", "load_friction", "efficiency_variation", "preload_change", "stribeck",
           "stiffness_nonlinearity", "clearance_growth", "force_sensor_bias")
OUTSIDE = ("torque_constant_loss", "backlash", "torque_ripple", "friction_drift")


@dataclass(frozen=True)
class Context:
    """What a form may depend on: the unit, the number of applications and their onset times."""

    act: Actuator
    onset: np.ndarray  # demand onset of each application from the recording start [s]
    duration: float  # recording length [s]
    rng: np.random.Generator


def _record(name: str, form: str, equation: str, quantity: str, s: float,
            **params: float | np.ndarray) -> dict:
    return {"name": name, "catalog": name in CATALOG, "form": form, "equation": equation,
            "params": {k: (v.tolist() if isinstance(v, np.ndarray) else float(v))
                       for k, v in params.items()},
            "quantity": quantity, "relative_change": float(s), "reference": REFERENCE}


def _on_both(phys: Physics, f) -> None:
    """Add ``f(F, w, th)`` to the sliding level and its standstill value to the breakaway level."""
    phys.kinetic_extra.append(f)
    phys.static_extra.append(lambda F, th: f(F, 0.0, th))


def _standstill_floor(phys: Physics, act: Actuator, kinetic_at_zero: float) -> float:
    """Raise ``C_s`` so that the breakaway level is never below the kinetic level at w = 0."""
    lift = max(0.0, kinetic_at_zero - act.T_fs)
    if lift > 0.0:
        phys.static_extra.append(lambda F, th: lift)
    return lift


# --- catalog effects ------------------------------------------------------------------------
def viscous_power(phys: Physics, ctx: Context, s: float) -> dict:
    c = s * ctx.act.B * W_REF**0.4
    phys.kinetic_extra.append(lambda F, w, th: c * np.abs(w) ** 0.6)
    return _record("viscous_friction", "power", "T_f += c |w_m|^0.6 sgn(w_m)",
                   "viscous torque B w_m at W_REF", s, c=c, exponent=0.6)


def viscous_shear_thinning(phys: Physics, ctx: Context, s: float) -> dict:
    w_c = float(ctx.rng.uniform(5.0, 15.0))
    k = s * ctx.act.B * (1 + W_REF / w_c)
    phys.kinetic_extra.append(lambda F, w, th: k * np.abs(w) / (1 + np.abs(w) / w_c))
    return _record("viscous_friction", "shear_thinning",
                   "T_f += k w_m / (1 + |w_m|/w_c), k = s B (1 + W_REF/w_c)",
                   "viscous torque B w_m at W_REF", s, k=k, w_c=w_c)


def load_power(phys: Physics, ctx: Context, s: float) -> dict:
    g = s * ctx.act.G * F_REF**-0.2
    _on_both(phys, lambda F, w, th: g * F**1.2)
    return _record("load_friction", "power", "T_f += g F^1.2 (sliding and breakaway)",
                   "load friction G F at F_REF", s, g=g, exponent=1.2)


def load_coaxiality(phys: Physics, ctx: Context, s: float) -> dict:
    m, phi = float(ctx.rng.uniform(0.5, 0.9)), float(ctx.rng.uniform(0, 2 * np.pi))
    G, i_g = ctx.act.G, ctx.act.i_g
    _on_both(phys, lambda F, w, th: s * G * F * (1 + m * np.cos(th / i_g + phi)))
    phys.absolute = True
    return _record("load_friction", "coaxiality",
                   "T_f += s G F (1 + m cos(theta_screw + phi)): misalignment load once per screw turn",
                   "load friction G F (mean over a screw turn)", s, m=m, phi=phi)


def _friction_at_ref(act: Actuator) -> float:
    return act.T_fc + act.G * F_REF


def efficiency_lowspeed_load(phys: Physics, ctx: Context, s: float) -> dict:
    act = ctx.act
    w_e = float(ctx.rng.uniform(8.0, 20.0))
    a = s * _friction_at_ref(act) / (act.r_g * F_REF)
    _on_both(phys, lambda F, w, th: a * act.r_g * F * np.sqrt(F / F_REF) * np.exp(-np.abs(w) / w_e))
    return _record("efficiency_variation", "lowspeed_load",
                   "T_f += a T_L sqrt(F/F_REF) exp(-|w_m|/w_e): boundary lubrication at low speed",
                   "sliding friction T_fc + G F at F_REF, standstill", s, a=a, w_e=w_e)


def efficiency_churning(phys: Physics, ctx: Context, s: float) -> dict:
    act = ctx.act
    w_h = float(ctx.rng.uniform(5.0, 20.0))
    a = s * _friction_at_ref(act) * (W_REF + w_h) / (act.r_g * F_REF * W_REF)
    phys.kinetic_extra.append(lambda F, w, th: a * act.r_g * F * (F / F_REF) ** 2
                              / (1 + (F / F_REF) ** 2) * 2 * np.abs(w) / (np.abs(w) + w_h))
    return _record("efficiency_variation", "churning",
                   "T_f += a T_L (F/F_REF)^2/(1+(F/F_REF)^2) 2|w_m|/(|w_m|+w_h)",
                   "sliding friction T_fc + G F at F_REF, W_REF", s, a=a, w_h=w_h)


def preload_coulomb_only(phys: Physics, ctx: Context, s: float) -> dict:
    act = ctx.act
    phys.kinetic_extra.append(lambda F, w, th: s * act.T_fc)
    lift = _standstill_floor(phys, act, (1 + s) * act.T_fc)
    return _record("preload_change", "coulomb_only",
                   "T_fc -> (1+s) T_fc, T_fs unchanged (raised by `lift` only to stay >= T_fc)",
                   "Coulomb friction T_fc", s, dT_fc=s * act.T_fc, lift=lift)


def preload_relief(phys: Physics, ctx: Context, s: float) -> dict:
    act = ctx.act
    F_r = float(ctx.rng.uniform(6e3, 12e3))
    d = s * act.T_fc
    _on_both(phys, lambda F, w, th: d * np.maximum(0.0, 1 - F / F_r))
    return _record("preload_change", "relief",
                   "T_fc, T_fs += s T_fc max(0, 1 - F/F_r): preload relieved by the axial load",
                   "Coulomb friction T_fc at zero load", s, dT=d, F_r=F_r)


def stribeck_exponential(phys: Physics, ctx: Context, s: float) -> dict:
    act = ctx.act
    w_s = float(ctx.rng.uniform(2.0, 8.0))
    phys.kinetic_extra.append(lambda F, w, th: s * act.T_fc * np.exp(-np.abs(w) / w_s))
    lift = _standstill_floor(phys, act, (1 + s) * act.T_fc)
    return _record("stribeck", "exponential", "T_f += s T_fc exp(-|w_m|/w_s)",
                   "Coulomb friction T_fc at zero speed", s, w_s=w_s, lift=lift)


def stribeck_rational(phys: Physics, ctx: Context, s: float) -> dict:
    act = ctx.act
    w_s = float(ctx.rng.uniform(2.0, 8.0))
    phys.kinetic_extra.append(lambda F, w, th: s * act.T_fc / (1 + (w / w_s) ** 2))
    lift = _standstill_floor(phys, act, (1 + s) * act.T_fc)
    return _record("stribeck", "rational", "T_f += s T_fc / (1 + (w_m/w_s)^2)",
                   "Coulomb friction T_fc at zero speed", s, w_s=w_s, lift=lift)


def stiffness_power(phys: Physics, ctx: Context, s: float) -> dict:
    K = ctx.act.K_b
    d5 = 5e3 / K
    p = 1 + np.log1p(s) / np.log(28.0 / 5.0)
    phys.clamp = lambda d, K_b: K_b * d5 * (d / d5) ** p
    return _record("stiffness_nonlinearity", "power",
                   "F = K_b d_5 (d/d_5)^p (equal to 004 eq. 5 at 5 kN)",
                   "clamp force at the nominal 28 kN penetration", s, p=p, d_5=d5)


def stiffness_bilinear(phys: Physics, ctx: Context, s: float) -> dict:
    K = ctx.act.K_b
    d_k = float(ctx.rng.uniform(8e3, 14e3)) / K
    d28 = 28e3 / K
    r = s * d28 / (d28 - d_k)
    phys.clamp = lambda d, K_b: K_b * d + K_b * r * np.maximum(d - d_k, 0.0)
    return _record("stiffness_nonlinearity", "bilinear",
                   "F = K_b d + r K_b max(0, d - d_k): a second spring engages at d_k",
                   "clamp force at the nominal 28 kN penetration", s, r=r, d_k=d_k)


def clearance_scatter(phys: Physics, ctx: Context, s: float) -> dict:
    n = ctx.onset.size
    dx = s * ctx.act.x_ag * np.maximum(1 + 0.15 * ctx.rng.standard_normal(n), 0.0)
    phys.clearance_extra = dx
    return _record("clearance_growth", "scatter", "x_ag,k = x_ag + s x_ag (1 + 0.15 N(0,1))",
                   "clearance x_ag (mean over the recording)", float(np.mean(dx)) / ctx.act.x_ag,
                   dx_m=dx)


def clearance_ramp(phys: Physics, ctx: Context, s: float) -> dict:
    n = ctx.onset.size
    dx = s * ctx.act.x_ag * (0.5 + np.arange(n) / max(n - 1, 1))
    phys.clearance_extra = dx
    return _record("clearance_growth", "ramp", "x_ag,k = x_ag + s x_ag (0.5 + k/(n-1))",
                   "clearance x_ag (mean over the recording)", float(np.mean(dx)) / ctx.act.x_ag,
                   dx_m=dx)


def sensor_gain_offset_quadratic(phys: Physics, ctx: Context, s: float) -> dict:
    b = float(ctx.rng.uniform(50.0, 200.0)) * float(ctx.rng.choice([-1.0, 1.0]))
    c = 0.02 * float(ctx.rng.choice([-1.0, 1.0]))
    g = s - c * F_REF / 50e3 - b / F_REF
    phys.cell = lambda F: (1 + g) * F + b + c * F**2 / 50e3
    return _record("force_sensor_bias", "gain_offset_quadratic", "F_cell = (1+g) F + b + c F^2/50 kN",
                   "measured force at F_REF", s, g=g, b=b, c=c)


def sensor_thermal_drift(phys: Physics, ctx: Context, s: float) -> dict:
    tau = ctx.onset / ctx.duration  # 0 .. 1 across the recording
    g = s / 1.15 * (1 + 0.3 * tau)  # mean over tau in [0, 1] is s
    b = float(ctx.rng.uniform(-100.0, 100.0)) + float(ctx.rng.uniform(50.0, 150.0)) * tau
    phys.cell = lambda F: (1 + g) * F + b
    return _record("force_sensor_bias", "thermal_drift",
                   "F_cell = (1 + g_k) F + b_k, g_k and b_k per application (warming sensor)",
                   "measured force at F_REF (mean over the recording)", float(np.mean(g)),
                   g_k=g, b_k_N=b)


# --- outside the catalog --------------------------------------------------------------------
def torque_constant_flux(phys: Physics, ctx: Context, s: float) -> dict:
    phys.kt_factor = 1 - s
    return _record("torque_constant_loss", "flux", "K_T, K_E -> (1 - s) K_T, (1 - s) K_E",
                   "motor torque constant K_T", -s, factor=1 - s)


def backlash_play(phys: Physics, ctx: Context, s: float) -> dict:
    b = s * ctx.act.x_ag / ctx.act.r_g
    share = float(ctx.rng.uniform(0.5, 0.8))
    phys.backlash = b
    phys.screw_friction_share = share
    return _record("backlash", "play",
                   "theta - b <= q <= theta (motor theta, screw q referred to the motor); under load "
                   "the screw rests on the forward flank; inside the play the motor turns against no "
                   "clamp load, only its own and the gear's inertia J_m + J_g and the friction share "
                   "1 - f_s not downstream of the gear mesh (f_s: screw-nut and support bearing)",
                   "play as a share of the clearance x_ag", s, b_motor_rad=b, b_axial_m=b * ctx.act.r_g,
                   screw_friction_share=share)


def ripple_screw_periodic(phys: Physics, ctx: Context, s: float) -> dict:
    act = ctx.act
    k = int(ctx.rng.integers(1, 5))
    phi = float(ctx.rng.uniform(0, 2 * np.pi))
    amp = s * act.T_fc
    phys.drive_extra.append(lambda th: amp * np.sin(k * th / act.i_g + phi))
    phys.absolute = True
    return _record("torque_ripple", "screw_periodic", "T_d += A sin(k theta_screw + phi)",
                   "Coulomb friction T_fc (ripple amplitude)", s, A=amp, k=k, phi=phi)


def _drift(phys: Physics, ctx: Context, m: np.ndarray) -> None:
    act = ctx.act
    phys.kinetic_extra.append(lambda F, w, th: (m - 1) * (act.T_fc + act.G * F))
    phys.static_extra.append(lambda F, th: (m - 1) * (act.T_fs + act.G * F))


def drift_rising(phys: Physics, ctx: Context, s: float) -> dict:
    m = 1 + s * ctx.onset / ctx.onset[-1]
    _drift(phys, ctx, m)
    return _record("friction_drift", "rising", "T_fs, T_fc, G x m_k, m_k = 1 + s t_k / t_last",
                   "friction of eq. 9 at the last application", s, m_k=m)


def drift_warming(phys: Physics, ctx: Context, s: float) -> dict:
    tau = float(ctx.rng.uniform(0.2, 0.5)) * ctx.duration
    m = 1 - s * (1 - np.exp(-ctx.onset / tau)) / (1 - np.exp(-ctx.onset[-1] / tau))
    _drift(phys, ctx, m)
    return _record("friction_drift", "warming",
                   "T_fs, T_fc, G x m_k, m_k = 1 - s (1 - exp(-t_k/tau)) / (1 - exp(-t_last/tau)): "
                   "grease warming up", "friction of eq. 9 at the last application", -s, m_k=m,
                   tau_s=tau)


FORMS = {
    "viscous_friction": {"power": viscous_power, "shear_thinning": viscous_shear_thinning},
    "load_friction": {"power": load_power, "coaxiality": load_coaxiality},
    "efficiency_variation": {"lowspeed_load": efficiency_lowspeed_load,
                             "churning": efficiency_churning},
    "preload_change": {"coulomb_only": preload_coulomb_only, "relief": preload_relief},
    "stribeck": {"exponential": stribeck_exponential, "rational": stribeck_rational},
    "stiffness_nonlinearity": {"power": stiffness_power, "bilinear": stiffness_bilinear},
    "clearance_growth": {"scatter": clearance_scatter, "ramp": clearance_ramp},
    "force_sensor_bias": {"gain_offset_quadratic": sensor_gain_offset_quadratic,
                          "thermal_drift": sensor_thermal_drift},
    "torque_constant_loss": {"flux": torque_constant_flux},
    "backlash": {"play": backlash_play},
    "torque_ripple": {"screw_periodic": ripple_screw_periodic},
    "friction_drift": {"rising": drift_rising, "warming": drift_warming},
}


def build(forms: tuple[tuple[str, str, float], ...], ctx: Context) -> tuple[Physics, list[dict]]:
    """Physics hooks and truth records for ``(name, form, magnitude)`` triples."""
    phys = Physics()
    records = []
    for name, form, s in forms:
        try:
            builder = FORMS[name][form]
        except KeyError:
            raise ValueError(f"unknown effect form {name}/{form}") from None
        records.append(builder(phys, ctx, float(s)))
    return phys, records
