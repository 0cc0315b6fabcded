"""Results of ``ebm-wear calc contact`` and ``ebm-wear calc wear`` (interface.md section 4; the
records and their JSON keys are declared in :mod:`ebm_wear_monitor.schema.calc`).

Physical envelope (:data:`~ebm_wear_monitor.physics.surrogate.ENVELOPE`, the range the wear model
is tabulated and tested over): axial force 0 < F_a <= 80 kN (four times the reference screw's
dynamic load rating, past the elastic-plastic switch of 000 eq. 6), a normal load per ball up to
the one 80 kN gives by 000 eq. 5, |screw speed| <= 200 rad/s (1,900 rpm). Outside it the
calculators refuse with one line: Hertz theory needs contact ellipses small against the ball (at
80 kN the reference ellipse's semi-major axis is already 0.8 r_b), and a number such as a 7.8e11 m
approach at 1e30 N would be arithmetic, not physics.
"""

from __future__ import annotations

import math
from dataclasses import asdict
from typing import Any

import numpy as np

from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.params.unit import UnitParams
from ebm_wear_monitor.physics.archard import ball_rate, clearance_growth
from ebm_wear_monitor.physics.contact import area_radius, softer_poisson, solve
from ebm_wear_monitor.physics.geometry import SIDES, ScrewGeometry, curvature
from ebm_wear_monitor.physics.hertz import deformation, houpert_max_pressure, houpert_semi_axes, normal_load
from ebm_wear_monitor.physics.options import ModelOptions
from ebm_wear_monitor.physics.plasticity import contact_area
from ebm_wear_monitor.physics.surrogate import ENVELOPE
from ebm_wear_monitor.schema.calc import ContactResult, ContactSide, ReadingOptions, WearResult, WearSide


def _positive(name: str, value: float, maximum: float, unit: str) -> float:
    """``value`` if it is a finite number in (0, maximum]; InputError (one line) otherwise."""
    if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0):
        raise InputError(f"{name} must be a positive finite number, got {value!r}")
    if value > maximum:
        raise InputError(f"{name} {value:g} {unit} is outside the physical envelope of the model "
                         f"(at most {maximum:.4g} {unit})")
    return float(value)


def check_speed(speed: float) -> float:
    """Screw speed [rad/s] within the envelope |w| <= ENVELOPE.speed_max; InputError otherwise."""
    if not (isinstance(speed, (int, float)) and math.isfinite(speed)):
        raise InputError(f"speed must be finite, got {speed!r}")
    if abs(speed) > ENVELOPE.speed_max:
        raise InputError(f"speed {speed:g} rad/s is outside the physical envelope of the model "
                         f"(|speed| at most {ENVELOPE.speed_max:g} rad/s)")
    return float(speed)


def check_axial_force(force: float, name: str = "axial force", *, allow_zero: bool = False) -> float:
    """Force [N] within the envelope 0 < F <= ENVELOPE.force_max (0 too with ``allow_zero``)."""
    if allow_zero and force == 0.0:
        return 0.0
    return _positive(name, force, ENVELOPE.force_max, "N")


def _contact_type(plastic: Any) -> str:
    return "elastic-plastic" if bool(plastic) else "elastic"


def contact_report(unit: UnitParams, axial_force: float | None = None, normal_load_n: float | None = None,
                   options: ModelOptions | None = None) -> ContactResult:
    """Static contact of one ball with each raceway (000 eq. 1-7, 003 eq. 1-5, 14-15).

    Quasi-static and frictionless as in 003 Sec. 2.1: the normal load is the given
    ``normal_load_n`` or 003 eq. 1 / 000 eq. 5 from ``axial_force`` at the unloaded contact
    angle; semi-axes and peak pressure by 003 eq. 2-5, 14-15; approach by 000 eq. 1;
    contact type and area by 000 eq. 6-7 under ``options``.
    """
    options = options or ModelOptions()
    if (axial_force is None) == (normal_load_n is None):
        raise InputError("give exactly one of axial force or normal load")
    geo = ScrewGeometry.from_unit(unit)
    alpha = geo.alpha0
    if axial_force is not None:
        q = float(normal_load(check_axial_force(axial_force), geo.z, alpha, geo.phi))
    else:
        q_max = float(normal_load(ENVELOPE.force_max, geo.z, alpha, geo.phi))
        q = _positive("normal load", normal_load_n, q_max, "N")  # type: ignore[arg-type]
    out: dict[str, ContactSide] = {}
    for side in SIDES:
        c = curvature(geo, side, alpha)
        e_red = geo.modulus(side)
        a, b = houpert_semi_axes(q, c.r_x, c.gamma, e_red)
        delta = deformation(q, c.sum_rho, c.gamma, e_red)
        mat = getattr(unit.materials, side)
        ca = contact_area(delta, c.gamma, area_radius(unit, c.sum_rho, options.radius), hardness=mat.hardness,
                          poisson_ratio=softer_poisson(unit, side), e_red=e_red, kappa_reading=options.kappa)
        out[side] = ContactSide(
            normal_load_N=q, semi_major_m=float(a), semi_minor_m=float(b),
            max_pressure_Pa=float(houpert_max_pressure(q, c.r_x, c.gamma, e_red)), deformation_m=float(delta),
            contact_type=_contact_type(ca.plastic), contact_area_m2=float(ca.area),
            contact_angle_deg=math.degrees(alpha), critical_interference_m=float(ca.delta_c))
    return ContactResult(**out)


def wear_report(unit: UnitParams, axial_force: float, speed: float,
                options: ModelOptions | None = None) -> WearResult:
    """Instantaneous wear state at constant axial force [N] and screw speed [rad/s] (000 eq. 5-23)."""
    options = options or ModelOptions()
    f = check_axial_force(axial_force)
    speed = check_speed(speed)
    eq, screw, nut = solve(unit, np.array([f]), np.array([abs(speed)]), options)
    if not eq.converged:
        raise InputError(f"the Fig. 6 equilibrium did not converge in {options.max_iter} iterations at "
                         f"{f:g} N, {speed:g} rad/s (friction coefficients mu_s {float(eq.mu_s[0]):.3g}, "
                         f"mu_n {float(eq.mu_n[0]):.3g}): outside the range the model solves")
    sides = {side: WearSide(
        normal_load_N=float(st.normal_load[0]), contact_angle_deg=math.degrees(float(st.alpha[0])),
        sliding_velocity_m_s=float(st.sliding_velocity[0]), contact_area_m2=float(st.area[0]),
        contact_type=_contact_type(st.plastic[0]), wear_rate_m_s=float(st.wear_rate[0]),
        deformation_m=float(st.deformation[0])) for side, st in (("screw", screw), ("nut", nut))}
    ball = float(ball_rate(screw.wear_rate, nut.wear_rate, unit.wear.raceway_share)[0])
    growth = clearance_growth(unit, screw.wear_rate[0], nut.wear_rate[0], ball)
    return WearResult(**sides, ball_wear_rate_m_s=ball, clearance_growth_rate_m_s=float(growth),
                      iterations=int(eq.iterations), options=ReadingOptions(**asdict(options)))
