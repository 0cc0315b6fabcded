"""Kinematics and force equilibrium (000 eq. 8-19, Fig. 6) against closed forms and invariants."""

import dataclasses
import math

import numpy as np
import pytest

from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.physics import ModelOptions
from ebm_wear_monitor.physics.equilibrium import solve_equilibrium
from ebm_wear_monitor.physics.geometry import NUT, SCREW, ScrewGeometry, curvature
from ebm_wear_monitor.physics.hertz import deformation
from ebm_wear_monitor.physics.kinematics import ball_motion, orbit_speed, spin_speed

UNIT = load_unit()
GEO = ScrewGeometry.from_unit(UNIT)
BETA = math.radians(47.0)


def frictionless_unit():
    return dataclasses.replace(UNIT, wear=dataclasses.replace(UNIT.wear, boundary_friction=0.0))


def test_orbit_speed_is_the_bearing_cage_speed_for_equal_angles():
    """Equal contact angles: w_m = w_s (1 - g' cos a) / 2, the cage speed with the outer race fixed."""
    a = np.radians([30.0, 45.0, 60.0])
    w_m = orbit_speed(GEO, 10.0, a, a, BETA)
    assert w_m == pytest.approx(10.0 * (1.0 - GEO.gamma_prime * np.cos(a)) / 2.0, rel=1e-12)


@pytest.mark.parametrize(("a_s", "a_n"), [(45.0, 45.0), (40.0, 52.0), (50.0, 44.0)])
def test_eq_8_9_are_the_rolling_conditions(a_s, a_n):
    """Rolling rate -w_R cos(beta - a) r_b matches both raceway surface speeds in the orbit frame."""
    a_s, a_n, w_s = math.radians(a_s), math.radians(a_n), 12.0
    w_m = float(orbit_speed(GEO, w_s, a_s, a_n, BETA))
    w_r = float(spin_speed(GEO, w_m, a_n, BETA))
    cphi = math.cos(GEO.phi)
    roll_n = -w_r * math.cos(BETA - a_n) * GEO.r_b
    roll_s = -w_r * math.cos(BETA - a_s) * GEO.r_b
    assert roll_n == pytest.approx(w_m * (GEO.d_m / 2 + GEO.r_b * math.cos(a_n)) * cphi, rel=1e-12)
    assert roll_s == pytest.approx((w_s - w_m) * (GEO.d_m / 2 - GEO.r_b * math.cos(a_s)) * cphi, rel=1e-12)


def test_literal_reading_slides_at_half_the_surface_speed_rolling_does_not():
    a = np.radians(45.0)
    w_s = 20.0
    lit = ball_motion(GEO, w_s, a, a, reading="literal", beta=BETA)
    surface = w_s * GEO.d_m / 2.0
    # taken literally the ball-spin terms cancel (a + beta ~ 92 deg): V ~ d w_m ~ surface speed / 2
    assert float(lit.v_nut) == pytest.approx(GEO.d_m / 2.0 * float(lit.omega_m), rel=0.05)
    assert 0.4 < float(lit.v_screw) / surface < 0.55
    roll = ball_motion(GEO, w_s, a, a, reading="rolling", beta=BETA)
    assert float(roll.v_nut) == 0.0
    assert float(roll.v_screw) == pytest.approx(GEO.r_b * w_s * math.sin(GEO.phi), rel=1e-12)
    assert float(roll.v_screw) < 0.02 * float(lit.v_screw)  # ~90x less sliding


def test_sliding_is_proportional_to_speed_and_direction_symmetric():
    a = np.radians(45.0)
    m1 = ball_motion(GEO, 5.0, a, a)
    m2 = ball_motion(GEO, -10.0, a, a)
    assert float(m2.v_screw) == pytest.approx(2.0 * float(m1.v_screw), rel=1e-12)
    assert float(m2.v_nut) == pytest.approx(2.0 * float(m1.v_nut), rel=1e-12)
    assert float(m2.centrifugal) == pytest.approx(4.0 * float(m1.centrifugal), rel=1e-12)


def test_frictionless_static_equilibrium_is_harris_closed_form():
    """No friction, no speed: a_s = a_n, cos a = B cos a0 / (B + d_s + d_n), Q = F / (Z sin a cos phi)."""
    unit = frictionless_unit()
    f = np.array([500.0, 5e3, 20e3, 60e3])
    eq = solve_equilibrium(unit, f, np.zeros_like(f), ModelOptions())
    assert eq.alpha_s == pytest.approx(eq.alpha_n, abs=1e-12)
    b0 = GEO.centre_distance0
    cos_a = b0 * math.cos(GEO.alpha0) / (b0 + eq.delta_s + eq.delta_n)
    assert np.cos(eq.alpha_s) == pytest.approx(cos_a, rel=1e-9)
    assert eq.q_s == pytest.approx(f / (GEO.z * np.sin(eq.alpha_s) * math.cos(GEO.phi)), rel=1e-9)
    # the deformations are eq. 1 of the loads (converged to the Fig. 6 accuracy)
    c = curvature(GEO, SCREW, eq.alpha_s)
    assert eq.delta_s == pytest.approx(deformation(eq.q_s, c.sum_rho, c.gamma, GEO.e_s), rel=1e-8)
    # contact angle grows with load (the ball climbs the groove)
    assert np.all(np.diff(eq.alpha_s) > 0.0) and eq.alpha_s[0] > GEO.alpha0


def test_converged_state_satisfies_eq_15_with_the_axial_closure():
    f = np.array([300.0, 3e3, 20e3])
    w = np.array([25.0, 10.0, 150.0])
    eq = solve_equilibrium(UNIT, f, w, ModelOptions())
    p = f / (GEO.z * math.cos(GEO.phi))
    fs, fn = eq.mu_s * eq.q_s, eq.mu_n * eq.q_n
    ss, cs, sn, cn = np.sin(eq.alpha_s), np.cos(eq.alpha_s), np.sin(eq.alpha_n), np.cos(eq.alpha_n)
    radial = -eq.q_s * cs + fs * ss + eq.q_n * cn + fn * sn - eq.motion.centrifugal
    axial = eq.q_s * ss + fs * cs - eq.q_n * sn + fn * cn
    closure = eq.q_s * ss + fs * cs - p
    for r in (radial, axial, closure):
        assert np.all(np.abs(r) < 1e-6 * p)
    # static friction angle split: a_n - a_s = atan(mu_s) + atan(mu_n) when F_c is negligible
    assert eq.alpha_n[1] - eq.alpha_s[1] == pytest.approx(np.arctan(eq.mu_s[1]) + np.arctan(eq.mu_n[1]),
                                                          rel=1e-3)
    # geometry of eq. 16-18: the ball centre closes the triangle of groove centres (delta_r = 0)
    l_s = GEO.r_s - GEO.r_b + eq.delta_s
    l_n = GEO.r_n - GEO.r_b + eq.delta_n
    assert l_s * cs + l_n * cn == pytest.approx(GEO.centre_distance0 * math.cos(GEO.alpha0), rel=1e-6)


def test_eq_15_as_printed_cannot_fix_the_load_level():
    """Without the closure, eq. 15 is homogeneous in (Q_s, Q_n) when F_c ~ 0: any multiple solves it."""
    eq = solve_equilibrium(UNIT, np.array([10e3]), np.array([0.0]), ModelOptions())
    ss, cs, sn, cn = (float(np.sin(eq.alpha_s[0])), float(np.cos(eq.alpha_s[0])),
                      float(np.sin(eq.alpha_n[0])), float(np.cos(eq.alpha_n[0])))
    ms, mn = float(eq.mu_s[0]), float(eq.mu_n[0])
    matrix = np.array([[-cs + ms * ss, cn + mn * sn], [ss + ms * cs, -sn + mn * cn]])
    assert abs(np.linalg.det(matrix)) < 1e-6 * np.linalg.norm(matrix) ** 2
    for scale in (1.0, 7.0):
        loads = scale * np.array([eq.q_s[0], eq.q_n[0]])
        assert np.all(np.abs(matrix @ loads) < 1e-6 * loads.max())


def test_theta_prime_of_2_degrees_makes_eq_17_unsolvable():
    """000 Sec. 4.2's theta' = 2 deg puts the groove centres theta' R* ~ 0.56 mm apart: no ball fits."""
    theta = math.radians(2.0)
    r_star = (GEO.d_m + 2 * (GEO.r_s - GEO.r_b) * math.cos(GEO.alpha0)) / (2 * math.cos(GEO.phi))
    a1 = GEO.centre_distance0 * math.sin(GEO.alpha0) + theta * r_star
    a2 = GEO.centre_distance0 * math.cos(GEO.alpha0)
    eq = solve_equilibrium(UNIT, np.array([60e3]), np.array([0.0]), ModelOptions())
    reach = (GEO.r_s - GEO.r_b + eq.delta_s[0]) + (GEO.r_n - GEO.r_b + eq.delta_n[0])
    assert math.hypot(a1, a2) > 2.0 * reach  # the two circles of eq. 17 cannot intersect
    # whereas the solved axial approach theta' R* + delta_a is microns
    assert 0.0 < eq.axial_approach[0] < 50e-6


def test_contact_angles_fall_back_without_load_dependence_on_speed():
    """At EMBU speeds F_c is negligible: the equilibrium barely depends on speed (<1e-3 relative)."""
    f = np.full(3, 10e3)
    eq = solve_equilibrium(UNIT, f, np.array([0.0, 25.0, 100.0]), ModelOptions())
    assert eq.q_s == pytest.approx(np.full(3, eq.q_s[0]), rel=2e-2)
    assert eq.iterations < 30
    assert NUT != SCREW


def test_an_unconverged_solve_is_refused_not_reported():
    """Fig. 6 cut short (one iteration) must not hand out its last iterate as the wear state."""
    from ebm_wear_monitor.errors import InputError
    from ebm_wear_monitor.physics.options import ModelOptions
    from ebm_wear_monitor.physics.reports import wear_report

    with pytest.raises(InputError, match="did not converge in 1 iterations"):
        wear_report(UNIT, 20e3, 20.0, ModelOptions(max_iter=1))
    assert wear_report(UNIT, 20e3, 20.0).screw.wear_rate_m_s > 0.0
